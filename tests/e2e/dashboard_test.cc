// The dashboard (GET /) end to end: the real daemon with a simulated mill
// replayed through the API, a calibration and a diagnosis run over HTTP,
// then headless Chromium loads the page. The DOM it renders must show every
// mounted roll position with the numbers of GET /v1/wear (at the page's
// printed precision), the calibration with the gaps of
// GET /v1/calibrations/{id} and the diagnosis's strongest finding, each
// mounted roll's predicted profile across the barrel with the numbers of
// GET /v1/wear/{stand}/{position}/profile, and the last ended campaigns'
// grinder profiles with the offline prediction at their points
// (core/fit/profile_fit.h ProfileResiduals, same model and shape); a
// screenshot at 1366x768 goes to <build>/tests/artifacts/dashboard.png, and
// at that size Chromium's own layout (over the DevTools pipe,
// chromium_pipe.h) puts every column of the mounted-rolls table inside its
// panel and the viewport, none clipped.
// Chromium (/usr/bin/chromium, or $ROLLWEAR_CHROMIUM) is required: the test
// fails when it is missing (deploy/install.sh installs it).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "api/dashboard_page.h"
#include "api/http_client.h"
#include "core/dataset/dataset_io.h"
#include "core/fit/profile_fit.h"
#include "tests/e2e/chromium_pipe.h"
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

std::string Fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

std::string ChromiumPath() {
  const char* env = std::getenv("ROLLWEAR_CHROMIUM");
  return env != nullptr && *env != '\0' ? env : "/usr/bin/chromium";
}

// <build>/tests/artifacts (the binary is <build>/service/rollwear).
std::filesystem::path ArtifactsDir() {
  const std::filesystem::path build =
      std::filesystem::path(ROLLWEAR_BINARY).parent_path().parent_path();
  return build / "tests" / "artifacts";
}

// Runs headless Chromium with `args` after the common flags; returns its
// exit code, stdout in *out (stderr, which Chromium fills with noise, goes
// to `log`).
int RunChromium(const std::string& profile,
                const std::vector<std::string>& args, const std::string& log,
                std::string* out) {
  std::string cmd =
      "'" + ChromiumPath() +
      "' --headless --no-sandbox --disable-gpu --no-first-run "
      "--disable-background-networking --disable-component-update "
      "--disable-sync --hide-scrollbars --user-data-dir='" +
      profile + "'";
  for (const std::string& a : args) cmd += " '" + a + "'";
  cmd += " 2>>'" + log + "'";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return -1;
  char buf[4096];
  size_t n;
  out->clear();
  while ((n = fread(buf, 1, sizeof(buf), pipe)) > 0) out->append(buf, n);
  const int status = pclose(pipe);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct PageRoll {
  std::map<std::string, std::string> attrs;
  std::string wear_text;
  std::string coils_text;
};

// The page is read by plain string search, not std::regex: libstdc++'s
// matcher recurses once per character, and on the page with its profile
// panels (long data-* lists) it overflows the stack under ASan.

// The attribute text and the body of each element of `dom` that opens with
// `open` (e.g. `<tr class="roll"`), the body up to the next `close` (no
// body when `close` is empty).
struct Element {
  std::string attrs, body;
};
std::vector<Element> ElementsOf(const std::string& dom, const std::string& open,
                                const std::string& close) {
  std::vector<Element> out;
  size_t pos = 0;
  while ((pos = dom.find(open, pos)) != std::string::npos) {
    const size_t gt = dom.find('>', pos + open.size());
    if (gt == std::string::npos) break;
    Element e;
    e.attrs = dom.substr(pos + open.size(), gt - pos - open.size());
    pos = gt + 1;
    if (!close.empty()) {
      const size_t end = dom.find(close, pos);
      if (end == std::string::npos) break;
      e.body = dom.substr(pos, end - pos);
      pos = end + close.size();
    }
    out.push_back(std::move(e));
  }
  return out;
}

// The data-NAME="VALUE" attributes of an element's attribute text.
std::map<std::string, std::string> DataAttributes(const std::string& attrs) {
  std::map<std::string, std::string> out;
  size_t pos = 0;
  while ((pos = attrs.find(" data-", pos)) != std::string::npos) {
    const size_t eq = attrs.find("=\"", pos);
    if (eq == std::string::npos) break;
    const size_t end = attrs.find('"', eq + 2);
    if (end == std::string::npos) break;
    out[attrs.substr(pos + 6, eq - pos - 6)] =
        attrs.substr(eq + 2, end - eq - 2);
    pos = end + 1;
  }
  return out;
}

// The text of the first `<td class="CLS">TEXT</td>` in `cells`.
std::string CellText(const std::string& cells, const std::string& cls) {
  const std::string open = "<td class=\"" + cls + "\">";
  const size_t b = cells.find(open);
  if (b == std::string::npos) return "";
  const size_t e = cells.find("</td>", b + open.size());
  return e == std::string::npos
             ? ""
             : cells.substr(b + open.size(), e - b - open.size());
}

// The roll rows of a rendered page, keyed "F6/top".
std::map<std::string, PageRoll> RollsOf(const std::string& dom) {
  std::map<std::string, PageRoll> rolls;
  for (const Element& row : ElementsOf(dom, "<tr class=\"roll\"", "</tr>")) {
    PageRoll r;
    r.attrs = DataAttributes(row.attrs);
    r.wear_text = CellText(row.body, "wear");
    r.coils_text = CellText(row.body, "coils");
    rolls["F" + r.attrs["stand"] + "/" + r.attrs["position"]] = r;
  }
  return rolls;
}

// The data-* attributes of every `<div class="CLASS" ...>` of a page.
std::vector<std::map<std::string, std::string>> DivsOf(const std::string& dom,
                                                       const std::string& cls) {
  std::vector<std::map<std::string, std::string>> out;
  for (const Element& div : ElementsOf(dom, "<div class=\"" + cls + "\"", "")) {
    out.push_back(DataAttributes(div.attrs));
  }
  return out;
}

// A data-* list of numbers ("1.5 2 3").
std::vector<double> NumbersOf(const std::string& text) {
  std::vector<double> out;
  std::istringstream in(text);
  double v;
  while (in >> v) out.push_back(v);
  return out;
}

// The page prints 9 significant digits: equal to that.
void ExpectNumbersNear(const std::string& page_text, const json& api,
                       const std::string& what) {
  const std::vector<double> page = NumbersOf(page_text);
  ASSERT_EQ(page.size(), api.size()) << what;
  for (size_t j = 0; j < page.size(); ++j) {
    const double v = api[j].get<double>();
    EXPECT_NEAR(page[j], v, 1e-8 * std::max(1.0, std::abs(v)))
        << what << " [" << j << "]";
  }
}

// Each mounted roll's profile panel against GET .../profile: the same
// shape state and, calibrated, the same numbers at every slice.
void ExpectMountedProfilesAsTheApi(const std::string& url,
                                   const std::string& dom, const json& wear) {
  const auto panels = DivsOf(dom, "roll-profile");
  ASSERT_EQ(panels.size(), wear["positions"].size());
  for (const json& p : wear["positions"]) {
    const std::string stand = p["stand"], position = p["position"];
    const std::string key = stand + "/" + position;
    json profile;
    ASSERT_EQ(HttpGet(url, "/v1/wear/" + key + "/profile", &profile), 200);
    ASSERT_EQ(profile["shape"], "calibrated") << key;
    const auto it = std::find_if(panels.begin(), panels.end(), [&](auto& a) {
      return "F" + a.at("stand") == stand && a.at("position") == position;
    });
    ASSERT_NE(it, panels.end()) << key;
    EXPECT_EQ(it->at("shape"), "calibrated") << key;
    ExpectNumbersNear(it->at("x-mm"), profile["x_mm"], key + " x_mm");
    ExpectNumbersNear(it->at("wear-um"), profile["predicted_wear_um"],
                      key + " predicted_wear_um");
    json lo = json::array(), hi = json::array();
    for (const json& iv : profile["interval_um"]) {
      lo.push_back(iv[0]);
      hi.push_back(iv[1]);
    }
    ExpectNumbersNear(it->at("lo-um"), lo, key + " interval lo");
    ExpectNumbersNear(it->at("hi-um"), hi, key + " interval hi");
  }
  EXPECT_EQ(dom.find("No profile model yet"), std::string::npos);
}

// The measured profiles' panels: the last two ended campaigns with grinder
// profiles, the points of profiles.csv, and the prediction of the active
// model with the served shape at each (ProfileResiduals offline).
void ExpectMeasuredProfilesAsOffline(const std::string& url,
                                     const std::string& dom,
                                     const Dataset& data) {
  json model, profile;
  ASSERT_EQ(HttpGet(url, "/v1/models/active", &model), 200);
  ASSERT_EQ(HttpGet(url, "/v1/wear/F6/top/profile", &profile), 200);
  StatusOr<WearModel> m = ModelOfAnswer(data, model);
  ASSERT_TRUE(m.ok()) << m.status().message();
  const json& c = profile["coefficients"];
  ProfileShape shape;
  shape.beta2 = c["beta2"].get<double>();
  shape.beta4 = c["beta4"].get<double>();
  shape.alpha = {c["alpha1"].get<double>(), c["alpha2"].get<double>(),
                 c["alpha3"].get<double>()};
  // The ended campaigns (all but the open last one) with profiles, newest
  // two.
  std::vector<int> with_profiles;
  for (const ProfilePoint& p : data.profile_points) {
    if (p.campaign + 1 < static_cast<int>(data.campaigns.size())) {
      with_profiles.push_back(p.campaign);
    }
  }
  std::sort(with_profiles.begin(), with_profiles.end(), [&](int a, int b) {
    return data.campaigns[a].started_at > data.campaigns[b].started_at;
  });
  with_profiles.erase(std::unique(with_profiles.begin(), with_profiles.end()),
                      with_profiles.end());
  ASSERT_GE(with_profiles.size(), 2u);
  std::vector<int> recent = {with_profiles[1], with_profiles[0]};
  std::sort(recent.begin(), recent.end());
  const DatasetIndex index(data);
  const std::vector<ProfileResidual> offline =
      ProfileResiduals(*m, shape, data, index, recent);
  // Offline points by panel ("C|F6/top").
  std::map<std::string, std::pair<json, json>> expected;  // measured, predicted
  for (const ProfileResidual& r : offline) {
    auto& [measured, predicted] =
        expected[data.campaigns[r.campaign].id + "|" +
                 RollPositionName(SlotStand(r.slot), SlotPosition(r.slot))];
    measured.push_back(r.measured_um);
    predicted.push_back(r.predicted_um);
  }
  ASSERT_GE(expected.size(), 2u);
  const auto panels = DivsOf(dom, "measured-profile");
  ASSERT_EQ(panels.size(), expected.size()) << dom.substr(0, 4000);
  for (const auto& a : panels) {
    const std::string key =
        a.at("campaign-id") + "|F" + a.at("stand") + "/" + a.at("position");
    auto it = expected.find(key);
    ASSERT_NE(it, expected.end()) << key;
    ExpectNumbersNear(a.at("measured-um"), it->second.first, key + " measured");
    ExpectNumbersNear(a.at("predicted-um"), it->second.second,
                      key + " predicted");
  }
}

// Every cell of the mounted-rolls table inside its panel and the viewport of
// a width x height window, none with clipped text (scrollWidth beyond its
// box), measured by Chromium's layout (chromium_pipe.h).
void ExpectRollsTableFits(const std::filesystem::path& profile,
                          const std::string& url, int width, int height) {
  PageMeasure m;
  m.chromium = ChromiumPath();
  m.profile = profile.string();
  m.url = url;
  m.width = width;
  m.height = height;
  m.expression = R"js((() => {
    const vw = document.documentElement.clientWidth;
    const section = document.getElementById('rolls');
    const table = section && section.querySelector('table');
    if (!table) return {error: 'no mounted-rolls table'};
    const s = section.getBoundingClientRect();
    const cut = [];
    for (const cell of table.querySelectorAll('th, td')) {
      const b = cell.getBoundingClientRect();
      if (b.right > Math.min(s.right, vw) + 0.5 || b.left < s.left - 0.5 ||
          cell.scrollWidth > cell.clientWidth + 1) {
        cut.push(cell.textContent.trim().slice(0, 24) + ' [' +
                 b.left.toFixed(0) + ', ' + b.right.toFixed(0) + ']');
      }
    }
    return {viewport: vw, panel_right: s.right, rows: table.rows.length,
            columns: table.rows[0].cells.length, cut: cut};
  })())js";
  const json got = MeasureInChromium(m);
  ASSERT_TRUE(got.is_object() && !got.contains("error")) << got.dump();
  EXPECT_EQ(got["viewport"], width) << got.dump();
  EXPECT_EQ(got["rows"], 5) << got.dump();  // the header and four rolls
  EXPECT_GE(got["columns"].get<int>(), 6) << got.dump();
  EXPECT_LE(got["panel_right"].get<double>(), width + 0.5) << got.dump();
  EXPECT_TRUE(got["cut"].empty())
      << "cells outside the panel or clipped at " << width << "x" << height
      << ": " << got["cut"].dump();
}

TEST(DashboardTest, ChromiumShowsTheMountedRollsWithTheApisNumbers) {
  const std::string chromium = ChromiumPath();
  ASSERT_EQ(access(chromium.c_str(), X_OK), 0)
      << chromium << " is missing: install the Debian package 'chromium' "
      << "(deploy/install.sh does) or set ROLLWEAR_CHROMIUM";

  TempDir dir;
  std::string output;
  ASSERT_EQ(
      RunRollwear({"simulate", "--out", dir / "data", "--campaigns", "30",
                   "--seed", "11", "--effect", "campaign_growth", "--profiles"},
                  &output),
      0)
      << output;
  Daemon daemon(dir / "rollwear.db", dir / "serve.log");
  std::string error;
  ASSERT_TRUE(daemon.Start(&error)) << error;
  ASSERT_EQ(
      RunRollwear({"replay", "--data", dir / "data", "--url", daemon.url(),
                   "--clients", "4", "--leave-last-open", "--quiet"},
                  &output),
      0)
      << output;

  json answer;
  ASSERT_EQ(HttpPost(daemon.url(), "/v1/calibrations", "{}", &answer), 202);
  const int64_t calibration_id = answer["id"].get<int64_t>();
  const json calibration = WaitForJob(
      daemon.url(), "/v1/calibrations/" + std::to_string(calibration_id));
  ASSERT_EQ(calibration["status"], "done") << calibration.dump();
  // Promoted with a profile shape fitted on the replayed grinder profiles.
  ASSERT_TRUE(calibration["promoted"].get<bool>()) << calibration.dump();
  ASSERT_EQ(HttpPost(daemon.url(), "/v1/diagnoses", "{}", &answer), 202);
  const int64_t diagnosis_id = answer["id"].get<int64_t>();
  const json diagnosis =
      WaitForJob(daemon.url(), "/v1/diagnoses/" + std::to_string(diagnosis_id));
  ASSERT_EQ(diagnosis["status"], "done") << diagnosis.dump().substr(0, 2000);

  json wear;
  ASSERT_EQ(HttpGet(daemon.url(), "/v1/wear", &wear), 200);
  ASSERT_EQ(wear["positions"].size(), 4u) << wear.dump();
  // A wear limit at every position but F7/bottom, twice its wear so far:
  // the page shows it, the remaining life and a forecast line to it.
  for (const json& p : wear["positions"]) {
    if (p["stand"] == "F7" && p["position"] == "bottom") continue;
    const json limit = {{"limit_um", 2 * p["predicted_wear_um"].get<double>()}};
    ASSERT_EQ(HttpPost(daemon.url(),
                       "/v1/limits/" + p["stand"].get<std::string>() + "/" +
                           p["position"].get<std::string>(),
                       limit.dump(), &answer),
              200)
        << answer.dump();
  }
  ASSERT_EQ(HttpGet(daemon.url(), "/v1/wear", &wear), 200);

  // The page as served: HTML, self-contained (nothing fetched from outside).
  api::HttpClient client(daemon.url());
  const api::HttpResult page = client.Get("/");
  ASSERT_EQ(page.status, 200) << page.body;
  EXPECT_NE(page.body.find("<svg"), std::string::npos);
  std::string stripped = page.body;
  const std::string svg_ns = "http://www.w3.org/2000/svg";
  for (size_t at = stripped.find(svg_ns); at != std::string::npos;
       at = stripped.find(svg_ns, at)) {
    stripped.erase(at, svg_ns.size());
  }
  for (const char* outside :
       {"http:", "https:", "<link", "src=", "url(", "@import"}) {
    EXPECT_EQ(stripped.find(outside), std::string::npos)
        << "the page must not load anything from elsewhere: " << outside;
  }

  // The DOM as Chromium renders it.
  const std::string log = dir / "chromium.log";
  std::string dom;
  ASSERT_EQ(RunChromium(dir / "profile1", {"--dump-dom", daemon.url() + "/"},
                        log, &dom),
            0)
      << ReadFile(log);
  const std::map<std::string, PageRoll> rolls = RollsOf(dom);
  ASSERT_EQ(rolls.size(), wear["positions"].size()) << dom.substr(0, 4000);
  for (const json& p : wear["positions"]) {
    // The API names stands "F6"; the page's data-stand is the number.
    const std::string key =
        p["stand"].get<std::string>() + "/" + p["position"].get<std::string>();
    auto it = rolls.find(key);
    ASSERT_NE(it, rolls.end()) << key;
    const PageRoll& r = it->second;
    const double w = p["predicted_wear_um"].get<double>();
    EXPECT_EQ(r.attrs.at("wear-um"), Fixed(w, 3)) << key;
    EXPECT_EQ(r.wear_text, Fixed(w, 1)) << key;
    EXPECT_EQ(r.attrs.at("roll-id"), p["roll_id"].get<std::string>()) << key;
    EXPECT_EQ(r.attrs.at("coils"), std::to_string(p["coils"].get<int>()))
        << key;
    EXPECT_EQ(r.coils_text, std::to_string(p["coils"].get<int>())) << key;
    EXPECT_EQ(r.attrs.at("length-m"),
              Fixed(p["rolled_length_m"].get<double>(), 3))
        << key;
    EXPECT_EQ(r.attrs.at("lo-um"), Fixed(p["interval_um"][0].get<double>(), 3))
        << key;
    EXPECT_EQ(r.attrs.at("hi-um"), Fixed(p["interval_um"][1].get<double>(), 3))
        << key;
    // The limit and the remaining life, as GET /v1/wear has them ("" for
    // null).
    auto fixed_or_empty = [](const json& v) {
      return v.is_null() ? std::string() : Fixed(v.get<double>(), 3);
    };
    EXPECT_EQ(r.attrs.at("limit-um"), fixed_or_empty(p["wear_limit_um"]))
        << key;
    EXPECT_EQ(r.attrs.at("remaining-m"),
              fixed_or_empty(p["remaining_length_m"]))
        << key;
    EXPECT_EQ(r.attrs.at("remaining-coils"),
              fixed_or_empty(p["remaining_coils"]))
        << key;
    const bool limited = key != "F7/bottom";
    const std::string legend =  // the chart's legend names "F6 top"
        p["stand"].get<std::string>() + " " + p["position"].get<std::string>();
    EXPECT_EQ(p["remaining_length_m"].is_null(), !limited) << key;
    if (limited) {
      // Twice the wear so far at the same mix: as much again.
      EXPECT_NEAR(p["remaining_length_m"].get<double>(),
                  p["rolled_length_m"].get<double>(),
                  1e-6 * p["rolled_length_m"].get<double>())
          << key;
      EXPECT_EQ(r.attrs.at("remaining-lo-m"),
                Fixed(p["remaining_length_interval_m"][0].get<double>(), 3))
          << key;
      EXPECT_NE(dom.find(legend + " to limit"), std::string::npos)
          << "no forecast line for " << key;
    } else {
      EXPECT_EQ(dom.find(legend + " to limit"), std::string::npos) << key;
    }
  }
  // The calibration row carries the API's gaps; the plots are drawn.
  const std::string cal_row =
      "<tr class=\"calibration\" data-id=\"" + std::to_string(calibration_id) +
      "\" data-gap-train-um=\"" +
      Fixed(calibration["gap_train_um"].get<double>(), 3) +
      "\" data-gap-val-um=\"" +
      Fixed(calibration["gap_val_um"].get<double>(), 3) + "\"";
  EXPECT_NE(dom.find(cal_row), std::string::npos) << cal_row;
  EXPECT_NE(dom.find("<polyline"), std::string::npos) << "no wear growth curve";
  EXPECT_NE(dom.find("class=\"identity\""), std::string::npos)
      << "no parity plot";
  EXPECT_NE(dom.find("diagnosis #" + std::to_string(diagnosis_id)),
            std::string::npos);
  ExpectMountedProfilesAsTheApi(daemon.url(), dom, wear);
  StatusOr<Dataset> data = ReadDataset(dir / "data");
  ASSERT_TRUE(data.ok()) << data.status().message();
  ExpectMeasuredProfilesAsOffline(daemon.url(), dom, *data);
  if (!diagnosis["findings"].empty()) {
    EXPECT_NE(
        dom.find("data-covariate=\"" +
                 diagnosis["findings"][0]["covariate"].get<std::string>() +
                 "\""),
        std::string::npos);
  }

  // The screenshot at the pulpit's screen size, kept in the build tree.
  std::error_code ec;
  std::filesystem::create_directories(ArtifactsDir(), ec);
  const std::string png = (ArtifactsDir() / "dashboard.png").string();
  std::filesystem::remove(png, ec);
  std::string ignored;
  ASSERT_EQ(RunChromium(dir / "profile2",
                        {"--screenshot=" + png, "--window-size=1366,768",
                         daemon.url() + "/"},
                        log, &ignored),
            0)
      << ReadFile(log);
  ASSERT_TRUE(std::filesystem::exists(png)) << ReadFile(log);
  const std::string bytes = ReadFile(png);
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");

  // At the pulpit's 1366x768 every column of the mounted-rolls table lies
  // inside its panel and the viewport, and no cell's text is clipped, as the
  // browser's layout computes it.
  ExpectRollsTableFits(dir / "profile3", daemon.url() + "/", 1366, 768);
  EXPECT_EQ(daemon.Terminate(), 0);
}

// A browser that exits at once (here /bin/false): the measurement says so
// instead of hanging or dying of SIGPIPE on the closed pipe.
TEST(DashboardTest, BrowserThatDiesIsReportedNotFatal) {
  TempDir dir;
  PageMeasure m;
  m.chromium = "/bin/false";
  m.profile = dir / "profile";
  m.url = "http://127.0.0.1:9/";
  m.expression = "1";
  m.timeout_ms = 10'000;
  const auto start = std::chrono::steady_clock::now();
  const json got = MeasureInChromium(m);
  EXPECT_TRUE(got.is_object() && got.contains("error")) << got.dump();
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(9));
}

// The page builder alone: empty states and escaping.
TEST(DashboardTest, PageWithoutRollsSaysSoAndEscapesLabels) {
  DashboardData d;
  d.title = "mill <2>";
  d.generated_at = "2024-01-01 00:00:00 UTC";
  const std::string html = DashboardHtml(d);
  EXPECT_NE(html.find("mill &lt;2&gt;"), std::string::npos);
  EXPECT_NE(html.find("no rolls are mounted"), std::string::npos);
  EXPECT_NE(html.find("No calibration yet"), std::string::npos);
  EXPECT_NE(html.find("No diagnosis has run"), std::string::npos);
  EXPECT_EQ(html.find("<tr class=\"roll\""), std::string::npos);
  EXPECT_NE(html.find("No grinder profile of an ended campaign yet"),
            std::string::npos);
}

// A roll without a calibrated profile shape: the page says so and draws no
// predicted profile (no numbers, no curve); a measured profile under such a
// model is drawn without its prediction.
TEST(DashboardTest, UncalibratedProfileIsNotDrawn) {
  DashboardData d;
  DashboardRoll r;
  r.stand = 6;
  r.position = "top";
  r.roll_id = "R1";
  r.profile_shape = "uncalibrated";
  r.profile_x_mm = {-10, 0, 10};
  r.profile_wear_um = {1, 2, 1};
  r.profile_lo_um = {0.5, 1, 0.5};
  r.profile_hi_um = {1.5, 3, 1.5};
  d.rolls.push_back(r);
  d.measured_profiles.push_back(DashboardMeasuredProfile{
      6, "top", "C1", "R0", false, {-10, 0, 10}, {3, 4, 3}, {2, 2, 2}});
  const std::string html = DashboardHtml(d);
  EXPECT_NE(html.find("No profile model yet for F6 top"), std::string::npos);
  const auto panels = DivsOf(html, "roll-profile");
  ASSERT_EQ(panels.size(), 1u);
  EXPECT_EQ(panels[0].at("shape"), "uncalibrated");
  EXPECT_EQ(panels[0].count("wear-um"), 0u);
  const size_t section = html.find("<section id=\"profiles\"");
  ASSERT_NE(section, std::string::npos);
  // Only the measured points' panel has an SVG; it has no line.
  const std::string profiles = html.substr(section);
  EXPECT_EQ(profiles.find("<polyline"), std::string::npos);
  const auto measured = DivsOf(html, "measured-profile");
  ASSERT_EQ(measured.size(), 1u);
  EXPECT_EQ(measured[0].at("predicted-um"), "");
  EXPECT_EQ(measured[0].at("measured-um"), "3 4 3");
  EXPECT_NE(html.find("drawn without a prediction"), std::string::npos);

  // Calibrated: the numbers and the three lines (profile, interval).
  d.rolls[0].profile_shape = "calibrated";
  d.measured_profiles.clear();
  const std::string drawn = DashboardHtml(d);
  const auto drawn_panels = DivsOf(drawn, "roll-profile");
  ASSERT_EQ(drawn_panels.size(), 1u);
  EXPECT_EQ(drawn_panels[0].at("wear-um"), "1 2 1");
  EXPECT_EQ(drawn_panels[0].at("hi-um"), "1.5 3 1.5");
  EXPECT_EQ(drawn.find("No profile model yet"), std::string::npos);
}

}  // namespace
}  // namespace rollwear::e2e
