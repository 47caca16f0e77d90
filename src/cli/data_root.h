// The data root: the folder that holds the shipped data (gaits/, scenarios/, optimizers/jobs/),
// against which every default data path of the CLI is taken. Found by one rule, first match wins:
//   1. the --data DIR option;
//   2. the RABBIT_DATA environment variable;
//   3. the current checkout: the working directory or the nearest folder above it that is a
//      rabbit-gait source tree (CMakeLists.txt, src/rabbit/ and scenarios/paper.toml);
//   4. the installation: share/rabbit-gait/ of the prefix the executable runs from
//      (PREFIX/bin/rabbit reads PREFIX/share/rabbit-gait/).
// A folder given by 1 or 2 must exist and hold scenarios/ or gaits/. Paths the user gives are
// never changed: relative ones stay relative to the working directory.
#ifndef RABBIT_CLI_DATA_ROOT_H_
#define RABBIT_CLI_DATA_ROOT_H_

#include <CLI/CLI.hpp>
#include <string>

namespace rabbit::cli {

struct DataRoot {
  std::string path;  // empty: none found
  std::string how;   // "--data", "RABBIT_DATA", "checkout", "install prefix" or why none was found
};

// Adds --data DIR to the app (before its subcommands, which take it too).
void AddDataOption(CLI::App* app);

// The data root by the rule (computed once). Throws InputError when --data or RABBIT_DATA names a
// folder that is not a data root.
const DataRoot& FindDataRoot();

// `relative` below the data root. Throws InputError when no data root is found.
std::string DataPath(const std::string& relative);

// Marks `value` (the default of `option` of subcommand `command`, relative to the data root) to be
// taken below the data root when the command runs and the user did not give the option:
// ResolveDataDefaults, after parsing, does it. Returns `option`.
CLI::Option* DataDefault(CLI::App* command, CLI::Option* option, std::string* value);
// The default of `option` is not taken below the data root when `instead` was given (an older
// flag that names the same thing differently).
void DataDefaultUnusedWith(CLI::Option* option, CLI::Option* instead);
void ResolveDataDefaults();

// "data root: DIR (found by: how)", for --version and verbose output.
std::string DataRootLine();

}  // namespace rabbit::cli

#endif  // RABBIT_CLI_DATA_ROOT_H_
