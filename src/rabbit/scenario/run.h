// One run of a scenario with one variant of its controller, and what the report needs of it:
// per-step records, the tracking log, the metrics of summary.csv and the pass criteria.
//   variant "fuzzy_cmac"   the chapter's walker (FuzzyCmacWalker);
//           "nearest_gait" baseline: the same walker with the fuzzy weights rounded to the
//                          strongest rule (nearest-gait switching);
//           "multi_cmac"   baseline: the same walker with the gait pattern given by multi-input
//                          CMACs over (e, V_M, d_obs) trained on the scenario's Fuzzy-CMAC
//                          (rabbit/learn/multi_cmac_pattern.h);
//           "pragmatic"    baseline: the pragmatic rules of the start gait (Scenario::start_gait:
//                          the gait the walker walks at V_d(0) unless the scenario names one), no
//                          velocity control;
//           "main"         any other controller (passive, pd_hold, pragmatic) as the scenario says.
#ifndef RABBIT_SCENARIO_RUN_H_
#define RABBIT_SCENARIO_RUN_H_

#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rabbit/control/fuzzy_cmac_walker.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/learn/fuzzy_cmac.h"
#include "rabbit/learn/multi_cmac_pattern.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/sim/simulator.h"

namespace rabbit {

// The multi-input CMAC baselines trained from one Fuzzy-CMAC's networks: each distinct (fuzzy
// system, domain, options) is trained once, on first use. Thread-safe: a training runs outside
// the map's lock, and callers that want the same pattern meanwhile wait for it. Keeps the last
// kMaxPatterns settings (2 MB each by default; a tuning job may change them at every evaluation):
// an older one is trained again if asked for again.
class MultiCmacPatternCache {
 public:
  static constexpr size_t kMaxPatterns = 8;
  // teacher: the library's pattern, or it with a scenario's fuzzy system (FuzzyCmac::WithFis).
  // Throws as TrainMultiCmacPattern (and again on the next call: a failure is not cached).
  std::shared_ptr<const MultiCmacPattern> Get(const FuzzyCmac& teacher,
                                              const MultiCmacPatternDomain& domain,
                                              const MultiCmacPatternOptions& options,
                                              MultiCmacTrainingSummary* summary = nullptr);
  int trainings() const;  // how many trainings have run

 private:
  struct Entry {
    std::mutex mutex;  // held while training
    std::shared_ptr<const MultiCmacPattern> pattern;
    MultiCmacTrainingSummary summary;
  };
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Entry>> entries_;
  std::vector<std::string> order_;  // keys of entries_, oldest first
  int trainings_ = 0;
};

// The gait pattern of walker scenarios and the reference gaits behind it, loaded once and shared
// read-only by every run that names the same files.
struct GaitLibrary {
  GaitPatternFiles files;
  FuzzyCmac pattern;                    // trunk pitches set (thigh frame)
  std::vector<std::string> gait_names;  // network order (gait k = O^{k+1})
  std::vector<GaitRecord> gaits;        // same order
  // The multi_cmac baselines learnt from `pattern`, trained when a run first needs them (the one
  // part of a library that changes after loading; shared by the library's copies).
  std::shared_ptr<MultiCmacPatternCache> multi_cmac = std::make_shared<MultiCmacPatternCache>();
};

// The multi_cmac baseline of a walker scenario: multi-input CMACs trained (once per library and
// settings) on the scenario's Fuzzy-CMAC (the library's networks with the scenario's fuzzy system),
// in the walker's frame, over the domain TeacherDomain gives for the library's gaits, the
// scenario's d_obs_max and its [controller.multi_cmac] options. Throws InputError (naming the
// scenario file and controller.multi_cmac) when the settings cannot be trained.
std::shared_ptr<const MultiCmacPattern> MultiCmacBaseline(
    const Scenario& scenario, const GaitLibrary& library,
    MultiCmacTrainingSummary* summary = nullptr);
// Throws InputError for bad or mismatched files.
std::shared_ptr<const GaitLibrary> LoadGaitLibrary(const GaitPatternFiles& files);

// Loads each distinct set of files once (thread-safe).
class GaitLibraryCache {
 public:
  std::shared_ptr<const GaitLibrary> Get(const GaitPatternFiles& files);

 private:
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const GaitLibrary>> loaded_;
};

// The variants a scenario runs: its main controller first, then its baselines.
std::vector<std::string> ScenarioVariants(const Scenario& scenario);
// "<scenario>" for the main variant, "<scenario>+<variant>" for a baseline.
std::string RunName(const Scenario& scenario, const std::string& variant);

struct StepRow {
  StepRecord step;
  double v_d = 0.0;
  double v_m_used = 0.0;  // what the controller used (stride mean, noise); the step's V_M if none
  double d_obs = 0.0;
  double q0_d = 0.0;            // rad
  std::vector<double> weights;  // per reference gait
  std::string rules;            // firing rules "d_obs set/V_M set:activation;..."
  bool warmup = false;          // walked by the warm-up's pragmatic rules (weights not used)
};

struct RunMetrics {
  double duration = 0.0, distance = 0.0;
  int steps = 0;
  double mean_abs_speed_error = 0.0, final_abs_speed_error = 0.0;  // NaN without measured steps
  double l_step_mean = 0.0, l_step_min = 0.0, l_step_max = 0.0, l_step_spread = 0.0;
  double saturation = 0.0;         // s, summed over the joints
  double energy = 0.0;             // J, positive actuator work
  double cost_of_transport = 0.0;  // energy / (m g distance), NaN when the robot did not advance
  // The walker's gait pattern's learnt weights, bytes: the Fuzzy-CMAC's 20 SISO CMACs for
  // fuzzy_cmac and nearest_gait, the four multi-input CMACs for multi_cmac; 0 for the others.
  std::size_t pattern_memory_bytes = 0;
};

struct RunOutput {
  std::string scenario, variant, run, controller;
  std::string family;  // the scenario's [[family]] (empty: a plain scenario)
  SimResult sim;
  std::vector<StepRow> steps;
  std::vector<WalkerTrack> tracking;
  // The reference gaits the steps' weights are over, in their order (empty: no weights).
  std::vector<std::string> weight_gaits;
  RunMetrics metrics;
  bool passed = true;
  bool required = false;  // its pass decides the exit code: a required scenario's main variant
  std::vector<std::string> failures;  // one message per failed criterion
  double wall = 0.0;                  // s (not deterministic: excluded from comparisons)
};

// Runs one variant; never throws for physical failures (they are outcomes). `library` is needed
// for walker scenarios and baselines (else may be null).
RunOutput RunScenario(const Scenario& scenario, const std::string& variant,
                      const GaitLibrary* library);

// Metrics and criteria of a finished run (deterministic functions of the run's records).
RunMetrics ComputeMetrics(const Scenario& scenario, const Model& model, const SimResult& sim,
                          const std::vector<StepRow>& steps);
// Every criterion of docs/outcomes.md: the expected outcome, the scenario's [criteria] and, for a
// walking scenario with a V_d profile, the forward travel (min_travel_ratio of VelocityIntegral
// over the run's simulated time).
void EvaluateCriteria(const Scenario& scenario, RunOutput* run);
// The integral of V_d from 0 to t_end (m; 0 for t_end <= 0).
double VelocityIntegral(const VelocityProfile& velocity, double t_end);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_RUN_H_
