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
const CLI::Validator kCount(
    [](std::string& value) -> std::string {
      if (value.empty() ||
          value.find_first_not_of("0123456789") != std::string::npos) {
        return "needs a non-negative integer, got '" + value + "'";
      }
      value.erase(0, std::min(value.find_first_not_of('0'), value.size() - 1));
      return "";
    },
    "", "non-negative integer");

template <typename T>
CLI::Option* AddCount(CLI::App* app, const std::string& name, T& value,
                      const std::string& help) {
  return app->add_option(name, value, help)
      ->transform(kCount)
      ->type_name("N")
      ->capture_default_str();
}

CLI::Option* AddNumber(CLI::App* app, const std::string& name, double& value,
                       const std::string& help) {
  return app->add_option(name, value, help)->type_name("X")->capture_default_str();
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
  c->add_option("--out", args->out, "dataset folder to write (required)")
      ->type_name("DIR");
  AddCount(c, "--seed", args->options.seed, "simulator seed");
  c->add_option("--effect", args->effects,
                "concealed effect(s) to simulate, comma-separated; repeatable; "
                "none = no effect (see --list-effects)")
      ->type_name("NAME[,NAME]")
      ->allow_extra_args(false);
  AddCount(c, "--campaigns", args->options.num_campaigns, "campaigns to simulate")
      ->check(CLI::Range(1, 100000));
  AddNumber(c, "--coils-per-campaign", args->options.coils_per_campaign,
            "mean coils per campaign");
  AddNumber(c, "--missing", args->options.missing_measurement_fraction,
            "fraction of grinder measurements left out");
  c->add_option("--truth", args->truth,
                "ground-truth JSON file (default DIR.truth.json, beside DIR; "
                "never inside it)")
      ->type_name("FILE");
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
  c->add_option("--data", args->data, "dataset folder")->type_name("DIR")->required();
  c->add_option("--model", args->model, "wear law")
      ->check(CLI::IsMember({"wang", "nikitenko", "cao"}))
      ->capture_default_str();
  AddCount(c, "--option", args->options.option, "K structure option")
      ->check(CLI::IsMember({1, 2, 3}));
  c->add_option("--start", args->start, "initial set of the coefficients")
      ->check(CLI::IsMember({"ones", "random", "empirical"}))
      ->capture_default_str();
  c->add_option("--protocol", args->protocol,
                "derivatives: exact (automatic) or paper (forward differences, "
                "the study's protocol)")
      ->check(CLI::IsMember({"exact", "paper"}))
      ->capture_default_str();
  AddCount(c, "--split-seed", args->split_seed, "seed of the campaign split");
  AddCount(c, "--seed", args->options.seed, "seed of --start random");
  c->add_option("--json", args->json, "write the result as JSON")->type_name("FILE");
  c->add_option("--figures", args->figures,
                "write measured vs calculated wear per stand as SVG into DIR")
      ->type_name("DIR");
  c->add_option("--terms", args->terms,
                "refit Wang's law, option 1, with the terms adopted by "
                "`rollwear diagnose --json` (or a model JSON with \"terms\")")
      ->type_name("FILE");
  return {c, [args] { return RunCalibrate(*args); }};
}

Command AddStudy(CLI::App* app) {
  auto args = std::make_shared<StudyArgs>();
  CLI::App* c = AddCommand(
      app, "study",
      "The study's Tables 1-3 on a dataset, as Markdown on stdout (and, with "
      "--out, study.md and study.json).");
  c->add_option("--data", args->data, "dataset folder")->type_name("DIR")->required();
  c->add_option("--out", args->out, "write study.md and study.json into DIR")
      ->type_name("DIR");
  c->add_option("--figures", args->figures,
                "write the study's measured vs calculated figures as SVG into DIR")
      ->type_name("DIR");
  AddCount(c, "--split-seed", args->options.split_seed, "seed of the campaign split");
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
  c->add_option("--data", args->data, "dataset folder")->type_name("DIR")->required();
  c->add_option("--json", args->json, "write the comparison as JSON")->type_name("FILE");
  AddCount(c, "--seeds", t.members, "ensemble members (training seeds)");
  AddCount(c, "--split-seed", args->options.split_seed, "seed of the campaign split");
  AddCount(c, "--seed", t.seed, "first training seed");
  c->add_option("--select", args->select,
                "ensemble: mean of the members, or the best on the holdout")
      ->check(CLI::IsMember({"mean", "best"}))
      ->capture_default_str();
  AddCount(c, "--max-epochs", t.max_epochs, "training epochs at most");
  AddCount(c, "--threads", t.threads, "training threads");
  AddNumber(c, "--weight-decay", t.weight_decay, "AdamW weight decay");
  c->add_flag("--no-early-stopping", args->no_early_stopping,
              "train all epochs; the holdout is only reported");
  c->add_flag("--linear-skip", t.linear_skip, "train the linear skip path");
  c->add_option("--model-out", args->model_out,
                "write the trained model in its text form")
      ->type_name("FILE");
  c->add_flag("--with-diagnosis", args->options.compare_adopted,
              "add the diagnosis engine's adopted model as a third row");
  c->add_option("--figures", args->figures,
                "write measured vs calculated wear, classical against the ANN, "
                "as SVG into DIR")
      ->type_name("DIR");
  return {c, [args] { return RunAnn(*args); }};
}

Command AddServe(CLI::App* app) {
  auto args = std::make_shared<ServeArgs>();
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
  c->add_option("--config", args->config, "config file (docs/operations.md)")
      ->type_name("FILE");
  return {c, [args] { return RunServe(*args); }};
}

Command AddImport(CLI::App* app) {
  auto args = std::make_shared<ImportArgs>();
  CLI::App* c = AddCommand(
      app, "import",
      "Load a dataset folder into the database, all-or-nothing: the first "
      "broken rule is reported as file:line:column and nothing is stored.");
  c->add_option("--db", args->db, "SQLite database")->type_name("FILE")->required();
  c->add_option("DIR", args->dir, "dataset folder (docs/data-format.md)")
      ->type_name("DIR")
      ->required();
  return {c, [args] { return RunImport(*args); }};
}

Command AddReplay(CLI::App* app) {
  auto args = std::make_shared<ReplayArgs>();
  CLI::App* c = AddCommand(
      app, "replay",
      "Post a dataset folder through the HTTP API in time order, as the "
      "mill's Level 2 system and the roll shop would; exit 0 only when every "
      "event was accepted.");
  c->add_option("--data", args->data, "dataset folder")->type_name("DIR")->required();
  c->add_option("--url", args->url, "the daemon, http://HOST:PORT")
      ->type_name("URL")
      ->required();
  c->add_option("--token", args->token, "bearer token (default $ROLLWEAR_TOKEN)")
      ->type_name("T");
  AddCount(c, "--clients", args->clients, "concurrent keep-alive clients")
      ->check(CLI::Range(1, 256));
  AddNumber(c, "--speed", args->speed,
            "pace at X times the dataset's clock (0 = as fast as possible)")
      ->check(CLI::NonNegativeNumber);
  AddNumber(c, "--retry-for", args->retry_for_s,
            "retry connection errors and 5xx answers for X seconds")
      ->check(CLI::NonNegativeNumber);
  AddNumber(c, "--show-wear", args->show_wear_s,
            "print GET /v1/wear every X seconds (0 = never)")
      ->check(CLI::NonNegativeNumber);
  c->add_option("--json", args->json, "write the summary as JSON")->type_name("FILE");
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
  c->add_option("--data", args->data, "dataset folder")->type_name("DIR")->required();
  c->add_option("--json", args->json, "write the report as JSON")->type_name("FILE");
  c->add_option("--html", args->html, "write the report as HTML")->type_name("FILE");
  AddCount(c, "--split-seed", args->options.split_seed, "seed of the campaign split");
  c->add_option("--model", args->model, "wear law of the baseline")
      ->check(CLI::IsMember({"wang", "nikitenko", "cao"}))
      ->capture_default_str();
  AddCount(c, "--threads", args->options.num_threads, "threads");
  return {c, [args] { return RunDiagnose(*args); }};
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

int RunCli(int argc, char** argv, const std::string& version) {
  CLI::App app("rollwear: work-roll wear prediction for a hot strip mill.",
               "rollwear");
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.get_formatter()->column_width(36);
  app.set_version_flag("--version", version, "print the version and the git commit");
  app.allow_extras();
  app.footer("Run 'rollwear COMMAND --help' for the options of a command.");
  const std::vector<Command> commands = {
      AddSimulate(&app), AddCalibrate(&app), AddStudy(&app), AddAnn(&app),
      AddServe(&app),    AddImport(&app),    AddReplay(&app), AddDiagnose(&app)};

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
  const std::string extra = FirstExtra(command == nullptr ? app : *command,
                                       command != nullptr);
  if (!extra.empty()) return UsageError(command, extra);
  if (!parse_error.empty()) return UsageError(command, parse_error);
  if (chosen == nullptr) {
    std::fputs(app.help().c_str(), stderr);
    return 2;
  }
  return chosen->run();
}

}  // namespace rollwear::cli
