// Training the SISO CMACs of a gait database (what `rabbit train` and `rabbit gaits build` do):
// four networks per reference gait (q_i1, q_i2, qd_i1, qd_i2 as functions of e), one structure for
// all of them (the chapter's: 6 layers, 1.5 deg fields, 0.25 deg quanta) over the e range of all
// the gaits plus a margin. Deterministic: the same gaits give the same weights.
#ifndef RABBIT_OPTIMIZERS_NETWORK_TRAINING_H_
#define RABBIT_OPTIMIZERS_NETWORK_TRAINING_H_

#include <map>
#include <string>
#include <vector>

#include "rabbit/gait/gait_database.h"
#include "rabbit/learn/cmac.h"
#include "rabbit/learn/gait_pattern.h"

namespace rabbit {

struct NetworkTrainingOptions {
  std::string method = "ceres";  // or "lms" (eq. 7)
  double beta = 0.5;             // LMS learning rate (0, 1]
  int epochs = 400;              // LMS passes
  double smoothness = 1e-4;      // Ceres: neighbour-difference weight
  double margin_deg = 5.0;       // of the e range
  bool IsValid(std::string* error) const;
};

struct TrainedNetwork {
  Cmac cmac;
  NetworkIndexEntry entry;  // gait, output, file, method, rms, weights
  std::map<std::string, std::string> metadata;
  double seconds = 0.0;  // fitting time
};

// The CMAC structure for these gaits (their e range plus the margin).
CmacOptions NetworkStructure(const std::vector<GaitRecord>& gaits, double margin_deg);

// Fits one CMAC with the named method on (x, y); returns the seconds it took.
double FitNetwork(const std::string& method, const NetworkTrainingOptions& options,
                  const std::vector<double>& x, const std::vector<double>& y, Cmac* cmac);

// Every gait's four networks, in gait then output order. Throws std::invalid_argument for no gaits
// or invalid options.
std::vector<TrainedNetwork> TrainGaitNetworks(const std::vector<GaitRecord>& gaits,
                                              const NetworkTrainingOptions& options);

// Writes the networks and their index.csv into `dir` (created; files replaced atomically).
void WriteGaitNetworks(const std::vector<TrainedNetwork>& networks, const std::string& dir);

// The default gait pattern (Table 3 generalised to the database's N_r speed gaits, V_M sets at
// their measured velocities; library gaits take no part) of the gaits in reference_dir/index.csv,
// as FLL text; *gaits (if given) = N_r. Throws InputError for speed gaits not listed by strictly
// increasing measured velocity, or fewer than 2 or more than kMaxGaitPatternGaits of them.
std::string DefaultGaitPatternFll(const std::string& reference_dir, size_t* gaits = nullptr);
// Writes it to `out` (atomically); returns N_r.
size_t WriteDefaultGaitPattern(const std::string& reference_dir, const std::string& out);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_NETWORK_TRAINING_H_
