// rabbit: the command-line entry point. Thin: parses arguments, calls the library, maps errors to
// exit codes (2 for bad input or usage).
#include <exception>
#include <iostream>
#include <vector>

#include "cli/app.h"
#include "cli/commands.h"
#include "cli/data_root.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/ranks.h"

namespace {

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
