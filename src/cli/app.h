// The rabbit command line: the app with every subcommand, its options and their help. Shared by
// the executable (cli/main.cc) and the test of the CLI's grammar, which walks it.
#ifndef RABBIT_CLI_APP_H_
#define RABBIT_CLI_APP_H_

#include <CLI/CLI.hpp>
#include <vector>

#include "cli/commands.h"

namespace rabbit::cli {

// Configures `app` (defaults shown in every --help, --data, --version) and adds every
// subcommand; returns them, in order.
std::vector<Command> BuildApp(CLI::App* app);

// rabbit --version: the version and the data root.
std::string VersionText();

}  // namespace rabbit::cli

#endif  // RABBIT_CLI_APP_H_
