// The rabbit app (cli/app.h).
#include "cli/app.h"

#include <string>

#include "cli/data_root.h"
#include "cli/flag_checks.h"

namespace rabbit::cli {
namespace {

// Every option that takes a value, of `app` and of its subcommands at any depth, refuses an empty
// text (NonEmptyText): no option but --filter gives '' a meaning (an empty regex selects every
// scenario, as no --filter does).
void RefuseEmptyValues(CLI::App* app) {
  for (CLI::Option* option : app->get_options()) {
    if (option->get_type_size_max() > 0 && !option->check_lname("filter")) {
      option->check(NonEmptyText());
    }
  }
  for (CLI::App* sub : app->get_subcommands([](CLI::App*) { return true; })) {
    RefuseEmptyValues(sub);
  }
}

}  // namespace

std::string VersionText() {
  std::string text = std::string("rabbit ") + RABBIT_VERSION + "\n";
  try {
    text += DataRootLine();
  } catch (const std::exception& e) {  // a bad --data or RABBIT_DATA
    text += std::string("data root: ") + e.what();
  }
  return text;
}

std::vector<Command> BuildApp(CLI::App* app) {
  // Every option shows its default in --help (subcommands inherit the option defaults); options
  // may follow the subcommand that takes them (--data).
  app->option_defaults()->always_capture_default();
  app->fallthrough();
  AddDataOption(app);
  app->set_version_flag("--version", VersionText, "Print the version and the data root, and exit");
  app->require_subcommand(1);
  std::vector<Command> commands = {RegisterSimulate(app), RegisterGaits(app), RegisterTrain(app),
                                   RegisterFis(app),      RegisterRun(app),   RegisterReport(app),
                                   RegisterTune(app)};
  RefuseEmptyValues(app);
  return commands;
}

}  // namespace rabbit::cli
