#include "service/predictions_csv.h"

#include <cmath>
#include <cstdio>
#include <fstream>

namespace rollwear::cli {

// 95 % two-sided normal quantile.
constexpr double kZ95 = 1.959964;

namespace {

// The row of measurement `me` of campaign `campaign` (index into data).
PredictionRow RowOf(const Dataset& data, int campaign, int me, bool train,
                    double measured_um, double predicted_um, double sd_um,
                    const std::vector<std::string>& original_id) {
  const Measurement& m = data.measurements[me];
  PredictionRow r;
  r.campaign_id = campaign < static_cast<int>(original_id.size())
                      ? original_id[campaign]
                      : data.campaigns[campaign].id;
  r.roll_id = m.roll_id;
  r.stand = m.stand;
  r.position = m.position;
  r.train = train;
  r.measured_um = measured_um;
  r.predicted_um = predicted_um;
  r.lo_um = predicted_um - kZ95 * sd_um;
  r.hi_um = predicted_um + kZ95 * sd_um;
  return r;
}

}  // namespace

std::vector<PredictionRow> PredictionRows(
    const Dataset& data, const WearStatistics& stats,
    const CampaignSplit& split, const std::vector<std::string>& original_id,
    const ObservationPredictor& predict) {
  std::vector<PredictionRow> rows;
  for (const bool train : {true, false}) {
    for (int o :
         stats.MeasuredObservations(train ? split.train : split.validation)) {
      const Observation& ob = stats.observations[o];
      double pred = 0, sd = NAN;
      predict(o, &pred, &sd);
      rows.push_back(RowOf(data, ob.campaign, ob.measurement, train,
                           ob.measured_um, pred, sd, original_id));
    }
  }
  return rows;
}

ObservationPredictor LawPredictor(const WearModel& model,
                                  const WearStatistics& stats) {
  return [&model, &stats](int o, double* pred, double* sd) {
    *pred = PredictObservation(model, stats, stats.observations[o]);
    *sd = std::hypot(model.noise_sd_um, model.noise_rel * *pred);
  };
}

std::vector<PredictionRow> MeasuredPredictionRows(
    const Dataset& data, const WearModel& model,
    const std::vector<MeasuredPrediction>& predictions, bool train,
    const std::vector<std::string>& original_id) {
  std::vector<PredictionRow> rows;
  for (const MeasuredPrediction& p : predictions) {
    // The roll's own factor's uncertainty too (model_terms.h).
    const double noise =
        std::hypot(model.noise_sd_um, model.noise_rel * p.wear_um);
    const double sd =
        WidenForRollFactor(model.terms,
                           data.measurements[p.measurement].roll_id,
                           p.wear_um, kZ95 * noise) /
        kZ95;
    rows.push_back(RowOf(data, p.campaign, p.measurement, train, p.measured_um,
                         p.expected_um, sd, original_id));
  }
  return rows;
}

Status WritePredictionsCsv(const std::string& file,
                           const std::vector<PredictionRow>& rows) {
  std::ofstream out(file);
  out << "campaign_id,stand,position,roll_id,set,measured_um,predicted_um,"
         "lo_um,hi_um\n";
  char buf[160];
  for (const PredictionRow& r : rows) {
    auto num = [](double v) {
      if (!std::isfinite(v)) return std::string();
      char b[32];
      std::snprintf(b, sizeof(b), "%.2f", v);
      return std::string(b);
    };
    std::snprintf(buf, sizeof(buf), "%s,%s,", StandName(r.stand).c_str(),
                  PositionName(r.position));
    // Ids are written as read: the format's ids carry no comma or quote
    // (dataset_io rejects neither, so quote when needed).
    auto field = [](const std::string& s) {
      if (s.find_first_of(",\"\n") == std::string::npos) return s;
      std::string q = "\"";
      for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
      return q + "\"";
    };
    out << field(r.campaign_id) << "," << buf << field(r.roll_id) << ","
        << (r.train ? "train" : "validation") << "," << num(r.measured_um)
        << "," << num(r.predicted_um) << "," << num(r.lo_um) << ","
        << num(r.hi_um) << "\n";
  }
  out.close();
  if (!out) return Status::InvalidArgument("cannot write " + file);
  return Status::Ok();
}

}  // namespace rollwear::cli
