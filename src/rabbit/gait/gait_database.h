// The CSV gait database (docs/formats/gait-csv.md). One file per gait:
//   # format = rabbit-gait/1
//   # key = value                 metadata: targets, measured figures, rule parameters, model hash,
//   ...                           generator, seed, source (angles in fields named _deg)
//   e_rad,q_i1_rad,q_i2_rad,qd_i1_rad_s,qd_i2_rad_s
//   ...                           one steady-state swing, averaged over several steps, e ascending
// and an index.csv beside them listing the gaits. Readers refuse anything malformed with an
// InputError naming the file and line.
#ifndef RABBIT_GAIT_GAIT_DATABASE_H_
#define RABBIT_GAIT_GAIT_DATABASE_H_

#include <map>
#include <string>
#include <vector>

#include "rabbit/gait/gait_walk.h"
#include "rabbit/model/params.h"

namespace rabbit {

constexpr const char* kGaitFormat = "rabbit-gait/1";
constexpr const char* kGaitIndexFile = "index.csv";  // beside the gait files

// What a gait is for. kSpeed: one of the gaits the chapter's walker blends over V_M (one per
// speed; the gait pattern's fuzzy system and the walker use these only). kLibrary: one more step
// length at a speed, for a step planner to choose among.
enum class GaitRole { kSpeed, kLibrary };
const char* GaitRoleName(GaitRole role);  // "speed", "library"
// Parses "speed" or "library"; false for anything else.
bool ParseGaitRole(const std::string& text, GaitRole* role);

struct GaitRecord {
  std::string name;            // e.g. vm_0.60
  double target_v_m = 0.0;     // m/s
  double target_l_step = 0.0;  // m, 0 = none requested
  GaitMetrics measured;        // steady-state figures of the walk that produced it
  GaitSpec spec;               // how to walk it again
  std::string model_hash;      // of the model parameters it was made with
  std::string source;          // "synthesized" or how else it was made
  unsigned seed = 0;
  std::vector<SwingSample> swing;    // e ascending
  GaitRole role = GaitRole::kSpeed;  // written as "# role = library" for library gaits only
};

// A short, stable hash of the model parameters (hex), recorded with every gait.
std::string ModelHash(const ModelParams& params);

void WriteGaitFile(const GaitRecord& gait, const std::string& path);  // atomic
std::string GaitFileText(const GaitRecord& gait);                     // what WriteGaitFile writes
GaitRecord ReadGaitFile(const std::string& path);                     // throws InputError

// index.csv: name,file,target_v_m,measured_v_m,l_step_m,t_step_s,steps,source,role,
// target_l_step_m (l_step_m is the measured step length). An index of the first eight columns
// only (written before gaits had roles) reads as speed gaits with no step-length target.
struct GaitIndexEntry {
  std::string name, file, source;
  double target_v_m = 0.0, measured_v_m = 0.0, l_step = 0.0, t_step = 0.0;
  int steps = 0;
  GaitRole role = GaitRole::kSpeed;
  double target_l_step = 0.0;  // m, 0 = none requested
};
// The entries of one role, in index order.
std::vector<GaitIndexEntry> GaitsOfRole(const std::vector<GaitIndexEntry>& index, GaitRole role);
void WriteGaitIndex(const std::vector<GaitIndexEntry>& entries, const std::string& path);
std::vector<GaitIndexEntry> ReadGaitIndex(const std::string& path);  // throws InputError
// Writes or replaces the gait's file in `dir` and its row in dir/index.csv (kept sorted: the
// speed gaits first, by target velocity, then the library gaits by target velocity and step
// length, so that the speed gaits' networks come first), in one commit (database_commit.h).
// Returns the gait file's path.
std::string AddGaitToDatabase(const GaitRecord& gait, const std::string& dir);

}  // namespace rabbit

#endif  // RABBIT_GAIT_GAIT_DATABASE_H_
