// The guard suites of a tuning job (rabbit tune, `guards = [...]`): the required scenarios a
// candidate must keep passing to be eligible as the job's best. A candidate's guard runs are the
// main variant of every required scenario of every guard suite, under the candidate's overlay
// (the one best.toml would hold), dealt over ranks and threads as the job's own runs.
#ifndef RABBIT_OPTIMIZERS_TUNE_GUARDS_H_
#define RABBIT_OPTIMIZERS_TUNE_GUARDS_H_

#include <string>
#include <vector>

#include "tune_evaluator.h"
#include "tune_job.h"

namespace rabbit::tune_internal {

class GuardRunner {
 public:
  GuardRunner(const TuneJob& job, int threads)
      : evaluator_(job, job.guards, "", /*required_only=*/true, threads) {}

  // Runs the guards of the candidates (on every rank, collectively). Per candidate: the required
  // guard scenarios it failed, as "suite/scenario" joined by "; " in suite order, or why the
  // guard suites could not be read under its overlay; empty when it kept them all.
  std::vector<std::string> Check(const std::vector<std::vector<double>>& xs);

 private:
  Evaluator evaluator_;
};

}  // namespace rabbit::tune_internal

#endif  // RABBIT_OPTIMIZERS_TUNE_GUARDS_H_
