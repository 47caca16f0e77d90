// Running a tuning job (`rabbit tune`): the optimizer's candidates are evaluated over the job's
// suites (every matching scenario's main variant; baselines are not run), in rounds:
//
//   - `starts` searches run side by side, each in its own thread (NLopt or Ceres drive it through
//     a callback); a round holds the next request of every search still running (Ceres asks for
//     a point and its forward differences at once), so the rounds, and therefore the results, are
//     the same whatever the number of threads or ranks;
//   - a round's runs (candidates x scenarios) are dealt over MPI ranks by index and over threads
//     within a rank (RunBatch), and gathered back in order;
//   - a job with guard suites runs their required scenarios for every candidate that beats its
//     search's best eligible objective so far (as it stood before the round, so the round's
//     guard runs go out as one batch); a candidate that fails one cannot be the best. The
//     searches still see its objective: a guard is a constraint on the result, not a term;
//   - every evaluation is appended to evaluations.csv (and its runs to runs.csv) as its round
//     finishes. --resume replays the recorded evaluations (keyed by search and request number, the
//     candidate checked bit for bit) and continues: the same result as an uninterrupted job.
//
// Output folder (default reports/<job name>/): evaluations.csv, runs.csv, best.toml (a parameter
// overlay for --params), comparison.csv (initial versus best, per scenario) and index.html.
// With --shard I/N the folder's shards/I-of-N/ gets the logs of searches s with s mod N = I - 1;
// a later --resume without --shard replays every shard's log and writes the result.
#ifndef RABBIT_OPTIMIZERS_TUNER_H_
#define RABBIT_OPTIMIZERS_TUNER_H_

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "rabbit/scenario/ranks.h"
#include "tune_job.h"

namespace rabbit {

// The objective of a candidate whose settings were invalid (e.g. a membership function's
// vertices out of order): worse than any evaluated one.
constexpr double kInvalidObjective = 1e6;

struct RunScore {
  std::string suite, scenario;
  bool passed = false;
  std::string outcome;
  std::array<double, kNumTuneTerms> value{};  // per term; NaN: the run has none (see missing)
};

struct Evaluation {
  int index = 0;  // evaluation number: log order (round by round, search by search)
  int round = 0;
  int start = 0;  // the search (0-based)
  int seq = 0;    // its request number
  std::vector<double> x;
  double objective = 0.0;
  std::array<double, kNumTuneTerms> terms{};  // per term: mean (or mean square) over the runs
  int runs = 0, failed = 0;
  std::string error;  // non-empty: invalid settings (objective kInvalidObjective, no runs)
  // Guards (a job with guard suites): whether they were run for this candidate (it beat its
  // search's best eligible objective so far), and the required guard scenarios it failed
  // ("suite/scenario", joined by "; "; or why the guards could not run). Empty: it kept them.
  bool guards_run = false;
  std::string guard_broken;
  std::vector<RunScore> scores;
  double wall = 0.0;  // s (not deterministic)
};

// Whether an evaluation may be the job's best: any, in a job without guards; else a valid one
// whose guards were run and kept.
bool EligibleAsBest(const TuneJob& job, const Evaluation& e);

struct TuneOptions {
  std::string out;  // output folder ("" : reports/<job name>)
  int threads = 0;  // per rank (0: all cores)
  bool resume = false;
  bool force = false;  // start afresh over an existing log
  Shard shard;
  bool quiet = false;
  bool html = true;
  std::string gnuplot = "gnuplot";  // for the report's figures
  // Called on rank 0 after every evaluation is logged (progress, tests).
  std::function<void(const Evaluation&)> on_evaluation;
};

struct TuneResult {
  std::vector<Evaluation> evaluations;  // in log order (this run's shard, or all)
  // Indices into evaluations (-1: not in this shard). best: the lowest objective among the
  // eligible ones (EligibleAsBest), the first of equals; -1 too when none is eligible.
  int initial = -1, best = -1;
  int replayed = 0;      // evaluations taken from the log, not run
  std::string out;       // the output folder
  bool complete = true;  // false for a shard (best.toml not written)
};

// Runs (or resumes) the job. Throws InputError for bad input (an existing log without --resume
// or --force, a log written by another job, a log that the job no longer reproduces).
TuneResult RunTune(const TuneJob& job, const TuneOptions& options);

// The terms and objective of a candidate from its runs' scores (missing values filled in).
void ScoreEvaluation(const TuneObjective& objective, Evaluation* e);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_TUNER_H_
