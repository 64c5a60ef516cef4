// The replay's view of a dataset (`rollwear replay`, service/cmd_replay.cc):
// its events in the order the mill and the roll shop would send them (for
// each campaign by start: the roll change, its coils by seq, the end; each
// measurement, then each grinder profile, once its campaign has ended and
// its measured_at has come) and each event's HTTP path and JSON body
// (api/request_encode.h).
//
// Thread-safety: const methods may be called from any thread; the dataset
// must outlive the object and not change.
#ifndef ROLLWEAR_SERVICE_REPLAY_REQUESTS_H_
#define ROLLWEAR_SERVICE_REPLAY_REQUESTS_H_

#include <string>
#include <vector>

#include "core/dataset/dataset.h"

namespace rollwear::cli {

enum class Kind { kRollChange, kCoil, kEnd, kMeasurement, kProfile };
constexpr int kKinds = 5;

struct Event {
  Kind kind;
  UnixSeconds at;
  // campaign (roll change, end), coil, measurement, or profile (index into
  // Requests' profile groups)
  int index;
};

class Requests {
 public:
  explicit Requests(const Dataset& d);

  int profiles() const { return static_cast<int>(profiles_.size()); }

  // Events in replay order (see the file comment). With `leave_last_open`
  // the last campaign gets no end and its measurements and profiles are
  // left out.
  std::vector<Event> Timeline(bool leave_last_open) const;
  std::string Path(const Event& e) const;
  std::string Body(const Event& e) const;

 private:
  // Measurements and profiles as events, stably sorted by measured_at:
  // measurements in file order, then profiles in the data's order.
  std::vector<Event> GrinderEvents() const;
  // The campaign of a measurement or profile event.
  int CampaignOf(const Event& e) const;

  const Dataset& d_;
  std::vector<std::vector<int>> mounts_of_;
  std::vector<std::vector<int>> passes_of_;
  std::vector<std::vector<int>> profiles_;  // api::ProfileGroups
};

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_REPLAY_REQUESTS_H_
