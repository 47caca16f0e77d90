#include "rabbit/report/shards.h"

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <system_error>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/io/test_hooks.h"
#include "rabbit/report/comparison.h"
#include "rabbit/scenario/run_files.h"
#include "rabbit/scenario/suite.h"
#include "rabbit/scenario/suite_inputs.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

constexpr const char* kShardTag = "rabbit-shard/1";

std::string ReadBytes(const fs::path& path, const FileLimits& limits) {
  return ReadBoundedFile(path.string(), limits);
}

// FNV-1a (64 bits) over length-prefixed fields, so that no two sequences of fields collide by
// concatenation.
class Fingerprint {
 public:
  void Add(const std::string& field) {
    const std::string length = std::to_string(field.size()) + ":";
    Bytes(length);
    Bytes(field);
  }
  std::string Hex() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash_));
    return text;
  }

 private:
  void Bytes(const std::string& bytes) {
    for (unsigned char c : bytes) {
      hash_ ^= c;
      hash_ *= 0x100000001b3ULL;
    }
  }
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

// A count in a marker: digits only, within size_t.
bool ParseCount(const std::string& text, size_t* value) {
  if (text.empty() || text.size() > 15 ||
      text.find_first_not_of("0123456789") != std::string::npos) {
    return false;
  }
  *value = static_cast<size_t>(std::stoull(text));
  return true;
}

// A run's folder name as summary.csv gives it: one path component of our own making.
bool SafeFolder(const std::string& name) {
  return !name.empty() && name[0] != '.' && name.find('/') == std::string::npos &&
         name.find('\\') == std::string::npos;
}

InputError FolderError(const fs::path& path, const std::string& message) {
  return InputError(path.string(), 0, "", message);
}

// One shard folder found below DIR/shards, read and checked on its own.
struct FoundShard {
  fs::path folder;
  ShardInfo info;
  std::vector<std::pair<size_t, std::string>> rows;  // plan index, summary row (no job column)
  std::vector<std::string> runs;                     // their folders, same order
};

void ReadShardSummary(FoundShard* found) {
  const fs::path path = found->folder / "summary.csv";
  const std::string text = ReadBytes(path, kCsvTableLimits);
  const CsvTable table = CsvTable::Parse(text, path.string());
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  if (lines.empty() || lines[0] != ShardSummaryHeader()) {
    throw InputError(path.string(), 1, "", "not a shard's summary of this rabbit (header differs)");
  }
  if (lines.size() != table.num_rows() + 1) {
    throw FolderError(path, "malformed: a blank line or a cell over several lines");
  }
  const ShardInfo& info = found->info;
  if (table.num_rows() != info.runs) {
    throw FolderError(path, "has " + std::to_string(table.num_rows()) + " rows but its marker " +
                                "says runs = " + std::to_string(info.runs));
  }
  const size_t job_column = table.Column("job"), run_column = table.Column("run");
  for (size_t k = 0; k < table.num_rows(); ++k) {
    const int job = table.Integer(k, job_column);
    if (job < 0 || static_cast<size_t>(job) >= info.jobs || !info.shard.Owns(job)) {
      throw InputError(path.string(), table.line(k), "job",
                       "job " + std::to_string(job) + " is not one of shard " +
                           ShardFolderName(info.shard) + "'s (of " + std::to_string(info.jobs) +
                           " jobs)");
    }
    const std::string prefix = std::to_string(job) + ",";
    const std::string& line = lines[k + 1];
    if (line.compare(0, prefix.size(), prefix) != 0) {
      throw InputError(path.string(), table.line(k), "job", "not written as rabbit writes it");
    }
    const std::string run = table.Text(k, run_column);
    if (!SafeFolder(run))
      throw InputError(path.string(), table.line(k), "run", "not a folder name");
    if (!fs::is_directory(found->folder / run)) {
      throw InputError(path.string(), table.line(k), "run",
                       "the folder of run " + run + " is missing from " + found->folder.string());
    }
    found->rows.emplace_back(static_cast<size_t>(job), line.substr(prefix.size()));
    found->runs.push_back(run);
  }
}

// At most 10 names, then how many in all.
std::string ListSome(const std::vector<std::string>& names) {
  std::string out;
  for (size_t k = 0; k < names.size() && k < 10; ++k) out += (k == 0 ? "" : ", ") + names[k];
  if (names.size() > 10) out += ", ... (" + std::to_string(names.size()) + " in all)";
  return out;
}

// A copy of the folder `from` at `to` whose files are hard links to the originals (one more name,
// no bytes copied); copied where the file system cannot link.
void LinkTree(const fs::path& from, const fs::path& to) {
  std::error_code error;
  fs::copy(from, to, fs::copy_options::recursive | fs::copy_options::create_hard_links, error);
  if (!error) return;
  fs::remove_all(to);
  fs::copy(from, to, fs::copy_options::recursive);
}

}  // namespace

std::string ReportMarkerText(const std::string& suite) {
  return "rabbit-report/1 suite " + suite + "\n";
}

std::string ShardFolderName(const Shard& shard) {
  return std::to_string(shard.index) + "-of-" + std::to_string(shard.count);
}

std::string PlanFingerprint(const Suite& suite, const std::vector<BatchJob>& plan,
                            const std::string& params_path) {
  Fingerprint print;
  print.Add("rabbit-plan/1");
  print.Add(RABBIT_VERSION);
  print.Add(suite.name);
  print.Add(ReadBytes(suite.file, kTomlFileLimits));
  print.Add(params_path.empty() ? "" : ReadBytes(params_path, kTomlFileLimits));
  // Every file the suite reads, by content (not by path: shards may run from other folders).
  for (const InputFile& f : HashInputFiles(SuiteInputFiles(suite))) print.Add(f.sha256);
  print.Add(std::to_string(plan.size()));
  for (const BatchJob& job : plan) {
    print.Add(job.scenario->name);
    print.Add(job.variant);
  }
  return print.Hex();
}

std::string ShardMarkerText(const ShardInfo& info) {
  std::ostringstream out;
  out << kShardTag << "\nsuite = " << info.suite << "\nshard = " << info.shard.index << '/'
      << info.shard.count << "\nplan = " << info.plan << "\njobs = " << info.jobs
      << "\nruns = " << info.runs << "\nfailed_required = " << info.failed_required << "\n";
  return out.str();
}

ShardInfo ReadShardMarker(const std::string& path) {
  std::istringstream in(ReadBytes(path, kMarkerFileLimits));
  std::string line;
  if (!std::getline(in, line) || line != kShardTag) {
    throw InputError(path, 1, "", std::string("not a shard marker (expected ") + kShardTag + ")");
  }
  ShardInfo info;
  std::set<std::string> seen;
  for (int number = 2; std::getline(in, line); ++number) {
    const size_t equals = line.find(" = ");
    const std::string key = line.substr(0, equals),
                      value = equals == std::string::npos ? "" : line.substr(equals + 3);
    std::string error;
    size_t count = 0;
    bool ok = equals != std::string::npos && seen.insert(key).second;
    if (!ok) {
      throw InputError(path, number, key, "expected one \"key = value\" per key");
    } else if (key == "suite") {
      info.suite = value;
      ok = !value.empty();
    } else if (key == "shard") {
      ok = ParseShard(value, &info.shard, &error);
    } else if (key == "plan") {
      info.plan = value;
      ok = value.size() == 16 && value.find_first_not_of("0123456789abcdef") == std::string::npos;
    } else if (key == "jobs" || key == "runs" || key == "failed_required") {
      ok = ParseCount(value, &count);
      if (key == "jobs") info.jobs = count;
      if (key == "runs") info.runs = count;
      if (key == "failed_required") info.failed_required = static_cast<int>(count);
    } else {
      throw InputError(path, number, key, "unknown key");
    }
    if (!ok) throw InputError(path, number, key, "bad value \"" + value + "\"");
  }
  for (const char* key : {"suite", "shard", "plan", "jobs", "runs", "failed_required"}) {
    if (seen.count(key) == 0) throw InputError(path, 0, key, "missing");
  }
  return info;
}

std::string ShardSummaryHeader() { return "job," + SummaryHeader(); }

void CheckShardOutput(const std::string& dir, const Shard& shard) {
  const fs::path base(dir);
  if (fs::exists(base)) {
    if (!fs::is_directory(base)) throw InputError("--out", 0, dir, "exists and is not a folder");
    if (!fs::exists(base / kReportMarker)) {
      for (const fs::directory_entry& entry : fs::directory_iterator(base)) {
        if (entry.path().filename() != kShardsFolder) {
          throw InputError("--out", 0, dir,
                           std::string("exists and is neither a report of rabbit run (no ") +
                               kReportMarker +
                               ") nor a folder of shards: refusing to write into it");
        }
      }
    }
  }
  const fs::path shards = base / kShardsFolder;
  if (fs::exists(shards) && !fs::is_directory(shards)) {
    throw InputError("--out", 0, shards.string(), "exists and is not a folder");
  }
  const fs::path mine = shards / ShardFolderName(shard);
  if (fs::exists(mine) &&
      !(fs::is_directory(mine) && (fs::is_empty(mine) || fs::exists(mine / kShardMarker)))) {
    throw InputError("--out", 0, mine.string(),
                     std::string("exists and is not a shard of rabbit run (no ") + kShardMarker +
                         "): refusing to replace it");
  }
}

bool HasShards(const std::string& dir) { return fs::is_directory(fs::path(dir) / kShardsFolder); }

fs::path MergeStagingFolder(const std::string& dir) {
  fs::path base = fs::path(dir).lexically_normal();
  if (base.filename().empty()) base = base.parent_path();
  return base.string() + ".merging";
}

void ClearMergeStaging(const std::string& dir) {
  const fs::path staging = MergeStagingFolder(dir);
  std::error_code error;
  const fs::file_status status = fs::symlink_status(staging, error);
  if (!fs::exists(status)) return;
  if (fs::is_directory(status) &&
      (fs::is_empty(staging, error) || HasMarker(staging, {kReportMarker}))) {
    RemoveOwnedFolder(staging);  // a killed merge's (its runs are still in the shards)
    return;
  }
  throw InputError(staging.string(), 0, "",
                   std::string("exists and is not a merge of rabbit report (no ") + kReportMarker +
                       "): refusing to touch it; remove it yourself to merge " + dir);
}

MergedShards MergeShards(const std::string& dir_text,
                         const std::function<void(const std::string& staging)>& finish) {
  fs::path dir = fs::path(dir_text).lexically_normal();
  if (dir.filename().empty()) dir = dir.parent_path();  // "dir/" -> "dir"
  if (dir.empty() || dir == "." || dir == ".." || dir.filename() == "..") {
    throw InputError(dir_text, 0, "", "name the report folder (not . or ..) to merge its shards");
  }
  const fs::path shards = dir / kShardsFolder;
  MergedShards merged;

  // DIR is replaced: it may hold an earlier report, or nothing but the shards.
  if (!fs::exists(dir / kReportMarker)) {
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
      if (entry.path().filename() != kShardsFolder) {
        throw FolderError(dir, "holds " + entry.path().filename().string() +
                                   " besides shards/ and is not a report of rabbit run (no " +
                                   kReportMarker + "): refusing to replace it");
      }
    }
  }
  // The shard folders, and nothing else.
  const std::regex shard_name("([0-9]+)-of-([0-9]+)");
  std::vector<FoundShard> found;
  std::vector<fs::path> entries;
  for (const fs::directory_entry& entry : fs::directory_iterator(shards)) {
    entries.push_back(entry.path());
  }
  std::sort(entries.begin(), entries.end());
  for (const fs::path& path : entries) {
    const std::string name = path.filename().string();
    std::smatch match;
    Shard shard;
    std::string error;
    if (!std::regex_match(name, match, shard_name) || !fs::is_directory(path) ||
        !ParseShard(match[1].str() + "/" + match[2].str(), &shard, &error)) {
      throw FolderError(path, "not a shard folder (I-of-N): remove it to merge");
    }
    if (!fs::exists(path / kShardMarker)) {
      throw FolderError(path, std::string("not a shard of rabbit run (no ") + kShardMarker + ")");
    }
    FoundShard f;
    f.folder = path;
    f.info = ReadShardMarker((path / kShardMarker).string());
    if (f.info.shard.index != shard.index || f.info.shard.count != shard.count) {
      throw FolderError(path, "its marker names shard " + ShardFolderName(f.info.shard));
    }
    found.push_back(std::move(f));
  }
  if (found.empty()) throw FolderError(shards, "holds no shard (I-of-N folders)");

  // One N, one suite, one plan: otherwise the shards are not parts of one run.
  std::map<int, std::vector<std::string>> by_count;
  for (const FoundShard& f : found) {
    by_count[f.info.shard.count].push_back(ShardFolderName(f.info.shard));
  }
  if (by_count.size() > 1) {
    std::string counts;
    for (const auto& [n, names] : by_count) {
      counts += (counts.empty() ? "" : "; ") + std::to_string(n) + ": " + ListSome(names);
    }
    throw FolderError(shards, "holds shards of different counts N (" + counts +
                                  "): remove the ones that do not belong to this run");
  }
  const ShardInfo& first = found.front().info;
  for (const FoundShard& f : found) {
    const std::string name = ShardFolderName(f.info.shard);
    const std::string other = ShardFolderName(first.shard);
    if (f.info.suite != first.suite) {
      throw FolderError(f.folder, "is a shard of suite " + f.info.suite + ", " + other +
                                      " of suite " + first.suite);
    }
    if (f.info.plan != first.plan || f.info.jobs != first.jobs) {
      throw FolderError(f.folder, "was run with another plan (fingerprint " + f.info.plan + ", " +
                                      std::to_string(f.info.jobs) + " jobs) than " + other + " (" +
                                      first.plan + ", " + std::to_string(first.jobs) +
                                      " jobs): the suite, its input files, --filter or --params "
                                      "differed; run the odd shards again");
    }
  }
  const int count = first.shard.count;
  std::vector<bool> present(static_cast<size_t>(count) + 1, false);
  for (const FoundShard& f : found) present[static_cast<size_t>(f.info.shard.index)] = true;
  std::vector<std::string> missing;
  for (int i = 1; i <= count; ++i) {
    if (!present[static_cast<size_t>(i)]) missing.push_back(ShardFolderName({i, count}));
  }
  if (!missing.empty()) {
    throw FolderError(
        shards, "missing shard(s) " + ListSome(missing) + " (N = " + std::to_string(count) +
                    "): run each with rabbit run --shard I/" + std::to_string(count) + " --out " +
                    dir.string() + " and the same suite, --filter and --params");
  }

  // Every job's row exactly once, with its folder.
  std::vector<const std::string*> rows(first.jobs, nullptr);
  std::set<std::string> runs;
  for (FoundShard& f : found) {
    ReadShardSummary(&f);
    for (size_t k = 0; k < f.rows.size(); ++k) {
      if (rows[f.rows[k].first] != nullptr || !runs.insert(f.runs[k]).second) {
        throw FolderError(f.folder / "summary.csv", "job " + std::to_string(f.rows[k].first) +
                                                        " (run " + f.runs[k] + ") is listed twice");
      }
      rows[f.rows[k].first] = &f.rows[k].second;
    }
    merged.runs += f.rows.size();
    merged.failed_required += f.info.failed_required;
  }
  for (size_t j = 0; j < rows.size(); ++j) {
    if (rows[j] == nullptr) {
      throw FolderError(shards, "job " + std::to_string(j) + " of the plan is in no shard");
    }
  }

  // Valid: build the merged report beside DIR, then put it in DIR's place. The shards are not
  // changed until that swap: the run folders are linked (or copied) into the staging folder, so
  // a kill at any moment before it leaves them whole, and the next merge starts again. The staging
  // folder carries the report marker from its first file on, and so does DIR before the swap (the
  // old content, at the staging path after the swap, is then recognised while it is removed).
  const fs::path staging = MergeStagingFolder(dir.string());
  ClearMergeStaging(dir.string());
  try {
    fs::create_directories(staging);
    WriteFileAtomically((staging / kReportMarker).string(),
                        [&](std::ostream& out) { out << ReportMarkerText(first.suite); });
    TestKillPoint("report-merge-staging");
    WriteFileAtomically((staging / "summary.csv").string(), [&](std::ostream& out) {
      out << SummaryHeader() << "\n";
      for (const std::string* row : rows) out << *row << "\n";
    });
    // The suite's success targets, the same in every shard.
    if (fs::exists(found.front().folder / kTargetsFile)) {
      fs::copy_file(found.front().folder / kTargetsFile, staging / kTargetsFile);
    }
    // So are the family members' draws.
    if (fs::exists(found.front().folder / kMembersFile)) {
      fs::copy_file(found.front().folder / kMembersFile, staging / kMembersFile);
    }
    bool first_run = true;
    for (const FoundShard& f : found) {
      for (const std::string& run : f.runs) {
        LinkTree(f.folder / run, staging / run);
        if (first_run) TestKillPoint("report-merge-linking");
        first_run = false;
      }
    }
    TestKillPoint("report-merge-linked");
    finish(staging.string());
    TestKillPoint("report-merge-written");
    if (!fs::exists(dir / kReportMarker)) {
      WriteFileAtomically((dir / kReportMarker).string(),
                          [&](std::ostream& out) { out << ReportMarkerText(first.suite); });
    }
  } catch (...) {
    try {
      RemoveOwnedFolder(staging);
    } catch (const std::exception&) {  // the first error is the one to report
    }
    throw;
  }
  // In DIR's place in one step; what is left of DIR (shards/ with their markers and summaries, an
  // earlier report) goes, its report marker last.
  ReplaceFolder(staging, dir);
  WriteInventory(dir);
  TestKillPoint("report-merge-replaced");
  merged.suite = first.suite;
  merged.count = count;
  return merged;
}

}  // namespace rabbit
