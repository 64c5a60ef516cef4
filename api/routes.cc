#include "api/routes.h"

#include <cstddef>
#include <string>

namespace rollwear::api {
namespace {

// A path parameter, decoded (a malformed escape is kept as sent).
std::string Decoded(std::string_view raw) {
  std::string out;
  if (!PercentDecode(raw, false, &out)) return std::string(raw);
  return out;
}

}  // namespace

bool MatchPattern(std::string_view pattern, std::string_view path,
                  PathArgs* args) {
  size_t arg = 0;
  while (!pattern.empty()) {
    const size_t open = pattern.find('{');
    if (open == std::string_view::npos) return pattern == path;
    // The literal text before the parameter.
    if (path.substr(0, open) != pattern.substr(0, open)) return false;
    path.remove_prefix(open);
    const size_t close = pattern.find('}', open);
    if (close == std::string_view::npos || arg >= args->size()) return false;
    const bool rest = pattern[close - 1] == '*';
    pattern.remove_prefix(close + 1);
    size_t len = 0;
    if (rest) {
      // Everything up to the literal tail, which must end the path.
      if (pattern.find('{') != std::string_view::npos ||
          path.size() <= pattern.size() ||
          path.substr(path.size() - pattern.size()) != pattern) {
        return false;
      }
      len = path.size() - pattern.size();
    } else {
      len = path.find('/');
      if (len == std::string_view::npos) len = path.size();
      if (len == 0) return false;
    }
    (*args)[arg++] = Decoded(path.substr(0, len));
    path.remove_prefix(len);
  }
  return path.empty();
}

}  // namespace rollwear::api
