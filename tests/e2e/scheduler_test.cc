// service/jobs/scheduler: the local-time due computation, the nightly trigger
// (only when measurements arrived since the last run) with an injected
// clock, the job worker running queued calibrations on the real store, and
// the event= log lines of a nightly run and its promotion.
#include "service/jobs/scheduler.h"

#include <stdlib.h>
#include <time.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "core/dataset/dataset_io.h"
#include "core/sim/simulator.h"
#include "engine/wear_prediction.h"
#include "service/jobs/job_log.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::service {
namespace {

UnixSeconds At(const char* iso) {
  UnixSeconds t = 0;
  EXPECT_TRUE(ParseTimestamp(iso, &t)) << iso;
  return t;
}

void SetTimeZone(const char* tz) {
  setenv("TZ", tz, 1);
  tzset();
}

TEST(NextLocalTimeTest, Utc) {
  SetTimeZone("UTC");
  EXPECT_EQ(NextLocalTime(At("2026-03-01T01:00:00Z"), 120),
            At("2026-03-01T02:00:00Z"));
  EXPECT_EQ(NextLocalTime(At("2026-03-01T02:00:00Z"), 120),
            At("2026-03-02T02:00:00Z"));
  EXPECT_EQ(NextLocalTime(At("2026-03-01T23:59:59Z"), 0),
            At("2026-03-02T00:00:00Z"));
  EXPECT_EQ(NextLocalTime(At("2026-12-31T03:00:00Z"), 120),
            At("2027-01-01T02:00:00Z"));
}

TEST(NextLocalTimeTest, LocalTimeZoneAndDaylightSaving) {
  if (!std::filesystem::exists("/usr/share/zoneinfo/Europe/Berlin")) {
    GTEST_SKIP() << "no tzdata";
  }
  SetTimeZone("Europe/Berlin");
  // Winter: 02:00 CET is 01:00Z; summer: 03:00 CEST is 01:00Z.
  EXPECT_EQ(NextLocalTime(At("2026-01-10T12:00:00Z"), 120),
            At("2026-01-11T01:00:00Z"));
  EXPECT_EQ(NextLocalTime(At("2026-07-10T12:00:00Z"), 180),
            At("2026-07-11T01:00:00Z"));
  SetTimeZone("UTC");
}

class SchedulerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    SetTimeZone("UTC");
    StatusOr<std::unique_ptr<storage::MillStore>> store =
        engine::OpenStore(dir_ / "scheduler.db");
    ASSERT_TRUE(store.ok()) << store.status().ToString();
    store_ = std::move(store).value();
  }

  void ImportSimulated(int campaigns) {
    SimulatorOptions options;
    options.seed = 9;
    options.num_campaigns = campaigns;
    StatusOr<Simulation> sim = Simulate(options);
    ASSERT_TRUE(sim.ok()) << sim.status().ToString();
    const Status s = store_->ImportDataset(sim->data);
    ASSERT_TRUE(s.ok()) << s.ToString();
  }

  e2e::TempDir dir_;
  std::unique_ptr<storage::MillStore> store_;
};

TEST_F(SchedulerTest, NightlyTriggerQueuesOnlyWhenMeasurementsArrived) {
  SchedulerOptions options;
  options.recalibration_minute = 120;
  engine::CalibrationRuns runs(store_.get());
  Scheduler scheduler(store_.get(), &runs, options);
  EXPECT_EQ(scheduler.Tick(At("2026-03-01T00:00:00Z")), 0);  // sets due
  EXPECT_EQ(scheduler.next_due(), At("2026-03-01T02:00:00Z"));
  EXPECT_EQ(scheduler.Tick(At("2026-03-01T01:59:59Z")), 0);
  // Due, but nothing was measured: no run, due moves to the next night.
  EXPECT_EQ(scheduler.Tick(At("2026-03-01T02:00:00Z")), 0);
  EXPECT_EQ(scheduler.next_due(), At("2026-03-02T02:00:00Z"));
  EXPECT_TRUE(store_->ListCalibrations(10).empty());

  ImportSimulated(12);
  ASSERT_GT(store_->Counters().measurements_since_last_calibration, 0);
  EXPECT_EQ(scheduler.Tick(At("2026-03-01T12:00:00Z")), 0);  // not due yet
  const int64_t id = scheduler.Tick(At("2026-03-02T02:00:30Z"));
  EXPECT_GT(id, 0);
  EXPECT_EQ(scheduler.next_due(), At("2026-03-03T02:00:00Z"));
  StatusOr<storage::CalibrationRecord> record = store_->GetCalibration(id);
  ASSERT_TRUE(record.ok());
  EXPECT_EQ(record->trigger, "nightly");
  EXPECT_EQ(record->status, storage::CalibrationStatus::kQueued);
}

TEST_F(SchedulerTest, WorkerRunsQueuedCalibrationsAndReportsThem) {
  ImportSimulated(12);
  std::atomic<int> finished{0};
  storage::CalibrationRecord last;
  SchedulerOptions options;
  options.recalibration_minute = -1;
  engine::CalibrationRuns runs(store_.get());
  Scheduler scheduler(store_.get(), &runs, options,
                      [&](const storage::CalibrationRecord& r, double) {
                        last = r;
                        ++finished;
                      });
  // Queued before Start (as by a previous process): picked up by Start.
  StatusOr<int64_t> id = store_->EnqueueCalibration("api", WearLaw::kWang, 1);
  ASSERT_TRUE(id.ok()) << id.status().ToString();
  scheduler.Start();
  ASSERT_TRUE(scheduler.WaitIdle(std::chrono::seconds(300)));
  EXPECT_EQ(finished.load(), 1);
  EXPECT_EQ(last.id, *id);
  EXPECT_EQ(last.status, storage::CalibrationStatus::kDone) << last.message;
  EXPECT_EQ(store_->Counters().measurements_since_last_calibration, 0);
  scheduler.Stop();
}

// The daemon's spdlog default logger replaced by one writing into a
// string, for the lifetime of this object.
class CapturedLog {
 public:
  CapturedLog() : previous_(spdlog::default_logger()) {
    auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(out_);
    sink->set_pattern("%l %v");
    spdlog::set_default_logger(
        std::make_shared<spdlog::logger>("captured", sink));
  }
  ~CapturedLog() { spdlog::set_default_logger(previous_); }
  std::string text() const { return out_.str(); }

 private:
  std::ostringstream out_;
  std::shared_ptr<spdlog::logger> previous_;
};

TEST_F(SchedulerTest, NightlyRunAndItsPromotionAreLogged) {
  ImportSimulated(12);
  CapturedLog log;
  SchedulerOptions options;
  options.recalibration_minute = 120;
  // The daemon's hook (service/cmd_serve.cc) logs every finished run.
  engine::CalibrationRuns runs(store_.get());
  Scheduler scheduler(store_.get(), &runs, options, &LogCalibrationFinished);
  EXPECT_EQ(scheduler.Tick(At("2026-03-01T00:00:00Z")), 0);  // sets due
  const int64_t id = scheduler.Tick(At("2026-03-01T02:00:30Z"));
  ASSERT_GT(id, 0);
  scheduler.Start();
  ASSERT_TRUE(scheduler.WaitIdle(std::chrono::seconds(300)));
  scheduler.Stop();
  StatusOr<storage::CalibrationRecord> record = store_->GetCalibration(id);
  ASSERT_TRUE(record.ok());
  // The prior model is active: the first calibration replaces it.
  ASSERT_TRUE(record->promoted) << record->message;
  const std::string n = std::to_string(id);
  const std::string text = log.text();
  for (const std::string& line :
       {"info event=calibration_queued id=" + n + " trigger=nightly\n",
        "info event=calibration_finished id=" + n +
            " trigger=nightly model=wang option=1 status=done ",
        "info event=model_promoted version=" +
            std::to_string(record->model_version) +
            " source=nightly trigger=nightly calibration_id=" + n +
            " model=wang option=1 gap_val_um="}) {
    EXPECT_NE(text.find(line), std::string::npos) << line << "\n" << text;
  }
}

}  // namespace
}  // namespace rollwear::service
