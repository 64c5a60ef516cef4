// libFuzzer target: the `rollwear serve` config file parser
// (service/config.h, ParseConfigText) followed by the whole-config check.
// The parser must return a Status for any text; a crash, a leak or a
// sanitizer report is a bug, and so is an accepted config that later
// formats a time of day it cannot parse back.
//
// Thread-safety: libFuzzer calls the entry point from one thread.
#include <cstddef>
#include <cstdint>
#include <string>

#include "service/config.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using rollwear::service::ServeConfig;
  const std::string text(reinterpret_cast<const char*>(data), size);
  ServeConfig config;
  const rollwear::Status status =
      rollwear::service::ParseConfigText(text, "fuzz.conf", &config);
  if (!status.ok()) {
    if (status.message().empty()) __builtin_trap();
    return 0;
  }
  std::string error;
  (void)config.IsValid(&error);
  int minutes = 0;
  if (!rollwear::service::ParseTimeOfDay(
          rollwear::service::FormatTimeOfDay(config.recalibration_minute),
          &minutes) ||
      minutes != config.recalibration_minute) {
    __builtin_trap();
  }
  return 0;
}
