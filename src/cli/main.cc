// rabbit: the command-line entry point. Thin: parses arguments, calls the library, maps errors to
// exit codes (2 for bad input or usage).
#include <algorithm>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "cli/app.h"
#include "cli/commands.h"
#include "cli/data_root.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/ranks.h"

namespace {

// For "A subcommand is required": the word where a command was expected that names none (`rabbit
// simulat x.toml`, `rabbit gaits lst`), and the commands that level offers; false when every word
// was a command, an option or an option's value (a command simply left out).
bool UnknownCommand(CLI::App* app, int argc, char** argv, std::string* word, std::string* commands,
                    std::string* where) {
  CLI::App* level = app;
  *where = "rabbit";
  for (int i = 1; i < argc; ++i) {
    const std::string token = argv[i];
    if (token.size() > 1 && token[0] == '-') {
      // An option; its value follows it unless given with '=' (or it takes none).
      if (token.find('=') != std::string::npos) continue;
      const CLI::Option* option = level->get_option_no_throw(token);
      if (option == nullptr) option = app->get_option_no_throw(token);
      // An option this level does not take: the word after it may be its value, not a command.
      if (option == nullptr) return false;
      if (option->get_type_size_max() > 0) ++i;
      continue;
    }
    const std::vector<CLI::App*> subs = level->get_subcommands([](CLI::App*) { return true; });
    if (subs.empty()) return false;  // a positional argument of a leaf command
    const auto named = std::find_if(subs.begin(), subs.end(),
                                    [&token](CLI::App* c) { return c->check_name(token); });
    if (named != subs.end()) {
      level = *named;
      *where += " " + level->get_name();
      continue;
    }
    *word = token;
    for (CLI::App* c : subs) *commands += (commands->empty() ? "" : ", ") + c->get_name();
    return true;
  }
  return false;
}

// Under mpirun every rank reads the same input and fails the same way: rank 0 speaks for all.
int Fail(const std::exception& e) {
  if (rabbit::Ranks::root()) std::cerr << "rabbit: error: " << e.what() << "\n";
  return 2;
}

int Main(int argc, char** argv) {
  CLI::App app{"rabbit-gait: offline design of biped gaits for the RABBIT robot", "rabbit"};
  const std::vector<rabbit::cli::Command> commands = rabbit::cli::BuildApp(&app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    std::string word, offered, where;
    if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr &&
        UnknownCommand(&app, argc, argv, &word, &offered, &where)) {
      if (rabbit::Ranks::root()) {
        std::cerr << "rabbit: error: '" << word << "' is not a command of " << where
                  << " (its commands: " << offered << "; " << where << " --help)\n";
      }
      return 2;
    }
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    rabbit::cli::ResolveDataDefaults();
    for (const rabbit::cli::Command& command : commands) {
      if (command.app->parsed()) return command.run();
    }
  } catch (const std::exception& e) {
    return Fail(e);
  }
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  rabbit::Ranks::Init(&argc, &argv);
  const int code = Main(argc, argv);
  rabbit::Ranks::Finalize();
  return code;
}
