// rabbit train: CMACs for every reference gait; rabbit fis eval: the gait pattern's fuzzy system.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "cli/commands.h"
#include "cli/data_root.h"
#include "cli/flag_checks.h"
#include "cmac_fit.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/learn/cmac_training.h"
#include "rabbit/learn/fll.h"
#include "rabbit/learn/gait_pattern.h"
#include "rabbit/learn/network_io.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit::cli {
namespace {

constexpr double kDeg = M_PI / 180.0;
// fis eval --vm: five times the fastest shipped gait, either way.
constexpr double kMaxFlagSpeed = 5.0;  // m/s

struct TrainArgs {
  std::string gaits = "gaits/reference";
  std::string out = "gaits/networks";
  std::string method = "ceres";
  double beta = 0.5;
  int epochs = 400;
  double smoothness = 1e-4;
  double margin_deg = 5.0;
  bool compare = false;
  bool quiet = false;
};

// Fits one CMAC with the named method; returns seconds taken.
double Fit(const std::string& method, const TrainArgs& a, const std::vector<double>& x,
           const std::vector<double>& y, Cmac* cmac) {
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

int RunTrain(const TrainArgs& a) {
  namespace fs = std::filesystem;
  if (!(a.beta > 0.0 && a.beta <= 1.0) || a.epochs < 1 || a.epochs > 1000000 ||
      !(a.smoothness >= 0.0 && a.smoothness <= 1e6)) {
    std::cerr << "rabbit train: need 0 < beta <= 1, 1 <= epochs <= 1e6, 0 <= smoothness <= 1e6\n";
    return 2;
  }
  // The networks folder, its staging folder and the lock, before any work: only a folder of
  // networks rabbit train wrote is replaced.
  const fs::path out(a.out), staging = out.string() + ".staging";
  const OutputLock lock = ClaimMarkedFolder("--out", out, staging, kNetworksMarker,
                                            "a networks folder of rabbit train");
  const std::vector<GaitIndexEntry> index =
      ReadGaitIndex((fs::path(a.gaits) / "index.csv").string());
  std::vector<GaitRecord> gaits;
  double e_min = std::numeric_limits<double>::infinity(), e_max = -e_min;
  std::set<std::string> names;
  // The networks' common input range spans the speed gaits (all gaits if none is one): library
  // gaits never change the structure, and so the networks, of the gaits the walker blends.
  const bool has_speed = !GaitsOfRole(index, GaitRole::kSpeed).empty();
  for (const GaitIndexEntry& entry : index) {
    const std::string path = (fs::path(a.gaits) / entry.file).string();
    gaits.push_back(ReadGaitFile(path));
    // The gait's name becomes file names: it must be safe and unique.
    if (!IsSafeName(gaits.back().name) || !names.insert(gaits.back().name).second) {
      throw InputError(path, 0, "name",
                       "gait names must be unique and " + SafeNameRule(gaits.back().name));
    }
    if (has_speed && entry.role != GaitRole::kSpeed) continue;
    for (const SwingSample& s : gaits.back().swing) {
      e_min = std::min(e_min, s.e);
      e_max = std::max(e_max, s.e);
    }
  }
  if (gaits.empty()) {
    std::cerr << "rabbit train: no gaits in " << a.gaits << "\n";
    return 2;
  }
  // One structure for every CMAC (the chapter's: 6 layers, 1.5 deg fields, 0.25 deg quanta), over
  // the e range of all the gaits plus a margin.
  CmacOptions options;
  options.x_min = e_min - a.margin_deg * kDeg;
  options.x_max = e_max + a.margin_deg * kDeg;
  // Everything is fitted first, then written into a staging directory that replaces --out at the
  // end: a failure leaves the old networks whole.
  struct Fitted {
    Cmac cmac;
    std::string file;
    std::map<std::string, std::string> metadata;
  };
  std::vector<Fitted> fitted;
  std::vector<NetworkIndexEntry> entries;
  // The table of the fits goes to stdout, or nowhere with --quiet.
  std::FILE* table = a.quiet ? nullptr : stdout;
  if (table != nullptr) {
    std::fprintf(table, "%-8s %-6s %8s %12s %10s", "gait", "output", "method", "RMS", "time ms");
    if (a.compare) std::fprintf(table, "   (other method: RMS, time ms)");
    std::fprintf(table, "\n");
  }
  for (const GaitRecord& g : gaits) {
    std::vector<double> x;
    std::array<std::vector<double>, kGaitOutputs> y;
    SplitSwing(g.swing, &x, &y);
    for (int o = 0; o < kGaitOutputs; ++o) {
      Cmac cmac(options);
      const double seconds = Fit(a.method, a, x, y[o], &cmac);
      const double rms = CmacRmsError(cmac, x, y[o]);
      const bool angle = o < 2;
      if (table != nullptr) {
        std::fprintf(table, "%-8s %-6s %8s %9.4f %s %10.2f", g.name.c_str(), kGaitOutputNames[o],
                     a.method.c_str(), rms / kDeg, angle ? "deg  " : "deg/s", seconds * 1e3);
        if (a.compare) {
          const std::string other = a.method == "lms" ? "ceres" : "lms";
          Cmac check(options);
          const double other_seconds = Fit(other, a, x, y[o], &check);
          std::fprintf(table, "   (%s: %.4f, %.2f)", other.c_str(),
                       CmacRmsError(check, x, y[o]) / kDeg, other_seconds * 1e3);
        }
        std::fprintf(table, "\n");
      }
      const std::string file = g.name + "_" + kGaitOutputNames[o] + ".csv";
      fitted.push_back({cmac,
                        file,
                        {{"gait", g.name},
                         {"output", kGaitOutputNames[o]},
                         {"method", a.method},
                         {"training_rms", std::to_string(rms)}}});
      entries.push_back({g.name, kGaitOutputNames[o], file, a.method, rms,
                         static_cast<int>(cmac.weights().size())});
    }
  }
  WriteMarkedFolder(staging, out, kNetworksMarker, "train", [&] {
    for (const Fitted& f : fitted) WriteCmacFile(f.cmac, f.metadata, (staging / f.file).string());
    WriteNetworkIndex(entries, (staging / "index.csv").string());
  });
  if (!a.quiet) std::printf("wrote %zu networks to %s\n", entries.size(), a.out.c_str());
  return 0;
}

struct FisArgs {
  std::string fll = "gaits/gait_pattern.fll";
  std::string networks = "gaits/networks";
  double v_m = 0.0, d_obs = 1.0, e = 0.0;
  bool has_e = false;
};

int RunFisEval(const FisArgs& a) {
  if (!std::isfinite(a.v_m) || std::isnan(a.d_obs) || a.d_obs < 0.0 ||
      (a.has_e && !std::isfinite(a.e))) {
    std::cerr << "rabbit fis eval: --vm and --e-deg must be finite, --dobs >= 0 (inf: none)\n";
    return 2;
  }
  const TsFis fis = LoadFll(a.fll);
  // Inputs by name, in whatever order the file declares them.
  std::vector<double> x(fis.inputs.size());
  int v_index = -1, d_index = -1;
  for (size_t i = 0; i < fis.inputs.size(); ++i) {
    if (fis.inputs[i].name == "V_M") v_index = static_cast<int>(i);
    if (fis.inputs[i].name == "d_obs") d_index = static_cast<int>(i);
  }
  if (fis.inputs.size() != 2 || v_index < 0 || d_index < 0) {
    throw InputError(a.fll, 0, "", "the gait pattern's inputs must be exactly V_M and d_obs");
  }
  x[v_index] = a.v_m;
  x[d_index] = a.d_obs;
  // Load everything before printing anything.
  std::unique_ptr<FuzzyCmac> pattern;
  if (a.has_e) {
    try {
      pattern = std::make_unique<FuzzyCmac>(fis, LoadGaitNetworks(a.networks, nullptr));
    } catch (const std::invalid_argument& e) {
      throw InputError(a.networks, 0, "", e.what());
    }
  }
  TsFis::Result result;
  fis.Evaluate(x, &result);
  std::printf("X = [V_M %.3f m/s, d_obs %.3f m]%s\n", a.v_m, a.d_obs,
              result.fired ? "" : ": no rule fires (output = the default)");
  for (size_t r = 0; r < fis.rules.size(); ++r) {
    if (result.activation[r] <= 0.0) continue;
    const FuzzyRule& rule = fis.rules[r];
    std::printf("  rule %2zu: if", r + 1);
    for (size_t i = 0; i < fis.inputs.size(); ++i) {
      std::printf("%s %s is %s", i ? " and" : "", fis.inputs[i].name.c_str(),
                  fis.inputs[i].sets[rule.antecedent[i]].name.c_str());
    }
    std::printf(" then %s is %s   u = %.4f\n", fis.output_name.c_str(),
                fis.output_terms[rule.consequent].c_str(), result.activation[r]);
  }
  std::printf("  output %s = %.4f\n", fis.output_name.c_str(), result.output);
  if (pattern != nullptr) {
    if (!pattern->SetContext(a.v_m, a.d_obs)) {
      std::printf("  no rule fires: no merged references\n");
      return 1;
    }
    const Eigen::Vector4d y = pattern->Query(a.e * kDeg);
    std::printf(
        "  e = %.3f deg: q_i1 %.3f deg, q_i2 %.3f deg, qd_i1 %.3f deg/s, qd_i2 %.3f deg/s\n", a.e,
        y[0] / kDeg, y[1] / kDeg, y[2] / kDeg, y[3] / kDeg);
  }
  return 0;
}

// Writes the default gait pattern (Table 3 generalised to the database's N_r speed gaits, V_M
// sets at their measured velocities) for a gait database; library gaits take no part in it.
int RunFisGenerate(const std::string& gaits_dir, const std::string& out, bool quiet) {
  namespace fs = std::filesystem;
  const std::string index_path = (fs::path(gaits_dir) / "index.csv").string();
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
  if (!IsStandardOutput(out)) {  // a new file, or an FLL file to replace
    CheckOwnedFile("--out", out, "Engine:", "an FLL file", /*skip_comments=*/true);
  }
  const std::string text = ToFll(DefaultGaitPattern(v), DefaultGaitPatternComment(v));
  WriteOutputFile(out, [&text](std::ostream& o) { o << text; });
  if (!quiet) {
    std::fprintf(IsStandardOutput(out) ? stderr : stdout, "wrote %s: N_r = %zu gaits, %zu rules\n",
                 out.c_str(), v.size(), 5 * v.size());
  }
  return 0;
}

}  // namespace

Command RegisterTrain(CLI::App* app) {
  auto a = std::make_shared<TrainArgs>();
  CLI::App* cmd = app->add_subcommand("train", "Train the CMACs of every reference gait");
  DataDefault(cmd,
              cmd->add_option("--gaits", a->gaits,
                              "Gait database folder (a default is below the data root)"),
              &a->gaits);
  DataDefault(cmd,
              cmd->add_option("--out,-o", a->out,
                              "Networks folder to write (a default is below the data root)"),
              &a->out);
  cmd->add_option("--method", a->method, "ceres (sparse least squares) or lms (eq. 7)")
      ->check(CLI::IsMember({"ceres", "lms"}));
  cmd->add_option("--beta", a->beta, "LMS: learning rate, in (0, 1]");
  cmd->add_option("--epochs", a->epochs, "LMS: passes over the samples");
  cmd->add_option("--smoothness", a->smoothness, "Ceres: neighbour-difference weight");
  cmd->add_flag("--compare", a->compare, "Also fit with the other method and print its RMS/time");
  cmd->add_flag("--quiet,-q", a->quiet, "Print nothing but errors (no table of the fits)");
  return {cmd, [a] { return RunTrain(*a); }};
}

Command RegisterFis(CLI::App* app) {
  CLI::App* fis = app->add_subcommand("fis", "The gait pattern's fuzzy system: eval, generate");
  fis->require_subcommand(1);
  auto a = std::make_shared<FisArgs>();
  CLI::App* eval = fis->add_subcommand("eval", "Rule activations at X = [V_M, d_obs]");
  DataDefault(eval, eval->add_option("fll", a->fll, "FLL file (a default is below the data root)"),
              &a->fll);
  eval->add_option("--vm", a->v_m, "Average velocity V_M, m/s")
      ->required()
      ->check(NumberIn(-kMaxFlagSpeed, kMaxFlagSpeed, "m/s"));
  eval->add_option("--dobs", a->d_obs, "Distance to the next obstacle, m (1 = none)")
      ->check(NumberIn(0.0, std::numeric_limits<double>::infinity(), "m"));
  CLI::Option* e =
      eval->add_option("--e-deg", a->e, "Stance hip angle e, deg: print the merged references")
          ->check(NumberIn(-180.0, 180.0, "deg"));
  DataDefault(
      eval,
      eval->add_option("--networks", a->networks,
                       "Networks folder, read with --e-deg (a default is below the data root)"),
      &a->networks);
  auto gen_gaits = std::make_shared<std::string>("gaits/reference");
  auto gen_out = std::make_shared<std::string>("gaits/gait_pattern.fll");
  CLI::App* gen = fis->add_subcommand(
      "generate", "Write the default gait pattern (Table 3 generalised) for a gait database");
  DataDefault(gen,
              gen->add_option("--gaits", *gen_gaits,
                              "Gait database folder (a default is below the data root)"),
              gen_gaits.get());
  DataDefault(
      gen,
      gen->add_option("--out,-o", *gen_out,
                      "FLL file to write (a default is below the data root; -: standard output)"),
      gen_out.get());
  auto gen_quiet = std::make_shared<bool>(false);
  gen->add_flag("--quiet,-q", *gen_quiet, "Print nothing but errors");
  return {fis, [a, e, gen, gen_gaits, gen_out, gen_quiet] {
            if (gen->parsed()) return RunFisGenerate(*gen_gaits, *gen_out, *gen_quiet);
            a->has_e = e->count() > 0;
            return RunFisEval(*a);
          }};
}

}  // namespace rabbit::cli
