// rabbit gaits build | synthesize | generate | report | list: the gait database.
#include <algorithm>
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
#include "cli/data_root.h"
#include "gait_build.h"
#include "gait_synthesis.h"
#include "gait_targets.h"
#include "rabbit/gait/database_commit.h"
#include "rabbit/gait/database_layout.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/io/test_hooks.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/report/gait_report.h"
#include "rabbit/scenario/ranks.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit::cli {
namespace {

// The reference folder the database flags name. A --gaits folder that exists must be a database
// (reference/ or manifest.csv) or empty: rabbit adds nothing to a folder of the user's. `adds`: the
// command adds gaits (a database the build made is only read).
std::string Reference(const std::string& dir, const std::string& reference_dir, bool adds = true) {
  if (!reference_dir.empty()) return reference_dir;
  namespace fs = std::filesystem;
  if (fs::exists(fs::path(dir) / kIndexFile)) return dir;
  const fs::path root = GaitDatabaseRoot(dir);
  std::error_code error;
  if (adds && fs::exists(root / kManifestFile)) {
    // A built database is changed as a whole: adding a gait alone would leave its networks, fuzzy
    // system and manifest behind.
    throw InputError("--gaits", 0, dir,
                     "is a database made by rabbit gaits build: add the gait to its targets file "
                     "and build it again (rabbit gaits build TARGETS --out DIR resumes)");
  }
  if (fs::is_directory(root, error) && !fs::is_empty(root, error) &&
      !fs::exists(root / kReferenceDir) && !fs::exists(root / kManifestFile)) {
    throw InputError("--gaits", 0, dir,
                     "is not a gait database (no reference/ folder, no manifest.csv, not empty): "
                     "refusing to write into it");
  }
  if (fs::exists(root) && !fs::is_directory(root, error)) {
    throw InputError("--gaits", 0, dir, "is not a folder");
  }
  return ReferenceDirOf(root.string());
}

struct BuildArgs {
  std::string targets = "gaits/targets.toml";
  std::string out;
  int jobs = 0;
  bool quiet = false;
};

int RunBuild(const BuildArgs& a) {
  const GaitTargets targets = ReadGaitTargets(a.targets);
  const auto speed_targets =
      std::count_if(targets.gaits.begin(), targets.gaits.end(),
                    [](const GaitTarget& g) { return g.role == GaitRole::kSpeed; });
  if (speed_targets < 2) {
    throw InputError(a.targets, 0, "gait",
                     "a database needs at least 2 speed gaits (the fuzzy system blends them); "
                     "found " +
                         std::to_string(speed_targets));
  }
  // One build of a database at a time (rank 0 holds the lock; every rank agrees on whether it got
  // it, so none is left waiting).
  // The path itself is the database's root: not a symbolic link to one (nor a dangling one).
  CheckOutputParents("--out", a.out);
  if (const std::string link = SymbolicLinkRefusal(a.out, "a gait database"); !link.empty()) {
    throw InputError("--out", 0, a.out, link);
  }
  OutputLock lock;
  RunAgreed([&] {
    if (Ranks::root()) lock = OutputLock(a.out, "--out");
  });
  GaitBuildOptions options;
  options.out = a.out;
  options.threads = a.jobs;
  if (!a.quiet) {
    options.log = [](const std::string& line) {
      std::printf("%s\n", line.c_str());
      std::fflush(stdout);
    };
  }
  bool staged = false;
  options.staged = &staged;
  GaitBuildResult r;
  try {
    r = BuildGaitDatabase(targets, options);
  } catch (...) {
    if (staged) {
      std::fprintf(stderr,
                   "rabbit gaits build: the gaits synthesized so far stay in %s/.build; the next "
                   "build of %s takes those whose targets are unchanged\n",
                   a.out.c_str(), a.out.c_str());
    }
    throw;
  }
  if (!Ranks::root()) return r.exit_code();
  for (const std::string& name : r.missed) {
    std::fprintf(stderr,
                 "rabbit gaits build: %s (%s) misses its criteria: nothing written for it\n",
                 name.c_str(), a.targets.c_str());
  }
  for (const std::string& run : r.check_failures) {
    std::fprintf(stderr, "rabbit gaits build: check walk %s failed\n", run.c_str());
  }
  if (r.too_few_speed_gaits) {
    std::fprintf(stderr,
                 "rabbit gaits build: fewer than 2 speed gaits met their criteria (the fuzzy "
                 "system blends at least 2): nothing written to %s\n",
                 a.out.c_str());
  }
  if (!a.quiet) {
    const std::string reused =
        r.reused.empty() ? ""
                         : " (" + std::to_string(r.reused.size()) +
                               " of them synthesized by an unfinished build of this folder)";
    std::printf(
        "gaits build: %zu built%s, %zu kept, %zu missed; %ld walks in %.1f s (%.1f walks/s); "
        "%.1f s wall; %s %s\n",
        r.built.size(), reused.c_str(), r.kept.size(), r.missed.size(), r.walks,
        r.synthesis_seconds, static_cast<double>(r.walks) / std::max(r.synthesis_seconds, 1e-9),
        r.wall_seconds, r.too_few_speed_gaits ? "nothing written to" : "wrote", a.out.c_str());
  }
  return r.exit_code();
}

struct SynthesizeArgs {
  double v_m = 0.0;
  double l_step = 0.0;
  unsigned seed = 1;
  int budget = 1500;
  std::string dir = "gaits";  // --gaits: a database (or its reference/ folder)
  std::string reference_dir;  // --dir: the reference folder itself (older form)
  std::string name;
  std::string role = "speed";
  int threads = 1;
  bool force = false;
  bool quiet = false;
};

// Before any work: the database folder is rabbit's own (or new), the gait's file is a gait of
// rabbit's (or new) under a name that is not one of the database's own files, and no other
// rabbit writes the database meanwhile (the database's one lock, on its root, held until the
// caller has written). What a killed writer left in the reference folder is finished or removed.
OutputLock ClaimGaitDatabase(const std::string& dir, const std::vector<std::string>& names) {
  CheckGaitDatabaseOutput("--gaits", dir);
  const std::string root = DatabaseRootOf(dir);
  OutputLock lock(root.empty() ? dir : root, "--gaits");
  CheckGaitDatabaseOutput("--gaits", dir);
  for (const std::string& name : names) {
    if (IsReservedGaitName(name)) {
      throw InputError("--name", 0, name,
                       "is the name of one of the database's own files (" + name +
                           ".csv): give the gait another name");
    }
    CheckOwnedFile("--gaits", std::filesystem::path(dir) / (name + ".csv"),
                   std::string("# format = ") + kGaitFormat, "a gait file of rabbit");
  }
  FinishGaitCommit(dir);
  // The index the new gaits join, read now as the commit will read it: a bad row is named before
  // the synthesis, not after it.
  const std::filesystem::path index = std::filesystem::path(dir) / kGaitIndexFile;
  if (std::filesystem::exists(index)) ReadGaitIndex(index.string());
  TestKillPoint("gaits-claimed");
  return lock;
}

int RunSynthesize(const SynthesizeArgs& a) {
  SynthesisOptions options;
  options.target_v_m = a.v_m;
  options.target_l_step = a.l_step;
  options.seed = a.seed;
  options.budget = a.budget;
  options.threads = a.threads;
  std::string error;
  if (!options.IsValid(&error)) {
    std::cerr << "rabbit gaits synthesize: " << error << "\n";
    return 2;
  }
  GaitRole role = GaitRole::kSpeed;
  if (!ParseGaitRole(a.role, &role) || (role == GaitRole::kLibrary && !(a.l_step > 0.0))) {
    std::cerr << "rabbit gaits synthesize: --role: speed, or library with an --lstep\n";
    return 2;
  }
  GaitRecord record;
  const std::string name = a.name.empty() ? DefaultGaitName(a.v_m, a.l_step, role) : a.name;
  if (!IsSafeName(name)) {
    std::cerr << "rabbit gaits synthesize: --name: " << SafeNameRule(name) << "\n";
    return 2;
  }
  const std::string reference = Reference(a.dir, a.reference_dir);
  const OutputLock database_lock = ClaimGaitDatabase(reference, {name});
  const bool ok = SynthesizeReferenceGait(options, ModelParams{}, name, a.quiet, &record);
  record.role = role;
  if (record.swing.empty() || (!ok && !a.force)) {
    std::cerr << "rabbit gaits synthesize: the gait misses the criteria; nothing written (--force "
                 "stores it anyway)\n";
    return 1;
  }
  const std::string path = AddGaitToDatabase(record, reference);
  if (!a.quiet) std::printf("wrote %s and %s/index.csv\n", path.c_str(), reference.c_str());
  return ok ? 0 : 1;
}

struct GenerateArgs {
  std::string config;
  std::string dir = "gaits";  // --gaits: a database (or its reference/ folder)
  std::string reference_dir;  // --dir: the reference folder itself (older form)
  int jobs = 0;
  int threads = 1;
  bool force = false;
  bool quiet = false;
};

int RunGenerate(const GenerateArgs& a) {
  GaitTargets file;
  if (!a.config.empty()) file = ReadGaitTargets(a.config);
  std::vector<GaitTarget> targets = a.config.empty() ? DefaultGaitTargets() : file.gaits;
  for (GaitTarget& t : targets) t.synthesis.threads = a.threads;
  std::vector<std::string> names;
  for (const GaitTarget& t : targets) names.push_back(t.name);  // distinct: ReadGaitTargets
  const std::string reference = Reference(a.dir, a.reference_dir);
  const OutputLock database_lock = ClaimGaitDatabase(reference, names);
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
      std::vector<std::string> limits;
      const auto started = std::chrono::steady_clock::now();
      try {
        met = SynthesizeReferenceGait(targets[i].synthesis, file.model, targets[i].name, true,
                                      &record, nullptr, &limits);
      } catch (const std::exception& e) {  // kept per target; the others go on
        errors[i] = e.what();
      }
      record.role = targets[i].role;
      records[i] = record;
      ok[i] = met;
      if (!a.quiet) {
        std::lock_guard<std::mutex> lock(print);
        std::printf(
            "%s: %s; %d steps, V_M %.3f m/s, L_step %.3f m (spread %.4f); %.1f s\n",
            targets[i].name.c_str(), met ? "criteria met" : "criteria NOT met",
            record.measured.steps, record.measured.v_m, record.measured.l_step,
            record.measured.l_step_spread,
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
        for (const std::string& why : limits) std::printf("  - %s\n", why.c_str());
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
  std::vector<GaitRecord> kept;
  for (size_t i = 0; i < records.size(); ++i) {
    if (!errors[i].empty()) std::fprintf(stderr, "target %zu: %s\n", i + 1, errors[i].c_str());
    failures += ok[i] ? 0 : 1;
    if (!ok[i] && !a.quiet) {
      std::fprintf(stderr, "%s (target at %s line %d) misses its criteria%s\n",
                   targets[i].name.c_str(), a.config.c_str(), targets[i].line,
                   a.force ? "; stored anyway (--force)" : "; nothing written for it");
    }
    // A gait that misses the criteria never replaces a stored one, unless --force.
    if (records[i].swing.empty() || (!ok[i] && !a.force)) continue;
    kept.push_back(records[i]);
  }
  // Every gait and the index in one commit.
  if (!kept.empty()) AddGaitsToDatabase(kept, reference);
  const int written = static_cast<int>(kept.size());
  if (!a.quiet) {
    std::printf("wrote %d of %zu gaits in %s (%.1f s wall, %d jobs); %d missed the criteria\n",
                written, records.size(), reference.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                jobs, failures);
  }
  return failures == 0 ? 0 : 1;
}

int RunList(const std::string& dir) {
  const std::vector<GaitIndexEntry> entries =
      ReadGaitIndex((std::filesystem::path(dir) / kIndexFile).string());
  std::printf("%-16s %-8s %9s %9s %9s %9s %8s %6s  %s\n", "name", "role", "target", "target",
              "V_M m/s", "L_step m", "t_step s", "steps", "source");
  std::printf("%-16s %-8s %9s %9s\n", "", "", "V_M m/s", "L_step m");
  for (const GaitIndexEntry& e : entries) {
    std::printf("%-16s %-8s %9.3f %9.3f %9.3f %9.3f %8.3f %6d  %s\n", e.name.c_str(),
                GaitRoleName(e.role), e.target_v_m, e.target_l_step, e.measured_v_m, e.l_step,
                e.t_step, e.steps, e.source.c_str());
  }
  return 0;
}

constexpr const char* kDatabaseHelp =
    "Gait database folder, or its reference/ folder (a default is below the data root)";

// --gaits DIR (a database, or its reference/ folder), and the older --dir REFERENCE (the
// reference folder itself, hidden).
void DatabaseOption(CLI::App* cmd, std::string* dir, std::string* reference_dir) {
  CLI::Option* gaits = DataDefault(cmd, cmd->add_option("--gaits", *dir, kDatabaseHelp), dir);
  CLI::Option* older = cmd->add_option("--dir", *reference_dir,
                                       "The reference folder itself (older form of --gaits)")
                           ->group("")
                           ->excludes(gaits);
  DataDefaultUnusedWith(gaits, older);
}

}  // namespace

Command RegisterGaits(CLI::App* app) {
  CLI::App* gaits =
      app->add_subcommand("gaits", "Gait databases: build, synthesize, generate, report, list");
  gaits->require_subcommand(1);
  auto synth = std::make_shared<SynthesizeArgs>();
  CLI::App* s = gaits->add_subcommand(
      "synthesize", "Search the pragmatic rules for a gait at a velocity (NLopt) and store it");
  s->add_option("--vm", synth->v_m, "Target average velocity V_M, m/s")->required();
  s->add_option("--lstep", synth->l_step, "Target step length, m (0: none)");
  s->add_option("--seed", synth->seed,
                "Seed of the global stage (the search is deterministic for it)");
  s->add_option("--budget", synth->budget, "Simulations (walks) at most")
      ->check(CLI::Range(1, 1000000));
  DatabaseOption(s, &synth->dir, &synth->reference_dir);
  s->add_option(
      "--name", synth->name,
      "Gait name (default: vm_<V_M>, e.g. vm_0.60, or vm_<V_M>_l_<L> for a library gait)");
  s->add_option("--role", synth->role,
                "speed (a gait the walker blends over V_M) or library (needs --lstep)")
      ->check(CLI::IsMember({"speed", "library"}));
  s->add_option("--threads", synth->threads,
                "Walks evaluated at once (the result is the same for any value)")
      ->check(CLI::Range(1, 1024));
  s->add_flag("--force", synth->force, "Store the gait even if it misses the criteria");
  s->add_flag("--quiet,-q", synth->quiet, "No progress output");
  auto gen = std::make_shared<GenerateArgs>();
  CLI::App* g = gaits->add_subcommand(
      "generate",
      "Regenerate the reference database: from a config's [[gait]] targets (the shipped eight: "
      "gaits/targets.toml), or without one the chapter's five of Table 2 (0.4 to 0.8 m/s)");
  g->add_option(
      "config", gen->config,
      "TOML with [[gait]] v_m, l_step, seed, budget (default: none, the five of Table 2)");
  DatabaseOption(g, &gen->dir, &gen->reference_dir);
  g->add_option("--jobs,-j", gen->jobs, "Parallel searches (0: all cores)")
      ->check(CLI::Range(0, 1024));
  g->add_option("--threads", gen->threads,
                "Walks evaluated at once within each search (the result is the same for any value)")
      ->check(CLI::Range(1, 1024));
  g->add_flag("--quiet,-q", gen->quiet, "No progress output");
  g->add_flag("--force", gen->force, "Store gaits even if they miss the criteria");
  auto report_dir = std::make_shared<std::string>("gaits");
  auto report_reference = std::make_shared<std::string>();
  auto report_out = std::make_shared<std::string>("reports/gaits");
  CLI::App* r = gaits->add_subcommand(
      "report", "Stick diagrams and swing trajectories of a database's gaits (HTML)");
  DatabaseOption(r, report_dir.get(), report_reference.get());
  r->add_option("--out,-o", *report_out, "Report folder to write (index.html and its figures)");
  auto report_quiet = std::make_shared<bool>(false);
  r->add_flag("--quiet,-q", *report_quiet, "Print nothing but errors");
  auto list_dir = std::make_shared<std::string>("gaits");
  auto list_reference = std::make_shared<std::string>();
  CLI::App* l = gaits->add_subcommand("list", "List the gaits of a database");
  DatabaseOption(l, list_dir.get(), list_reference.get());
  auto build = std::make_shared<BuildArgs>();
  CLI::App* b = gaits->add_subcommand(
      "build",
      "Build a whole gait database from a targets file (synthesis, networks, FLL, manifest)");
  DataDefault(b,
              b->add_option("targets", build->targets,
                            "Targets file (TOML; a default is below the data root)"),
              &build->targets);
  b->add_option("--out,-o", build->out,
                "Database folder to write: new, empty, or a database to resume")
      ->required();
  b->add_option("--jobs,-j", build->jobs, "Threads per process (0: all cores)")
      ->check(CLI::Range(0, 1024));
  b->add_flag("--quiet,-q", build->quiet, "Print nothing but errors");
  return {gaits, [=] {
            if (s->parsed()) return RunSynthesize(*synth);
            if (g->parsed()) return RunGenerate(*gen);
            if (r->parsed()) {
              const std::string page =
                  WriteGaitReport(Reference(*report_dir, *report_reference, false), *report_out);
              if (!*report_quiet) std::printf("wrote %s\n", page.c_str());
              return 0;
            }
            if (l->parsed()) return RunList(Reference(*list_dir, *list_reference, false));
            if (b->parsed()) return RunBuild(*build);
            return 2;
          }};
}

}  // namespace rabbit::cli
