// NLopt gait synthesis: searches the pragmatic rules' parameters for a stable periodic
// gait at a requested average velocity (and step length, when given). Derivative-free: a local
// stage (SBPLX or BOBYQA) from the chapter's Table 2 values interpolated at the target velocity;
// when that does not reach the criteria, a global stage (CRS2 with local mutation, seeded) and a
// local polish of its best point. Deterministic for a seed, whatever options.threads: every walk is
// a pure function of its parameters, so walks run ahead of the search on other threads (the
// global stage's initial population) give the same values the search would compute itself.
#ifndef RABBIT_OPTIMIZERS_GAIT_SYNTHESIS_H_
#define RABBIT_OPTIMIZERS_GAIT_SYNTHESIS_H_

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/gait/gait_walk.h"

namespace rabbit {

// The searched parameters, in this order (angles in degrees, as in a targets file's `bounds`).
constexpr int kSynthesisParams = 10;
extern const std::array<const char*, kSynthesisParams> kSynthesisParamNames;
// Default bounds of each searched parameter (degrees, N m, s, gains, m/s).
std::array<std::pair<double, double>, kSynthesisParams> DefaultSynthesisBounds();

struct SynthesisOptions {
  double target_v_m = 0.6;     // m/s
  double target_l_step = 0.0;  // m; 0 = no step-length target
  unsigned seed = 1;
  int budget = 1500;            // simulations at most, all stages together
  double walk_duration = 10.0;  // s of walking per evaluation, without falling
  int window = 10;              // steady-state steps measured at the end (at least window + 2)
  std::string local_algorithm = "sbplx";  // or "bobyqa"
  // Success: the criteria a synthesized gait must meet.
  double v_tolerance = 0.02;    // m/s
  double l_tolerance = 0.02;    // m
  double max_l_spread = 0.008;  // m, step-to-step variation of L_step over the window
  // Search box, per parameter of kSynthesisParamNames (lower < upper).
  std::array<std::pair<double, double>, kSynthesisParams> bounds = DefaultSynthesisBounds();
  // The search's starting point, per parameter of kSynthesisParamNames (in the units of
  // `bounds`, within them); an unset one starts at InitialGaitSpec's value. When any is set, the
  // start itself is walked first, exactly as given, and is the result if it meets the criteria.
  std::array<std::optional<double>, kSynthesisParams> start{};
  // Walks evaluated at once (1: all on the calling thread). The result does not depend on it.
  int threads = 1;
  bool IsValid(std::string* error) const;
};

struct SynthesisProgress {
  int evaluation = 0;
  const char* stage = "";
  double cost = 0.0, best_cost = 0.0;
  GaitMetrics best;
};

struct SynthesisResult {
  GaitSpec spec;
  GaitMetrics metrics;
  double cost = 0.0;
  int evaluations = 0;  // objective values the search asked for (at most options.budget)
  int walks = 0;        // simulations run: evaluations not already known, and walks run ahead
  int walks_ahead = 0;  // of which run ahead on other threads (options.threads > 1)
  double wall_seconds = 0.0;
  bool success = false;
  // When !success: what stops the search, one phrase each (the criteria the best candidate
  // misses and by how much, the bounds it lies on, the actuator limits it runs into, the budget).
  std::vector<std::string> limits;
};

// The starting point: Table 2's (qr1_dsw, qi2_dsw, q0_d) interpolated (or extrapolated) at v, with
// the default pulse and gains.
GaitSpec InitialGaitSpec(double target_v_m);
// The search's starting point for `options`: InitialGaitSpec(target_v_m) with options.start's
// values over it.
GaitSpec StartGaitSpec(const SynthesisOptions& options);
// The value of searched parameter i in `spec`, in the units of SynthesisOptions::bounds.
double SynthesisParamValue(const GaitSpec& spec, int i);

// The objective's value for one walk of options.walk_duration seconds (lower is better):
//   did not walk (fell, or fewer than window + 2 steps): 1000 + 500 (1 - time walked / duration)
//     + 10 per missing step, so that longer survival ranks better;
//   walked: ((V_M - V_d) / v_tolerance)^2 + ((L - L_d) / l_tolerance)^2 (when L_d is given)
//     + (L_step spread / max_l_spread)^2 over the last `window` steps.
double GaitCost(const GaitMetrics& m, const SynthesisOptions& options);
bool MeetsCriteria(const GaitMetrics& m, const SynthesisOptions& options);

// The phrases of SynthesisResult::limits for a search that ended at `best` (re-walks it once,
// recording, to measure its actuator saturation).
std::vector<std::string> DiagnoseMiss(const SimSetup& setup, const SynthesisOptions& options,
                                      const SynthesisResult& best);

SynthesisResult SynthesizeGait(const SimSetup& setup, const SynthesisOptions& options,
                               const std::function<void(const SynthesisProgress&)>& progress);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_GAIT_SYNTHESIS_H_
