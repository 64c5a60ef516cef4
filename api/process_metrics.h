// Process figures of GET /metrics, read from /proc/self at scrape time
// with the names of the Prometheus client libraries' process collector:
//   process_cpu_seconds_total       counter  user + system CPU time
//   process_resident_memory_bytes   gauge    resident set size
//   process_virtual_memory_bytes    gauge    virtual memory size
//   process_open_fds                gauge    open file descriptors
//   process_max_fds                 gauge    RLIMIT_NOFILE (soft)
//   process_start_time_seconds      gauge    start, Unix seconds
// A figure that cannot be read (no /proc) is left out.
//
// Thread-safety: thread-safe (reads files, no state).
#ifndef ROLLWEAR_API_PROCESS_METRICS_H_
#define ROLLWEAR_API_PROCESS_METRICS_H_

#include <optional>
#include <string>

namespace rollwear::api {

struct ProcessFigures {
  std::optional<double> cpu_seconds;
  std::optional<double> resident_bytes;
  std::optional<double> virtual_bytes;
  std::optional<double> open_fds;
  std::optional<double> max_fds;
  std::optional<double> start_time_seconds;
};

// The figures of this process now.
ProcessFigures ReadProcessFigures();

// Appends their exposition (HELP, TYPE and sample of each figure read).
void AppendProcessMetrics(std::string* out);

}  // namespace rollwear::api

#endif  // ROLLWEAR_API_PROCESS_METRICS_H_
