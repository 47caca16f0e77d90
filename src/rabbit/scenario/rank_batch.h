// A batch run dealt over the ranks of a distributed job (rabbit/scenario/ranks.h), with every run's
// files gathered into rank 0's report folder. The jobs are dealt as the ranks' threads become
// free (a counter shared by the ranks hands out the next job index), so a rank that drew long runs
// takes fewer; which rank ran a job changes nothing in its files. Rank 0 creates the report folder
// and writes its own runs' folders into it as they finish. Another rank that sees that folder
// (the ranks of one machine, or of a shared file system: rank 0 writes a random token into it and
// the rank reads it back) writes its runs' folders into it too; a rank that does not (or every
// rank, with RABBIT_RANK_FILES=transfer) writes them into a private temporary folder (so that its
// memory does not grow with the suite), sends them to rank 0 in pieces of bounded size once every
// rank has finished, and removes it. Whatever the rank, each run's folder gets its completion
// marker (kRunMarker) last, so a folder without one is a run cut short (rabbit run --resume runs
// it again; it removes the markers once the report is complete). In one process this is RunBatch
// writing the folders.
#ifndef RABBIT_SCENARIO_RANK_BATCH_H_
#define RABBIT_SCENARIO_RANK_BATCH_H_

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/run.h"

namespace rabbit {

// What rank 0 needs of a run once its files are written: the summary row, and what the console
// table and the exit code use.
struct RunBrief {
  size_t job = 0;           // index into the jobs given
  std::string run;          // its name, which is its folder's
  std::string summary_row;  // SummaryRow(suite, run)
  Outcome outcome = Outcome::kCompleted;
  bool passed = true;
  std::vector<std::string> failures;
  RunMetrics metrics;
  double simulated = 0.0;  // s (the run's t_end)
};

// The last file of every run's folder: a CSV of the summary header and the run's row, from which
// its brief is rebuilt without running it again (rabbit run --resume).
constexpr const char* kRunMarker = ".rabbit-run";

// The brief of a finished run from its folder's marker (job left 0). Throws InputError naming the
// file when it is missing or malformed.
RunBrief ReadRunMarker(const std::string& path);

struct RankBatchResult {
  std::vector<RunBrief> runs;  // rank 0: every job's, in job order; other ranks: none
  int threads = 1;             // the threads this rank ran on
};

// A collective: every rank passes the same jobs. Rank 0 creates `dir` and ends with every run's
// folder in it. `threads` is per rank (0: all cores). on_local_done is called for each of this
// rank's own runs as it finishes (from its worker thread, serialised; may be empty), e.g. for
// progress. When a run, a write or the transfer failed on any rank, throws on every rank
// (RunAgreed): the caller's collectives stay in step. RABBIT_RANK_FILES other than "auto" (the
// default) or "transfer" is an InputError on every rank.
RankBatchResult RunBatchOverRanks(const std::vector<BatchJob>& jobs, const std::string& suite,
                                  int threads, GaitLibraryCache* libraries, const std::string& dir,
                                  const std::function<void(const RunBrief&)>& on_local_done);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_RANK_BATCH_H_
