// Batch runs: every scenario of some suites with each of its variants, on a pool of threads.
// Each run is a pure function of its scenario (seeded), so results do not depend on the number of
// threads or on the order in which runs finish.
#ifndef RABBIT_SCENARIO_BATCH_H_
#define RABBIT_SCENARIO_BATCH_H_

#include <functional>
#include <string>
#include <vector>

#include "rabbit/scenario/run.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {

struct BatchJob {
  const Scenario* scenario = nullptr;
  std::string variant;
};

// The runs of a suite: each scenario whose name matches `filter` (ECMAScript regex, searched;
// empty = all), with its main variant then its baselines. Throws InputError for a bad regex.
std::vector<BatchJob> PlanBatch(const Suite& suite, const std::string& filter);

// Why std::regex must not be given `filter`, or "" when it may: a number in a back-reference or a
// {n,m} repeat above kMaxRegexNumber. libstdc++ reads those numbers with a signed overflow (found
// by fuzzing: the back-reference \4444444444444444444) and builds one state per repeat, so huge
// ones are undefined behaviour or exhaust memory; names of scenarios need neither.
constexpr long kMaxRegexNumber = 1000;
std::string RegexFilterProblem(const std::string& filter);

// Runs the jobs on `threads` threads (0: all cores). Loads each gait library once. For every
// finished run calls on_done(job index, run) from the worker thread that ran it, serialised by a
// mutex (so it may write files and print). Stops taking new jobs after an exception in a run or
// in on_done, and rethrows the first one once all threads have finished.
// `libraries` (may be null: a private cache) holds the gait libraries of walker scenarios.
void RunBatch(const std::vector<BatchJob>& jobs, int threads, GaitLibraryCache* libraries,
              const std::function<void(size_t, RunOutput&&)>& on_done);

// The threads RunBatch uses for these jobs when asked for `threads` (0: all cores).
int BatchThreads(const std::vector<BatchJob>& jobs, int threads);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_BATCH_H_
