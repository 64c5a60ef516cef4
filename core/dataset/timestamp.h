// The timestamps of the data format and the API: ISO 8601 with a UTC
// offset or Z on input, always UTC Z on output, held as seconds since
// 1970-01-01T00:00:00Z (UnixSeconds). Date arithmetic after H. Hinnant,
// "chrono-Compatible Low-Level Date Algorithms" (2013,
// http://howardhinnant.github.io/date_algorithms.html).
//
// Thread-safety: pure functions (NowSeconds reads the system clock).
#ifndef ROLLWEAR_CORE_DATASET_TIMESTAMP_H_
#define ROLLWEAR_CORE_DATASET_TIMESTAMP_H_

#include <string>
#include <string_view>

#include "core/dataset/dataset.h"

namespace rollwear {

// ISO 8601 with offset or Z ("2026-03-01T06:12:00Z",
// "2026-03-01T07:12:00+01:00", fractional seconds accepted and truncated).
bool ParseTimestamp(const std::string& text, UnixSeconds* out);
// The same without the std::string. With `local_offset_s` non-null, a
// timestamp without offset ("2026-03-01T07:12:00") is a local time at that
// fixed offset from UTC (seconds east); one with an offset keeps its own.
bool ParseTimestampView(std::string_view text, UnixSeconds* out,
                        const int* local_offset_s = nullptr);
// A UTC offset setting: "Z", "+HH:MM", "-HH:MM", "+HHMM" or "-HHMM" (hours
// up to 23) as seconds east of UTC; false when it is none of these.
bool ParseUtcOffset(std::string_view text, int* offset_s);
// Always "YYYY-MM-DDTHH:MM:SSZ".
std::string FormatTimestamp(UnixSeconds t);
// The system clock now, whole seconds (the time records are stamped with).
UnixSeconds NowSeconds();

}  // namespace rollwear

#endif  // ROLLWEAR_CORE_DATASET_TIMESTAMP_H_
