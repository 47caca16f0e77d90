// rabbit run [SUITE...] [--out DIR] [--jobs N] [--filter REGEX] [--shard I/N] [--resume]: the main
// job. Runs every scenario of the suites (and their baselines) in parallel, writes summary.csv,
// each run's CSV files and index.html. Nothing is written before every suite has loaded; each
// report is built in a staging folder renamed into place at the end, so a failed run never leaves
// half a report. The staging folder has a stable name (DIR.partial) and every run's folder in it a
// completion marker written last, so that after a kill --resume runs only the runs without one (see
// ClaimStaging). Under mpirun every rank loads and plans the same jobs, job i of a suite runs on
// rank i mod size, and rank 0 alone writes (rabbit/report/rank_batch.h). With --shard I/N only the
// jobs i with i mod N = I - 1 run, into DIR/shards/I-of-N/, which rabbit report DIR merges
// (rabbit/report/shards.h).
#include <fcntl.h>
#include <sched.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli/commands.h"
#include "rabbit/gait/database_layout.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/io/error.h"
#include "rabbit/report/comparison.h"
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
  std::string gaits;  // a gait database replacing every walker scenario's
  std::string shard_text;
  bool resume = false;
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

// A staging folder's marker (which plan it holds) and lock (which process writes it).
constexpr const char* kStagingMarker = ".rabbit-staging";
constexpr const char* kStagingLock = ".lock";
constexpr const char* kStagingTag = "rabbit-staging/1";

std::string StagingMarkerText(const std::string& suite, const std::string& plan) {
  return std::string(kStagingTag) + "\nsuite = " + suite + "\nplan = " + plan + "\n";
}

std::string ReadSmallFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Rank 0's hold on a suite's staging folder: the lock (an flock on DIR.partial/.lock, which the
// kernel releases when the process dies, so a killed run leaves no stale lock). Unless released,
// the folder is removed on failure, but kept when it holds finished runs, for --resume.
struct StagingGuard {
  fs::path path;
  int lock = -1;
  bool keep = false;
  ~StagingGuard() {
    if (lock < 0) return;  // not ours (another rank's, or another process holds it)
    std::error_code ignored;
    if (!keep) {
      bool finished = false;
      for (fs::directory_iterator it(path, ignored), end; !ignored && it != end;
           it.increment(ignored)) {
        finished = finished || fs::exists(it->path() / kRunMarker, ignored);
      }
      if (finished) {
        std::cerr << "rabbit run: the finished runs are kept in " << path.string()
                  << ": the same command with --resume runs the rest\n";
      } else {
        fs::remove_all(path, ignored);
      }
    }
    ::close(lock);
  }
};

// Where a suite's output goes: its report folder, and the folder written (the report folder, or
// its shard's below DIR/shards).
struct SuiteTarget {
  fs::path report;
  fs::path written;
  std::string plan;  // the plan's fingerprint (PlanFingerprint)
  fs::path staging;  // beside the report: DIR.partial, or DIR.shard-I-of-N.partial
};

// What a resume found finished in a suite's staging folder, per job of this invocation (the
// shard's jobs when sharded). The briefs are rank 0's only.
struct Finished {
  std::vector<bool> done;
  std::vector<RunBrief> briefs;  // briefs[k] valid where done[k]
  size_t count() const { return static_cast<size_t>(std::count(done.begin(), done.end(), true)); }
};

// The jobs of the plan this invocation runs (a shard's, or all), as plan indices.
std::vector<size_t> OwnedJobs(const std::vector<BatchJob>& plan, const RunArgs& args) {
  std::vector<size_t> owned;
  for (size_t j = 0; j < plan.size(); ++j) {
    if (!args.sharded || args.shard.Owns(j)) owned.push_back(j);
  }
  return owned;
}

// For the resume tests: RABBIT_RUN_KILL_AFTER=N makes rank 0 kill itself (SIGKILL, no clean-up)
// once N runs' folders are complete, counted over the invocation's suites.
struct KillSwitch {
  int after = 0, written = 0;
  void Finished() {
    if (after > 0 && ++written == after) std::raise(SIGKILL);
  }
};

struct SuiteOutcome {
  int failed_required = 0;  // rank 0's count (0 elsewhere)
};

// Runs a suite (its shard's jobs, if sharded) over the ranks into rank 0's staging folder; the
// caller renames it into place once every suite has succeeded. A collective.
SuiteOutcome RunOneSuite(const Suite& suite, const std::vector<BatchJob>& plan,
                         const SuiteTarget& target, const RunArgs& args,
                         GaitLibraryCache* libraries, const Finished& finished, KillSwitch* kill) {
  const fs::path& staging = target.staging;
  std::vector<BatchJob> jobs;
  const std::vector<size_t> plan_index = OwnedJobs(plan, args);  // jobs[k] is plan[plan_index[k]]
  for (size_t j : plan_index) jobs.push_back(plan[j]);
  // Only the runs not finished before (every rank skips the same ones: rank 0 decided).
  std::vector<BatchJob> todo;
  std::vector<size_t> todo_of;  // todo[i] is jobs[todo_of[i]]
  for (size_t k = 0; k < jobs.size(); ++k) {
    if (finished.done[k]) continue;
    todo.push_back(jobs[k]);
    todo_of.push_back(k);
  }
  const bool root = Ranks::root(), ranks = Ranks::size() > 1;
  const bool terminal = root && !args.quiet && ::isatty(STDERR_FILENO) != 0;
  // Progress shows rank 0's own runs (the others report at the end).
  const size_t local =
      (todo.size() + static_cast<size_t>(Ranks::size() - 1)) / static_cast<size_t>(Ranks::size());
  size_t done = 0;
  const auto start = std::chrono::steady_clock::now();
  RankBatchResult batch = RunBatchOverRanks(
      todo, suite.name, ThreadsPerRank(args.jobs), libraries, staging.string(),
      [&](const RunBrief& run) {
        if (root) kill->Finished();
        if (!terminal) return;
        std::fprintf(stderr, "\r\033[K%s[%zu/%zu] %s: %s%s", ranks ? "rank 0 " : "", ++done, local,
                     run.run.c_str(), OutcomeName(run.outcome),
                     run.passed ? "" : " (failed criteria)");
        std::fflush(stderr);
      });
  if (root) {  // every job's brief, in job order: the resumed ones from their markers
    std::vector<RunBrief> runs(jobs.size());
    for (size_t k = 0; k < jobs.size(); ++k) {
      if (finished.done[k]) runs[k] = finished.briefs[k];
    }
    for (size_t i = 0; i < todo.size(); ++i) runs[todo_of[i]] = std::move(batch.runs[i]);
    batch.runs = std::move(runs);
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (terminal) std::fprintf(stderr, "\r\033[K");

  SuiteOutcome outcome;
  // Rank 0 writes; agreeing afterwards keeps the ranks in step if it fails.
  RunAgreed([&] {
    if (!root) return;
    double simulated_now = 0.0;  // by the runs of this invocation
    for (size_t k = 0; k < jobs.size(); ++k) {
      const RunBrief& r = batch.runs[k];
      if (!finished.done[k]) simulated_now += r.simulated;
      const bool main_variant = r.run == jobs[k].scenario->name;
      if (!r.passed && main_variant && jobs[k].scenario->required) ++outcome.failed_required;
    }
    if (!suite.targets.empty()) {
      WriteFileAtomically((staging / kTargetsFile).string(),
                          [&suite](std::ostream& out) { out << TargetsCsv(suite); });
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
      if (args.html) {  // the page, and comparison.csv with it
        SuiteReportOptions report = args.report;
        report.source_label = target.report.string();
        WriteSuiteReport(staging.string(), report, &warnings);
      } else {
        WriteComparison(staging.string());
      }
      for (const std::string& w : warnings) std::cerr << "rabbit run: warning: " << w << "\n";
    }
    if (args.quiet) return;
    std::string runs = args.sharded
                           ? "shard " + args.shard_text + ", " + std::to_string(jobs.size()) +
                                 " of " + std::to_string(plan.size()) + " runs"
                           : std::to_string(jobs.size()) + " runs";
    if (finished.count() > 0) runs += " (" + std::to_string(finished.count()) + " resumed)";
    const std::string where = ranks ? std::to_string(Ranks::size()) + " ranks x " +
                                          std::to_string(batch.threads) + " threads"
                                    : std::to_string(batch.threads) + " threads";
    std::printf("suite      %s (%s): %s in %.1f s wall on %s (%.1f runs/min, %.0fx real time)\n",
                suite.name.c_str(), suite.file.c_str(), runs.c_str(), wall, where.c_str(),
                wall > 0 ? 60.0 * static_cast<double>(todo.size()) / wall : 0.0,
                wall > 0 ? simulated_now / wall : 0.0);
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

// Rank 0: takes each suite's staging folder (its lock) and finds what a killed run of the same
// plan finished there. Looks at every suite before changing anything. Without --resume, a staging
// folder left behind is emptied (a note says so); with it, one of another plan (its marker's
// fingerprint differs) is an InputError, and a run folder without its marker (cut short) is
// removed, to run again. Throws InputError when another process holds a suite's lock.
void ClaimStaging(const std::vector<Suite>& suites, const std::vector<std::vector<BatchJob>>& plans,
                  const std::vector<SuiteTarget>& targets, const RunArgs& args,
                  std::vector<std::unique_ptr<StagingGuard>>* guards,
                  std::vector<Finished>* finished) {
  std::vector<bool> existed;
  for (size_t i = 0; i < suites.size(); ++i) {
    const fs::path& staging = targets[i].staging;
    const std::vector<size_t> owned = OwnedJobs(plans[i], args);
    Finished& f = (*finished)[i];
    f.done.assign(owned.size(), false);
    f.briefs.assign(owned.size(), RunBrief());
    if (fs::exists(staging) && !fs::is_directory(staging)) {
      throw InputError("--out", 0, staging.string(), "exists and is not a staging folder");
    }
    existed.push_back(fs::exists(staging));
    fs::create_directories(staging);
    auto guard = std::make_unique<StagingGuard>();
    guard->path = staging;
    const int lock = ::open((staging / kStagingLock).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (lock < 0 || ::flock(lock, LOCK_EX | LOCK_NB) != 0) {
      if (lock >= 0) ::close(lock);
      throw InputError("--out", 0, targets[i].report.string(),
                       "another rabbit run is writing this report (" + staging.string() +
                           " is locked): wait for it to end, or give another --out");
    }
    guard->lock = lock;
    guard->keep = existed.back();  // a failure before the second pass leaves it as it was
    guards->push_back(std::move(guard));
    if (!existed.back() || !args.resume) continue;
    if (ReadSmallFile(staging / kStagingMarker) !=
        StagingMarkerText(suites[i].name, targets[i].plan)) {
      throw InputError("--resume", 0, staging.string(),
                       "holds an unfinished run of another plan (the suite file, --params, "
                       "--filter or the program's version differ): nothing to resume; run "
                       "without --resume to discard it");
    }
    for (size_t k = 0; k < owned.size(); ++k) {
      const BatchJob& job = plans[i][owned[k]];
      const std::string name = RunName(*job.scenario, job.variant);
      const fs::path marker = staging / name / kRunMarker;
      if (!fs::exists(marker)) continue;
      try {
        RunBrief brief = ReadRunMarker(marker.string());
        if (brief.run != name) continue;
        f.briefs[k] = std::move(brief);
        f.done[k] = true;
      } catch (const InputError&) {
        // A marker this version cannot read: run it again.
      }
    }
  }
  for (size_t i = 0; i < suites.size(); ++i) {
    const fs::path& staging = targets[i].staging;
    const Finished& f = (*finished)[i];
    std::set<std::string> keep = {kStagingLock};
    const std::vector<size_t> owned = OwnedJobs(plans[i], args);
    for (size_t k = 0; k < owned.size(); ++k) {
      const BatchJob& job = plans[i][owned[k]];
      if (f.done[k]) keep.insert(RunName(*job.scenario, job.variant));
    }
    size_t removed = 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(staging)) {
      if (keep.count(entry.path().filename().string()) != 0) continue;
      removed += entry.is_directory() ? 1 : 0;
      fs::remove_all(entry.path());
    }
    WriteFileAtomically((staging / kStagingMarker).string(), [&](std::ostream& out) {
      out << StagingMarkerText(suites[i].name, targets[i].plan);
    });
    (*guards)[i]->keep = false;
    if (args.quiet) continue;
    if (existed[i] && !args.resume) {
      std::cerr << "rabbit run: note: discarded the unfinished run left in " << staging.string()
                << " (--resume would have continued it)\n";
    } else if (args.resume && !existed[i]) {
      std::printf("resume     nothing to resume for suite %s (no %s): running all %zu runs\n",
                  suites[i].name.c_str(), staging.string().c_str(), owned.size());
    } else if (args.resume) {
      std::printf("resume     suite %s: %zu of %zu runs already finished in %s, running %zu%s\n",
                  suites[i].name.c_str(), f.count(), owned.size(), staging.string().c_str(),
                  owned.size() - f.count(),
                  removed > 0 ? (" (" + std::to_string(removed) + " cut short)").c_str() : "");
    }
  }
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
    if (!args.gaits.empty()) overlay.gait_database = GaitDatabaseRoot(args.gaits);
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
      SuiteTarget target{out, out, PlanFingerprint(suite, plans[i], args.params),
                         fs::path(out.string() + ".partial")};
      if (args.sharded) {
        CheckShardOutput(out.string(), args.shard);
        target.written = out / kShardsFolder / ShardFolderName(args.shard);
        // Beside the report folder, not in it, so that a killed shard leaves nothing in
        // DIR/shards.
        target.staging = out.string() + ".shard-" + ShardFolderName(args.shard) + ".partial";
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
  // into place, so a failure in a later suite leaves every earlier report as it was. Rank 0
  // decides which runs a resume skips; every rank skips the same.
  std::vector<std::unique_ptr<StagingGuard>> staged;
  std::vector<Finished> finished(suites.size());
  RunAgreed([&] {
    if (Ranks::root()) ClaimStaging(suites, plans, targets, args, &staged, &finished);
  });
  std::string done_text;
  for (const Finished& f : finished) {
    for (bool d : f.done) done_text += d ? '1' : '0';
    done_text += '\n';
  }
  std::istringstream agreed(Ranks::Broadcast(done_text));
  for (size_t i = 0; i < suites.size(); ++i) {
    std::string line;
    std::getline(agreed, line);
    finished[i].done.assign(line.size(), false);
    for (size_t k = 0; k < line.size(); ++k) finished[i].done[k] = line[k] == '1';
    finished[i].briefs.resize(line.size());
  }
  KillSwitch kill;
  if (const char* after = std::getenv("RABBIT_RUN_KILL_AFTER")) kill.after = std::atoi(after);
  int failed = 0;
  for (size_t i = 0; i < suites.size(); ++i) {
    failed += RunOneSuite(suites[i], plans[i], targets[i], args, &libraries, finished[i], &kill)
                  .failed_required;
  }
  RunAgreed([&] {
    if (!Ranks::root()) return;
    for (size_t i = 0; i < suites.size(); ++i) {
      const fs::path& written = targets[i].written;
      const fs::path& staging = targets[i].staging;
      // The markers served the resume only: the report is as it always was.
      for (const fs::directory_entry& entry : fs::directory_iterator(staging)) {
        if (entry.is_directory()) fs::remove(entry.path() / kRunMarker);
      }
      fs::remove(staging / kStagingMarker);
      fs::remove(staging / kStagingLock);  // still held (the descriptor) until the guard ends
      if (fs::exists(written)) fs::remove_all(written);
      fs::create_directories(written.parent_path().empty() ? "." : written.parent_path());
      fs::rename(staging, written);
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
  cmd->add_option("--gaits", args->gaits,
                  "Gait database (folder with reference/, networks/, walker.csv) for every walker "
                  "scenario, instead of the one each names");
  cmd->add_option("--shard", args->shard_text,
                  "Run only shard I of N (e.g. 2/8): the jobs i of each suite with i mod N = I-1, "
                  "into DIR/shards/I-of-N/; rabbit report DIR merges the N shards");
  cmd->add_flag("--resume", args->resume,
                "Continue a run that was killed: keep the runs it finished (in DIR.partial) and "
                "run only the rest, for the same suites, --out, --params and --filter");
  cmd->add_option("--gnuplot", args->report.gnuplot, "gnuplot executable for the figures");
  cmd->add_option("--family-details", args->report.family_details,
                  "Figures, steps and replays for the first N members of each family only "
                  "(default 3; -1: every member)");
  cmd->add_flag(
      "--no-html", [args](std::int64_t) { args->html = false; },
      "Write the CSV files only (summary.csv, comparison.csv, the runs')");
  cmd->add_flag("--quiet,-q", args->quiet, "Print nothing but errors and warnings");
  return {cmd, [args] { return RunRun(*args); }};
}

}  // namespace rabbit::cli
