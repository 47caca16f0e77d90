// Loading the shipped gait pattern: the reference gaits' trained CMACs (gaits/networks/) and the
// fuzzy system (gaits/gait_pattern.fll), assembled into a FuzzyCmac.
#ifndef RABBIT_LEARN_GAIT_PATTERN_H_
#define RABBIT_LEARN_GAIT_PATTERN_H_

#include <string>
#include <vector>

#include "rabbit/learn/fuzzy_cmac.h"

namespace rabbit {

// The four outputs' names, also the network files' suffixes.
extern const char* const kGaitOutputNames[kGaitOutputs];  // q_i1, q_i2, qd_i1, qd_i2

// gaits/networks/index.csv: gait,output,file,method,rms,weights (one row per CMAC), in the order of
// the reference gaits (gait k = 1..N_r).
struct NetworkIndexEntry {
  std::string gait, output, file, method;
  double rms = 0.0;  // training RMS error, in the output's units (rad or rad/s)
  int weights = 0;
  int line = 0;  // where the reader found it (0: not read from a file)
};
std::vector<NetworkIndexEntry> ReadNetworkIndex(const std::string& path);  // throws InputError
void WriteNetworkIndex(const std::vector<NetworkIndexEntry>& entries, const std::string& path);

// Reads networks_dir/index.csv and its CMAC files, grouped per gait in index order.
std::vector<GaitCmacs> LoadGaitNetworks(const std::string& networks_dir,
                                        std::vector<std::string>* gait_names);

// The Fuzzy-CMAC from an FLL file and a networks directory. Throws InputError for bad files and
// std::invalid_argument when they do not fit together.
FuzzyCmac LoadGaitPattern(const std::string& fll_path, const std::string& networks_dir);

}  // namespace rabbit

#endif  // RABBIT_LEARN_GAIT_PATTERN_H_
