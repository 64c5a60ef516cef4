#include "service/flags.h"

#include <charconv>

namespace rollwear::cli {

bool Flags::Parse(const std::vector<std::string>& args,
                  const std::set<std::string>& known,
                  const std::set<std::string>& switches, std::string* error) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a.rfind("--", 0) != 0) {
      positional_.push_back(a);
      continue;
    }
    std::string name = a.substr(2);
    std::string value;
    const size_t eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    if (known.count(name) == 0 && switches.count(name) == 0) {
      *error = "unknown option --" + name;
      return false;
    }
    if (switches.count(name) > 0) {
      values_[name].push_back(inline_value ? value : "1");
      continue;
    }
    if (!inline_value) {
      if (i + 1 >= args.size()) {
        *error = "option --" + name + " needs a value";
        return false;
      }
      value = args[++i];
    }
    values_[name].push_back(value);
  }
  return true;
}

std::string Flags::Get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second.back();
}

std::vector<std::string> Flags::GetAll(const std::string& name) const {
  auto it = values_.find(name);
  return it == values_.end() ? std::vector<std::string>{} : it->second;
}

namespace {

// Parses the whole of `v` as a number of type T (std::from_chars).
template <typename T>
bool ParseWhole(const std::string& name, const std::string& v, const char* what, T* out,
                std::string* error) {
  auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), *out);
  if (ec != std::errc() || p != v.data() + v.size()) {
    *error = "option --" + name + " needs " + what + ", got '" + v + "'";
    return false;
  }
  return true;
}

}  // namespace

bool Flags::GetInt(const std::string& name, long long fallback, long long* out,
                   std::string* error) const {
  *out = fallback;
  return !Has(name) || ParseWhole(name, Get(name), "an integer", out, error);
}

bool Flags::GetDouble(const std::string& name, double fallback, double* out,
                      std::string* error) const {
  *out = fallback;
  return !Has(name) || ParseWhole(name, Get(name), "a number", out, error);
}

}  // namespace rollwear::cli
