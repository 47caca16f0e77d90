// The data root rule (cli/data_root.h).
#include "cli/data_root.h"

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/io/error.h"

#ifndef RABBIT_DATA_FROM_BIN
#define RABBIT_DATA_FROM_BIN "../share/rabbit-gait"
#endif

namespace rabbit::cli {
namespace {

namespace fs = std::filesystem;

std::string& DataFlag() {
  static std::string flag;
  return flag;
}

struct Default {
  CLI::App* command;
  CLI::Option* option;
  std::string* value;
  CLI::Option* instead = nullptr;  // an option that, given, makes this default unused
};

std::vector<Default>& Defaults() {
  static std::vector<Default> defaults;
  return defaults;
}

bool IsDir(const fs::path& p) {
  std::error_code ignored;
  return fs::is_directory(p, ignored);
}

bool IsFile(const fs::path& p) {
  std::error_code ignored;
  return fs::is_regular_file(p, ignored);
}

bool LooksLikeCheckout(const fs::path& dir) {
  return IsFile(dir / "CMakeLists.txt") && IsDir(dir / "src" / "rabbit") &&
         IsFile(dir / "scenarios" / "paper.toml");
}

// A folder named by --data or RABBIT_DATA: absolute, and checked.
std::string Given(const std::string& dir, const std::string& source) {
  std::error_code ec;
  const fs::path path = fs::absolute(dir, ec).lexically_normal();
  if (ec || !IsDir(path)) throw InputError(source, 0, dir, "is not a folder");
  if (!IsDir(path / "scenarios") && !IsDir(path / "gaits")) {
    throw InputError(source, 0, dir, "is not a data root: it holds neither scenarios/ nor gaits/");
  }
  return path.string();
}

DataRoot Find() {
  if (!DataFlag().empty()) return {Given(DataFlag(), "--data"), "--data"};
  if (const char* env = std::getenv("RABBIT_DATA"); env != nullptr && *env != '\0') {
    return {Given(env, "RABBIT_DATA"), "RABBIT_DATA"};
  }
  std::error_code ec;
  for (fs::path dir = fs::current_path(ec); !ec && !dir.empty(); dir = dir.parent_path()) {
    if (LooksLikeCheckout(dir)) return {dir.string(), "checkout"};
    if (dir == dir.root_path()) break;
  }
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path share = (exe.parent_path() / RABBIT_DATA_FROM_BIN).lexically_normal();
    if (IsDir(share / "scenarios") || IsDir(share / "gaits")) {
      return {share.string(), "install prefix"};
    }
  }
  return {"",
          "none found: no --data, no RABBIT_DATA, no rabbit-gait checkout at or above the "
          "working directory, and no share/rabbit-gait beside the executable's bin/"};
}

}  // namespace

void AddDataOption(CLI::App* app) {
  app->add_option("--data", DataFlag(),
                  "Data root: the folder of the shipped gaits/, scenarios/ and optimizers/jobs/ "
                  "(default: $RABBIT_DATA, else the rabbit-gait checkout at or above the working "
                  "directory, else PREFIX/share/rabbit-gait of the installed program)");
}

const DataRoot& FindDataRoot() {
  static std::optional<DataRoot> root;
  if (!root) root = Find();
  return *root;
}

std::string DataPath(const std::string& relative) {
  const DataRoot& root = FindDataRoot();
  if (root.path.empty()) {
    throw InputError("--data", 0, relative,
                     "no data root to find the default " + relative + " in (" + root.how +
                         "): give --data DIR, set RABBIT_DATA, or name the file");
  }
  return (fs::path(root.path) / relative).lexically_normal().string();
}

CLI::Option* DataDefault(CLI::App* command, CLI::Option* option, std::string* value) {
  Defaults().push_back({command, option, value});
  return option;
}

void DataDefaultUnusedWith(CLI::Option* option, CLI::Option* instead) {
  for (Default& d : Defaults()) {
    if (d.option == option) d.instead = instead;
  }
}

void ResolveDataDefaults() {
  for (const Default& d : Defaults()) {
    if (d.command->parsed() && d.option->count() == 0 && !d.value->empty() &&
        (d.instead == nullptr || d.instead->count() == 0)) {
      *d.value = DataPath(*d.value);
    }
  }
}

std::string DataRootLine() {
  const DataRoot& root = FindDataRoot();
  if (root.path.empty()) return "data root: " + root.how;
  return "data root: " + root.path + " (found by: " + root.how + ")";
}

}  // namespace rabbit::cli
