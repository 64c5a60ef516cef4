#include "service/config.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace rollwear::service {
namespace {

std::string Trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

Status Bad(const std::string& where, const std::string& key,
           const std::string& rule, const std::string& value) {
  return Status::InvalidArgument(where + ": " + key + ": " + rule + ", got '" +
                                 value + "'");
}

bool ParseInt(const std::string& text, long long lo, long long hi,
              long long* out) {
  if (text.empty()) return false;
  const auto [p, ec] =
      std::from_chars(text.data(), text.data() + text.size(), *out);
  return ec == std::errc() && p == text.data() + text.size() && *out >= lo &&
         *out <= hi;
}

Status SetInt(const std::string& key, const std::string& value,
              const std::string& where, long long lo, long long hi,
              long long* out) {
  if (!ParseInt(value, lo, hi, out)) {
    return Bad(where, key,
               "must be an integer in [" + std::to_string(lo) + ", " +
                   std::to_string(hi) + "]",
               value);
  }
  return Status::Ok();
}

}  // namespace

bool ParseTimeOfDay(const std::string& text, int* minutes) {
  if (text == "off" || text == "none" || text == "disabled") {
    *minutes = -1;
    return true;
  }
  if (text.size() != 5 || text[2] != ':') return false;
  long long h = 0, m = 0;
  if (!ParseInt(text.substr(0, 2), 0, 23, &h) ||
      !ParseInt(text.substr(3, 2), 0, 59, &m)) {
    return false;
  }
  *minutes = static_cast<int>(h * 60 + m);
  return true;
}

std::string FormatTimeOfDay(int minutes) {
  if (minutes < 0) return "off";
  char buf[16];
  std::snprintf(buf, sizeof(buf), "%02d:%02d", minutes / 60, minutes % 60);
  return buf;
}

namespace {

// "wear_limit_um_f6_top" for slot 10.
std::string WearLimitKey(int slot) {
  return "wear_limit_um_f" + std::to_string(SlotStand(slot)) + "_" +
         PositionName(SlotPosition(slot));
}

// A wear limit in µm: (0, 5000], or "off" (0).
Status SetWearLimit(const std::string& key, const std::string& value,
                    const std::string& where, double* out) {
  if (value == "off") {
    *out = 0;
    return Status::Ok();
  }
  char* end = nullptr;
  const double v = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !(v > 0) ||
      !(v <= 5000)) {
    return Bad(where, key, "must be a number in (0, 5000] µm or off", value);
  }
  *out = v;
  return Status::Ok();
}

}  // namespace

std::array<double, kNumRollPositionSlots> ServeConfig::WearLimits() const {
  std::array<double, kNumRollPositionSlots> out{};
  for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
    out[slot] =
        wear_limit_um_at[slot] > 0 ? wear_limit_um_at[slot] : wear_limit_um;
  }
  return out;
}

const std::vector<std::string>& ConfigKeys() {
  static const std::vector<std::string> kKeys = [] {
    std::vector<std::string> keys = {"port",
                                     "bind",
                                     "db",
                                     "token",
                                     "body_limit_bytes",
                                     "recalibration_time",
                                     "model",
                                     "option",
                                     "threads",
                                     "keep_alive_max",
                                     "keep_alive_timeout",
                                     "max_connections",
                                     "max_connections_per_client",
                                     "head_timeout",
                                     "body_timeout",
                                     "read_timeout",
                                     "max_buffered_input_bytes",
                                     "log_level",
                                     "cpu_wakeup_latency_us",
                                     "wear_limit_um"};
    for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
      keys.push_back(WearLimitKey(slot));
    }
    return keys;
  }();
  return kKeys;
}

Status SetConfigValue(const std::string& key, const std::string& value,
                      const std::string& where, ServeConfig* c) {
  long long n = 0;
  if (key == "port") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 0, 65535, &n));
    c->port = static_cast<int>(n);
  } else if (key == "bind") {
    if (value.empty()) return Bad(where, key, "must not be empty", value);
    c->bind = value;
  } else if (key == "db") {
    if (value.empty()) return Bad(where, key, "must not be empty", value);
    c->db = value;
  } else if (key == "token") {
    for (char ch : value) {
      if (std::isspace(static_cast<unsigned char>(ch)) || ch < 0x21) {
        return Status::InvalidArgument(
            where + ": token: must not contain spaces or control characters");
      }
    }
    c->token = value;
  } else if (key == "body_limit_bytes") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 1024, 1LL << 30, &n));
    c->body_limit_bytes = static_cast<size_t>(n);
  } else if (key == "recalibration_time") {
    if (!ParseTimeOfDay(value, &c->recalibration_minute)) {
      return Bad(where, key, "must be HH:MM (local time, 00:00..23:59) or off",
                 value);
    }
  } else if (key == "model") {
    if (!ParseWearLaw(value, &c->model)) {
      return Bad(where, key, "must be wang, nikitenko or cao", value);
    }
  } else if (key == "option") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 1, 3, &n));
    c->option = static_cast<int>(n);
  } else if (key == "threads") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 1, 1024, &n));
    c->threads = static_cast<int>(n);
  } else if (key == "keep_alive_max") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 1, 1000000, &n));
    c->keep_alive_max = static_cast<int>(n);
  } else if (key == "keep_alive_timeout") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 1, 3600, &n));
    c->keep_alive_timeout_s = static_cast<int>(n);
  } else if (key == "max_connections") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 1, 1000000, &n));
    c->max_connections = static_cast<int>(n);
  } else if (key == "max_connections_per_client") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 1, 1000000, &n));
    c->max_connections_per_client = static_cast<int>(n);
  } else if (key == "head_timeout" || key == "body_timeout" ||
             key == "read_timeout") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 1, 3600, &n));
    (key == "head_timeout"   ? c->head_timeout_s
     : key == "body_timeout" ? c->body_timeout_s
                             : c->read_timeout_s) = static_cast<int>(n);
  } else if (key == "max_buffered_input_bytes") {
    ROLLWEAR_RETURN_IF_ERROR(SetInt(key, value, where, 1 << 20, 1LL << 36, &n));
    c->max_buffered_input_bytes = static_cast<size_t>(n);
  } else if (key == "log_level") {
    static constexpr const char* kLevels[] = {"trace", "debug", "info",
                                              "warn",  "error", "off"};
    if (std::find(std::begin(kLevels), std::end(kLevels), value) ==
        std::end(kLevels)) {
      return Bad(where, key, "must be trace, debug, info, warn, error or off",
                 value);
    }
    c->log_level = value;
  } else if (key == "cpu_wakeup_latency_us") {
    if (value == "off") {
      c->cpu_wakeup_latency_us = -1;
    } else if (!ParseInt(value, 0, 1000000, &n)) {
      return Bad(where, key, "must be an integer in [0, 1000000] or off",
                 value);
    } else {
      c->cpu_wakeup_latency_us = static_cast<int>(n);
    }
  } else if (key == "wear_limit_um") {
    ROLLWEAR_RETURN_IF_ERROR(
        SetWearLimit(key, value, where, &c->wear_limit_um));
  } else if (key.rfind("wear_limit_um_f", 0) == 0 &&
             std::find(ConfigKeys().begin(), ConfigKeys().end(), key) !=
                 ConfigKeys().end()) {
    for (int slot = 0; slot < kNumRollPositionSlots; ++slot) {
      if (key == WearLimitKey(slot)) {
        ROLLWEAR_RETURN_IF_ERROR(
            SetWearLimit(key, value, where, &c->wear_limit_um_at[slot]));
      }
    }
  } else {
    std::string known;
    for (const std::string& k : ConfigKeys()) {
      known += known.empty() ? "" : ", ";
      known += k;
    }
    return Status::InvalidArgument(where + ": unknown key '" + key +
                                   "' (known keys: " + known + ")");
  }
  return Status::Ok();
}

Status ParseConfigText(const std::string& text, const std::string& name,
                       ServeConfig* config) {
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string where = name + ":" + std::to_string(number);
    // A '#' starts a comment unless it is inside a quoted value.
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
      if (line[i] == '"') quoted = !quoted;
      if (line[i] == '#' && !quoted) {
        line.resize(i);
        break;
      }
    }
    line = Trim(line);
    if (line.empty()) continue;
    const size_t eq = line.find('=');
    if (eq == std::string::npos) {
      return Status::InvalidArgument(where + ": expected 'key = value', got '" +
                                     line + "'");
    }
    const std::string key = Trim(line.substr(0, eq));
    std::string value = Trim(line.substr(eq + 1));
    if (key.empty()) {
      return Status::InvalidArgument(where + ": missing key before '='");
    }
    if (value.size() >= 2 && value.front() == '"' && value.back() == '"') {
      value = value.substr(1, value.size() - 2);
    }
    ROLLWEAR_RETURN_IF_ERROR(SetConfigValue(key, value, where, config));
  }
  return Status::Ok();
}

Status LoadConfigFile(const std::string& path, ServeConfig* config) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::IoError(path + ": cannot open config file");
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return Status::IoError(path + ": cannot read config file");
  return ParseConfigText(text.str(), path, config);
}

Status ApplyEnvironment(
    ServeConfig* config,
    const std::function<const char*(const char*)>& getenv_fn) {
  for (const std::string& key : ConfigKeys()) {
    std::string name = "ROLLWEAR_";
    for (char ch : key) {
      name += static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    }
    const char* value =
        getenv_fn ? getenv_fn(name.c_str()) : std::getenv(name.c_str());
    // An empty variable counts as unset: an empty ROLLWEAR_TOKEN must not
    // silently switch authentication off.
    if (value == nullptr || *value == '\0') continue;
    ROLLWEAR_RETURN_IF_ERROR(SetConfigValue(key, value, name, config));
  }
  return Status::Ok();
}

bool ServeConfig::IsValid(std::string* error) const {
  if (db.empty()) {
    *error =
        "no database: give --db FILE, 'db = FILE' in the config file or "
        "ROLLWEAR_DB";
    return false;
  }
  if (port < 0 || port > 65535) {
    *error = "port must be in [0, 65535]";
    return false;
  }
  if (option < 1 || option > 3) {
    *error = "option must be 1, 2 or 3";
    return false;
  }
  if (threads < 1) {
    *error = "threads must be >= 1";
    return false;
  }
  if (cpu_wakeup_latency_us < -1 || cpu_wakeup_latency_us > 1000000) {
    *error = "cpu_wakeup_latency_us must be off or in [0, 1000000]";
    return false;
  }
  return true;
}

}  // namespace rollwear::service
