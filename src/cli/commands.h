// Subcommands of the `rabbit` CLI. Each Register function adds its subcommand to the app and
// stores the callback that runs it; the callbacks return the process exit code
// (0 success, 1 a run failed its criteria, 2 bad input or usage).
#ifndef RABBIT_CLI_COMMANDS_H_
#define RABBIT_CLI_COMMANDS_H_

#include <CLI/CLI.hpp>
#include <functional>

namespace rabbit::cli {

using CommandFn = std::function<int()>;
struct Command {
  CLI::App* app = nullptr;  // the subcommand
  CommandFn run;
};

Command RegisterSimulate(CLI::App* app);
Command RegisterGaits(CLI::App* app);
Command RegisterTrain(CLI::App* app);
Command RegisterFis(CLI::App* app);
Command RegisterReport(CLI::App* app);
Command RegisterRun(CLI::App* app);
Command RegisterTune(CLI::App* app);

}  // namespace rabbit::cli

#endif  // RABBIT_CLI_COMMANDS_H_
