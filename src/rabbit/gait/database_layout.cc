#include "rabbit/gait/database_layout.h"

#include <filesystem>

namespace rabbit {
namespace fs = std::filesystem;

std::string GaitDatabaseRoot(const std::string& dir) {
  const fs::path p(dir);
  const fs::path name = p.filename().empty() ? p.parent_path().filename() : p.filename();
  if (name == kReferenceDir && fs::exists(p / kIndexFile) && !fs::exists(p / kReferenceDir)) {
    const fs::path parent = (p.filename().empty() ? p.parent_path() : p).parent_path();
    return parent.empty() ? "." : parent.string();
  }
  return dir;
}

std::string ReferenceDirOf(const std::string& root) {
  return (fs::path(root) / kReferenceDir).string();
}
std::string NetworksDirOf(const std::string& root) {
  return (fs::path(root) / kNetworksDir).string();
}
std::string GaitPatternOf(const std::string& root) {
  return (fs::path(root) / kGaitPatternFile).string();
}

}  // namespace rabbit
