// Tuning jobs (`rabbit tune JOB.toml`): which settings to tune, within which bounds, to minimise
// which weighted terms over which scenario suites, with which algorithm and budget. See
// docs/formats/tune-job.md for the file format; LoadTuneJob validates everything before anything
// runs.
//
//   [job]        name, description, suites = [...] (relative to the job file), guards = [...]
//                (suites whose required scenarios the best must keep passing), filter (regex on
//                scenario names), params (a base overlay under the tuned values), algorithm,
//                max_evaluations, seed, starts, initial_step, population, xtol_rel, ftol_rel
//   [objective]  weights of the terms (TuneTerm), form = "mean" | "mean_square", missing.<term>
//   [[parameter]] path (a scenario key path, as in a parameter overlay, or an array of them that
//                take the same value), name, lower, upper, initial
//   [ceres]      fd_step, max_iterations, function_tolerance
#ifndef RABBIT_OPTIMIZERS_TUNE_JOB_H_
#define RABBIT_OPTIMIZERS_TUNE_JOB_H_

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "rabbit/scenario/params.h"
#include "rabbit/scenario/suite_inputs.h"

namespace rabbit {

// The terms of an objective, per run (main variant of each scenario; baselines are not run).
enum TuneTerm {
  kFailureRate,       // 1 when the run failed its pass criteria (a fall included), else 0
  kSpeedError,        // m/s, mean |V_M - V_d| over the run's measured steps
  kStepLengthSpread,  // m, L_step max - min over the criteria's last spread_steps steps
  kEnergy,            // J, positive actuator work
  kCostOfTransport,   // energy / (m g distance)
  kSaturationTime,    // s, summed over the joints
  kIncompleteRate,    // 1 when the run did not complete (fell, tripped, stalled, ...), else 0
  kNumTuneTerms
};
// "failure_rate", "speed_error", "step_length_spread", "energy", "cost_of_transport",
// "saturation_time", "incomplete_rate": the keys of [objective] and the columns of
// evaluations.csv.
const char* TuneTermName(int term);

struct TuneParameter {
  std::string path;  // scenario key path (see params.h): the first of `paths`
  // Every key path the value goes to (tied settings, e.g. a breakpoint two fuzzy sets share).
  std::vector<std::string> paths;
  std::string name;  // column name in the CSV files: `name`, else the path
  double lower = 0.0, upper = 0.0;
  double initial = 0.0;  // the job's `initial`, else the suites' current value
  int line = 0;          // of its [[parameter]] in the job file
};

struct TuneObjective {
  std::array<double, kNumTuneTerms> weight{};  // >= 0; at least one > 0
  // A run without a value for a term (e.g. no measured step: no speed error) counts this value.
  std::array<double, kNumTuneTerms> missing{};
  bool squares = false;  // form = "mean_square": each term is the mean of its squared values
};

enum class TuneAlgorithm {
  kBobyqa,
  kSbplx,
  kCobyla,
  kNelderMead,  // NLopt, local, derivative-free
  kCrs2,
  kIsres,
  kEsch,
  kDirect,
  kDirectL,  // NLopt, global
  kCeres     // Ceres, least squares, numeric derivatives
};
const char* TuneAlgorithmName(TuneAlgorithm a);
bool IsGlobal(TuneAlgorithm a);

struct TuneJob {
  std::string file;  // the job file
  std::string name, description;
  std::vector<std::string> suites;  // paths, resolved against the job file's directory
  // Guard suites (paths, resolved likewise): a candidate that fails a required scenario of one
  // (main variant, under the candidate's overlay) cannot be the job's best.
  std::vector<std::string> guards;
  std::string filter;
  ParamOverlay base;  // the job's `params` overlay (may be empty), under the tuned values
  std::vector<TuneParameter> parameters;
  TuneObjective objective;
  TuneAlgorithm algorithm = TuneAlgorithm::kBobyqa;
  int max_evaluations = 40;  // candidate evaluations, over all starts, the initial point included
  std::uint64_t seed = 1;
  int starts = 1;  // independent searches run side by side (start 1 at the initial point)
  double initial_step = 0.1;  // local algorithms' first step, a fraction of each range
  int population = 0;         // NLopt's population of CRS2, ISRES, ESCH (0: NLopt's default)
  double xtol_rel = 1e-4, ftol_rel = 0.0;
  // Ceres: forward-difference step (a fraction of each range), iterations, tolerance.
  double fd_step = 0.02;
  int ceres_iterations = 50;
  double function_tolerance = 1e-6;
  std::string fingerprint;  // a hash of the job, its suites, guards and overlays: resume checks it
  std::vector<InputFile> inputs;  // every file the suites read, by content (in the fingerprint)

  // The overlay of a candidate: the base overlay, then the parameters at x.
  ParamOverlay Overlay(const std::vector<double>& x) const;
};

// Reads and validates a job: bounds, algorithm, weights, and every parameter path against every
// scenario of the suites (it must name a numeric setting of each; its current value is the
// default initial value, which must then be the same in every scenario). Throws InputError naming
// the job file, line and key.
// `params` (may be null): an overlay over the job's own `params` (rabbit tune --params).
TuneJob LoadTuneJob(const std::string& path, const ParamOverlay* params = nullptr);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_TUNE_JOB_H_
