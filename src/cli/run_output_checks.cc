#include "cli/run_output_checks.h"

#include <string>

#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/report/shards.h"

namespace rabbit::cli {

namespace fs = std::filesystem;

namespace {
constexpr const char* kLegacyStagingLock = ".lock";  // the lock's place in earlier versions
}  // namespace

void CheckReportOutput(const fs::path& out) {
  // The path itself, not what a symbolic link there points to: the swap at the end would replace
  // the link, which rabbit did not make.
  CheckOutputParents("--out", out);
  const fs::file_status status = fs::symlink_status(out);
  if (!fs::exists(status)) return;
  if (const std::string link = SymbolicLinkRefusal(out, "a report of rabbit run"); !link.empty()) {
    throw InputError("--out", 0, out.string(), link);
  }
  if (fs::is_directory(status) && fs::is_empty(out)) return;
  if (fs::is_directory(status) && fs::exists(out / kReportMarker)) {
    CheckInventory("--out", out);  // a file added to the report is not rabbit's to delete
    return;
  }
  if (fs::is_directory(status) && fs::is_directory(out / kShardsFolder)) {
    throw InputError("--out", 0, out.string(),
                     "holds the shards of a sharded run: merge them with rabbit report " +
                         out.string() + ", or remove " + (out / kShardsFolder).string());
  }
  throw InputError("--out", 0, out.string(),
                   std::string("exists and is not a report of rabbit run (no ") + kReportMarker +
                       "): refusing to replace it");
}

void CheckStagingOutput(const fs::path& staging) {
  if (fs::is_directory(staging)) {
    bool only_lock = true;
    for (const fs::directory_entry& e : fs::directory_iterator(staging)) {
      only_lock = only_lock && e.path().filename() == kLegacyStagingLock;
    }
    if (only_lock) return;
  }
  CheckOwnedFolder("--out", staging, {kStagingMarker, kReportMarker, kShardMarker},
                   "a staging folder of rabbit run");
}

}  // namespace rabbit::cli
