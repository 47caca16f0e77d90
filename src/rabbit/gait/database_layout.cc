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

std::string DatabaseRootOf(const std::string& path) {
  fs::path p = fs::path(path).lexically_normal();
  if (p.filename().empty()) p = p.parent_path();
  fs::path parent = p.parent_path();
  if (parent.empty()) parent = fs::current_path();
  std::error_code error;
  if (p.filename() == kReferenceDir || fs::exists(parent / kReferenceDir, error) ||
      fs::exists(parent / kManifestFile, error)) {
    return parent.string();
  }
  return "";
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
