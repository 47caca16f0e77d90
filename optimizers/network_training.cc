#include "network_training.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "cmac_fit.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/learn/cmac_training.h"
#include "rabbit/learn/fll.h"
#include "rabbit/learn/network_io.h"
#include "rabbit/learn/ts_fis.h"

namespace rabbit {
namespace {
constexpr double kDeg = M_PI / 180.0;
}  // namespace

bool NetworkTrainingOptions::IsValid(std::string* error) const {
  if (method != "ceres" && method != "lms") {
    *error = "method must be ceres or lms";
    return false;
  }
  // One message per setting, naming it and the value given.
  auto bad = [error](const std::string& name, const std::string& range, double value) {
    *error = name + " must be " + range + ", got " + FormatLimit(value);
    return false;
  };
  if (!(beta > 0.0 && beta <= 1.0)) return bad("beta", "in (0, 1]", beta);
  if (epochs < 1 || epochs > 1000000) return bad("epochs", "in [1, 1e6]", epochs);
  if (!(smoothness >= 0.0 && smoothness <= 1e6)) {
    return bad("smoothness", "in [0, 1e6]", smoothness);
  }
  if (!(margin_deg >= 0.0 && margin_deg <= 90.0)) {
    return bad("margin_deg", "in [0, 90] deg", margin_deg);
  }
  return true;
}

CmacOptions NetworkStructure(const std::vector<GaitRecord>& gaits, double margin_deg) {
  double e_min = std::numeric_limits<double>::infinity(), e_max = -e_min;
  const bool has_speed = std::any_of(
      gaits.begin(), gaits.end(), [](const GaitRecord& g) { return g.role == GaitRole::kSpeed; });
  for (const GaitRecord& g : gaits) {
    if (has_speed && g.role != GaitRole::kSpeed) continue;
    for (const SwingSample& s : g.swing) {
      e_min = std::min(e_min, s.e);
      e_max = std::max(e_max, s.e);
    }
  }
  CmacOptions options;
  options.x_min = e_min - margin_deg * kDeg;
  options.x_max = e_max + margin_deg * kDeg;
  return options;
}

double FitNetwork(const std::string& method, const NetworkTrainingOptions& a,
                  const std::vector<double>& x, const std::vector<double>& y, Cmac* cmac) {
  const auto start = std::chrono::steady_clock::now();
  if (method == "lms") {
    LmsOptions lms;
    lms.beta = a.beta;
    lms.epochs = a.epochs;
    TrainCmacLms(x, y, lms, cmac);
  } else {
    CmacFitOptions fit;
    fit.smoothness = a.smoothness;
    FitCmacCeres(x, y, fit, cmac);
  }
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<TrainedNetwork> TrainGaitNetworks(const std::vector<GaitRecord>& gaits,
                                              const NetworkTrainingOptions& a) {
  std::string error;
  if (!a.IsValid(&error)) throw std::invalid_argument("network training: " + error);
  if (gaits.empty()) throw std::invalid_argument("network training: no gaits");
  const CmacOptions options = NetworkStructure(gaits, a.margin_deg);
  std::vector<TrainedNetwork> out;
  for (const GaitRecord& g : gaits) {
    std::vector<double> x;
    std::array<std::vector<double>, kGaitOutputs> y;
    SplitSwing(g.swing, &x, &y);
    for (int o = 0; o < kGaitOutputs; ++o) {
      TrainedNetwork n{Cmac(options), {}, {}, 0.0};
      n.seconds = FitNetwork(a.method, a, x, y[o], &n.cmac);
      const double rms = CmacRmsError(n.cmac, x, y[o]);
      const std::string file = g.name + "_" + kGaitOutputNames[o] + ".csv";
      n.metadata = {{"gait", g.name},
                    {"output", kGaitOutputNames[o]},
                    {"method", a.method},
                    {"training_rms", std::to_string(rms)}};
      n.entry = {g.name, kGaitOutputNames[o],
                 file,   a.method,
                 rms,    static_cast<int>(n.cmac.weights().size())};
      out.push_back(std::move(n));
    }
  }
  return out;
}

void WriteGaitNetworks(const std::vector<TrainedNetwork>& networks, const std::string& dir) {
  std::filesystem::create_directories(dir);
  // The marker by which rabbit recognises a networks folder as its own (output_ownership.h).
  WriteFileAtomically((std::filesystem::path(dir) / kNetworksMarker).string(),
                      [](std::ostream& out) { out << "rabbit-networks/1\n"; });
  std::vector<NetworkIndexEntry> entries;
  for (const TrainedNetwork& n : networks) {
    WriteCmacFile(n.cmac, n.metadata, (std::filesystem::path(dir) / n.entry.file).string());
    entries.push_back(n.entry);
  }
  WriteNetworkIndex(entries, (std::filesystem::path(dir) / "index.csv").string());
}

std::string DefaultGaitPatternFll(const std::string& reference_dir, size_t* gaits) {
  const std::string index_path = (std::filesystem::path(reference_dir) / "index.csv").string();
  const std::vector<GaitIndexEntry> index =
      GaitsOfRole(ReadGaitIndex(index_path), GaitRole::kSpeed);
  std::vector<double> v;
  for (const GaitIndexEntry& e : index) {
    if (!v.empty() && !(e.measured_v_m > v.back())) {
      throw InputError(
          index_path, 0, "measured_v_m",
          "the gaits must be listed by strictly increasing measured velocity (" + e.name + ")");
    }
    v.push_back(e.measured_v_m);
  }
  if (v.size() < 2 || v.size() > kMaxGaitPatternGaits) {
    throw InputError(index_path, 0, "",
                     "the gait pattern needs 2 to " + std::to_string(kMaxGaitPatternGaits) +
                         " speed gaits, found " + std::to_string(v.size()));
  }
  if (gaits != nullptr) *gaits = v.size();
  return ToFll(DefaultGaitPattern(v), DefaultGaitPatternComment(v));
}

size_t WriteDefaultGaitPattern(const std::string& reference_dir, const std::string& out) {
  size_t gaits = 0;
  const std::string text = DefaultGaitPatternFll(reference_dir, &gaits);
  WriteFileAtomically(out, [&text](std::ostream& o) { o << text; });
  return gaits;
}

}  // namespace rabbit
