#include "rabbit/gait/database_commit.h"

#include <algorithm>
#include <filesystem>
#include <set>
#include <system_error>
#include <tuple>

#include "rabbit/io/error.h"
#include "rabbit/io/test_hooks.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

constexpr const char* kPendingSuffix = ".rabbit-pending";

void CheckField(const std::string& dir, const std::string& field) {
  if (field.find_first_of(",\n\r") != std::string::npos || field.find("..") != std::string::npos ||
      field.find('/') != std::string::npos) {
    throw InputError(dir, 0, field,
                     "gait names and sources may not hold ',', '/', '..' or newlines");
  }
}

bool IsRegular(const fs::path& path) {
  std::error_code error;
  return fs::is_regular_file(fs::symlink_status(path, error));
}

}  // namespace

std::string PendingGaitFile(const std::string& file) { return "." + file + kPendingSuffix; }

bool FinishGaitCommit(const std::string& dir_text) {
  const fs::path dir(dir_text);
  std::error_code error;
  if (!fs::is_directory(fs::symlink_status(dir, error))) return false;
  const fs::path index = dir / kGaitIndexFile,
                 pending_index = dir / PendingGaitFile(kGaitIndexFile);
  bool found = false;
  if (IsRegular(pending_index)) {  // decided: the gaits it lists go in, then the index
    for (const GaitIndexEntry& e : ReadGaitIndex(pending_index.string())) {
      const fs::path pending = dir / PendingGaitFile(e.file);
      if (IsRegular(pending)) fs::rename(pending, dir / e.file);
    }
    fs::rename(pending_index, index);
    found = true;
  }
  // Undecided (or left over): the pending gaits go.
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 1 + 4 + std::string(kPendingSuffix).size() && name[0] == '.' &&
        name.compare(name.size() - std::string(kPendingSuffix).size(), std::string::npos,
                     kPendingSuffix) == 0 &&
        IsRegular(entry.path())) {
      fs::remove(entry.path());
      found = true;
    }
  }
  return found;
}

std::vector<std::string> AddGaitsToDatabase(const std::vector<GaitRecord>& gaits,
                                            const std::string& dir) {
  std::set<std::string> names;
  for (const GaitRecord& gait : gaits) {
    CheckField(dir, gait.name);
    CheckField(dir, gait.source);
    if (!names.insert(gait.name).second) {
      throw InputError(dir, 0, gait.name, "two gaits of this name in one write");
    }
  }
  FinishGaitCommit(dir);
  const fs::path root(dir);
  const std::string index_path = (root / kGaitIndexFile).string();
  // Read (and so validate) the index before writing anything.
  std::vector<GaitIndexEntry> entries;
  if (fs::exists(index_path)) entries = ReadGaitIndex(index_path);
  std::vector<std::string> paths;
  for (const GaitRecord& gait : gaits) {
    const std::string file = gait.name + ".csv";
    WriteGaitFile(gait, (root / PendingGaitFile(file)).string());
    paths.push_back((root / file).string());
    entries.erase(std::remove_if(entries.begin(), entries.end(),
                                 [&](const GaitIndexEntry& e) { return e.name == gait.name; }),
                  entries.end());
    entries.push_back({gait.name, file, gait.source, gait.target_v_m, gait.measured.v_m,
                       gait.measured.l_step, gait.measured.t_step, gait.measured.steps, gait.role,
                       gait.target_l_step});
  }
  std::sort(entries.begin(), entries.end(), [](const GaitIndexEntry& a, const GaitIndexEntry& b) {
    return std::make_tuple(a.role, a.target_v_m, a.target_l_step, a.name) <
           std::make_tuple(b.role, b.target_v_m, b.target_l_step, b.name);
  });
  TestKillPoint("gaits-add-staged");
  WriteGaitIndex(entries, (root / PendingGaitFile(kGaitIndexFile)).string());
  TestKillPoint("gaits-add-decided");
  for (size_t k = 0; k < gaits.size(); ++k) {
    fs::rename(root / PendingGaitFile(gaits[k].name + ".csv"), paths[k]);
    if (k == 0) TestKillPoint("gaits-add-renaming");
  }
  fs::rename(root / PendingGaitFile(kGaitIndexFile), index_path);
  TestKillPoint("gaits-add-done");
  return paths;
}

std::string AddGaitToDatabase(const GaitRecord& gait, const std::string& dir) {
  return AddGaitsToDatabase({gait}, dir).front();
}

}  // namespace rabbit
