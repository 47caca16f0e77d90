// rabbit gaits synthesize | generate | report | list: the reference-gait database.
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
#include "gait_synthesis.h"
#include "gait_targets.h"
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
constexpr int kRecordSteps = 30;                   // steps the recorded walk must take
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
  std::string role = "speed";
  int threads = 1;
  bool force = false;
  bool quiet = false;
};

// Synthesizes one gait and re-walks it long enough to measure it (30+ steps); fills *record.
// When the gait misses the criteria, *limits (if given) says what stops it.
bool SynthesizeOne(const SynthesisOptions& options, const std::string& name, bool quiet,
                   GaitRecord* record, std::vector<std::string>* limits = nullptr) {
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
  GaitRun run = WalkGait(record_setup, r.spec, kRecordWalk, 10);
  double record_walk = kRecordWalk;
  if (!run.metrics.fell && run.metrics.steps > 12 && run.metrics.steps < kRecordSteps) {
    // A slow-stepping gait (t_step over 20 s / 30): walked for the time of 31 steps at its pace.
    record_walk = kRecordWalk * (kRecordSteps + 1) / run.metrics.steps;
    run = WalkGait(record_setup, r.spec, record_walk, 10);
  }
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
    std::printf(
        "%s: %s after %d simulations (%d walked, %d of them ahead on %d threads; %.1f s, "
        "%.1f walks/s)\n",
        name.c_str(), r.success ? "criteria met" : "criteria NOT met", r.evaluations, r.walks,
        r.walks_ahead, options.threads, r.wall_seconds, r.walks / std::max(r.wall_seconds, 1e-9));
    std::printf(
        "  %d steps in %.0f s%s; last 10: V_M %.3f m/s (spread %.3f), L_step %.3f m "
        "(spread %.4f), t_step %.3f s\n",
        run.metrics.steps, record_walk,
        run.metrics.fell ? (" (" + run.metrics.reason + ")").c_str() : "", run.metrics.v_m,
        run.metrics.v_m_spread, run.metrics.l_step, run.metrics.l_step_spread, run.metrics.t_step);
  }
  // The acceptance on the recorded walk: 30 steps, the last 10 within 0.03 m/s of the
  // target, L_step varying by less than 1 cm (and within 0.03 m of a requested step length).
  const GaitMetrics& m = run.metrics;
  std::vector<std::string> missed = r.limits;
  if (r.success) {  // the search's criteria met: the acceptance of the recorded walk
    char text[200];
    if (m.fell || record->swing.empty()) {
      std::snprintf(text, sizeof text,
                    "the %.0f s walk of the found gait falls after %d steps (%s)", record_walk,
                    m.steps, m.reason.c_str());
      missed.push_back(text);
    } else if (m.steps < kRecordSteps) {
      std::snprintf(text, sizeof text,
                    "the found gait takes %d steps in %.0f s, fewer than the %d its record needs",
                    m.steps, record_walk, kRecordSteps);
      missed.push_back(text);
    } else {
      if (std::abs(m.v_m - options.target_v_m) > kAcceptedVelocityError) {
        std::snprintf(text, sizeof text, "over %.0f s, V_M %.3f m/s drifts %.3f from the target",
                      record_walk, m.v_m, m.v_m - options.target_v_m);
        missed.push_back(text);
      }
      if (!(m.l_step_spread < kAcceptedStepSpread)) {
        std::snprintf(text, sizeof text, "over %.0f s, L_step varies by %.4f m", record_walk,
                      m.l_step_spread);
        missed.push_back(text);
      }
      if (options.target_l_step > 0.0 &&
          std::abs(m.l_step - options.target_l_step) > kAcceptedStepLengthError) {
        std::snprintf(text, sizeof text, "over %.0f s, L_step %.3f m drifts %.3f from the target",
                      record_walk, m.l_step, m.l_step - options.target_l_step);
        missed.push_back(text);
      }
    }
  }
  if (!quiet && !missed.empty()) {
    std::printf("  what stops it:\n");
    for (const std::string& why : missed) std::printf("    - %s\n", why.c_str());
  }
  if (limits != nullptr) *limits = missed;
  return r.success && missed.empty();
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
  const OutputLock database_lock = ClaimGaitDatabase(a.dir, {name});
  const bool ok = SynthesizeOne(options, name, a.quiet, &record);
  record.role = role;
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
  int threads = 1;
  bool force = false;
  bool quiet = false;
};

int RunGenerate(const GenerateArgs& a) {
  std::vector<GaitTarget> targets =
      a.config.empty() ? DefaultGaitTargets() : ReadGaitTargets(a.config);
  for (GaitTarget& t : targets) t.options.threads = a.threads;
  std::vector<std::string> names;
  for (const GaitTarget& t : targets) names.push_back(t.name);  // distinct: ReadGaitTargets
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
      std::vector<std::string> limits;
      const auto started = std::chrono::steady_clock::now();
      try {
        met = SynthesizeOne(targets[i].options, targets[i].name, true, &record, &limits);
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
  int failures = 0, written = 0;
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
    AddGaitToDatabase(records[i], a.dir);
    ++written;
  }
  if (!a.quiet) {
    std::printf("wrote %d of %zu gaits in %s (%.1f s wall, %d jobs); %d missed the criteria\n",
                written, records.size(), a.dir.c_str(),
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                jobs, failures);
  }
  return failures == 0 ? 0 : 1;
}

int RunList(const std::string& dir) {
  const std::vector<GaitIndexEntry> entries =
      ReadGaitIndex((std::filesystem::path(dir) / "index.csv").string());
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

constexpr const char* kDatabaseHelp = "Gait database folder (a default is below the data root)";

}  // namespace

Command RegisterGaits(CLI::App* app) {
  CLI::App* gaits =
      app->add_subcommand("gaits", "Reference gaits: synthesize, generate, report, list");
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
  DataDefault(s, s->add_option("--dir", synth->dir, kDatabaseHelp), &synth->dir);
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
  DataDefault(g, g->add_option("--dir", gen->dir, kDatabaseHelp), &gen->dir);
  g->add_option("--jobs,-j", gen->jobs, "Parallel searches (0: all cores)")
      ->check(CLI::Range(0, 1024));
  g->add_option("--threads", gen->threads,
                "Walks evaluated at once within each search (the result is the same for any value)")
      ->check(CLI::Range(1, 1024));
  g->add_flag("--quiet,-q", gen->quiet, "No progress output");
  g->add_flag("--force", gen->force, "Store gaits even if they miss the criteria");
  auto report_dir = std::make_shared<std::string>("gaits/reference");
  auto report_out = std::make_shared<std::string>("reports/gaits");
  CLI::App* r = gaits->add_subcommand(
      "report", "Stick diagrams and swing trajectories of a database's gaits (HTML)");
  DataDefault(r, r->add_option("--dir", *report_dir, kDatabaseHelp), report_dir.get());
  r->add_option("--out,-o", *report_out, "Report folder to write (index.html and its figures)");
  auto report_quiet = std::make_shared<bool>(false);
  r->add_flag("--quiet,-q", *report_quiet, "Print nothing but errors");
  auto list_dir = std::make_shared<std::string>("gaits/reference");
  CLI::App* l = gaits->add_subcommand("list", "List the gaits of a database");
  DataDefault(l, l->add_option("--dir", *list_dir, kDatabaseHelp), list_dir.get());
  return {gaits, [=] {
            if (s->parsed()) return RunSynthesize(*synth);
            if (g->parsed()) return RunGenerate(*gen);
            if (r->parsed()) {
              const std::string page = WriteGaitReport(*report_dir, *report_out);
              if (!*report_quiet) std::printf("wrote %s\n", page.c_str());
              return 0;
            }
            if (l->parsed()) return RunList(*list_dir);
            return 2;
          }};
}

}  // namespace rabbit::cli
