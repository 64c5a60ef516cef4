// WriteTruthJson: the simulator's ground truth as a small hand-formatted
// JSON document (core carries no JSON library). Numbers are written in the
// shortest form that reads back to the same double; non-finite numbers as
// null.
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>

#include "core/simulator.h"

namespace rollwear {
namespace {

void AppendNumber(std::string* out, double v) {
  if (!std::isfinite(v)) {
    *out += "null";
    return;
  }
  char buf[64];
  // Whole numbers in plain digits ("100000", not the shorter "1e+05").
  const auto res =
      v == std::floor(v) && std::fabs(v) < 1e15
          ? std::to_chars(buf, buf + sizeof(buf), v, std::chars_format::fixed)
          : std::to_chars(buf, buf + sizeof(buf), v);
  out->append(buf, res.ptr);
}

void AppendString(std::string* out, const std::string& s) {
  *out += '"';
  for (unsigned char ch : s) {
    switch (ch) {
      case '"':
        *out += "\\\"";
        break;
      case '\\':
        *out += "\\\\";
        break;
      case '\n':
        *out += "\\n";
        break;
      case '\r':
        *out += "\\r";
        break;
      case '\t':
        *out += "\\t";
        break;
      default:
        if (ch < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", ch);
          *out += buf;
        } else {
          *out += static_cast<char>(ch);
        }
    }
  }
  *out += '"';
}

void AppendObject(std::string* out, const std::map<std::string, double>& m,
                  const char* indent) {
  *out += "{";
  bool first = true;
  for (const auto& [key, value] : m) {
    *out += first ? "\n" : ",\n";
    first = false;
    *out += indent;
    *out += "  ";
    AppendString(out, key);
    *out += ": ";
    AppendNumber(out, value);
  }
  if (!first) {
    *out += "\n";
    *out += indent;
  }
  *out += "}";
}

}  // namespace

Status WriteTruthJson(const SimulationTruth& truth, const std::string& path) {
  std::string out = "{\n  \"seed\": " + std::to_string(truth.seed) + ",\n";
  out += "  \"law\": ";
  AppendString(&out, truth.law);
  out += ",\n  \"option\": 1,\n  \"k_position\": ";
  AppendObject(&out, truth.k_position, "  ");
  out += ",\n  \"k_roll_type\": ";
  AppendObject(&out, truth.k_roll_type, "  ");
  out += ",\n  \"k_grade\": ";
  AppendObject(&out, truth.k_grade, "  ");
  out += ",\n  \"effects\": [";
  for (size_t i = 0; i < truth.effects.size(); ++i) {
    const SimulatedEffect& e = truth.effects[i];
    out += i == 0 ? "\n" : ",\n";
    out += "    {\"name\": ";
    AppendString(&out, e.name);
    out += ", \"covariate\": ";
    AppendString(&out, e.covariate);
    out += ",\n     \"description\": ";
    AppendString(&out, e.description);
    out += ",\n     \"parameters\": ";
    AppendObject(&out, e.parameters, "     ");
    out += "}";
  }
  out += truth.effects.empty() ? "],\n" : "\n  ],\n";
  out += "  \"noise_floor_um\": ";
  AppendNumber(&out, truth.noise_floor_um);
  out += ",\n  \"grinder_noise_sd_um\": ";
  AppendNumber(&out, truth.grinder_noise_sd_um);
  out += ",\n  \"roll_scatter_sd\": ";
  AppendNumber(&out, truth.roll_scatter_sd);
  out += ",\n  \"noise_free_wear_um\": [";
  const bool keyed =
      truth.noise_free_keys.size() == truth.noise_free_wear_um.size();
  for (size_t i = 0; i < truth.noise_free_wear_um.size(); ++i) {
    out += i == 0 ? "\n    " : ",\n    ";
    if (keyed) {
      const SimulatedMeasurementKey& k = truth.noise_free_keys[i];
      out += "{\"campaign_id\": ";
      AppendString(&out, k.campaign_id);
      out +=
          ", \"stand\": \"F" + std::to_string(k.stand) + "\", \"position\": \"";
      out += PositionName(k.position);
      out += "\", \"noise_free_wear_um\": ";
      AppendNumber(&out, truth.noise_free_wear_um[i]);
      out += "}";
    } else {
      AppendNumber(&out, truth.noise_free_wear_um[i]);
    }
  }
  out += truth.noise_free_wear_um.empty() ? "]\n}\n" : "\n  ]\n}\n";

  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  if (!file) return Status::IoError("cannot open " + path + " for writing");
  file.write(out.data(), static_cast<std::streamsize>(out.size()));
  file.close();
  if (!file) return Status::IoError("cannot write " + path);
  return Status::Ok();
}

}  // namespace rollwear
