#include "file_safety_fixture.h"

namespace rabbit::testing {

namespace fs = std::filesystem;

std::map<std::string, std::string> TreeSnapshot(const fs::path& root) {
  std::map<std::string, std::string> files;
  if (!fs::exists(fs::symlink_status(root))) return files;
  if (!fs::is_directory(fs::symlink_status(root))) {
    files[root.string()] = fs::is_fifo(fs::symlink_status(root)) ? "<fifo>" : ReadText(root);
    return files;
  }
  files[root.string()] = "<dir>";
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const fs::file_status s = fs::symlink_status(e.path());
    files[e.path().string()] = fs::is_directory(s) ? "<dir>"
                               : fs::is_fifo(s)    ? "<fifo>"
                                                   : ReadText(e.path());
  }
  return files;
}

}  // namespace rabbit::testing
