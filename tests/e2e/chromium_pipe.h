// A real browser's measurement of a page: headless Chromium driven over the
// DevTools protocol on its --remote-debugging-pipe (fd 3 in, fd 4 out,
// NUL-terminated JSON messages; https://chromedevtools.github.io/devtools-
// protocol/), so a test can read what the layout engine computed (element
// boxes, overflow), which --dump-dom cannot give. No WebSocket, no driver
// package: the same /usr/bin/chromium the other dashboard tests run.
//
// Thread-safety: one call at a time per profile directory.
#ifndef ROLLWEAR_TESTS_E2E_CHROMIUM_PIPE_H_
#define ROLLWEAR_TESTS_E2E_CHROMIUM_PIPE_H_

#include <string>

#include <nlohmann/json.hpp>

namespace rollwear::e2e {

struct PageMeasure {
  std::string chromium;  // the browser binary
  std::string profile;   // a fresh --user-data-dir
  std::string url;
  int width = 1366;  // the viewport, CSS pixels (Emulation override)
  int height = 768;
  // A JavaScript expression evaluated once the page's load event has fired;
  // its value comes back as JSON (returnByValue).
  std::string expression;
  int timeout_ms = 60'000;
};

// The expression's value, or a JSON object {"error": "..."} saying which
// step failed (launch, a protocol error, the timeout, an exception thrown
// by the expression).
nlohmann::json MeasureInChromium(const PageMeasure& m);

}  // namespace rollwear::e2e

#endif  // ROLLWEAR_TESTS_E2E_CHROMIUM_PIPE_H_
