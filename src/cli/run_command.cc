// rabbit run [SUITE...] [--out DIR] [--jobs N] [--filter REGEX]: the main job. Runs every scenario
// of the suites (and their baselines) in parallel, writes summary.csv, each run's CSV files and
// index.html. Nothing is written before every suite has loaded; each report is built in a staging
// folder renamed into place at the end, so a failed run never leaves half a report.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "cli/commands.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/io/error.h"
#include "rabbit/report/run_files.h"
#include "rabbit/report/suite_report.h"
#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/suite.h"

namespace rabbit::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kDefaultSuite = "scenarios/paper.toml";
// Written into every report folder: only such folders (or empty ones) are ever replaced.
constexpr const char* kReportMarker = ".rabbit-report";

struct RunArgs {
  std::vector<std::string> suites;
  std::string out;
  int jobs = 0;
  std::string filter;
  std::string params;
  bool quiet = false;
  bool html = true;
  SuiteReportOptions report;
};

// The default suite: scenarios/paper.toml below the working directory, else the one shipped with
// the sources this binary was built from.
std::string DefaultSuite() {
  if (fs::exists(kDefaultSuite)) return kDefaultSuite;
  const fs::path shipped = fs::path(RABBIT_SOURCE_DIR) / kDefaultSuite;
  return fs::exists(shipped) ? shipped.string() : kDefaultSuite;
}

// Removes a staging folder unless released.
struct StagingGuard {
  fs::path path;
  bool keep = false;
  ~StagingGuard() {
    std::error_code ignored;
    if (!keep) fs::remove_all(path, ignored);
  }
};

struct SuiteOutcome {
  int failed_required = 0;
  double simulated = 0.0;
};

// Runs a suite into its staging folder (guard->path); the caller renames it into place once every
// suite has succeeded.
SuiteOutcome RunOneSuite(const Suite& suite, const std::vector<BatchJob>& jobs,
                         const fs::path& out_dir, const RunArgs& args, GaitLibraryCache* libraries,
                         StagingGuard* guard) {
  const fs::path staging = guard->path;
  fs::remove_all(staging);
  fs::create_directories(staging);
  const bool terminal = !args.quiet && ::isatty(STDERR_FILENO) != 0;
  std::vector<std::string> rows(jobs.size());
  std::vector<RunOutput> brief(jobs.size());  // metrics and outcome only (no samples)
  size_t done = 0;
  SuiteOutcome outcome;
  const auto start = std::chrono::steady_clock::now();
  const int threads = BatchThreads(jobs, args.jobs);
  RunBatch(jobs, threads, libraries, [&](size_t i, RunOutput&& run) {
    WriteRunFiles(*jobs[i].scenario, run, staging.string());
    rows[i] = SummaryRow(suite.name, run);
    outcome.simulated += run.sim.t_end;
    if (terminal) {
      std::fprintf(stderr, "\r\033[K[%zu/%zu] %s: %s%s", ++done, jobs.size(), run.run.c_str(),
                   OutcomeName(run.sim.outcome), run.passed ? "" : " (failed criteria)");
      std::fflush(stderr);
    }
    run.sim.samples.clear();
    run.sim.samples.shrink_to_fit();
    run.sim.events.clear();
    run.steps.clear();
    run.tracking.clear();
    brief[i] = std::move(run);
  });
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (terminal) std::fprintf(stderr, "\r\033[K");
  WriteFileAtomically((staging / kReportMarker).string(), [&suite](std::ostream& out) {
    out << "rabbit-report/1 suite " << suite.name << "\n";
  });
  WriteFileAtomically((staging / "summary.csv").string(), [&rows](std::ostream& out) {
    out << SummaryHeader() << "\n";
    for (const std::string& r : rows) out << r << "\n";
  });
  std::vector<std::string> warnings;
  if (args.html) {
    SuiteReportOptions report = args.report;
    report.source_label = out_dir.string();
    WriteSuiteReport(staging.string(), report, &warnings);
  }
  for (const std::string& w : warnings) std::cerr << "rabbit run: warning: " << w << "\n";

  for (size_t i = 0; i < jobs.size(); ++i) {
    const RunOutput& r = brief[i];
    const bool main_variant = r.run == jobs[i].scenario->name;
    if (!r.passed && main_variant && jobs[i].scenario->required) ++outcome.failed_required;
  }
  if (!args.quiet) {
    std::printf(
        "suite      %s (%s): %zu runs in %.1f s wall on %d threads (%.1f runs/min, %.0fx "
        "real time)\n",
        suite.name.c_str(), suite.file.c_str(), jobs.size(), wall, threads,
        wall > 0 ? 60.0 * static_cast<double>(jobs.size()) / wall : 0.0,
        wall > 0 ? outcome.simulated / wall : 0.0);
    std::printf("%-34s %-10s %-6s %6s %8s %9s %8s\n", "run", "outcome", "pass", "steps", "dist m",
                "|V-Vd| m/s", "L_step m");
    for (size_t i = 0; i < jobs.size(); ++i) {
      const RunOutput& r = brief[i];
      std::printf(
          "%-34s %-10s %-6s %6d %8.2f %9.3f %8.3f\n", r.run.c_str(), OutcomeName(r.sim.outcome),
          r.passed ? "yes"
                   : (r.run == jobs[i].scenario->name && jobs[i].scenario->required ? "NO" : "no"),
          r.metrics.steps, r.metrics.distance, r.metrics.mean_abs_speed_error,
          r.metrics.l_step_mean);
      for (const std::string& f : r.failures) std::printf("    - %s\n", f.c_str());
    }
    std::printf("wrote      %s\n",
                (out_dir / (args.html ? "index.html" : "summary.csv")).string().c_str());
  }
  return outcome;
}

int RunRun(RunArgs args) {
  std::string error;
  if (!args.report.IsValid(&error)) {
    std::cerr << "rabbit run: " << error << "\n";
    return 2;
  }
  if (args.suites.empty()) args.suites.push_back(DefaultSuite());
  // Load and plan everything first: bad input leaves nothing behind.
  std::vector<Suite> suites;
  ParamOverlay overlay;
  if (!args.params.empty()) overlay = LoadParamOverlay(args.params);
  for (const std::string& path : args.suites) suites.push_back(LoadSuite(path, &overlay));
  std::vector<std::vector<BatchJob>> plans;
  for (const Suite& s : suites) {
    plans.push_back(PlanBatch(s, args.filter));
    if (plans.back().empty()) {
      throw InputError(s.file, 0, "--filter",
                       "no scenario of suite " + s.name + " matches \"" + args.filter + "\"");
    }
  }
  for (size_t i = 0; i < suites.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (suites[i].name == suites[j].name) {
        throw InputError(suites[i].file, 0, "suite.name",
                         "two suites named \"" + suites[i].name + "\" would share a report");
      }
    }
  }
  int failed = 0;
  // One suite: --out is its report folder; several: --out is their parent. An existing folder is
  // replaced only when it is empty or a report written by rabbit run (has the marker file).
  std::vector<fs::path> outs;
  for (const Suite& suite : suites) {
    fs::path out = args.out.empty()     ? fs::path("reports") / suite.name
                   : suites.size() == 1 ? fs::path(args.out)
                                        : fs::path(args.out) / suite.name;
    out = out.lexically_normal();
    if (out.filename().empty()) out = out.parent_path();  // "dir/" -> "dir"
    if (out.empty() || out == "." || out == "..") {
      throw InputError("--out", 0, args.out, "name a folder for the report");
    }
    if (fs::exists(out) &&
        !(fs::is_directory(out) && (fs::is_empty(out) || fs::exists(out / kReportMarker)))) {
      throw InputError("--out", 0, out.string(),
                       std::string("exists and is not a report of rabbit run (no ") +
                           kReportMarker + "): refusing to replace it");
    }
    outs.push_back(out);
  }
  // Every gait library loads now: a bad gait pattern is bad input, found before anything runs.
  GaitLibraryCache libraries;
  for (const std::vector<BatchJob>& plan : plans) {
    for (const BatchJob& job : plan) {
      if (job.scenario->controller == ControllerKind::kFuzzyCmac) {
        libraries.Get(job.scenario->pattern);
      }
    }
  }
  // All suites run into staging folders; only when every one succeeded are they renamed into
  // place, so a failure in a later suite leaves every earlier report as it was.
  std::vector<std::unique_ptr<StagingGuard>> staged;
  for (size_t i = 0; i < suites.size(); ++i) {
    staged.push_back(std::make_unique<StagingGuard>(
        StagingGuard{outs[i].string() + ".partial-" + std::to_string(::getpid())}));
    failed += RunOneSuite(suites[i], plans[i], outs[i], args, &libraries, staged.back().get())
                  .failed_required;
  }
  for (size_t i = 0; i < suites.size(); ++i) {
    if (fs::exists(outs[i])) fs::remove_all(outs[i]);
    fs::create_directories(outs[i].parent_path().empty() ? "." : outs[i].parent_path());
    fs::rename(staged[i]->path, outs[i]);
    staged[i]->keep = true;
  }
  if (failed > 0) {
    std::cerr << "rabbit run: " << failed << " required scenario(s) failed their criteria\n";
    return 1;
  }
  return 0;
}

}  // namespace

Command RegisterRun(CLI::App* app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = app->add_subcommand(
      "run", "Run scenario suites in parallel and write their report (default: the paper suite)");
  cmd->add_option("suites", args->suites,
                  std::string("Suite files (TOML; default ") + kDefaultSuite + ")");
  cmd->add_option("--out,-o", args->out,
                  "Report folder (one suite; default reports/<suite name>), or the parent of the "
                  "suites' folders (several)");
  cmd->add_option("--jobs,-j", args->jobs, "Threads (default: all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--filter", args->filter, "Run only scenarios whose name matches this regex");
  cmd->add_option("--params", args->params,
                  "Parameter overlay (TOML [params], e.g. a tuning job's best.toml) over every "
                  "scenario's settings");
  cmd->add_option("--gnuplot", args->report.gnuplot, "gnuplot executable for the figures");
  cmd->add_flag(
      "--no-html", [args](std::int64_t) { args->html = false; }, "Write the CSV files only");
  cmd->add_flag("--quiet,-q", args->quiet, "Print nothing but errors and warnings");
  return {cmd, [args] { return RunRun(*args); }};
}

}  // namespace rabbit::cli
