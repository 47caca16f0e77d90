// The CSV gait database (DESIGN.md section 5). One file per gait:
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

struct GaitRecord {
  std::string name;            // e.g. vm_0.60
  double target_v_m = 0.0;     // m/s
  double target_l_step = 0.0;  // m, 0 = none requested
  GaitMetrics measured;        // steady-state figures of the walk that produced it
  GaitSpec spec;               // how to walk it again
  std::string model_hash;      // of the model parameters it was made with
  std::string source;          // "synthesized" or how else it was made
  unsigned seed = 0;
  std::vector<SwingSample> swing;  // e ascending
};

// A short, stable hash of the model parameters (hex), recorded with every gait.
std::string ModelHash(const ModelParams& params);

void WriteGaitFile(const GaitRecord& gait, const std::string& path);  // atomic
std::string GaitFileText(const GaitRecord& gait);                     // what WriteGaitFile writes
GaitRecord ReadGaitFile(const std::string& path);                     // throws InputError

// index.csv: name,file,target_v_m,measured_v_m,l_step_m,t_step_s,steps,source.
struct GaitIndexEntry {
  std::string name, file, source;
  double target_v_m = 0.0, measured_v_m = 0.0, l_step = 0.0, t_step = 0.0;
  int steps = 0;
};
void WriteGaitIndex(const std::vector<GaitIndexEntry>& entries, const std::string& path);
std::vector<GaitIndexEntry> ReadGaitIndex(const std::string& path);  // throws InputError
// Writes or replaces the gait's file in `dir` and its row in dir/index.csv (kept sorted by
// target velocity). Returns the gait file's path.
std::string AddGaitToDatabase(const GaitRecord& gait, const std::string& dir);

}  // namespace rabbit

#endif  // RABBIT_GAIT_GAIT_DATABASE_H_
