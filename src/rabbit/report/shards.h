// Sharded runs (`rabbit run --shard I/N`, for array jobs on batch schedulers without MPI) and
// their merge (`rabbit report DIR`). Shard I of N of a suite whose report folder is DIR runs the
// jobs j of the plan (0-based, in plan order) with j mod N = I - 1, and writes only
// DIR/shards/I-of-N/:
//   .rabbit-shard  the marker: "rabbit-shard/1", then "key = value" lines: suite, shard (I/N),
//                  plan (the plan's fingerprint), jobs (the plan's), runs (this shard's),
//                  failed_required (its required main-variant runs that failed their criteria)
//   summary.csv    "job," and the summary header, then per run its plan index and its row
//   <run>/         each run's folder, as in a report
// It is built in a staging folder beside DIR (DIR.shard-I-of-N.partial, locked
// while a process writes it; rabbit run --resume continues a killed one) and renamed into
// place, so shards run at the same time, or one killed, leave the others' folders alone.
// Merging checks that DIR/shards holds exactly the shards 1..N of one N, of one suite and plan,
// each with a row and a folder for every job it owns, then makes DIR the report an unsharded run
// would have written: summary.csv in plan order, the run folders, the report marker (and the
// page, which the caller writes); shards/ is gone.
#ifndef RABBIT_REPORT_SHARDS_H_
#define RABBIT_REPORT_SHARDS_H_

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/ranks.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {

// Written into every report folder: only such folders (or empty ones) are ever replaced.
constexpr const char* kReportMarker = ".rabbit-report";
constexpr const char* kShardMarker = ".rabbit-shard";
constexpr const char* kShardsFolder = "shards";

// The report marker's text for a suite.
std::string ReportMarkerText(const std::string& suite);

// "I-of-N": the shard's folder below DIR/shards.
std::string ShardFolderName(const Shard& shard);

// 16 hex digits hashing what decides a plan's runs: the program's version, the suite's name and
// file (its bytes, wherever it lies), the parameter overlay's bytes (empty path: none) and the
// runs in plan order, and the content of every file the suite reads (SuiteInputFiles: model,
// FLL, networks, gaits). Shards merge, and runs resume, only with equal fingerprints.
std::string PlanFingerprint(const Suite& suite, const std::vector<BatchJob>& plan,
                            const std::string& params_path);

struct ShardInfo {
  std::string suite;
  Shard shard;
  std::string plan;  // PlanFingerprint
  size_t jobs = 0;   // in the plan
  size_t runs = 0;   // in this shard
  int failed_required = 0;
};
std::string ShardMarkerText(const ShardInfo& info);
// Throws InputError (file, line, key) for a missing or malformed marker.
ShardInfo ReadShardMarker(const std::string& path);

// The shard's summary.csv header: "job," + SummaryHeader().
std::string ShardSummaryHeader();

// Throws InputError unless DIR/shards/I-of-N may be written: DIR missing, or a folder that is
// empty, a report (has the marker) or holds only shards/; the shard's folder missing, empty or a
// shard (has its marker). Other shards' folders are not looked at.
void CheckShardOutput(const std::string& dir, const Shard& shard);

// Whether DIR/shards exists (rabbit report then merges).
bool HasShards(const std::string& dir);

// The staging folder of a merge: DIR.merging beside DIR.
std::filesystem::path MergeStagingFolder(const std::string& dir);
// Removes a merge's staging folder that a killed merge left (marked with kReportMarker, or
// empty); throws InputError, nothing touched, when something else is at that path. The caller
// holds DIR's lock.
void ClearMergeStaging(const std::string& dir);

struct MergedShards {
  std::string suite;
  int count = 0;  // N
  size_t runs = 0;
  int failed_required = 0;
};

// Validates DIR/shards, changing nothing and throwing InputError naming what is missing or
// inconsistent (a shard absent, another N, another suite or plan, a row or folder missing, DIR
// holding anything but shards/ while not a report). Then builds the merged report in a staging
// folder beside DIR (MergeStagingFolder: the marker, summary.csv in plan order, the run folders
// linked in, then finish(staging), e.g. the page) and replaces DIR with it in one step. The
// shards are untouched until that step, so a failure or a kill before it loses nothing: the next
// merge removes the staging folder (ClearMergeStaging) and starts again. Test kill points:
// report-merge-staging, -linking, -linked, -written, -replaced.
MergedShards MergeShards(const std::string& dir,
                         const std::function<void(const std::string& staging)>& finish);

}  // namespace rabbit

#endif  // RABBIT_REPORT_SHARDS_H_
