// `rabbit gaits build`: a whole gait database from a targets file. Synthesizes every target that
// needs it (on threads, and dealt over MPI ranks), re-walks each to record it, trains the networks,
// writes the fuzzy system, the per-gait walker settings and the manifest, then runs the targets'
// check suite on the result. Deterministic: the same targets give the same bytes whatever the
// number of threads or ranks. Resumable: a gait whose inputs (target, model, simulator settings,
// program version) and file are unchanged is kept. See docs/gait-database.md.
#ifndef RABBIT_OPTIMIZERS_GAIT_BUILD_H_
#define RABBIT_OPTIMIZERS_GAIT_BUILD_H_

#include <functional>
#include <string>
#include <vector>

#include "gait_targets.h"
#include "network_training.h"
#include "rabbit/gait/gait_database.h"

namespace rabbit {

// Synthesizes one gait (SynthesizeGait) and re-walks it for 20 s to record it (30+ steps, the
// swing averaged over the last 10; a gait slower than 30 steps in 20 s, but for 13 or more, is
// walked again for the time of 31 of its steps). True when the gait meets the acceptance
// criteria: the synthesis's, no fall, 30 steps, the last 10 within 0.03 m/s of the target, L_step
// spread under 1 cm (within 0.03 m of a requested step length). *walks: simulations run; when
// the gait misses, *limits says what stops it (criteria, bounds, motor limits, budget).
bool SynthesizeReferenceGait(const SynthesisOptions& options, const ModelParams& model,
                             const std::string& name, bool quiet, GaitRecord* record,
                             int* walks = nullptr, std::vector<std::string>* limits = nullptr);

// The canonical text of the simulator settings synthesis walks with (every default that shapes a
// walk), hashed into each gait's inputs.
std::string SimulatorSettingsText();

struct GaitBuildOptions {
  std::string out;  // the database folder: new, empty, or a database (has manifest.csv)
  int threads = 0;  // per rank (0: all cores)
  NetworkTrainingOptions training;
  std::function<void(const std::string&)> log;  // progress lines (rank 0 only); may be empty
  // Set true (rank 0) once this build has left its synthesized gaits in the staging folder for
  // the next build (docs/gait-database.md, "Resume"), so that a caller catching a later error
  // can say so; false again when the build drops the list, before it writes its manifest.
  bool* staged = nullptr;
};

struct GaitBuildResult {
  // built: the gaits new to the database; kept: taken from it unchanged (see "Resume" in
  // docs/gait-database.md); missed: synthesized without meeting their criteria.
  std::vector<std::string> built, kept, missed, check_failures;
  // Of `built`, the gaits an earlier build of the same folder synthesized from the same inputs
  // and stopped before its commit (an error or a kill after the synthesis): taken from its
  // staging folder instead of synthesized again.
  std::vector<std::string> reused;
  // Fewer than 2 speed gaits met their criteria: nothing was written.
  bool too_few_speed_gaits = false;
  long walks = 0;  // simulations of the synthesis, over all ranks
  double synthesis_seconds = 0.0;
  double wall_seconds = 0.0;
  // 0 all built and checked; 1 a target missed its criteria (nothing written for it) or a check
  // walk failed.
  // the same on every rank (rank 0's verdict, broadcast).
  int code = 0;
  int exit_code() const { return code; }
};

// Throws InputError (nothing written) when `out` exists and is neither empty nor a database, or is
// a database whose manifest, index and files disagree. Every rank calls it (a collective).
GaitBuildResult BuildGaitDatabase(const GaitTargets& targets, const GaitBuildOptions& options);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_GAIT_BUILD_H_
