// rabbit run [SUITE...] [--out DIR] [--jobs N] [--filter REGEX] [--shard I/N]: the main job. Runs
// every scenario of the suites (and their baselines) in parallel, writes summary.csv, each run's
// CSV files and index.html. Nothing is written before every suite has loaded; each report is built
// in a staging folder renamed into place at the end, so a failed run never leaves half a report.
// Under mpirun every rank loads and plans the same jobs, job i of a suite runs on rank i mod size,
// and rank 0 alone writes (rabbit/report/rank_batch.h). With --shard I/N only the jobs i with
// i mod N = I - 1 run, into DIR/shards/I-of-N/, which rabbit report DIR merges
// (rabbit/report/shards.h).
#include <sched.h>
#include <unistd.h>

#include <algorithm>
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
#include "rabbit/report/rank_batch.h"
#include "rabbit/report/run_files.h"
#include "rabbit/report/shards.h"
#include "rabbit/report/suite_report.h"
#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/ranks.h"
#include "rabbit/scenario/suite.h"

namespace rabbit::cli {
namespace {

namespace fs = std::filesystem;

constexpr const char* kDefaultSuite = "scenarios/paper.toml";

struct RunArgs {
  std::vector<std::string> suites;
  std::string out;
  int jobs = 0;
  std::string filter;
  std::string params;
  std::string shard_text;
  bool quiet = false;
  bool html = true;
  SuiteReportOptions report;
  // Parsed from the above.
  bool sharded = false;
  Shard shard;
};

// The default suite: scenarios/paper.toml below the working directory, else the one shipped with
// the sources this binary was built from.
std::string DefaultSuite() {
  if (fs::exists(kDefaultSuite)) return kDefaultSuite;
  const fs::path shipped = fs::path(RABBIT_SOURCE_DIR) / kDefaultSuite;
  return fs::exists(shipped) ? shipped.string() : kDefaultSuite;
}

// Removes a staging folder unless released (only rank 0 has one: the path is empty elsewhere).
struct StagingGuard {
  fs::path path;
  bool keep = false;
  ~StagingGuard() {
    std::error_code ignored;
    if (!keep && !path.empty()) fs::remove_all(path, ignored);
  }
};

// Where a suite's output goes: its report folder, and the folder written (the report folder, or
// its shard's below DIR/shards).
struct SuiteTarget {
  fs::path report;
  fs::path written;
  std::string plan;  // the plan's fingerprint (sharded runs)
};

struct SuiteOutcome {
  int failed_required = 0;  // rank 0's count (0 elsewhere)
};

// Runs a suite (its shard's jobs, if sharded) over the ranks into rank 0's staging folder; the
// caller renames it into place once every suite has succeeded. A collective.
SuiteOutcome RunOneSuite(const Suite& suite, const std::vector<BatchJob>& plan,
                         const SuiteTarget& target, const RunArgs& args,
                         GaitLibraryCache* libraries, const fs::path& staging) {
  std::vector<BatchJob> jobs;
  std::vector<size_t> plan_index;  // jobs[k] is plan[plan_index[k]]
  for (size_t j = 0; j < plan.size(); ++j) {
    if (args.sharded && !args.shard.Owns(j)) continue;
    jobs.push_back(plan[j]);
    plan_index.push_back(j);
  }
  const bool root = Ranks::root(), ranks = Ranks::size() > 1;
  const bool terminal = root && !args.quiet && ::isatty(STDERR_FILENO) != 0;
  // Progress shows rank 0's own runs (the others report at the end).
  const size_t local =
      (jobs.size() + static_cast<size_t>(Ranks::size() - 1)) / static_cast<size_t>(Ranks::size());
  size_t done = 0;
  const auto start = std::chrono::steady_clock::now();
  const RankBatchResult batch = RunBatchOverRanks(
      jobs, suite.name, ThreadsPerRank(args.jobs), libraries, staging.string(),
      [&](const RunBrief& run) {
        if (!terminal) return;
        std::fprintf(stderr, "\r\033[K%s[%zu/%zu] %s: %s%s", ranks ? "rank 0 " : "", ++done, local,
                     run.run.c_str(), OutcomeName(run.outcome),
                     run.passed ? "" : " (failed criteria)");
        std::fflush(stderr);
      });
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (terminal) std::fprintf(stderr, "\r\033[K");

  SuiteOutcome outcome;
  // Rank 0 writes; agreeing afterwards keeps the ranks in step if it fails.
  RunAgreed([&] {
    if (!root) return;
    double simulated = 0.0;
    for (size_t k = 0; k < jobs.size(); ++k) {
      const RunBrief& r = batch.runs[k];
      simulated += r.simulated;
      const bool main_variant = r.run == jobs[k].scenario->name;
      if (!r.passed && main_variant && jobs[k].scenario->required) ++outcome.failed_required;
    }
    if (args.sharded) {
      const ShardInfo info{suite.name,  args.shard,  target.plan,
                           plan.size(), jobs.size(), outcome.failed_required};
      WriteFileAtomically((staging / kShardMarker).string(),
                          [&info](std::ostream& out) { out << ShardMarkerText(info); });
      WriteFileAtomically((staging / "summary.csv").string(), [&](std::ostream& out) {
        out << ShardSummaryHeader() << "\n";
        for (size_t k = 0; k < jobs.size(); ++k) {
          out << plan_index[k] << ',' << batch.runs[k].summary_row << "\n";
        }
      });
    } else {
      WriteFileAtomically((staging / kReportMarker).string(),
                          [&suite](std::ostream& out) { out << ReportMarkerText(suite.name); });
      WriteFileAtomically((staging / "summary.csv").string(), [&](std::ostream& out) {
        out << SummaryHeader() << "\n";
        for (const RunBrief& r : batch.runs) out << r.summary_row << "\n";
      });
      std::vector<std::string> warnings;
      if (args.html) {
        SuiteReportOptions report = args.report;
        report.source_label = target.report.string();
        WriteSuiteReport(staging.string(), report, &warnings);
      }
      for (const std::string& w : warnings) std::cerr << "rabbit run: warning: " << w << "\n";
    }
    if (args.quiet) return;
    const std::string runs = args.sharded
                                 ? "shard " + args.shard_text + ", " + std::to_string(jobs.size()) +
                                       " of " + std::to_string(plan.size()) + " runs"
                                 : std::to_string(jobs.size()) + " runs";
    const std::string where = ranks ? std::to_string(Ranks::size()) + " ranks x " +
                                          std::to_string(batch.threads) + " threads"
                                    : std::to_string(batch.threads) + " threads";
    std::printf("suite      %s (%s): %s in %.1f s wall on %s (%.1f runs/min, %.0fx real time)\n",
                suite.name.c_str(), suite.file.c_str(), runs.c_str(), wall, where.c_str(),
                wall > 0 ? 60.0 * static_cast<double>(jobs.size()) / wall : 0.0,
                wall > 0 ? simulated / wall : 0.0);
    std::printf("%-34s %-10s %-6s %6s %8s %9s %8s\n", "run", "outcome", "pass", "steps", "dist m",
                "|V-Vd| m/s", "L_step m");
    for (size_t k = 0; k < jobs.size(); ++k) {
      const RunBrief& r = batch.runs[k];
      std::printf(
          "%-34s %-10s %-6s %6d %8.2f %9.3f %8.3f\n", r.run.c_str(), OutcomeName(r.outcome),
          r.passed ? "yes"
                   : (r.run == jobs[k].scenario->name && jobs[k].scenario->required ? "NO" : "no"),
          r.metrics.steps, r.metrics.distance, r.metrics.mean_abs_speed_error,
          r.metrics.l_step_mean);
      for (const std::string& f : r.failures) std::printf("    - %s\n", f.c_str());
    }
    if (args.sharded) {
      std::printf("wrote      %s\n", (target.written / "summary.csv").string().c_str());
      std::printf("merge      rabbit report %s (once all %d shards are written)\n",
                  target.report.string().c_str(), args.shard.count);
    } else {
      std::printf("wrote      %s\n",
                  (target.report / (args.html ? "index.html" : "summary.csv")).string().c_str());
    }
  });
  return outcome;
}

// Throws InputError unless rabbit run may replace the report folder `out`.
void CheckReportOutput(const fs::path& out) {
  if (!fs::exists(out)) return;
  if (fs::is_directory(out) && (fs::is_empty(out) || fs::exists(out / kReportMarker))) return;
  if (fs::is_directory(out / kShardsFolder)) {
    throw InputError("--out", 0, out.string(),
                     "holds the shards of a sharded run: merge them with rabbit report " +
                         out.string() + ", or remove " + (out / kShardsFolder).string());
  }
  throw InputError("--out", 0, out.string(),
                   std::string("exists and is not a report of rabbit run (no ") + kReportMarker +
                       "): refusing to replace it");
}

int RunRun(RunArgs args) {
  std::string error;
  args.sharded = !args.shard_text.empty();
  if (!args.report.IsValid(&error) ||
      (args.sharded && !ParseShard(args.shard_text, &args.shard, &error))) {
    if (Ranks::root()) std::cerr << "rabbit run: " << error << "\n";
    return 2;
  }
  if (args.suites.empty()) args.suites.push_back(DefaultSuite());
  std::vector<Suite> suites;
  std::vector<std::vector<BatchJob>> plans;
  std::vector<SuiteTarget> targets;
  GaitLibraryCache libraries;
  // Load and plan everything first: bad input leaves nothing behind. Every rank does, and they
  // agree before going on, so a rank that failed alone (a file it cannot read) stops them all.
  RunAgreed([&] {
    ParamOverlay overlay;
    if (!args.params.empty()) overlay = LoadParamOverlay(args.params);
    for (const std::string& path : args.suites) suites.push_back(LoadSuite(path, &overlay));
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
    // One suite: --out is its report folder; several: --out is their parent. An existing folder is
    // replaced only when it is empty or a report written by rabbit run (has the marker file); a
    // shard writes only its own folder below it.
    for (size_t i = 0; i < suites.size(); ++i) {
      const Suite& suite = suites[i];
      fs::path out = args.out.empty()     ? fs::path("reports") / suite.name
                     : suites.size() == 1 ? fs::path(args.out)
                                          : fs::path(args.out) / suite.name;
      out = out.lexically_normal();
      if (out.filename().empty()) out = out.parent_path();  // "dir/" -> "dir"
      if (out.empty() || out == "." || out == "..") {
        throw InputError("--out", 0, args.out, "name a folder for the report");
      }
      SuiteTarget target{out, out, ""};
      if (args.sharded) {
        CheckShardOutput(out.string(), args.shard);
        target.written = out / kShardsFolder / ShardFolderName(args.shard);
        target.plan = PlanFingerprint(suite, plans[i], args.params);
      } else {
        CheckReportOutput(out);
      }
      targets.push_back(target);
    }
    // Every gait library loads now: a bad gait pattern is bad input, found before anything runs.
    for (const std::vector<BatchJob>& plan : plans) {
      for (const BatchJob& job : plan) {
        if (job.scenario->controller == ControllerKind::kFuzzyCmac) {
          libraries.Get(job.scenario->pattern);
        }
      }
    }
  });
  // All suites run into staging folders (rank 0's); only when every one succeeded are they renamed
  // into place, so a failure in a later suite leaves every earlier report as it was. A shard's
  // staging folder lies beside the report folder, not in it, so that a killed shard leaves
  // nothing in DIR/shards.
  int failed = 0;
  std::vector<std::unique_ptr<StagingGuard>> staged;
  for (size_t i = 0; i < suites.size(); ++i) {
    const std::string pid = std::to_string(::getpid());
    const fs::path staging = args.sharded
                                 ? fs::path(targets[i].report.string() + ".shard-" +
                                            ShardFolderName(args.shard) + ".partial-" + pid)
                                 : fs::path(targets[i].report.string() + ".partial-" + pid);
    staged.push_back(
        std::make_unique<StagingGuard>(StagingGuard{Ranks::root() ? staging : fs::path()}));
    failed +=
        RunOneSuite(suites[i], plans[i], targets[i], args, &libraries, staging).failed_required;
  }
  RunAgreed([&] {
    if (!Ranks::root()) return;
    for (size_t i = 0; i < suites.size(); ++i) {
      const fs::path& written = targets[i].written;
      if (fs::exists(written)) fs::remove_all(written);
      fs::create_directories(written.parent_path().empty() ? "." : written.parent_path());
      fs::rename(staged[i]->path, written);
      staged[i]->keep = true;
    }
  });
  // Every rank returns rank 0's verdict.
  if (Ranks::Broadcast(failed > 0 ? "1" : "0") == "1") {
    if (Ranks::root()) {
      std::cerr << "rabbit run: " << failed << " required scenario(s) failed their criteria\n";
    }
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
  cmd->add_option("--jobs,-j", args->jobs,
                  "Threads per process (default: all cores, shared by the MPI ranks of a machine)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--filter", args->filter, "Run only scenarios whose name matches this regex");
  cmd->add_option("--params", args->params,
                  "Parameter overlay (TOML [params], e.g. a tuning job's best.toml) over every "
                  "scenario's settings");
  cmd->add_option("--shard", args->shard_text,
                  "Run only shard I of N (e.g. 2/8): the jobs i of each suite with i mod N = I-1, "
                  "into DIR/shards/I-of-N/; rabbit report DIR merges the N shards");
  cmd->add_option("--gnuplot", args->report.gnuplot, "gnuplot executable for the figures");
  cmd->add_flag(
      "--no-html", [args](std::int64_t) { args->html = false; }, "Write the CSV files only");
  cmd->add_flag("--quiet,-q", args->quiet, "Print nothing but errors and warnings");
  return {cmd, [args] { return RunRun(*args); }};
}

}  // namespace rabbit::cli
