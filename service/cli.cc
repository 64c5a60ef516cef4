#include "service/cli.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "service/commands.h"
#include "service/config.h"

namespace rollwear::cli {
namespace {

// A sub-command and what runs it once it has been parsed.
struct Command {
  CLI::App* app;
  std::function<int()> run;
};

// Integer options take plain decimal digits: CLI11's own conversion
// (strtoll, base 0) would read "010" as octal and wrap "-1" into a huge
// unsigned seed.
CLI::Validator Count() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        if (value.empty() ||
            value.find_first_not_of("0123456789") != std::string::npos) {
          return "needs a non-negative integer, got '" + value + "'";
        }
        value.erase(0,
                    std::min(value.find_first_not_of('0'), value.size() - 1));
        return "";
      },
      "", "non-negative integer");
}

template <typename T>
CLI::Option* AddCount(CLI::App* app, const std::string& name, T& value,
                      const std::string& help) {
  return app->add_option(name, value, help)
      ->transform(Count())
      ->type_name("N")
      ->capture_default_str();
}

CLI::Option* AddNumber(CLI::App* app, const std::string& name, double& value,
                       const std::string& help) {
  return app->add_option(name, value, help)
      ->type_name("X")
      ->capture_default_str();
}

// A string option whose value is a path or a name, shown as `type`.
CLI::Option* AddPath(CLI::App* app, const std::string& name, std::string& value,
                     const std::string& type, const std::string& help) {
  return app->add_option(name, value, help)->type_name(type);
}

// One of `choices`; the help shows them and the default.
CLI::Option* AddChoice(CLI::App* app, const std::string& name,
                       std::string& value,
                       const std::vector<std::string>& choices,
                       const std::string& help) {
  return app->add_option(name, value, help)
      ->check(CLI::IsMember(choices))
      ->capture_default_str();
}

CLI::Option* AddLaw(CLI::App* app, std::string& value,
                    const std::string& help) {
  return AddChoice(app, "--model", value, {"wang", "nikitenko", "cao"}, help);
}

CLI::Option* AddData(CLI::App* app, std::string& value) {
  return AddPath(app, "--data", value, "DIR", "dataset folder")->required();
}

// --strict: data-quality warnings (core/dataset/data_quality.h) are errors.
void AddStrict(CLI::App* app, bool& value) {
  app->add_flag("--strict", value,
                "refuse the dataset (exit 1) when it has any data-quality "
                "warning (suspect measurement, roll position without a pass)");
}

CLI::App* AddCommand(CLI::App* app, const std::string& name,
                     const std::string& help) {
  CLI::App* sub = app->add_subcommand(name, help);
  // Unknown options and stray arguments are reported by RunCli, in order.
  sub->allow_extras();
  return sub;
}

Command AddSimulate(CLI::App* app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* c = AddCommand(
      app, "simulate",
      "Write a synthetic mill dataset folder and, beside it, the simulator's "
      "ground truth (JSON); print a summary.");
  AddPath(c, "--out", args->out, "DIR", "dataset folder to write (required)");
  AddCount(c, "--seed", args->options.seed, "simulator seed");
  c->add_option("--effect", args->effects,
                "concealed effect(s) to simulate, comma-separated; "
                "repeatable; none = no effect; a family takes NAME:K for "
                "its variant K (see --list-effects)")
      ->type_name("NAME[,NAME]")
      ->allow_extra_args(false);  // one value per --effect
  AddCount(c, "--campaigns", args->options.num_campaigns,
           "campaigns to simulate")
      ->check(CLI::Range(1, 100000));
  AddNumber(c, "--coils-per-campaign", args->options.coils_per_campaign,
            "mean coils per campaign");
  AddNumber(c, "--missing", args->options.missing_measurement_fraction,
            "fraction of grinder measurements left out");
  AddNumber(c, "--roll-wear-factor", args->options.roll_wear_factor_sd,
            "sd of the log of a lifelong wear factor per physical roll "
            "(0: none; truth: roll_wear_factor)");
  AddNumber(c, "--gross-errors", args->options.gross_error_fraction,
            "fraction of readings with gross grinder errors, on top of any "
            "effect (0 = none)");
  AddPath(c, "--truth", args->truth, "FILE",
          "ground-truth JSON file (default DIR.truth.json, beside DIR; "
          "never inside it)");
  c->add_flag("--profiles", args->options.profiles,
              "also write profiles.csv: the grinder's wear profile across "
              "the barrel for most measured rolls (every 10 mm)");
  c->add_flag("--no-shift{false}", args->options.shifting,
              "no work-roll shifting (every pass at shift_mm 0)");
  c->add_flag("--list-effects", args->list_effects,
              "list the effects the simulator can conceal, and exit");
  return {c, [args] { return RunSimulate(*args); }};
}

Command AddCalibrate(CLI::App* app) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* c = AddCommand(
      app, "calibrate",
      "Calibrate a wear model on a seeded 2/3 training / 1/3 validation split "
      "by campaign; print the coefficients with standard errors and the "
      "figures of merit.");
  AddData(c, args->data);
  AddStrict(c, args->strict);
  AddLaw(c, args->model, "wear law");
  AddCount(c, "--option", args->options.option, "K structure option")
      ->check(CLI::IsMember({1, 2, 3}));
  AddChoice(c, "--start", args->start, {"ones", "random", "empirical"},
            "initial set of the coefficients");
  AddChoice(c, "--protocol", args->protocol, {"exact", "paper"},
            "derivatives: exact (automatic) or paper (forward differences, "
            "the study's protocol)");
  AddCount(c, "--split-seed", args->split_seed, "seed of the campaign split");
  AddPath(c, "--split", args->split, "FILE",
          "use the split of FILE (CSV campaign_id,stand,position,set; set = "
          "train or validation) instead of the seeded one; readings not listed "
          "are not used");
  AddPath(c, "--predictions", args->predictions, "FILE",
          "write one CSV row per measured reading used: campaign_id,stand,"
          "position,roll_id,set,measured_um,predicted_um,lo_um,hi_um");
  c->add_flag("--per-roll", args->per_roll,
              "give every physical roll its own wear multiplier, shrunk "
              "towards its roll type (empirical Bayes random effect)");
  c->add_flag("--free-grades{false}", args->options.shrink_grades,
              "fit option 1's grade factors freely, as the study did, instead "
              "of shrinking them toward the typical grade (random effect)");
  AddCount(c, "--seed", args->options.seed, "seed of --start random");
  AddPath(c, "--json", args->json, "FILE", "write the result as JSON");
  AddPath(c, "--figures", args->figures, "DIR",
          "write measured vs calculated wear per stand as SVG into DIR");
  AddPath(c, "--terms", args->terms, "FILE",
          "refit Wang's law, option 1, with the terms adopted by "
          "`rollwear diagnose --json` (or a model JSON with \"terms\")");
  return {c, [args] { return RunCalibrate(*args); }};
}

Command AddStudy(CLI::App* app) {
  auto args = std::make_shared<StudyArgs>();
  CLI::App* c = AddCommand(
      app, "study",
      "The study's Tables 1-3 on a dataset, as Markdown on stdout (and, with "
      "--out, study.md and study.json).");
  AddData(c, args->data);
  AddStrict(c, args->strict);
  AddPath(c, "--out", args->out, "DIR",
          "write study.md and study.json into DIR");
  AddPath(c, "--figures", args->figures, "DIR",
          "write the study's measured vs calculated figures as SVG into DIR");
  AddCount(c, "--split-seed", args->options.split_seed,
           "seed of the campaign split");
  AddPath(c, "--split", args->split, "FILE",
          "use the split of FILE (CSV campaign_id,stand,position,set; set = "
          "train or validation) instead of the seeded one; readings not listed "
          "are not used");
  AddCount(c, "--seed", args->options.random_start_seed,
           "seed of the random initial sets");
  return {c, [args] { return RunStudy(*args); }};
}

Command AddAnn(CLI::App* app) {
  auto args = std::make_shared<AnnArgs>();
  AnnTrainingOptions& t = args->options.training;
  CLI::App* c = AddCommand(
      app, "ann",
      "Train the recurrent K-estimator and compare it with classical "
      "calibration (Wang, option 1) on the same split: the study's Table 4.");
  AddData(c, args->data);
  AddStrict(c, args->strict);
  AddPath(c, "--json", args->json, "FILE", "write the comparison as JSON");
  AddCount(c, "--seeds", t.members, "ensemble members (training seeds)");
  AddCount(c, "--split-seed", args->options.split_seed,
           "seed of the campaign split");
  AddPath(c, "--split", args->split, "FILE",
          "use the split of FILE (CSV campaign_id,stand,position,set; set = "
          "train or validation) instead of the seeded one; readings not listed "
          "are not used");
  AddPath(c, "--predictions", args->predictions, "FILE",
          "write the network's prediction of every measured reading used "
          "as CSV (as calibrate --predictions; lo_um, hi_um empty)");
  AddCount(c, "--seed", t.seed, "first training seed");
  AddChoice(c, "--select", args->select, {"mean", "best"},
            "ensemble: mean of the members, or the best on the holdout");
  AddCount(c, "--max-epochs", t.max_epochs, "training epochs at most");
  AddCount(c, "--threads", t.threads, "training threads");
  AddNumber(c, "--weight-decay", t.weight_decay, "AdamW weight decay");
  c->add_flag("--no-early-stopping", args->no_early_stopping,
              "train all epochs; the holdout is only reported");
  c->add_flag("--linear-skip", t.linear_skip, "train the linear skip path");
  AddPath(c, "--model-out", args->model_out, "FILE",
          "write the trained model in its text form");
  c->add_flag("--with-diagnosis", args->options.compare_adopted,
              "add the diagnosis engine's adopted model as a third row");
  AddPath(c, "--figures", args->figures, "DIR",
          "write measured vs calculated wear, classical against the ANN, "
          "as SVG into DIR");
  return {c, [args] { return RunAnn(*args); }};
}

Command AddServe(CLI::App* app, const BuildVersion& build) {
  auto args = std::make_shared<ServeArgs>();
  args->build = build;
  const service::ServeConfig defaults;
  CLI::App* c = AddCommand(
      app, "serve",
      "The daemon: the HTTP API of docs/api.md on the database, queued and "
      "nightly calibrations; stops gracefully on SIGINT/SIGTERM. Settings: "
      "defaults, then --config, then ROLLWEAR_* variables, then these flags.");
  struct Setting {
    const char* flag;
    const char* key;
    const char* type;
    const char* help;
    std::string fallback;
  };
  const Setting settings[] = {
      {"--db", "db", "FILE", "SQLite database (created or migrated)", ""},
      {"--port", "port", "N", "TCP port (0 = ephemeral)",
       std::to_string(defaults.port)},
      {"--bind", "bind", "ADDR", "address to listen on", defaults.bind},
      {"--log-level", "log_level", "LEVEL",
       "trace, debug, info, warn, error or off", defaults.log_level},
      {"--threads", "threads", "N", "HTTP worker threads",
       std::to_string(defaults.threads)}};
  for (const Setting& s : settings) {
    const std::string key = s.key;
    c->add_option_function<std::string>(
         s.flag,
         [args, key](const std::string& value) {
           args->settings.emplace_back(key, value);
         },
         s.help)
        ->type_name(s.type)
        ->default_str(s.fallback);
  }
  AddPath(c, "--config", args->config, "FILE",
          "config file (docs/operations.md)");
  return {c, [args] { return RunServe(*args); }};
}

Command AddImport(CLI::App* app) {
  auto args = std::make_shared<ImportArgs>();
  CLI::App* c = AddCommand(
      app, "import",
      "Load a dataset folder into the database, all-or-nothing: the first "
      "broken rule is reported as file:line:column and nothing is stored.");
  AddPath(c, "--db", args->db, "FILE", "SQLite database")->required();
  AddStrict(c, args->strict);
  c->add_option("DIR", args->dir, "dataset folder (docs/data-format.md)")
      ->type_name("DIR")
      ->required();
  return {c, [args] { return RunImport(*args); }};
}

Command AddExport(CLI::App* app) {
  auto args = std::make_shared<ExportArgs>();
  CLI::App* c = AddCommand(
      app, "export",
      "Write what a database holds as a dataset folder (the inverse of "
      "import); works while a daemon runs on the database.");
  AddPath(c, "--db", args->db, "FILE", "SQLite database")->required();
  AddPath(c, "--out", args->out, "DIR",
          "dataset folder to write (missing or empty)")
      ->required();
  return {c, [args] { return RunExport(*args); }};
}

Command AddReplay(CLI::App* app) {
  auto args = std::make_shared<ReplayArgs>();
  CLI::App* c = AddCommand(
      app, "replay",
      "Post a dataset folder through the HTTP API in time order, as the "
      "mill's Level 2 system and the roll shop would; exit 0 only when every "
      "event was accepted.");
  AddData(c, args->data);
  AddPath(c, "--url", args->url, "URL", "the daemon, http://HOST:PORT")
      ->required();
  AddPath(c, "--token", args->token, "T",
          "bearer token (default $ROLLWEAR_TOKEN)");
  AddCount(c, "--clients", args->clients,
           "concurrent keep-alive connections (one thread drives them)")
      ->check(CLI::Range(1, 256));
  AddNumber(c, "--speed", args->speed,
            "pace at X times the dataset's clock (0 = as fast as possible)")
      ->check(CLI::NonNegativeNumber);
  AddNumber(c, "--retry-for", args->retry_for_s,
            "retry lost connections and 502/503/504 answers of a daemon that "
            "has answered for X seconds (a refused connection before any "
            "answer, or a 401, stops the replay at once)")
      ->check(CLI::NonNegativeNumber);
  AddNumber(c, "--show-wear", args->show_wear_s,
            "print GET /v1/wear every X seconds (0 = never)")
      ->check(CLI::NonNegativeNumber);
  AddPath(c, "--json", args->json, "FILE", "write the summary as JSON");
  c->add_flag("--leave-last-open", args->leave_last_open,
              "leave the last campaign running (no end, no measurements)");
  c->add_flag("--quiet", args->quiet, "no progress lines");
  return {c, [args] { return RunReplay(*args); }};
}

Command AddDiagnose(CLI::App* app) {
  auto args = std::make_shared<DiagnoseArgs>();
  CLI::App* c = AddCommand(
      app, "diagnose",
      "Locate model-vs-measurement mismatch, name and fit the missing "
      "physics, show the gain on held-out campaigns (docs/diagnosis.md).");
  AddData(c, args->data);
  AddStrict(c, args->strict);
  AddPath(c, "--json", args->json, "FILE", "write the report as JSON");
  AddPath(c, "--html", args->html, "FILE", "write the report as HTML");
  AddCount(c, "--split-seed", args->options.split_seed,
           "seed of the campaign split");
  AddPath(c, "--split", args->split, "FILE",
          "use the split of FILE (CSV campaign_id,stand,position,set; set = "
          "train or validation) instead of the seeded one; readings not listed "
          "are not used");
  AddLaw(c, args->model, "wear law of the baseline");
  AddCount(c, "--threads", args->options.num_threads, "threads");
  return {c, [args] { return RunDiagnose(*args); }};
}

Command AddScorecard(CLI::App* app) {
  auto args = std::make_shared<ScorecardArgs>();
  CLI::App* c = AddCommand(
      app, "scorecard",
      "Simulate every effect x seed, diagnose each dataset and score the "
      "report against the truth: named right, wrong physics, quiet on clean "
      "data, validation gap / noise floor, time (docs/diagnosis.md).");
  AddCount(c, "--seeds", args->seeds, "seeds per case")
      ->check(CLI::Range(1, 1000));
  AddCount(c, "--first-seed", args->first_seed, "first simulator seed");
  AddPath(c, "--effects", args->effects, "CASE[,CASE]",
          "cases: simulator effects, several joined by '+', clean for none "
          "(default: clean, gross_errors and every effect)");
  AddCount(c, "--campaigns", args->campaigns, "campaigns per dataset")
      ->check(CLI::Range(20, 100000));
  AddCount(c, "--threads", args->threads, "threads of each diagnosis")
      ->check(CLI::Range(1, 256));
  AddPath(c, "--json", args->json, "FILE", "write cases and summary as JSON");
  return {c, [args] { return RunScorecard(*args); }};
}

// Exit 2 with "rollwear[ COMMAND]: MESSAGE" and where the help is.
int UsageError(const CLI::App* command, const std::string& message) {
  const std::string who =
      command == nullptr ? "rollwear" : "rollwear " + command->get_name();
  std::fprintf(stderr, "%s: %s\nRun '%s --help' for the options.\n",
               who.c_str(), message.c_str(), who.c_str());
  return 2;
}

// The first argument `parser` did not take, as an error; "" when none.
std::string FirstExtra(const CLI::App& parser, bool is_command) {
  const std::vector<std::string> extra = parser.remaining();
  if (extra.empty()) return "";
  const std::string& first = extra.front();
  if (first.rfind("-", 0) == 0) {
    return "unknown option " + first.substr(0, first.find('='));
  }
  return (is_command ? "unexpected argument '" : "unknown command '") + first +
         "'";
}

}  // namespace

int RunCli(int argc, char** argv, const BuildVersion& build) {
  const std::string version =
      "rollwear " + build.version + " (commit " + build.commit + ")";
  CLI::App app("rollwear: work-roll wear prediction for a hot strip mill.",
               "rollwear");
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.get_formatter()->column_width(36);
  app.set_version_flag("--version", version,
                       "print the version and the git commit");
  app.allow_extras();
  app.footer("Run 'rollwear COMMAND --help' for the options of a command.");
  const std::vector<Command> commands = {
      AddSimulate(&app), AddCalibrate(&app),    AddStudy(&app),
      AddAnn(&app),      AddServe(&app, build), AddImport(&app),
      AddExport(&app),   AddReplay(&app),       AddDiagnose(&app),
      AddScorecard(&app)};

  std::string parse_error;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    parse_error = e.what();
  }
  const Command* chosen = nullptr;
  for (const Command& c : commands) {
    if (c.app->parsed()) chosen = &c;
  }
  const CLI::App* command = chosen == nullptr ? nullptr : chosen->app;
  // An unknown option explains a missing or malformed one better than the
  // other way round, so it is reported first.
  const std::string extra =
      FirstExtra(command == nullptr ? app : *command, command != nullptr);
  if (!extra.empty()) return UsageError(command, extra);
  if (!parse_error.empty()) return UsageError(command, parse_error);
  if (chosen == nullptr) {
    std::fputs(app.help().c_str(), stderr);
    return 2;
  }
  return chosen->run();
}

}  // namespace rollwear::cli
