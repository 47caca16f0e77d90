#include "rabbit/learn/gait_pattern.h"

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"
#include "rabbit/learn/fll.h"
#include "rabbit/learn/network_io.h"

namespace rabbit {

const char* const kGaitOutputNames[kGaitOutputs] = {"q_i1", "q_i2", "qd_i1", "qd_i2"};

std::vector<NetworkIndexEntry> ReadNetworkIndex(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "", "cannot open network index");
  std::vector<NetworkIndexEntry> out;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 || line.empty()) continue;
    const std::vector<std::string> c = SplitCsv(line);
    if (c.size() != 6) throw InputError(path, number, "", "expected 6 cells");
    NetworkIndexEntry e;
    e.gait = c[0];
    e.output = c[1];
    e.file = c[2];
    e.method = c[3];
    e.rms = ParseFiniteNumber(c[4], path, number, "rms");
    const double weights = ParseFiniteNumber(c[5], path, number, "weights");
    if (!(weights >= 0.0 && weights <= 1e9))
      throw InputError(path, number, "weights", "out of range");
    e.weights = static_cast<int>(weights);
    out.push_back(e);
  }
  return out;
}

void WriteNetworkIndex(const std::vector<NetworkIndexEntry>& entries, const std::string& path) {
  WriteFileAtomically(path, [&entries](std::ostream& out) {
    out << "gait,output,file,method,rms,weights\n" << std::setprecision(6);
    for (const NetworkIndexEntry& e : entries) {
      out << e.gait << ',' << e.output << ',' << e.file << ',' << e.method << ',' << e.rms << ','
          << e.weights << "\n";
    }
  });
}

std::vector<GaitCmacs> LoadGaitNetworks(const std::string& dir,
                                        std::vector<std::string>* gait_names) {
  namespace fs = std::filesystem;
  const std::string index_path = (fs::path(dir) / "index.csv").string();
  const std::vector<NetworkIndexEntry> index = ReadNetworkIndex(index_path);
  std::vector<GaitCmacs> gaits;
  std::vector<std::string> names;
  std::map<std::string, size_t> slot;
  for (const NetworkIndexEntry& e : index) {
    if (slot.count(e.gait) == 0) {
      slot[e.gait] = gaits.size();
      names.push_back(e.gait);
      gaits.emplace_back();
    }
    gaits[slot[e.gait]].push_back(ReadCmacFile((fs::path(dir) / e.file).string(), nullptr));
  }
  for (size_t k = 0; k < gaits.size(); ++k) {
    if (gaits[k].size() != kGaitOutputs) {
      throw InputError(index_path, 0, names[k],
                       "gait needs " + std::to_string(kGaitOutputs) + " networks, has " +
                           std::to_string(gaits[k].size()));
    }
  }
  if (gait_names != nullptr) *gait_names = names;
  return gaits;
}

FuzzyCmac LoadGaitPattern(const std::string& fll_path, const std::string& networks_dir) {
  return FuzzyCmac(LoadFll(fll_path), LoadGaitNetworks(networks_dir, nullptr));
}

}  // namespace rabbit
