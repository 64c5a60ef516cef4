#include "service/replay_requests.h"

#include <algorithm>
#include <cctype>
#include <cstdint>

#include "api/request_encode.h"

namespace rollwear::cli {
namespace {

std::string UrlEncode(const std::string& s) {
  static constexpr const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (unsigned char c : s) {
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 15];
    }
  }
  return out;
}

}  // namespace

Requests::Requests(const Dataset& d) : d_(d), profiles_(api::ProfileGroups(d)) {
  mounts_of_.resize(d.campaigns.size());
  for (size_t i = 0; i < d.mounts.size(); ++i) {
    mounts_of_[d.mounts[i].campaign].push_back(static_cast<int>(i));
  }
  passes_of_.resize(d.coil_ids.size());
  for (size_t i = 0; i < d.passes.size(); ++i) {
    passes_of_[d.passes[i].coil].push_back(static_cast<int>(i));
  }
}

std::vector<Event> Requests::Timeline(bool leave_last_open) const {
  std::vector<int> order(d_.campaigns.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return d_.campaigns[a].started_at < d_.campaigns[b].started_at;
  });
  std::vector<std::vector<int>> coils_of(d_.campaigns.size());
  for (size_t k = 0; k < passes_of_.size(); ++k) {
    if (passes_of_[k].empty()) continue;
    coils_of[d_.passes[passes_of_[k][0]].campaign].push_back(
        static_cast<int>(k));
  }
  // The grinder's events (measurements, then profiles) by measured_at.
  const std::vector<Event> measured = GrinderEvents();
  std::vector<char> ended(d_.campaigns.size(), 0);
  std::vector<Event> out;
  size_t next_m = 0;
  std::vector<Event> waiting;  // due before their campaign ended
  auto flush = [&](UnixSeconds until) {
    // Grinder events due by `until` whose campaign has ended.
    std::vector<Event> still;
    for (const Event& m : waiting) {
      (ended[CampaignOf(m)] ? out : still).push_back(m);
    }
    waiting.swap(still);
    while (next_m < measured.size() && measured[next_m].at <= until) {
      const Event& m = measured[next_m++];
      (ended[CampaignOf(m)] ? out : waiting).push_back(m);
    }
  };
  for (int c : order) {
    const Campaign& campaign = d_.campaigns[c];
    flush(campaign.started_at);
    out.push_back({Kind::kRollChange, campaign.started_at, c});
    std::vector<int>& coils = coils_of[c];
    std::stable_sort(coils.begin(), coils.end(), [&](int a, int b) {
      return d_.passes[passes_of_[a][0]].seq < d_.passes[passes_of_[b][0]].seq;
    });
    for (int k : coils) {
      const UnixSeconds at = d_.passes[passes_of_[k][0]].rolled_at;
      flush(at);
      out.push_back({Kind::kCoil, at, k});
    }
    if (leave_last_open && c == order.back()) break;
    flush(campaign.ended_at);
    out.push_back({Kind::kEnd, campaign.ended_at, c});
    ended[c] = 1;
  }
  flush(INT64_MAX);
  return out;
}

std::string Requests::Path(const Event& e) const {
  switch (e.kind) {
    case Kind::kRollChange:
      return "/v1/roll-changes";
    case Kind::kCoil:
      return "/v1/coils";
    case Kind::kEnd:
      return "/v1/campaigns/" + UrlEncode(d_.campaigns[e.index].id) + "/end";
    case Kind::kMeasurement:
      return "/v1/measurements";
    case Kind::kProfile:
      return "/v1/profiles";
  }
  return "/";
}

std::string Requests::Body(const Event& e) const {
  switch (e.kind) {
    case Kind::kRollChange:
      return api::RollChangeRequest(d_, e.index, mounts_of_[e.index]);
    case Kind::kCoil:
      return api::CoilRequest(d_, passes_of_[e.index]);
    case Kind::kEnd:
      return api::CampaignEndRequest(d_, e.index);
    case Kind::kMeasurement:
      return api::MeasurementRequest(d_, e.index);
    case Kind::kProfile:
      return api::ProfileRequest(d_, profiles_[e.index]);
  }
  return "{}";
}

std::vector<Event> Requests::GrinderEvents() const {
  std::vector<Event> out;
  for (size_t i = 0; i < d_.measurements.size(); ++i) {
    out.push_back({Kind::kMeasurement, d_.measurements[i].measured_at,
                   static_cast<int>(i)});
  }
  for (size_t i = 0; i < profiles_.size(); ++i) {
    out.push_back({Kind::kProfile,
                   d_.profile_points[profiles_[i].front()].measured_at,
                   static_cast<int>(i)});
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const Event& a, const Event& b) { return a.at < b.at; });
  return out;
}

int Requests::CampaignOf(const Event& e) const {
  return e.kind == Kind::kMeasurement
             ? d_.measurements[e.index].campaign
             : d_.profile_points[profiles_[e.index].front()].campaign;
}

}  // namespace rollwear::cli
