// Batch runs: every scenario of some suites with each of its variants, on a pool of threads.
// Each run is a pure function of its scenario (seeded), so results do not depend on the number of
// threads or on the order in which runs finish.
#ifndef RABBIT_SCENARIO_BATCH_H_
#define RABBIT_SCENARIO_BATCH_H_

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "rabbit/scenario/run.h"
#include "rabbit/scenario/suite.h"

namespace re2 {
class RE2;
}  // namespace re2

namespace rabbit {

struct BatchJob {
  const Scenario* scenario = nullptr;
  std::string variant;
};

// A filter of scenario names (--filter, a tuning job's `filter`): a regular expression in RE2's
// syntax (https://github.com/google/re2/wiki/Syntax), searched anywhere in the name, as
// ECMAScript's regex_search would; RE2 matches in time linear in the name, whatever the pattern.
// It has no back-references (\1) and no look-around ((?=...), (?!...)); repeats {n,m} go up to
// 1000. An empty pattern matches every name.
class NameFilter {
 public:
  NameFilter() = default;
  // Throws InputError(where, 0, key, ...) when `pattern` is not a valid RE2 expression.
  NameFilter(const std::string& pattern, const std::string& where, const std::string& key);
  bool Matches(const std::string& name) const;

 private:
  std::shared_ptr<const re2::RE2> re_;  // null: match everything
};

// Why `filter` is not a usable name filter (RE2's own message), or "" when it is.
std::string RegexFilterProblem(const std::string& filter);

// The runs of a suite: each scenario whose name matches `filter` (a NameFilter; empty = all), with
// its main variant then its baselines. Throws InputError naming --filter for a bad pattern.
std::vector<BatchJob> PlanBatch(const Suite& suite, const std::string& filter);

// Runs the jobs on `threads` threads (0: all cores). Loads each gait library once. For every
// finished run calls on_done(job index, run) from the worker thread that ran it, serialised by a
// mutex (so it may write files and print). Stops taking new jobs after an exception in a run or
// in on_done, and rethrows the first one once all threads have finished.
// `libraries` (may be null: a private cache) holds the gait libraries of walker scenarios.
void RunBatch(const std::vector<BatchJob>& jobs, int threads, GaitLibraryCache* libraries,
              const std::function<void(size_t, RunOutput&&)>& on_done);

// Whether the job's run needs a trained multi_cmac pattern (its variant is the multi_cmac
// baseline): the one run of a batch with a start-up cost of seconds, trained once per process.
bool NeedsTrainedPattern(const BatchJob& job);

// The order in which RunBatch (and the ranks' dealing) starts the jobs: the first job that needs a
// trained multi_cmac pattern first, so that its training starts at once, then every job that needs
// none, then the other multi_cmac jobs: the other threads walk while one trains, instead of waiting
// for the pattern. Results do not depend on it (each run is a pure function of its scenario).
std::vector<size_t> ExecutionOrder(const std::vector<BatchJob>& jobs);

// The threads RunBatch uses for these jobs when asked for `threads` (0: all cores).
int BatchThreads(const std::vector<BatchJob>& jobs, int threads);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_BATCH_H_
