#include "api/http_server_options.h"

namespace rollwear::api {

bool HttpServerOptions::IsValid(std::string* error) const {
  if (port < 0 || port > 65535) {
    *error = "port must be in [0, 65535]";
    return false;
  }
  if (threads < 1 || threads > 4096) {
    *error = "threads must be in [1, 4096]";
    return false;
  }
  if (max_connections < 1) {
    *error = "max_connections must be >= 1";
    return false;
  }
  if (max_connections_per_client < 1) {
    *error = "max_connections_per_client must be >= 1";
    return false;
  }
  if (max_buffered_input_bytes < (size_t{1} << 20)) {
    *error = "max_buffered_input_bytes must be >= 1 MiB";
    return false;
  }
  if (keep_alive_max_count < 1) {
    *error = "keep_alive_max must be >= 1";
    return false;
  }
  if (keep_alive_timeout_s < 1 || read_timeout_s < 1 || write_timeout_s < 1 ||
      head_timeout_s < 1 || body_timeout_s < 1) {
    *error = "timeouts must be >= 1 s";
    return false;
  }
  if (max_header_count < 8 || max_header_bytes < 1024) {
    *error = "header limits must be >= 8 fields and >= 1024 bytes";
    return false;
  }
  if (payload_max_bytes < 256 || payload_max_bytes > (size_t{1} << 30)) {
    *error = "payload limit must be in [256 B, 1 GiB]";
    return false;
  }
  if (max_header_bytes > (size_t{1} << 20) || max_header_count > 10000) {
    *error = "header limits must be <= 1 MiB and <= 10000 fields";
    return false;
  }
  if (bind_address.empty()) {
    *error = "bind address must not be empty";
    return false;
  }
  return true;
}

}  // namespace rollwear::api
