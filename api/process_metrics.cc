#include "api/process_metrics.h"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace rollwear::api {
namespace {

// The fields of /proc/self/stat after "(comm)", which may hold spaces:
// index 0 is field 3 (state) of proc(5).
std::vector<std::string> StatFields() {
  std::ifstream in("/proc/self/stat");
  std::string stat((std::istreambuf_iterator<char>(in)),
                   std::istreambuf_iterator<char>());
  const size_t paren = stat.rfind(')');
  std::vector<std::string> fields;
  if (paren == std::string::npos) return fields;
  std::istringstream rest(stat.substr(paren + 1));
  for (std::string f; rest >> f;) fields.push_back(f);
  return fields;
}

// The boot time of /proc/stat ("btime"), Unix seconds.
std::optional<double> BootTime() {
  std::ifstream in("/proc/stat");
  for (std::string key; in >> key;) {
    if (key == "btime") {
      double t = 0;
      if (in >> t) return t;
      return std::nullopt;
    }
    in.ignore(1 << 20, '\n');
  }
  return std::nullopt;
}

void Append(std::string* out, const char* name, const char* type,
            const char* help, const std::optional<double>& value) {
  if (!value) return;
  char number[64];
  std::snprintf(number, sizeof(number), "%.15g", *value);
  *out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name +
          " " + type + "\n" + name + " " + number + "\n";
}

}  // namespace

ProcessFigures ReadProcessFigures() {
  ProcessFigures f;
  const double ticks = static_cast<double>(sysconf(_SC_CLK_TCK));
  const double page = static_cast<double>(sysconf(_SC_PAGESIZE));
  // proc(5): utime 14, stime 15, starttime 22, vsize 23, rss 24 (pages).
  const std::vector<std::string> s = StatFields();
  if (s.size() > 21 && ticks > 0) {
    f.cpu_seconds = (std::stod(s[11]) + std::stod(s[12])) / ticks;
    f.virtual_bytes = std::stod(s[20]);
    f.resident_bytes = std::stod(s[21]) * page;
    if (std::optional<double> boot = BootTime()) {
      f.start_time_seconds = *boot + std::stod(s[19]) / ticks;
    }
  }
  std::error_code ec;
  double fds = 0;
  for (std::filesystem::directory_iterator it("/proc/self/fd", ec), end;
       !ec && it != end; it.increment(ec)) {
    ++fds;
  }
  // The iterator's own descriptor is counted; the figure is "open now".
  if (!ec && fds > 0) f.open_fds = fds;
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    f.max_fds = static_cast<double>(limit.rlim_cur);
  return f;
}

void AppendProcessMetrics(std::string* out) {
  const ProcessFigures f = ReadProcessFigures();
  Append(out, "process_cpu_seconds_total", "counter",
         "Total user and system CPU time spent in seconds.", f.cpu_seconds);
  Append(out, "process_resident_memory_bytes", "gauge",
         "Resident memory size in bytes.", f.resident_bytes);
  Append(out, "process_virtual_memory_bytes", "gauge",
         "Virtual memory size in bytes.", f.virtual_bytes);
  Append(out, "process_open_fds", "gauge", "Number of open file descriptors.",
         f.open_fds);
  Append(out, "process_max_fds", "gauge",
         "Maximum number of open file descriptors.", f.max_fds);
  Append(out, "process_start_time_seconds", "gauge",
         "Start time of the process since unix epoch in seconds.",
         f.start_time_seconds);
}

}  // namespace rollwear::api
