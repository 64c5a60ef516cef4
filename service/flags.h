// A small command-line flag parser shared by the CLI sub-commands:
// "--name value" pairs, repeatable flags, and positional arguments.
//
// Thread-safety: plain value; not shared.
#ifndef ROLLWEAR_SERVICE_FLAGS_H_
#define ROLLWEAR_SERVICE_FLAGS_H_

#include <map>
#include <set>
#include <string>
#include <vector>

namespace rollwear::cli {

class Flags {
 public:
  // `known` lists accepted flag names without dashes; `switches` are flags
  // that take no value. Returns false and sets `error` on an unknown flag or
  // a flag missing its value.
  bool Parse(const std::vector<std::string>& args,
             const std::set<std::string>& known,
             const std::set<std::string>& switches, std::string* error);

  bool Has(const std::string& name) const { return values_.count(name) > 0; }
  // Last value of a flag, or `fallback`.
  std::string Get(const std::string& name, const std::string& fallback = "") const;
  // All values of a repeatable flag.
  std::vector<std::string> GetAll(const std::string& name) const;
  // Parses an integer/double flag; false with `error` when malformed.
  bool GetInt(const std::string& name, long long fallback, long long* out,
              std::string* error) const;
  bool GetDouble(const std::string& name, double fallback, double* out,
                 std::string* error) const;
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positional_;
};

}  // namespace rollwear::cli

#endif  // ROLLWEAR_SERVICE_FLAGS_H_
