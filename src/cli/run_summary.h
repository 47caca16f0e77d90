// What `rabbit run` prints about a suite's runs: the table (every plain scenario's run; for a
// family, its failed main runs and one line with its success rate and its baselines'), its
// legend, and the closing verdict over every suite of the invocation.
#ifndef RABBIT_CLI_RUN_SUMMARY_H_
#define RABBIT_CLI_RUN_SUMMARY_H_

#include <cstdio>
#include <string>
#include <vector>

#include "rabbit/scenario/rank_batch.h"
#include "rabbit/scenario/batch.h"

namespace rabbit::cli {

// A family's tally of one variant.
struct FamilyTally {
  std::string suite, family, variant;  // variant "" for the main one
  int runs = 0, passed = 0;
};

// The tally of an invocation: main-variant runs of required and optional scenarios (a baseline's
// runs are comparisons: counted apart), and every family's variants.
struct RunTally {
  int required_passed = 0, required_failed = 0;
  int optional_passed = 0, optional_failed = 0;
  int baseline_passed = 0, baseline_failed = 0;
  std::vector<FamilyTally> families;
};

// Adds a suite's runs (runs[k] is jobs[k]'s) to *tally.
void TallyRuns(const std::string& suite, const std::vector<BatchJob>& jobs,
               const std::vector<RunBrief>& runs, RunTally* tally);

// Adds `from` to *into (the families of several suites side by side).
void TallyMerge(const RunTally& from, RunTally* into);

// Prints the table of a suite's runs and its legend. Without `verbose`, a family's passed runs and
// its baselines' runs are left out (its summary lines count them), and at most
// kFamilyFailuresShown of its failed runs are listed, without the reasons.
constexpr int kFamilyFailuresShown = 10;
void PrintRunTable(std::FILE* out, const std::string& suite, const std::vector<BatchJob>& jobs,
                   const std::vector<RunBrief>& runs, bool verbose);

// The closing verdict, one line, e.g. "verdict    FAILED: required 41/43 passed (2 failed);
// optional 3/5 passed; family obstacle_anywhere 12/20 (95% CI 39-78%)".
std::string VerdictLine(const RunTally& tally);

}  // namespace rabbit::cli

#endif  // RABBIT_CLI_RUN_SUMMARY_H_
