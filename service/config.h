// ServeConfig: the settings of `rollwear serve` and where they come from.
//
// Precedence, lowest first: built-in defaults, the config file (--config),
// environment variables ROLLWEAR_<KEY> (ROLLWEAR_TOKEN wins over the file,
// so the secret can stay out of it), then explicit command-line flags.
//
// File format: one `key = value` per line; `#` starts a comment (whole line
// or after the value); blank lines are ignored; values may be wrapped in
// double quotes. Keys:
//   port                 TCP port (0 = ephemeral)                   8080
//   bind                 listen address                              127.0.0.1
//   db                   SQLite database file                        (required)
//   token                bearer token for POSTs (empty = no auth)    ""
//   body_limit_bytes     largest request body                        1048576
//   recalibration_time   nightly run, HH:MM local time, or "off"     02:00
//   model                wang | nikitenko | cao                      wang
//   option               K structure 1 | 2 | 3                       1
//   threads              HTTP worker threads                         32
//   keep_alive_max       requests per kept-alive connection          10000
//   keep_alive_timeout   idle seconds before a connection closes     5
//   max_connections      open connections (then accepting pauses)    1000
//   max_connections_per_client  from one address (then 503)          64
//   head_timeout         seconds for a request's head, from its      10
//                        first byte (total)
//   body_timeout         seconds for a body, from the head's end     60
//   read_timeout         longest pause within a head or body (s)     5
//   max_buffered_input_bytes  request bytes buffered in all;         67108864
//                        over it, big partial requests wait
//   log_level            trace|debug|info|warn|error|off             info
//   cpu_wakeup_latency_us  CPU wake-up limit held while traffic        off
//                        arrives (0..1000000 us, or off); needs write
//                        access to /dev/cpu_dma_latency (cpu_latency.h)
//   wear_limit_um        wear limit of every roll position, µm        off
//                        (0 < x <= 5000, or off); GET /v1/wear's
//                        remaining life counts to it
//   wear_limit_um_f6_top  the limit of one position (f1..f7, top or
//                        bottom), wins over wear_limit_um; a limit set
//                        with POST /v1/limits/... wins over both
// Errors name the place: "rollwear.conf:7: port: must be an integer in
// [0, 65535], got 'http'" or "ROLLWEAR_PORT: ...".
//
// Thread-safety: plain value and stateless functions.
#ifndef ROLLWEAR_SERVICE_CONFIG_H_
#define ROLLWEAR_SERVICE_CONFIG_H_

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/dataset/dataset.h"
#include "core/model/wear_law.h"

namespace rollwear::service {

struct ServeConfig {
  int port = 8080;
  std::string bind = "127.0.0.1";
  std::string db;
  std::string token;
  size_t body_limit_bytes = 1 << 20;
  // Minutes after local midnight of the nightly recalibration; -1 = off.
  int recalibration_minute = 2 * 60;
  WearLaw model = WearLaw::kWang;
  int option = 1;
  int threads = 32;
  int keep_alive_max = 10000;
  int keep_alive_timeout_s = 5;
  int max_connections = 1000;
  int max_connections_per_client = 64;
  int head_timeout_s = 10;
  int body_timeout_s = 60;
  int read_timeout_s = 5;
  size_t max_buffered_input_bytes = size_t{64} << 20;
  std::string log_level = "info";
  // Microseconds; -1 = off (no CPU latency QoS request).
  int cpu_wakeup_latency_us = -1;
  // Wear limits, µm (0 = none): every position's, and per roll position
  // slot (core/dataset/dataset.h RollPositionSlot) overrides.
  double wear_limit_um = 0;
  std::array<double, kNumRollPositionSlots> wear_limit_um_at{};
  // The limit in force at each slot from the configuration (0 = none).
  std::array<double, kNumRollPositionSlots> WearLimits() const;

  // Checks the whole configuration (db set, ranges).
  bool IsValid(std::string* error) const;
};

// Every key the file and the environment accept.
const std::vector<std::string>& ConfigKeys();

// Sets one key from its text value; `where` prefixes the error message
// ("rollwear.conf:7" or "ROLLWEAR_PORT").
Status SetConfigValue(const std::string& key, const std::string& value,
                      const std::string& where, ServeConfig* config);

// Applies the lines of a config file's text; `name` labels errors.
Status ParseConfigText(const std::string& text, const std::string& name,
                       ServeConfig* config);
// Reads and applies a config file.
Status LoadConfigFile(const std::string& path, ServeConfig* config);

// Applies ROLLWEAR_<KEY> variables found by `getenv` (default ::getenv);
// empty variables count as unset.
Status ApplyEnvironment(
    ServeConfig* config,
    const std::function<const char*(const char*)>& getenv_fn = nullptr);

// "HH:MM" (00:00..23:59) -> minutes after midnight; "off" -> -1.
bool ParseTimeOfDay(const std::string& text, int* minutes);
std::string FormatTimeOfDay(int minutes);  // "02:00" or "off"

}  // namespace rollwear::service

#endif  // ROLLWEAR_SERVICE_CONFIG_H_
