#include "rabbit/learn/gait_pattern.h"

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <sstream>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"
#include "rabbit/learn/fll.h"
#include "rabbit/learn/network_io.h"

namespace rabbit {

const char* const kGaitOutputNames[kGaitOutputs] = {"q_i1", "q_i2", "qd_i1", "qd_i2"};

namespace {
constexpr const char* kNetworkIndexHeader = "gait,output,file,method,rms,weights";
}  // namespace

std::vector<NetworkIndexEntry> ReadNetworkIndex(const std::string& path) {
  std::istringstream in(ReadBoundedFile(path, kIndexFileLimits));
  std::vector<NetworkIndexEntry> out;
  std::string line;
  int number = 0;
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++number;
    if (Trim(line).empty()) continue;
    const std::vector<std::string> c = SplitCsv(line);
    if (!header_seen) {
      header_seen = true;
      if (Trim(line) != kNetworkIndexHeader) {
        throw InputError(path, number, "",
                         std::string("expected the header row \"") + kNetworkIndexHeader +
                             "\", got \"" + Trim(line) + "\"");
      }
      continue;
    }
    if (c.size() != 6) {
      throw InputError(path, number, "",
                       std::string("expected 6 cells (") + kNetworkIndexHeader + "), got " +
                           std::to_string(c.size()));
    }
    NetworkIndexEntry e;
    e.line = number;
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
  if (!header_seen) {
    throw InputError(
        path, 0, "",
        std::string("empty file: expected the header row \"") + kNetworkIndexHeader + "\"");
  }
  return out;
}

void WriteNetworkIndex(const std::vector<NetworkIndexEntry>& entries, const std::string& path) {
  WriteFileAtomically(path, [&entries](std::ostream& out) {
    out << kNetworkIndexHeader << "\n" << std::setprecision(6);
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
  // Each CMAC goes to its gait and output by name (the index's rows may come in any order).
  std::vector<std::array<std::unique_ptr<Cmac>, kGaitOutputs>> slots;
  for (const NetworkIndexEntry& e : index) {
    const auto output =
        std::find(std::begin(kGaitOutputNames), std::end(kGaitOutputNames), e.output);
    if (output == std::end(kGaitOutputNames)) {
      throw InputError(index_path, e.line, e.output, "unknown output (q_i1, q_i2, qd_i1 or qd_i2)");
    }
    const fs::path file(e.file);
    if (file.is_absolute() || e.file.find("..") != std::string::npos) {
      throw InputError(index_path, e.line, e.file,
                       "network files must lie in the networks directory");
    }
    if (slot.count(e.gait) == 0) {
      slot[e.gait] = slots.size();
      names.push_back(e.gait);
      slots.emplace_back();
    }
    std::unique_ptr<Cmac>& place = slots[slot[e.gait]][output - std::begin(kGaitOutputNames)];
    if (place != nullptr) {
      throw InputError(index_path, e.line, e.gait + " " + e.output, "listed twice");
    }
    const std::string cmac_path = (fs::path(dir) / file).string();
    std::map<std::string, std::string> metadata;
    place = std::make_unique<Cmac>(ReadCmacFile(cmac_path, &metadata));
    // The file's own header says which gait and output it holds (when it says): they must be the
    // index row's.
    for (const auto& [key, want] :
         {std::pair<const char*, const std::string&>("gait", e.gait),
          std::pair<const char*, const std::string&>("output", e.output)}) {
      const auto it = metadata.find(key);
      if (it != metadata.end() && it->second != want) {
        throw InputError(index_path, e.line, key,
                         "the row says " + std::string(key) + " \"" + want + "\" but " + cmac_path +
                             " says \"" + it->second + "\"");
      }
    }
  }
  for (size_t k = 0; k < slots.size(); ++k) {
    gaits.emplace_back();
    for (const std::unique_ptr<Cmac>& c : slots[k]) {
      if (c != nullptr) gaits[k].push_back(*c);
    }
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
  TsFis fis = LoadFll(fll_path);
  std::vector<GaitCmacs> networks = LoadGaitNetworks(networks_dir, nullptr);
  try {
    return FuzzyCmac(std::move(fis), std::move(networks));
  } catch (const std::invalid_argument& e) {
    throw InputError(fll_path, 0, "", std::string(e.what()) + " (networks: " + networks_dir + ")");
  }
}

}  // namespace rabbit
