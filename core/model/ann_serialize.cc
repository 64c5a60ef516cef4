// Text serialisation of AnnModel (declared in ann_model.h).
//
// Format, version 1: whitespace-separated tokens (line breaks are only for
// the reader):
//   rollwear-ann-model 1
//   hidden H1 H2
//   positions P label...      roll_types R label...      grades S label...
//   inputs D name...          (layout check: must equal InputNames())
//   input_mean D x...         input_sd D x...
//   members M
//   member a H1 D x... b1 H1 x... b H2 H1 x... b2 H2 x... v H2 x... q D x...
//          c x
//   ... (M times)
//   end
// Matrices are column-major. Doubles are written with %.17g, which strtod
// reads back to the identical double (IEEE 754 binary64 needs at most 17
// significant digits). Labels are percent-encoded (bytes <= 0x20, 0x7f and
// '%' as %XX) so a label is always one non-empty token.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/model/ann_model.h"

namespace rollwear {
namespace {

constexpr char kMagic[] = "rollwear-ann-model";

std::string EncodeLabel(const std::string& s) {
  std::string out;
  for (unsigned char ch : s) {
    if (ch <= 0x20 || ch == 0x7f || ch == '%') {
      char buf[4];
      std::snprintf(buf, sizeof(buf), "%%%02X", ch);
      out += buf;
    } else {
      out += static_cast<char>(ch);
    }
  }
  return out;
}

bool DecodeLabel(const std::string& s, std::string* out) {
  out->clear();
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '%') {
      *out += s[i];
      continue;
    }
    if (i + 2 >= s.size()) return false;
    const std::string hex = s.substr(i + 1, 2);
    char* end = nullptr;
    const long v = std::strtol(hex.c_str(), &end, 16);
    if (end != hex.c_str() + 2) return false;
    *out += static_cast<char>(v);
    i += 2;
  }
  return true;
}

void PutDouble(std::string* out, double x) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), " %.17g", x);
  *out += buf;
}

void PutMatrix(std::string* out, const char* name, const Eigen::MatrixXd& m) {
  *out += std::string(" ") + name + " " + std::to_string(m.rows()) + " " +
          std::to_string(m.cols());
  for (Eigen::Index i = 0; i < m.size(); ++i) PutDouble(out, m.data()[i]);
  *out += "\n";
}

void PutVector(std::string* out, const char* name, const Eigen::VectorXd& v) {
  *out += std::string(" ") + name + " " + std::to_string(v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) PutDouble(out, v[i]);
  *out += "\n";
}

void PutLabels(std::string* out, const char* name,
               const std::vector<std::string>& labels) {
  *out += std::string(name) + " " + std::to_string(labels.size());
  for (const std::string& l : labels) *out += " " + EncodeLabel(l);
  *out += "\n";
}

// Token reader with error context.
class Reader {
 public:
  explicit Reader(const std::string& text) : in_(text) {}

  bool Token(std::string* t) {
    if (!(in_ >> *t)) return Fail("unexpected end of input");
    ++count_;
    return true;
  }
  bool Expect(const std::string& want) {
    std::string t;
    if (!Token(&t)) return false;
    if (t != want) return Fail("expected '" + want + "', found '" + t + "'");
    return true;
  }
  bool Int(int* v, int lo, int hi) {
    std::string t;
    if (!Token(&t)) return false;
    char* end = nullptr;
    errno = 0;
    const long x = std::strtol(t.c_str(), &end, 10);
    if (errno != 0 || end != t.c_str() + t.size() || x < lo || x > hi) {
      return Fail("expected an integer in [" + std::to_string(lo) + ", " +
                  std::to_string(hi) + "], found '" + t + "'");
    }
    *v = static_cast<int>(x);
    return true;
  }
  bool Double(double* v) {
    std::string t;
    if (!Token(&t)) return false;
    char* end = nullptr;
    const double x = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size() || !std::isfinite(x)) {
      return Fail("expected a finite number, found '" + t + "'");
    }
    *v = x;
    return true;
  }
  bool Labels(const char* name, std::vector<std::string>* out) {
    int n = 0;
    if (!Expect(name) || !Int(&n, 0, 1 << 20)) return false;
    out->resize(n);
    for (int i = 0; i < n; ++i) {
      std::string t;
      if (!Token(&t)) return false;
      if (!DecodeLabel(t, &(*out)[i])) return Fail("bad label '" + t + "'");
    }
    return true;
  }
  bool Vector(const char* name, Eigen::Index size, Eigen::VectorXd* v) {
    int n = 0;
    if (!Expect(name) || !Int(&n, 0, 1 << 24)) return false;
    if (n != size) {
      return Fail(std::string(name) + " has size " + std::to_string(n) +
                  ", expected " + std::to_string(size));
    }
    v->resize(n);
    for (int i = 0; i < n; ++i) {
      if (!Double(&(*v)[i])) return false;
    }
    return true;
  }
  bool Matrix(const char* name, Eigen::Index rows, Eigen::Index cols,
              Eigen::MatrixXd* m) {
    int r = 0, c = 0;
    if (!Expect(name) || !Int(&r, 0, 1 << 20) || !Int(&c, 0, 1 << 20)) {
      return false;
    }
    if (r != rows || c != cols) {
      return Fail(std::string(name) + " is " + std::to_string(r) + "x" +
                  std::to_string(c) + ", expected " + std::to_string(rows) +
                  "x" + std::to_string(cols));
    }
    m->resize(r, c);
    for (Eigen::Index i = 0; i < m->size(); ++i) {
      if (!Double(&m->data()[i])) return false;
    }
    return true;
  }
  bool AtEnd() {
    std::string t;
    if (in_ >> t) return Fail("trailing data '" + t + "' after 'end'");
    return true;
  }
  bool Fail(const std::string& message) {
    if (error_.empty()) {
      error_ =
          "ann model text, token " + std::to_string(count_) + ": " + message;
    }
    return false;
  }
  const std::string& error() const { return error_; }

 private:
  std::istringstream in_;
  int count_ = 0;
  std::string error_;
};

}  // namespace

std::string SerializeAnnModel(const AnnModel& m) {
  std::string out = std::string(kMagic) + " " +
                    std::to_string(AnnModel::kFormatVersion) + "\n";
  out += "hidden " + std::to_string(m.hidden1) + " " +
         std::to_string(m.hidden2) + "\n";
  PutLabels(&out, "positions", m.positions);
  PutLabels(&out, "roll_types", m.roll_types);
  PutLabels(&out, "grades", m.grades);
  PutLabels(&out, "inputs", m.InputNames());
  PutVector(&out, "input_mean", m.input_mean);
  PutVector(&out, "input_sd", m.input_sd);
  out += "members " + std::to_string(m.members.size()) + "\n";
  for (const AnnNetwork& n : m.members) {
    out += "member\n";
    PutMatrix(&out, "a", n.a);
    PutVector(&out, "b1", n.b1);
    PutMatrix(&out, "b", n.b);
    PutVector(&out, "b2", n.b2);
    PutVector(&out, "v", n.v);
    PutVector(&out, "q", n.q);
    out += " c";
    PutDouble(&out, n.c);
    out += "\n";
  }
  out += "end\n";
  return out;
}

StatusOr<AnnModel> ParseAnnModel(const std::string& text) {
  Reader r(text);
  AnnModel m;
  int version = 0;
  if (!r.Expect(kMagic) || !r.Int(&version, 0, 1 << 20)) {
    return Status::InvalidArgument(r.error());
  }
  if (version != AnnModel::kFormatVersion) {
    return Status::InvalidArgument(
        "ann model text: format version " + std::to_string(version) +
        " is not supported (this build reads version " +
        std::to_string(AnnModel::kFormatVersion) + ")");
  }
  std::vector<std::string> inputs;
  int num_members = 0;
  bool ok = r.Expect("hidden") && r.Int(&m.hidden1, 1, 1 << 16) &&
            r.Int(&m.hidden2, 1, 1 << 16) &&
            r.Labels("positions", &m.positions) &&
            r.Labels("roll_types", &m.roll_types) &&
            r.Labels("grades", &m.grades) && r.Labels("inputs", &inputs);
  if (ok && inputs != m.InputNames()) {
    ok = r.Fail("input layout differs from this build's");
  }
  const int d = m.num_inputs();
  ok = ok && r.Vector("input_mean", d, &m.input_mean) &&
       r.Vector("input_sd", d, &m.input_sd) && r.Expect("members") &&
       r.Int(&num_members, 1, 1 << 16);
  for (int k = 0; ok && k < num_members; ++k) {
    AnnNetwork n;
    ok = r.Expect("member") && r.Matrix("a", m.hidden1, d, &n.a) &&
         r.Vector("b1", m.hidden1, &n.b1) &&
         r.Matrix("b", m.hidden2, m.hidden1, &n.b) &&
         r.Vector("b2", m.hidden2, &n.b2) && r.Vector("v", m.hidden2, &n.v) &&
         r.Vector("q", d, &n.q) && r.Expect("c") && r.Double(&n.c);
    m.members.push_back(std::move(n));
  }
  ok = ok && r.Expect("end") && r.AtEnd();
  if (!ok) return Status::InvalidArgument(r.error());
  ROLLWEAR_RETURN_IF_ERROR(m.Validate());
  return m;
}

}  // namespace rollwear
