// rabbit gaits synthesize | generate | list: the reference-gait database (issue 3).
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "cli/commands.h"
#include "gait_synthesis.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/report/gait_report.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit::cli {
namespace {

// Seconds of walking over which a synthesized gait is measured and recorded: at least 30 steps
// for the slowest gaits (t_step up to 0.65 s).
constexpr double kRecordWalk = 20.0;
constexpr double kAcceptedVelocityError = 0.03;    // m/s
constexpr double kAcceptedStepSpread = 0.01;       // m
constexpr double kAcceptedStepLengthError = 0.03;  // m

struct SynthesizeArgs {
  double v_m = 0.0;
  double l_step = 0.0;
  unsigned seed = 1;
  int budget = 1500;
  std::string dir = "gaits/reference";
  std::string name;
  bool force = false;
  bool quiet = false;
};

// Synthesizes one gait and re-walks it long enough to measure it (30+ steps); fills *record.
bool SynthesizeOne(const SynthesisOptions& options, const std::string& name, bool quiet,
                   GaitRecord* record) {
  const Model model{ModelParams{}};
  SimSetup setup;
  setup.model = &model;
  setup.options.record_every = 0;
  const SynthesisResult r = SynthesizeGait(setup, options, [&](const SynthesisProgress& p) {
    if (quiet || (p.evaluation % 25 != 0)) return;
    std::fprintf(stderr, "  [%s %4d] best cost %.3g: %d steps, V_M %.3f m/s, L_step %.3f m\n",
                 p.stage, p.evaluation, p.best_cost, p.best.steps, p.best.v_m, p.best.l_step);
  });
  // Measure the result over a longer walk (the acceptance figures: at least 30 steps, last 10).
  SimSetup record_setup = setup;
  record_setup.options.record_every = 1;
  const GaitRun run = WalkGait(record_setup, r.spec, kRecordWalk, 10);
  record->name = name;
  record->target_v_m = options.target_v_m;
  record->target_l_step = options.target_l_step;
  record->measured = run.metrics;
  record->spec = r.spec;
  record->model_hash = ModelHash(model.params());
  record->source = "synthesized";
  record->seed = options.seed;
  record->swing = AverageSwingTrajectory(run, 10, 101);
  if (!quiet) {
    std::printf("%s: %s after %d simulations (%.1f s, %.0f simulations/s)\n", name.c_str(),
                r.success ? "criteria met" : "criteria NOT met", r.evaluations, r.wall_seconds,
                r.evaluations / std::max(r.wall_seconds, 1e-9));
    std::printf(
        "  %d steps in %.0f s%s; last 10: V_M %.3f m/s (spread %.3f), L_step %.3f m "
        "(spread %.4f), t_step %.3f s\n",
        run.metrics.steps, kRecordWalk,
        run.metrics.fell ? (" (" + run.metrics.reason + ")").c_str() : "", run.metrics.v_m,
        run.metrics.v_m_spread, run.metrics.l_step, run.metrics.l_step_spread, run.metrics.t_step);
  }
  // Issue 3's acceptance on the recorded walk: 30 steps, the last 10 within 0.03 m/s of the
  // target, L_step varying by less than 1 cm (and within 0.03 m of a requested step length).
  const GaitMetrics& m = run.metrics;
  return r.success && !m.fell && m.steps >= 30 && !record->swing.empty() &&
         std::abs(m.v_m - options.target_v_m) <= kAcceptedVelocityError &&
         m.l_step_spread < kAcceptedStepSpread &&
         (options.target_l_step <= 0.0 ||
          std::abs(m.l_step - options.target_l_step) <= kAcceptedStepLengthError);
}

// Before any work: the database folder is rabbit's own (or new), the gait's file is a gait of
// rabbit's (or new) under a name that is not one of the database's own files, and no other
// rabbit writes the database meanwhile (the lock, held until the caller has written).
OutputLock ClaimGaitDatabase(const std::string& dir, const std::vector<std::string>& names) {
  CheckGaitDatabaseOutput("--dir", dir);
  OutputLock lock(dir, "--dir");
  CheckGaitDatabaseOutput("--dir", dir);
  for (const std::string& name : names) {
    if (IsReservedGaitName(name)) {
      throw InputError("--name", 0, name,
                       "is the name of one of the database's own files (" + name +
                           ".csv): give the gait another name");
    }
    CheckOwnedFile("--dir", std::filesystem::path(dir) / (name + ".csv"),
                   std::string("# format = ") + kGaitFormat, "a gait file of rabbit");
  }
  return lock;
}

std::string DefaultName(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "vm_%.2f", v);
  return buffer;
}

int RunSynthesize(const SynthesizeArgs& a) {
  SynthesisOptions options;
  options.target_v_m = a.v_m;
  options.target_l_step = a.l_step;
  options.seed = a.seed;
  options.budget = a.budget;
  std::string error;
  if (!options.IsValid(&error)) {
    std::cerr << "rabbit gaits synthesize: " << error << "\n";
    return 2;
  }
  GaitRecord record;
  const std::string name = a.name.empty() ? DefaultName(a.v_m) : a.name;
  if (!IsSafeName(name)) {
    std::cerr << "rabbit gaits synthesize: --name: use letters, digits, '.', '_' and '-' only\n";
    return 2;
  }
  const OutputLock database_lock = ClaimGaitDatabase(a.dir, {name});
  const bool ok = SynthesizeOne(options, name, a.quiet, &record);
  if (record.swing.empty() || (!ok && !a.force)) {
    std::cerr << "rabbit gaits synthesize: the gait misses the criteria; nothing written (--force "
                 "stores it anyway)\n";
    return 1;
  }
  const std::string path = AddGaitToDatabase(record, a.dir);
  if (!a.quiet) std::printf("wrote %s and %s/index.csv\n", path.c_str(), a.dir.c_str());
  return ok ? 0 : 1;
}

struct GenerateArgs {
  std::string config;
  std::string dir = "gaits/reference";
  int jobs = 0;
  bool force = false;
  bool quiet = false;
};

// The default targets: the chapter's Table 2 (V_M, L_step).
std::vector<SynthesisOptions> DefaultTargets() {
  const double table[5][2] = {{0.4, 0.24}, {0.5, 0.30}, {0.6, 0.34}, {0.7, 0.38}, {0.8, 0.43}};
  std::vector<SynthesisOptions> out;
  for (const auto& row : table) {
    SynthesisOptions o;
    o.target_v_m = row[0];
    o.target_l_step = row[1];
    out.push_back(o);
  }
  return out;
}

// A `bounds` table: `name = [lower, upper]` for any of kSynthesisParamNames, over *bounds.
void ReadBounds(TomlReader& t, std::array<std::pair<double, double>, kSynthesisParams>* bounds) {
  if (!t.Has("bounds")) return;
  TomlReader b = t.Table("bounds");
  for (int i = 0; i < kSynthesisParams; ++i) {
    const char* name = kSynthesisParamNames[i];
    if (!b.Has(name)) continue;
    const std::vector<double> v = b.Doubles(name, {}, 2);
    if (!(v[0] < v[1])) b.Fail(name, "need [lower, upper] with lower < upper");
    (*bounds)[i] = {v[0], v[1]};
  }
  b.Finish();
}

std::vector<SynthesisOptions> ReadTargets(const std::string& path, std::vector<int>* lines) {
  TomlReader root = TomlReader::ParseFile(path);
  std::array<std::pair<double, double>, kSynthesisParams> common = DefaultSynthesisBounds();
  ReadBounds(root, &common);
  std::vector<SynthesisOptions> out;
  for (TomlReader& t : root.TableArray("gait")) {
    SynthesisOptions o;
    o.bounds = common;
    ReadBounds(t, &o.bounds);
    o.target_v_m = t.RequiredDouble("v_m");
    o.target_l_step = t.Double("l_step", 0.0);
    o.seed = static_cast<unsigned>(t.Integer("seed", o.seed, 0, 4294967295L));
    o.budget = static_cast<int>(t.Integer("budget", o.budget, 1, 1000000));
    t.Finish();
    std::string error;
    if (!o.IsValid(&error)) t.Fail("", error);
    out.push_back(o);
    lines->push_back(t.line());
  }
  root.Finish();
  if (out.empty()) root.Fail("gait", "no [[gait]] targets");
  return out;
}

int RunGenerate(const GenerateArgs& a) {
  std::vector<int> lines;
  const std::vector<SynthesisOptions> targets =
      a.config.empty() ? DefaultTargets() : ReadTargets(a.config, &lines);
  // Two targets of one name would write one gait file: refused, naming both.
  std::vector<std::string> names;
  for (size_t i = 0; i < targets.size(); ++i) {
    names.push_back(DefaultName(targets[i].target_v_m));
    for (size_t j = 0; j < i; ++j) {
      if (names[j] != names[i]) continue;
      auto where = [&](size_t k) {
        return "target " + std::to_string(k + 1) +
               (lines.empty() ? std::string() : " (line " + std::to_string(lines[k]) + ")");
      };
      throw InputError(a.config.empty() ? "the default targets" : a.config,
                       lines.empty() ? 0 : lines[i], "v_m",
                       where(j) + " and " + where(i) + " are both gait " + names[i] +
                           ": give each target its own velocity");
    }
  }
  const OutputLock database_lock = ClaimGaitDatabase(a.dir, names);
  std::vector<GaitRecord> records(targets.size());
  std::vector<char> ok(targets.size(), 0);
  std::vector<std::string> errors(targets.size());
  const auto start = std::chrono::steady_clock::now();
  // Each target is an independent search (its own simulations and NLopt state): run them on
  // all cores; each is deterministic for its seed, whatever the number of threads.
  std::atomic<size_t> next{0};
  std::mutex print;
  auto worker = [&] {
    for (size_t i = next++; i < targets.size(); i = next++) {
      GaitRecord record;
      bool met = false;
      try {
        met = SynthesizeOne(targets[i], DefaultName(targets[i].target_v_m), true, &record);
      } catch (const std::exception& e) {  // kept per target; the others go on
        errors[i] = e.what();
      }
      records[i] = record;
      ok[i] = met;
      if (!a.quiet) {
        std::lock_guard<std::mutex> lock(print);
        std::printf("%s: %s; %d steps, V_M %.3f m/s, L_step %.3f m (spread %.4f)\n",
                    record.name.c_str(), met ? "criteria met" : "criteria NOT met",
                    record.measured.steps, record.measured.v_m, record.measured.l_step,
                    record.measured.l_step_spread);
        std::fflush(stdout);
      }
    }
  };
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int jobs =
      std::min(static_cast<int>(targets.size()), a.jobs > 0 ? std::min(a.jobs, 4 * cores) : cores);
  std::vector<std::thread> threads;
  for (int j = 0; j < jobs; ++j) threads.emplace_back(worker);
  for (std::thread& t : threads) t.join();
  int failures = 0;
  for (size_t i = 0; i < records.size(); ++i) {
    if (!errors[i].empty()) std::fprintf(stderr, "target %zu: %s\n", i + 1, errors[i].c_str());
    failures += ok[i] ? 0 : 1;
    // A gait that misses the criteria never replaces a stored one, unless --force.
    if (records[i].swing.empty() || (!ok[i] && !a.force)) continue;
    AddGaitToDatabase(records[i], a.dir);
  }
  if (!a.quiet) {
    std::printf("generated %zu gaits in %s (%.1f s wall, %d jobs); %d missed the criteria\n",
                records.size(), a.dir.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                jobs, failures);
  }
  return failures == 0 ? 0 : 1;
}

int RunList(const std::string& dir) {
  const std::vector<GaitIndexEntry> entries =
      ReadGaitIndex((std::filesystem::path(dir) / "index.csv").string());
  std::printf("%-10s %9s %9s %9s %8s %6s  %s\n", "name", "target", "V_M m/s", "L_step m",
              "t_step s", "steps", "source");
  for (const GaitIndexEntry& e : entries) {
    std::printf("%-10s %9.3f %9.3f %9.3f %8.3f %6d  %s\n", e.name.c_str(), e.target_v_m,
                e.measured_v_m, e.l_step, e.t_step, e.steps, e.source.c_str());
  }
  return 0;
}

}  // namespace

Command RegisterGaits(CLI::App* app) {
  CLI::App* gaits = app->add_subcommand("gaits", "Reference gaits: synthesize, generate, list");
  gaits->require_subcommand(1);
  auto synth = std::make_shared<SynthesizeArgs>();
  CLI::App* s = gaits->add_subcommand(
      "synthesize", "Search the pragmatic rules for a gait at a velocity (NLopt) and store it");
  s->add_option("--vm", synth->v_m, "Target average velocity V_M, m/s")->required();
  s->add_option("--lstep", synth->l_step, "Target step length, m (default: none)");
  s->add_option("--seed", synth->seed, "Seed of the global stage");
  s->add_option("--budget", synth->budget, "Simulations at most")->check(CLI::Range(1, 1000000));
  s->add_option("--dir", synth->dir, "Gait database directory");
  s->add_option("--name", synth->name, "Gait name (default vm_<V>)");
  s->add_flag("--force", synth->force, "Store the gait even if it misses the criteria");
  s->add_flag("--quiet,-q", synth->quiet, "No progress output");
  auto gen = std::make_shared<GenerateArgs>();
  CLI::App* g = gaits->add_subcommand(
      "generate", "Regenerate the reference database: the five gaits of Table 2, or a config's");
  g->add_option("config", gen->config, "TOML with [[gait]] v_m, l_step, seed, budget");
  g->add_option("--dir", gen->dir, "Gait database directory");
  g->add_option("--jobs", gen->jobs, "Parallel searches (default: all cores)")
      ->check(CLI::Range(1, 1024));
  g->add_flag("--quiet,-q", gen->quiet, "No progress output");
  g->add_flag("--force", gen->force, "Store gaits even if they miss the criteria");
  auto report_dir = std::make_shared<std::string>("gaits/reference");
  auto report_out = std::make_shared<std::string>("reports/gaits");
  CLI::App* r = gaits->add_subcommand(
      "report", "Stick diagrams and swing trajectories of a database's gaits (HTML)");
  r->add_option("--dir", *report_dir, "Gait database directory");
  r->add_option("--out", *report_out, "Report directory");
  auto list_dir = std::make_shared<std::string>("gaits/reference");
  CLI::App* l = gaits->add_subcommand("list", "List the gaits of a database");
  l->add_option("--dir", *list_dir, "Gait database directory");
  return {gaits, [=] {
            if (s->parsed()) return RunSynthesize(*synth);
            if (g->parsed()) return RunGenerate(*gen);
            if (r->parsed()) {
              std::printf("wrote %s\n", WriteGaitReport(*report_dir, *report_out).c_str());
              return 0;
            }
            if (l->parsed()) return RunList(*list_dir);
            return 2;
          }};
}

}  // namespace rabbit::cli
