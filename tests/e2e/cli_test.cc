// The `rollwear` command line (service/cli.cc), run as a subprocess: help of
// every command on stdout with exit 0 and exactly the options of the table
// below (a new option missing from the table, or a table entry missing from
// the help, fails), --version, unknown options and commands, missing
// required options and malformed values (exit 2, stderr names the option),
// repeatable --effect; README.md's CLI table lists every option.
#include <algorithm>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "rollwear_build_commit.h"  // generated at every build
#include "tests/e2e/e2e_util.h"

namespace rollwear::e2e {
namespace {

struct CommandSpec {
  std::string name;
  std::set<std::string> options;      // every option but --help
  std::vector<std::string> required;  // options (or the positional) needed
};

// Every command and every option; README.md's CLI table lists the same.
const std::vector<CommandSpec>& Commands() {
  static const std::vector<CommandSpec> kCommands = {
      {"simulate",
       {"--out", "--seed", "--effect", "--campaigns", "--coils-per-campaign",
        "--missing", "--gross-errors", "--roll-wear-factor", "--truth",
        "--profiles", "--no-shift",
        "--list-effects"},
       {"--out"}},
      {"calibrate",
       {"--data", "--model", "--option", "--start", "--protocol",
        "--split-seed", "--split", "--per-roll", "--free-grades", "--predictions",
        "--seed",
        "--json", "--figures", "--terms", "--strict"},
       {"--data"}},
      {"study",
       {"--data", "--out", "--figures", "--split-seed", "--split", "--seed",
        "--strict"},
       {"--data"}},
      {"ann",
       {"--data", "--json", "--seeds", "--split-seed", "--split",
        "--predictions", "--seed", "--select",
        "--max-epochs", "--threads", "--weight-decay", "--no-early-stopping",
        "--linear-skip", "--model-out", "--with-diagnosis", "--figures",
        "--strict"},
       {"--data"}},
      {"serve",
       {"--db", "--port", "--bind", "--log-level", "--threads", "--config"},
       {}},  // --db may come from the config file or ROLLWEAR_DB
      {"import", {"--db", "--strict"}, {"--db", "DIR"}},
      {"export", {"--db", "--out"}, {"--db", "--out"}},
      {"replay",
       {"--data", "--url", "--token", "--clients", "--speed", "--retry-for",
        "--show-wear", "--json", "--leave-last-open", "--quiet"},
       {"--data", "--url"}},
      {"diagnose",
       {"--data", "--json", "--html", "--split-seed", "--split", "--model",
        "--threads", "--strict"},
       {"--data"}},
      {"scorecard",
       {"--seeds", "--first-seed", "--effects", "--campaigns", "--threads",
        "--json"},
       {}},
  };
  return kCommands;
}

// Lines of `text` after the line `heading` up to the next blank line.
std::vector<std::string> Section(const std::string& text,
                                 const std::string& heading) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (inside && line.empty()) break;
    if (inside) lines.push_back(line);
    if (line == heading) inside = true;
  }
  return lines;
}

// The long option names a help text lists ("  -h,--help  ...",
// "  --out DIR  ..."); continuation lines of descriptions are skipped.
std::set<std::string> HelpOptions(const std::string& help) {
  std::set<std::string> names;
  const std::regex option_line(R"(^  (-[a-z],)?(--[a-z][a-z0-9-]*)\b.*)");
  for (const std::string& line : Section(help, "Options:")) {
    std::smatch m;
    if (std::regex_match(line, m, option_line)) names.insert(m[2]);
  }
  return names;
}

class CliCommandTest : public ::testing::TestWithParam<CommandSpec> {};

TEST_P(CliCommandTest, HelpOnStdoutListsExactlyTheCommandsOptions) {
  const CommandSpec& spec = GetParam();
  std::string out, err;
  ASSERT_EQ(RunRollwear({spec.name, "--help"}, &out, &err), 0) << err;
  EXPECT_EQ(err, "");
  EXPECT_NE(out.find("Usage: rollwear " + spec.name + " [OPTIONS]"),
            std::string::npos)
      << out;
  std::set<std::string> expected = spec.options;
  expected.insert("--help");
  EXPECT_EQ(HelpOptions(out), expected) << out;
  for (const std::string& option : spec.options) {
    EXPECT_NE(out.find(option), std::string::npos) << option << "\n" << out;
  }
  // -h is the same help.
  std::string short_out;
  EXPECT_EQ(RunRollwear({spec.name, "-h"}, &short_out, &err), 0);
  EXPECT_EQ(short_out, out);
}

TEST_P(CliCommandTest, UnknownOptionIsAUsageErrorNamingIt) {
  const CommandSpec& spec = GetParam();
  std::string out, err;
  EXPECT_EQ(RunRollwear({spec.name, "--no-such-option", "1"}, &out, &err), 2);
  EXPECT_EQ(out, "");
  EXPECT_EQ(
      err.rfind("rollwear " + spec.name + ": unknown option --no-such-option\n",
                0),
      0u)
      << err;
  EXPECT_NE(err.find("rollwear " + spec.name + " --help"), std::string::npos)
      << err;
  // Also with =value, and when required options are missing too.
  EXPECT_EQ(RunRollwear({spec.name, "--no-such-option=1"}, &out, &err), 2);
  EXPECT_NE(err.find("unknown option --no-such-option\n"), std::string::npos)
      << err;
}

TEST_P(CliCommandTest, EachMissingRequiredOptionIsNamed) {
  const CommandSpec& spec = GetParam();
  for (const std::string& missing : spec.required) {
    std::vector<std::string> args = {spec.name};
    std::string positional;
    for (const std::string& r : spec.required) {
      if (r == missing) continue;
      if (r.rfind("--", 0) == 0) {
        args.insert(args.end(), {r, "/nonexistent/x"});
      } else {
        positional = "/nonexistent/dir";
      }
    }
    if (!positional.empty()) args.push_back(positional);
    std::string out, err;
    EXPECT_EQ(RunRollwear(args, &out, &err), 2) << missing;
    EXPECT_EQ(out, "");
    EXPECT_NE(err.find("rollwear " + spec.name + ": " + missing),
              std::string::npos)
        << missing << ": " << err;
    EXPECT_NE(err.find("required"), std::string::npos) << err;
  }
}

// README.md's CLI table names every option of the command.
TEST_P(CliCommandTest, ReadmeTableListsEveryOption) {
  const CommandSpec& spec = GetParam();
  const std::string readme = ReadFile(ROLLWEAR_SOURCE_DIR "/README.md");
  std::string usage;  // the first cells of the command's rows
  std::istringstream in(readme);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `" + spec.name + " ", 0) == 0) {
      usage += line.substr(0, line.find(" | ")) + " ";
    }
  }
  ASSERT_FALSE(usage.empty()) << spec.name << " has no row in README.md";
  for (const std::string& option : spec.options) {
    EXPECT_TRUE(std::regex_search(usage, std::regex(option + "[^a-z-]")))
        << option << " missing from README.md's row of " << spec.name;
  }
}

INSTANTIATE_TEST_SUITE_P(Cli, CliCommandTest, ::testing::ValuesIn(Commands()),
                         [](const ::testing::TestParamInfo<CommandSpec>& info) {
                           return info.param.name;
                         });

TEST(CliTest, TopHelpListsExactlyTheCommands) {
  std::string out, err;
  ASSERT_EQ(RunRollwear({"--help"}, &out, &err), 0) << err;
  EXPECT_EQ(err, "");
  std::set<std::string> listed;
  for (const std::string& line : Section(out, "Subcommands:")) {
    listed.insert(line.substr(2, line.find(' ', 2) - 2));
  }
  std::set<std::string> expected;
  for (const CommandSpec& c : Commands()) expected.insert(c.name);
  EXPECT_EQ(listed, expected) << out;
  EXPECT_EQ(HelpOptions(out), (std::set<std::string>{"--help", "--version"}))
      << out;
}

TEST(CliTest, VersionNamesTheVersionAndTheCommit) {
  std::string out, err;
  ASSERT_EQ(RunRollwear({"--version"}, &out, &err), 0) << err;
  EXPECT_EQ(out,
            "rollwear " ROLLWEAR_VERSION " (commit " ROLLWEAR_GIT_COMMIT ")\n");
  EXPECT_TRUE(std::regex_match(
      out,
      std::regex(
          R"(rollwear \d+\.\d+\.\d+ \(commit ([0-9a-f]{7,}|unknown)\)\n)")))
      << out;
  EXPECT_EQ(err, "");
}

TEST(CliTest, NoCommandOrAnUnknownOneIsAUsageError) {
  std::string out, err;
  EXPECT_EQ(RunRollwear({}, &out, &err), 2);
  EXPECT_EQ(out, "");
  EXPECT_NE(err.find("simulate"), std::string::npos) << err;
  EXPECT_EQ(RunRollwear({"simulat"}, &out, &err), 2);
  EXPECT_EQ(err.rfind("rollwear: unknown command 'simulat'\n", 0), 0u) << err;
  EXPECT_EQ(RunRollwear({"--frobnicate"}, &out, &err), 2);
  EXPECT_EQ(err.rfind("rollwear: unknown option --frobnicate\n", 0), 0u) << err;
  EXPECT_EQ(RunRollwear({"import", "--db", "x.db", "dir1", "dir2"}, &out, &err),
            2);
  EXPECT_EQ(err.rfind("rollwear import: unexpected argument 'dir2'\n", 0), 0u)
      << err;
}

TEST(CliTest, MalformedValuesAreUsageErrorsNamingTheOption) {
  struct Case {
    std::vector<std::string> args;
    std::string option;
  };
  const std::vector<Case> cases = {
      {{"simulate", "--out", "/nonexistent/d", "--seed", "-1"}, "--seed"},
      {{"simulate", "--out", "/nonexistent/d", "--seed", "0x10"}, "--seed"},
      {{"simulate", "--out", "/nonexistent/d", "--campaigns", "0"},
       "--campaigns"},
      {{"simulate", "--out", "/nonexistent/d", "--missing", "lots"},
       "--missing"},
      {{"calibrate", "--data", "/nonexistent/d", "--model", "wagn"}, "--model"},
      {{"calibrate", "--data", "/nonexistent/d", "--option", "4"}, "--option"},
      {{"calibrate", "--data", "/nonexistent/d", "--protocol", "fast"},
       "--protocol"},
      {{"ann", "--data", "/nonexistent/d", "--select", "worst"}, "--select"},
      {{"replay", "--data", "/nonexistent/d", "--url", "http://x", "--clients",
        "0"},
       "--clients"},
      {{"replay", "--data", "/nonexistent/d", "--url", "http://x", "--speed",
        "-2"},
       "--speed"},
      {{"simulate", "--out"}, "--out"},  // value missing
  };
  for (const Case& c : cases) {
    std::string out, err;
    EXPECT_EQ(RunRollwear(c.args, &out, &err), 2) << c.args.back();
    EXPECT_EQ(err.rfind("rollwear " + c.args[0] + ": ", 0), 0u) << err;
    EXPECT_NE(err.find(c.option), std::string::npos) << c.option << ": " << err;
    EXPECT_EQ(out, "");
  }
}

TEST(CliTest, EffectIsRepeatableAndTakesCommaLists) {
  std::string effects, err;
  ASSERT_EQ(RunRollwear({"simulate", "--list-effects"}, &effects, &err), 0)
      << err;
  std::vector<std::string> names;
  std::istringstream in(effects);
  for (std::string line; std::getline(in, line);) {
    names.push_back(line.substr(0, line.find(' ')));
  }
  ASSERT_GE(names.size(), 3u) << effects;
  TempDir dir;
  std::string out;
  // Leading zeros are decimal, and the last of a repeated option wins.
  ASSERT_EQ(
      RunRollwear({"simulate", "--out", dir / "data", "--seed", "9", "--seed",
                   "012", "--campaigns", "4", "--coils-per-campaign", "10",
                   "--effect", names[0], "--effect", names[1] + "," + names[2]},
                  &out, &err),
      0)
      << err;
  EXPECT_NE(out.find("(seed 12)"), std::string::npos) << out;
  EXPECT_NE(out.find("Concealed effects: " + names[0] + ", " + names[1] + ", " +
                     names[2] + "."),
            std::string::npos)
      << out;
}

}  // namespace
}  // namespace rollwear::e2e
