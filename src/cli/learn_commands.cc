// rabbit train: CMACs for every speed gait of a database; rabbit fis eval | generate: the gait
// pattern's fuzzy system.
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
#include "network_training.h"
#include "rabbit/gait/database_layout.h"
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

// A database that rabbit gaits build made changes as a whole: its manifest lists every file's
// hash, so networks or a fuzzy system written into it alone would leave it disagreeing with its
// manifest (and refused by every command that reads it).
void RefuseBuiltDatabase(const std::string& out) {
  const std::string root = DatabaseRootOf(out);
  if (!root.empty() && std::filesystem::exists(std::filesystem::path(root) / kManifestFile)) {
    throw InputError("--out", 0, out,
                     "is part of a database made by rabbit gaits build (" + root +
                         "/manifest.csv lists its files): write elsewhere with --out, or change "
                         "its targets file and build it again (rabbit gaits build TARGETS --out "
                         "DIR resumes)");
  }
}

constexpr double kDeg = M_PI / 180.0;
// fis eval --vm: five times the fastest shipped gait, either way.
constexpr double kMaxFlagSpeed = 5.0;  // m/s

struct TrainArgs {
  std::string gaits = "gaits";  // database (or its reference/ folder)
  std::string out;              // default: the database's networks/
  std::string method = "ceres";
  double beta = 0.5;
  int epochs = 400;
  double smoothness = 1e-4;
  double margin_deg = 5.0;
  bool compare = false;
  bool quiet = false;
};

int RunTrain(const TrainArgs& a) {
  namespace fs = std::filesystem;
  NetworkTrainingOptions training;
  training.method = a.method;
  training.beta = a.beta;
  training.epochs = a.epochs;
  training.smoothness = a.smoothness;
  training.margin_deg = a.margin_deg;
  std::string error;
  if (!training.IsValid(&error)) {
    std::cerr << "rabbit train: " << error << "\n";
    return 2;
  }
  // --gaits names a database (its reference/ folder is read, its networks/ written) or, as
  // before databases had a root, a reference folder.
  const std::string root = GaitDatabaseRoot(a.gaits);
  const std::string reference =
      fs::exists(fs::path(a.gaits) / "index.csv") ? a.gaits : ReferenceDirOf(root);
  const std::string out_dir = a.out.empty() ? NetworksDirOf(root) : a.out;
  // The networks folder, its staging folder and the lock, before any work: only a folder of
  // networks rabbit wrote is replaced.
  RefuseBuiltDatabase(out_dir);
  const fs::path out(out_dir), staging = out.string() + ".staging";
  // Into a database (its networks/): the database's one lock, on its root.
  const OutputLock lock =
      ClaimMarkedFolder("--out", out, staging, kNetworksMarker, "a networks folder of rabbit train",
                        DatabaseRootOf(out_dir));
  const std::vector<GaitIndexEntry> index =
      ReadGaitIndex((fs::path(reference) / "index.csv").string());
  std::vector<GaitRecord> gaits;
  std::set<std::string> names;
  for (const GaitIndexEntry& entry : index) {
    const std::string path = (fs::path(reference) / entry.file).string();
    gaits.push_back(ReadGaitFile(path));
    // The gait's name becomes file names: it must be safe and unique.
    if (!IsSafeName(gaits.back().name) || !names.insert(gaits.back().name).second) {
      throw InputError(path, 0, "name",
                       "gait names must be unique and " + SafeNameRule(gaits.back().name));
    }
  }
  if (gaits.empty()) {
    std::cerr << "rabbit train: no gaits in " << reference << "\n";
    return 2;
  }
  // Everything is fitted first, then written into a staging directory that replaces the
  // networks folder at the end: a failure leaves the old networks whole.
  const std::vector<TrainedNetwork> fitted = TrainGaitNetworks(gaits, training);
  // The table of the fits goes to stdout, or nowhere with --quiet.
  std::FILE* table = a.quiet ? nullptr : stdout;
  if (table != nullptr) {
    std::fprintf(table, "%-8s %-6s %8s %12s %10s", "gait", "output", "method", "RMS", "time ms");
    if (a.compare) std::fprintf(table, "   (other method: RMS, time ms)");
    std::fprintf(table, "\n");
  }
  const CmacOptions structure = NetworkStructure(gaits, a.margin_deg);
  for (size_t i = 0; i < fitted.size() && table != nullptr; ++i) {
    const TrainedNetwork& n = fitted[i];
    const int o = static_cast<int>(i % kGaitOutputs);
    const bool angle = o < 2;
    std::fprintf(table, "%-8s %-6s %8s %9.4f %s %10.2f", n.entry.gait.c_str(),
                 n.entry.output.c_str(), a.method.c_str(), n.entry.rms / kDeg,
                 angle ? "deg  " : "deg/s", n.seconds * 1e3);
    if (a.compare) {
      std::vector<double> x;
      std::array<std::vector<double>, kGaitOutputs> y;
      SplitSwing(gaits[i / kGaitOutputs].swing, &x, &y);
      const std::string other = a.method == "lms" ? "ceres" : "lms";
      Cmac check(structure);
      const double other_seconds = FitNetwork(other, training, x, y[o], &check);
      std::fprintf(table, "   (%s: %.4f, %.2f)", other.c_str(), CmacRmsError(check, x, y[o]) / kDeg,
                   other_seconds * 1e3);
    }
    std::fprintf(table, "\n");
  }
  WriteMarkedFolder(staging, out, kNetworksMarker, "train",
                    [&] { WriteGaitNetworks(fitted, staging.string()); });
  if (!a.quiet) std::printf("wrote %zu networks to %s\n", fitted.size(), out_dir.c_str());
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

// Writes the default gait pattern of a gait database (DefaultGaitPatternFll): to a new file, an
// FLL file of rabbit's, or standard output (-).
int RunFisGenerate(const std::string& gaits_dir, const std::string& out_flag, bool quiet) {
  namespace fs = std::filesystem;
  const std::string reference = fs::exists(fs::path(gaits_dir) / kIndexFile)
                                    ? gaits_dir
                                    : ReferenceDirOf(GaitDatabaseRoot(gaits_dir));
  const std::string out = out_flag.empty() ? GaitPatternOf(GaitDatabaseRoot(gaits_dir)) : out_flag;
  if (!IsStandardOutput(out)) {  // a new file, or an FLL file to replace
    RefuseBuiltDatabase(out);
    CheckOwnedFile("--out", out, "Engine:", "an FLL file", /*skip_comments=*/true);
  }
  // Into a database: its one lock, on its root (else the file's own).
  OutputLock lock;
  if (!IsStandardOutput(out)) {
    const std::string root = DatabaseRootOf(out);
    lock = OutputLock(root.empty() ? out : root, "--out");
    CheckOwnedFile("--out", out, "Engine:", "an FLL file", /*skip_comments=*/true);
  }
  size_t n = 0;
  const std::string text = DefaultGaitPatternFll(reference, &n);
  WriteOutputFile(out, [&text](std::ostream& o) { o << text; });
  if (!quiet) {
    std::fprintf(IsStandardOutput(out) ? stderr : stdout, "wrote %s: N_r = %zu gaits, %zu rules\n",
                 out.c_str(), n, 5 * n);
  }
  return 0;
}

// --gaits DIR, and the older --dir as a hidden alias of it (counted as --gaits, so that the data
// root's default does not replace what the user gave); both accept a database or its reference/.
void DatabaseOption(CLI::App* cmd, std::string* dir) {
  CLI::Option* gaits = DataDefault(
      cmd,
      cmd->add_option("--gaits", *dir,
                      "Gait database folder, or its reference/ folder (a default is below the "
                      "data root)"),
      dir);
  cmd->add_option("--dir", *dir, "Same as --gaits (older form)")
      ->group("")
      ->each([gaits](const std::string& value) { gaits->add_result(value); });
}

}  // namespace

Command RegisterTrain(CLI::App* app) {
  auto a = std::make_shared<TrainArgs>();
  CLI::App* cmd = app->add_subcommand("train", "Train the CMACs of every reference gait");
  DatabaseOption(cmd, &a->gaits);
  cmd->add_option("--out,-o", a->out,
                  "Networks folder to write (default: the database's networks/)");
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
  auto gen_gaits = std::make_shared<std::string>("gaits");
  auto gen_out = std::make_shared<std::string>();  // default: the database's gait_pattern.fll
  CLI::App* gen = fis->add_subcommand(
      "generate", "Write the default gait pattern (Table 3 generalised) for a gait database");
  DatabaseOption(gen, gen_gaits.get());
  gen->add_option(
      "--out,-o", *gen_out,
      "FLL file to write (default: the database's gait_pattern.fll; -: standard output)");
  auto gen_quiet = std::make_shared<bool>(false);
  gen->add_flag("--quiet,-q", *gen_quiet, "Print nothing but errors");
  return {fis, [a, e, gen, gen_gaits, gen_out, gen_quiet] {
            if (gen->parsed()) return RunFisGenerate(*gen_gaits, *gen_out, *gen_quiet);
            a->has_e = e->count() > 0;
            return RunFisEval(*a);
          }};
}

}  // namespace rabbit::cli
