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
#include "gait_build.h"
#include "gait_synthesis.h"
#include "gait_targets.h"
#include "rabbit/gait/database_layout.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/io/error.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/report/gait_report.h"
#include "rabbit/scenario/ranks.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit::cli {
namespace {

// The reference/ folder of the database `dir` names (or `dir` itself when it is one).
std::string ReferenceFolder(const std::string& dir) {
  if (std::filesystem::exists(std::filesystem::path(dir) / "index.csv")) return dir;
  return ReferenceDirOf(GaitDatabaseRoot(dir));
}

struct BuildArgs {
  std::string targets = "gaits/targets.toml";
  std::string out;
  int jobs = 0;
  bool quiet = false;
};

int RunBuild(const BuildArgs& a) {
  const GaitTargets targets = ReadGaitTargets(a.targets);
  GaitBuildOptions options;
  options.out = a.out;
  options.threads = a.jobs;
  if (!a.quiet) {
    options.log = [](const std::string& line) {
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    };
  }
  const GaitBuildResult r = BuildGaitDatabase(targets, options);
  if (!Ranks::root()) return r.exit_code();
  for (const std::string& name : r.missed) {
    std::fprintf(stderr,
                 "rabbit gaits build: %s (%s) misses its criteria: nothing written for it\n",
                 name.c_str(), a.targets.c_str());
  }
  for (const std::string& run : r.check_failures) {
    std::fprintf(stderr, "rabbit gaits build: check walk %s failed\n", run.c_str());
  }
  if (!a.quiet) {
    std::printf(
        "gaits build: %zu built, %zu kept, %zu missed; %ld walks in %.1f s (%.1f walks/s); "
        "%.1f s wall; wrote %s\n",
        r.built.size(), r.kept.size(), r.missed.size(), r.walks, r.synthesis_seconds,
        static_cast<double>(r.walks) / std::max(r.synthesis_seconds, 1e-9), r.wall_seconds,
        a.out.c_str());
  }
  return r.exit_code();
}

struct SynthesizeArgs {
  double v_m = 0.0;
  double l_step = 0.0;
  unsigned seed = 1;
  int budget = 1500;
  std::string dir = "gaits";  // database (or its reference/ folder)
  std::string reference_dir;  // --dir: the reference folder itself (older form)
  std::string name;
  bool force = false;
  bool quiet = false;
};

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
  const std::string name = a.name.empty() ? DefaultGaitName(a.v_m) : a.name;
  if (!IsSafeName(name)) {
    std::cerr << "rabbit gaits synthesize: --name: use letters, digits, '.', '_' and '-' only\n";
    return 2;
  }
  const bool ok = SynthesizeReferenceGait(options, ModelParams{}, name, a.quiet, &record);
  if (record.swing.empty() || (!ok && !a.force)) {
    std::cerr << "rabbit gaits synthesize: the gait misses the criteria; nothing written (--force "
                 "stores it anyway)\n";
    return 1;
  }
  const std::string reference = a.reference_dir.empty() ? ReferenceFolder(a.dir) : a.reference_dir;
  const std::string path = AddGaitToDatabase(record, reference);
  if (!a.quiet) std::printf("wrote %s and %s/index.csv\n", path.c_str(), reference.c_str());
  return ok ? 0 : 1;
}

struct GenerateArgs {
  std::string config;
  std::string dir = "gaits";
  std::string reference_dir;  // --dir: the reference folder itself (older form)
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

int RunGenerate(const GenerateArgs& a) {
  std::vector<SynthesisOptions> targets;
  std::vector<std::string> names;
  if (a.config.empty()) {
    targets = DefaultTargets();
    for (const SynthesisOptions& t : targets) names.push_back(DefaultGaitName(t.target_v_m));
  } else {
    for (const GaitTarget& t : ReadGaitTargets(a.config).gaits) {
      targets.push_back(t.synthesis);
      names.push_back(t.name);
    }
  }
  const std::string reference = a.reference_dir.empty() ? ReferenceFolder(a.dir) : a.reference_dir;
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
        met = SynthesizeReferenceGait(targets[i], ModelParams{}, names[i], true, &record);
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
    AddGaitToDatabase(records[i], reference);
  }
  if (!a.quiet) {
    std::printf("generated %zu gaits in %s (%.1f s wall, %d jobs); %d missed the criteria\n",
                records.size(), reference.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                jobs, failures);
  }
  return failures == 0 ? 0 : 1;
}

int RunList(const std::string& dir) {
  const std::vector<GaitIndexEntry> entries =
      ReadGaitIndex((std::filesystem::path(ReferenceFolder(dir)) / "index.csv").string());
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
  CLI::App* gaits =
      app->add_subcommand("gaits", "Reference gaits: build, synthesize, generate, list, report");
  gaits->require_subcommand(1);
  auto synth = std::make_shared<SynthesizeArgs>();
  CLI::App* s = gaits->add_subcommand(
      "synthesize", "Search the pragmatic rules for a gait at a velocity (NLopt) and store it");
  s->add_option("--vm", synth->v_m, "Target average velocity V_M, m/s")->required();
  s->add_option("--lstep", synth->l_step, "Target step length, m (default: none)");
  s->add_option("--seed", synth->seed, "Seed of the global stage");
  s->add_option("--budget", synth->budget, "Simulations at most")->check(CLI::Range(1, 1000000));
  s->add_option("--gaits", synth->dir, "Gait database to add the gait to (default gaits)");
  s->add_option("--dir", synth->reference_dir, "A reference folder (older form)")->group("");
  s->add_option("--name", synth->name, "Gait name (default vm_<V>)");
  s->add_flag("--force", synth->force, "Store the gait even if it misses the criteria");
  s->add_flag("--quiet,-q", synth->quiet, "No progress output");
  auto gen = std::make_shared<GenerateArgs>();
  CLI::App* g = gaits->add_subcommand(
      "generate", "Regenerate the reference database: the five gaits of Table 2, or a config's");
  g->add_option("config", gen->config, "TOML with [[gait]] v_m, l_step, seed, budget");
  g->add_option("--gaits", gen->dir, "Gait database to add the gaits to (default gaits)");
  g->add_option("--dir", gen->reference_dir, "A reference folder (older form)")->group("");
  g->add_option("--jobs", gen->jobs, "Parallel searches (default: all cores)")
      ->check(CLI::Range(1, 1024));
  g->add_flag("--quiet,-q", gen->quiet, "No progress output");
  g->add_flag("--force", gen->force, "Store gaits even if they miss the criteria");
  auto report_dir = std::make_shared<std::string>("gaits");
  auto report_out = std::make_shared<std::string>("reports/gaits");
  CLI::App* r = gaits->add_subcommand(
      "report", "Stick diagrams and swing trajectories of a database's gaits (HTML)");
  r->add_option("--gaits", *report_dir, "Gait database (default gaits)");
  r->add_option("--dir", *report_dir, "Same as --gaits")->group("");
  r->add_option("--out", *report_out, "Report directory");
  auto list_dir = std::make_shared<std::string>("gaits");
  CLI::App* l = gaits->add_subcommand("list", "List the gaits of a database");
  l->add_option("--gaits", *list_dir, "Gait database (default gaits)");
  l->add_option("--dir", *list_dir, "Same as --gaits")->group("");
  auto build = std::make_shared<BuildArgs>();
  CLI::App* b = gaits->add_subcommand(
      "build",
      "Build a whole gait database from a targets file (synthesis, networks, FLL, manifest)");
  b->add_option("targets", build->targets, "Targets file (TOML; default gaits/targets.toml)");
  b->add_option("--out", build->out, "Database folder: new, empty, or a database to resume")
      ->required();
  b->add_option("--jobs,-j", build->jobs, "Threads per process (default: all cores)")
      ->check(CLI::Range(0, 1024));
  b->add_flag("--quiet,-q", build->quiet, "No progress output");
  return {gaits, [=] {
            if (s->parsed()) return RunSynthesize(*synth);
            if (g->parsed()) return RunGenerate(*gen);
            if (r->parsed()) {
              std::printf("wrote %s\n",
                          WriteGaitReport(ReferenceFolder(*report_dir), *report_out).c_str());
              return 0;
            }
            if (l->parsed()) return RunList(*list_dir);
            if (b->parsed()) return RunBuild(*build);
            return 2;
          }};
}

}  // namespace rabbit::cli
