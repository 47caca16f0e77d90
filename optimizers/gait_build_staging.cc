#include "gait_build_staging.h"

#include <exception>
#include <vector>

#include "rabbit/gait/database_layout.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/io/sha256.h"
#include "rabbit/io/test_hooks.h"
#include "rabbit/scenario/ranks.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit {
namespace fs = std::filesystem;
namespace {

// In the staging folder until its manifest is written.
constexpr const char* kSynthesizedFile = "synthesized.csv";
constexpr const char* kSynthesizedFormat = "# format = rabbit-gait-synthesized/1\n";
constexpr const char* kSynthesizedColumns = "name,inputs_sha256,sha256";

// The gaits an incomplete staging folder's list names whose files are there with their hashes.
// The list is the build's own scratch: a row or file that does not agree is skipped (its gait is
// synthesized again), and a list that cannot be read is ignored, never an error.
std::map<std::string, SynthesizedGait> ReadSynthesizedList(const fs::path& staging) {
  std::map<std::string, SynthesizedGait> gaits;
  const fs::path list = staging / kSynthesizedFile;
  if (!fs::exists(list)) return gaits;
  try {
    const std::string text = ReadBoundedFile(list.string(), kGaitFileLimits);
    if (text.rfind(kSynthesizedFormat, 0) != 0) return gaits;
    const CsvTable t =
        CsvTable::Parse(text.substr(std::string(kSynthesizedFormat).size()), list.string());
    if (t.header() != std::vector<std::string>{"name", "inputs_sha256", "sha256"}) return gaits;
    for (size_t r = 0; r < t.num_rows(); ++r) {
      const std::string name = t.Text(r, 0), inputs = t.Text(r, 1), sha = t.Text(r, 2);
      // A gait's name as the targets allow it, so the names travel to the other ranks intact.
      if (!IsSafeName(name) || !IsHex64(inputs)) continue;
      const fs::path file = staging / kReferenceDir / (name + ".csv");
      if (!fs::exists(file)) continue;
      std::string gait = ReadBoundedFile(file.string(), kGaitFileLimits);
      if (Sha256Hex(gait) != sha) continue;
      gaits[name] = {inputs, std::move(gait)};
    }
  } catch (const std::exception&) {
    gaits.clear();  // an unreadable list: every gait is synthesized again
  }
  return gaits;
}

}  // namespace

void CommitStaging(const fs::path& out, const std::set<std::string>& old_files) {
  const fs::path staging = out / kStagingDir;
  const Manifest fresh = ReadManifest((staging / kManifestFile).string());
  std::set<std::string> now;
  for (const ManifestRow& r : fresh.rows) {
    now.insert(r.file);
    const fs::path from = staging / r.file;
    if (!fs::exists(from)) continue;  // moved by an interrupted commit already
    fs::create_directories((out / r.file).parent_path());
    fs::rename(from, out / r.file);
    TestKillPoint("gaits-build-swapping");
  }
  for (const std::string& f : old_files) {
    if (now.count(f) == 0) fs::remove(out / f);
  }
  fs::rename(staging / kManifestFile, out / kManifestFile);
  fs::remove_all(staging);
}

bool InspectOut(const fs::path& out, Manifest* manifest,
                std::map<std::string, SynthesizedGait>* synthesized) {
  const fs::path staging = out / kStagingDir;
  if (fs::exists(staging / kManifestFile) && Ranks::root()) {
    std::set<std::string> old_files;
    if (fs::exists(out / kManifestFile)) {
      for (const ManifestRow& r : ReadManifest((out / kManifestFile).string()).rows) {
        old_files.insert(r.file);
      }
    }
    CommitStaging(out, old_files);
  }
  if (fs::exists(staging) && Ranks::root()) {
    // An incomplete staging folder of an interrupted build: dropped when the folder is a database
    // or holds nothing else (else it is not ours, and the folder is refused below).
    bool alone = true;
    for (const fs::directory_entry& e : fs::directory_iterator(out)) {
      alone = alone && e.path().filename() == kStagingDir;
    }
    if (alone || fs::exists(out / kManifestFile)) {
      *synthesized = ReadSynthesizedList(staging);
      fs::remove_all(staging);
    }
  }
  if (!fs::exists(out)) return false;
  if (!fs::is_directory(out)) {
    throw InputError(out.string(), 0, "--out", "exists and is not a folder: nothing written");
  }
  const fs::path manifest_path = out / kManifestFile;
  if (!fs::exists(manifest_path)) {
    for (const fs::directory_entry& e : fs::directory_iterator(out)) {
      if (e.path().filename() == kStagingDir) continue;
      throw InputError(out.string(), 0, "--out",
                       "neither empty nor a gait database (no manifest.csv): nothing written");
    }
    return false;
  }
  *manifest = ReadManifest(manifest_path.string());
  VerifyManifest(*manifest, out.string(), manifest_path.string());
  // The index must list exactly the manifest's gaits.
  const std::string index_path = (out / kReferenceDir / kIndexFile).string();
  std::set<std::string> gaits, listed;
  for (const ManifestRow& r : manifest->rows) {
    if (r.kind == "gait") gaits.insert(r.name);
  }
  if (fs::exists(index_path)) {
    for (const GaitIndexEntry& e : ReadGaitIndex(index_path)) listed.insert(e.name);
  }
  if (gaits != listed) {
    throw InputError(index_path, 0, "",
                     "the gait index and the manifest list different gaits: nothing written");
  }
  return true;
}

void WriteSynthesizedList(const fs::path& staging,
                          const std::map<std::string, SynthesizedGait>& gaits) {
  WriteFileAtomically((staging / kSynthesizedFile).string(), [&gaits](std::ostream& out) {
    out << kSynthesizedFormat << kSynthesizedColumns << "\n";
    for (const auto& [name, gait] : gaits) {
      out << name << "," << gait.inputs_sha256 << "," << Sha256Hex(gait.text) << "\n";
    }
  });
}

void RemoveSynthesizedList(const fs::path& staging) { fs::remove(staging / kSynthesizedFile); }

}  // namespace rabbit
