// The offline path of adoption, through the binary: `rollwear diagnose
// --json` names the concealed effect, and `rollwear calibrate --terms` with
// that JSON refits the adopted term on the same split and shows the gain
// over plain option 1 on the validation campaigns. Bad term files are
// refused with the file and field named.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

TEST(CliTermsTest, CalibrateWithTheDiagnosisTermsImprovesValidation) {
  TempDir dir;
  std::string out;
  ASSERT_EQ(RunRollwear({"simulate", "--out", dir / "data", "--seed", "5",
                         "--campaigns", "240", "--effect", "lubrication"},
                        &out),
            0)
      << out;
  ASSERT_EQ(RunRollwear({"diagnose", "--data", dir / "data", "--json",
                         dir / "diag.json"},
                        &out),
            0)
      << out;
  ASSERT_EQ(RunRollwear({"calibrate", "--data", dir / "data", "--terms",
                         dir / "diag.json", "--json", dir / "cal.json"},
                        &out),
            0)
      << out;
  EXPECT_NE(out.find("with terms"), std::string::npos) << out;
  const nlohmann::json diag =
      nlohmann::json::parse(ReadFile(dir / "diag.json"));
  const nlohmann::json cal = nlohmann::json::parse(ReadFile(dir / "cal.json"));
  ASSERT_FALSE(diag["adopted_model"]["terms"].empty()) << diag.dump();
  ASSERT_EQ(cal["terms"].size(), diag["adopted_model"]["terms"].size());
  EXPECT_EQ(cal["terms"][0]["covariate"], "lubrication");
  // Same split as the diagnosis: the refit lands on its validation gap and
  // beats option 1 alone.
  EXPECT_NEAR(cal["gap_val_um"].get<double>(),
              diag["final"]["gap_val_um"].get<double>(),
              0.02 * diag["final"]["gap_val_um"].get<double>())
      << cal.dump();
  EXPECT_LT(cal["gap_val_um"].get<double>(),
            0.97 * cal["baseline"]["gap_val_um"].get<double>());

  // A term file without terms, and one with a bad form: exit 1, named.
  {
    std::ofstream(dir / "bad.json")
        << R"({"terms":[{"covariate":"force_kn","form":"cubic"}]})";
  }
  EXPECT_EQ(RunRollwear({"calibrate", "--data", dir / "data", "--terms",
                         dir / "bad.json"},
                        &out),
            1);
  EXPECT_NE(out.find("bad.json"), std::string::npos) << out;
  EXPECT_NE(out.find("terms[0].form"), std::string::npos) << out;
  { std::ofstream(dir / "none.json") << R"({"model":"wang"})"; }
  EXPECT_EQ(RunRollwear({"calibrate", "--data", dir / "data", "--terms",
                         dir / "none.json"},
                        &out),
            1);
  EXPECT_NE(out.find("no \"terms\""), std::string::npos) << out;
}

}  // namespace
}  // namespace rollwear::e2e
