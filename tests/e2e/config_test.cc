// service/config: the config file format, environment overrides and the
// error messages that name file:line and key.
#include "service/config.h"

#include <map>
#include <string>

#include <gtest/gtest.h>

namespace rollwear::service {
namespace {

TEST(ConfigTest, DefaultsNeedOnlyADatabase) {
  ServeConfig c;
  std::string error;
  EXPECT_FALSE(c.IsValid(&error));
  EXPECT_NE(error.find("--db"), std::string::npos);
  c.db = "/var/lib/rollwear/rollwear.db";
  EXPECT_TRUE(c.IsValid(&error)) << error;
  EXPECT_EQ(c.port, 8080);
  EXPECT_EQ(c.bind, "127.0.0.1");
  EXPECT_EQ(c.recalibration_minute, 120);
}

TEST(ConfigTest, ParsesEveryKeyWithCommentsAndQuotes) {
  ServeConfig c;
  const Status s = ParseConfigText(
      "# rollwear daemon\n"
      "port = 9090\n"
      "  bind=0.0.0.0   # all interfaces\n"
      "db = \"/srv/roll wear/db.sqlite\"\n"
      "token = \"abc#def\"\n"
      "\n"
      "body_limit_bytes = 65536\n"
      "recalibration_time = 03:30\n"
      "model = nikitenko\n"
      "option = 2\n"
      "threads = 16\n"
      "keep_alive_max = 500\n"
      "keep_alive_timeout = 10\n"
      "log_level = debug\n"
      "cpu_wakeup_latency_us = 0\n",
      "rollwear.conf", &c);
  ASSERT_TRUE(s.ok()) << s.ToString();
  EXPECT_EQ(c.port, 9090);
  EXPECT_EQ(c.bind, "0.0.0.0");
  EXPECT_EQ(c.db, "/srv/roll wear/db.sqlite");
  EXPECT_EQ(c.token, "abc#def");
  EXPECT_EQ(c.body_limit_bytes, 65536u);
  EXPECT_EQ(c.recalibration_minute, 3 * 60 + 30);
  EXPECT_EQ(c.model, WearLaw::kNikitenko);
  EXPECT_EQ(c.option, 2);
  EXPECT_EQ(c.threads, 16);
  EXPECT_EQ(c.keep_alive_max, 500);
  EXPECT_EQ(c.keep_alive_timeout_s, 10);
  EXPECT_EQ(c.log_level, "debug");
  EXPECT_EQ(c.cpu_wakeup_latency_us, 0);
}

TEST(ConfigTest, CpuWakeupLatencyIsOffByDefaultAndRangeChecked) {
  ServeConfig c;
  EXPECT_EQ(c.cpu_wakeup_latency_us, -1);
  ASSERT_TRUE(
      ParseConfigText("cpu_wakeup_latency_us = 50\n", "a.conf", &c).ok());
  EXPECT_EQ(c.cpu_wakeup_latency_us, 50);
  ASSERT_TRUE(
      ParseConfigText("cpu_wakeup_latency_us = off\n", "a.conf", &c).ok());
  EXPECT_EQ(c.cpu_wakeup_latency_us, -1);
  for (const char* bad : {"-1", "1000001", "fast", "1.5"}) {
    const Status s = ParseConfigText(
        std::string("\ncpu_wakeup_latency_us = ") + bad + "\n", "a.conf", &c);
    ASSERT_FALSE(s.ok()) << bad;
    EXPECT_EQ(s.message(),
              std::string("a.conf:2: cpu_wakeup_latency_us: must be an integer "
                          "in [0, 1000000] or off, got '") +
                  bad + "'");
    EXPECT_EQ(c.cpu_wakeup_latency_us, -1);  // unchanged
  }
}

TEST(ConfigTest, WearLimitsDefaultAndPerPosition) {
  ServeConfig c;
  for (double l : c.WearLimits()) EXPECT_EQ(l, 0);  // none by default
  ASSERT_TRUE(ParseConfigText("wear_limit_um = 350\n"
                              "wear_limit_um_f7_bottom = 280.5\n",
                              "a.conf", &c)
                  .ok());
  const auto limits = c.WearLimits();
  EXPECT_EQ(limits[RollPositionSlot(7, Position::kBottom)], 280.5);
  EXPECT_EQ(limits[RollPositionSlot(7, Position::kTop)], 350);
  EXPECT_EQ(limits[RollPositionSlot(1, Position::kTop)], 350);
  for (const char* bad : {"0", "-3", "5000.5", "lots", "1e400"}) {
    const Status s = ParseConfigText(
        std::string("\nwear_limit_um_f6_top = ") + bad + "\n", "a.conf", &c);
    ASSERT_FALSE(s.ok()) << bad;
    EXPECT_EQ(s.message(),
              std::string("a.conf:2: wear_limit_um_f6_top: must be a number "
                          "in (0, 5000] µm or off, got '") +
                  bad + "'");
  }
  EXPECT_FALSE(ParseConfigText("wear_limit_um_f8_top = 100\n", "a.conf", &c)
                   .ok());
}

TEST(ConfigTest, ErrorsNameFileLineAndKey) {
  ServeConfig c;
  Status s = ParseConfigText("port = 1\n# ok\nport = http\n", "a.conf", &c);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(s.message().rfind("a.conf:3: port: must be an integer", 0), 0u)
      << s.message();
  s = ParseConfigText("colour = blue\n", "a.conf", &c);
  EXPECT_EQ(s.message().rfind("a.conf:1: unknown key 'colour'", 0), 0u)
      << s.message();
  s = ParseConfigText("\nport 8080\n", "a.conf", &c);
  EXPECT_EQ(s.message().rfind("a.conf:2: expected 'key = value'", 0), 0u)
      << s.message();
  s = ParseConfigText("recalibration_time = 24:00\n", "a.conf", &c);
  EXPECT_EQ(s.message().rfind("a.conf:1: recalibration_time:", 0), 0u)
      << s.message();
  s = ParseConfigText("model = archard\n", "a.conf", &c);
  EXPECT_EQ(s.message().rfind("a.conf:1: model:", 0), 0u) << s.message();
  s = ParseConfigText("option = 4\n", "a.conf", &c);
  EXPECT_EQ(s.message().rfind("a.conf:1: option:", 0), 0u) << s.message();
  s = LoadConfigFile("/nonexistent/rollwear.conf", &c);
  EXPECT_EQ(s.code(), StatusCode::kIoError);
}

TEST(ConfigTest, EnvironmentOverridesTheFileAndEmptyMeansUnset) {
  ServeConfig c;
  ASSERT_TRUE(ParseConfigText("token = file-token\nport = 9090\n"
                              "recalibration_time = 01:00\n",
                              "f", &c)
                  .ok());
  const std::map<std::string, std::string> env = {
      {"ROLLWEAR_TOKEN", "env-token"},
      {"ROLLWEAR_PORT", "7070"},
      {"ROLLWEAR_RECALIBRATION_TIME", "off"},
      {"ROLLWEAR_BIND", ""}};
  auto getenv_fn = [&env](const char* name) -> const char* {
    auto it = env.find(name);
    return it == env.end() ? nullptr : it->second.c_str();
  };
  ASSERT_TRUE(ApplyEnvironment(&c, getenv_fn).ok());
  EXPECT_EQ(c.token, "env-token");
  EXPECT_EQ(c.port, 7070);
  EXPECT_EQ(c.recalibration_minute, -1);
  EXPECT_EQ(c.bind, "127.0.0.1");  // empty variable = unset

  const std::map<std::string, std::string> bad = {{"ROLLWEAR_PORT", "-1"}};
  auto bad_fn = [&bad](const char* name) -> const char* {
    auto it = bad.find(name);
    return it == bad.end() ? nullptr : it->second.c_str();
  };
  const Status s = ApplyEnvironment(&c, bad_fn);
  EXPECT_EQ(s.message().rfind("ROLLWEAR_PORT: port:", 0), 0u) << s.message();
}

TEST(ConfigTest, TimeOfDay) {
  int m = 0;
  EXPECT_TRUE(ParseTimeOfDay("00:00", &m));
  EXPECT_EQ(m, 0);
  EXPECT_TRUE(ParseTimeOfDay("23:59", &m));
  EXPECT_EQ(m, 23 * 60 + 59);
  EXPECT_TRUE(ParseTimeOfDay("off", &m));
  EXPECT_EQ(m, -1);
  EXPECT_FALSE(ParseTimeOfDay("2:00", &m));
  EXPECT_FALSE(ParseTimeOfDay("12:60", &m));
  EXPECT_FALSE(ParseTimeOfDay("ab:cd", &m));
  EXPECT_EQ(FormatTimeOfDay(150), "02:30");
  EXPECT_EQ(FormatTimeOfDay(-1), "off");
}

}  // namespace
}  // namespace rollwear::service
