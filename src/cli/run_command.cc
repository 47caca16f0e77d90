// rabbit run [SUITE...] [--out DIR] [--jobs N] [--filter REGEX] [--shard I/N] [--resume]: the main
// job. Runs every scenario of the suites (and their baselines) in parallel, writes summary.csv,
// each run's CSV files and index.html. Nothing is written before every suite has loaded; each
// report is built in a staging folder renamed into place at the end, so a failed run never leaves
// half a report. The staging folder has a stable name (DIR.partial) and every run's folder in it a
// completion marker written last, so that after a kill --resume runs only the runs without one (see
// ClaimStaging). Under mpirun every rank loads and plans the same jobs, each rank takes the next
// job whenever one of its threads is free, and rank 0 alone writes (rabbit/scenario/rank_batch.h).
// With --shard I/N only the jobs i with i mod N = I - 1 run, into DIR/shards/I-of-N/, which rabbit
// report DIR merges (rabbit/report/shards.h).
#include <sched.h>
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
#include "cli/data_root.h"
#include "cli/flag_checks.h"
#include "cli/run_output_checks.h"
#include "cli/run_summary.h"
#include "rabbit/gait/database_layout.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/io/test_hooks.h"
#include "rabbit/report/comparison.h"
#include "rabbit/report/push_survival.h"
#include "rabbit/report/shards.h"
#include "rabbit/report/suite_report.h"
#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/rank_batch.h"
#include "rabbit/scenario/ranks.h"
#include "rabbit/scenario/run_files.h"
#include "rabbit/scenario/suite.h"
#include "rabbit/scenario/suite_inputs.h"

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
  bool verbose = false;
  bool html = true;
  SuiteReportOptions report;
  // Parsed from the above.
  bool sharded = false;
  Shard shard;
};

// The default suite: scenarios/paper.toml below the data root (cli/data_root.h).
std::string DefaultSuite() { return DataPath(kDefaultSuite); }

constexpr const char* kStagingTag = "rabbit-staging/1";

std::string StagingMarkerText(const std::string& suite, const std::string& plan,
                              const std::vector<InputFile>& inputs) {
  return std::string(kStagingTag) + "\nsuite = " + suite + "\nplan = " + plan + "\n" +
         InputLines(inputs);
}

std::string ReadSmallFile(const fs::path& path) {
  return ReadBoundedFileIfExists(path.string(), kMarkerFileLimits);
}

// Rank 0's hold on a suite's output: the lock (OutputLock, on the folder finally written), held
// until the last rename. Unless released, the staging folder is removed on failure, but kept when
// it holds finished runs, for --resume.
struct StagingGuard {
  fs::path path;
  OutputLock lock;
  bool keep = false;
  ~StagingGuard() {
    if (!lock.held()) return;  // not ours (another rank's, or another process holds it)
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
        RemoveOwnedFolder(path);
      }
    }
  }
};

// Where a suite's output goes: its report folder, and the folder written (the report folder, or
// its shard's below DIR/shards).
struct SuiteTarget {
  fs::path report;
  fs::path written;
  std::string plan;               // the plan's fingerprint (PlanFingerprint)
  fs::path staging;               // beside the report: DIR.partial, or DIR.shard-I-of-N.partial
  std::vector<InputFile> inputs;  // every file the suite reads, hashed at planning
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
  RunTally tally;           // rank 0's (empty elsewhere)
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
    TallyRuns(suite.name, jobs, batch.runs, &outcome.tally);
    if (!suite.targets.empty()) {
      WriteFileAtomically((staging / kTargetsFile).string(),
                          [&suite](std::ostream& out) { out << TargetsCsv(suite); });
    }
    if (!suite.members.empty()) {
      WriteFileAtomically((staging / kMembersFile).string(),
                          [&suite](std::ostream& out) { out << MembersCsv(suite); });
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
        WritePushSurvival(staging.string(), args.report.survival_bin_n_s, &warnings);
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
    PrintRunTable(stdout, suite.name, jobs, batch.runs, args.verbose);
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
    // One writer per output, from here until the last rename: a shard's lock is its staging
    // folder's (shards of one report run side by side), a report's is the report's.
    auto guard = std::make_unique<StagingGuard>();
    guard->path = staging;
    guard->lock = OutputLock(args.sharded ? staging : targets[i].written, "--out");
    // Again, now that no other rabbit can change them.
    if (!args.sharded) CheckReportOutput(targets[i].written);
    CheckStagingOutput(staging);
    existed.push_back(fs::exists(staging));
    guard->keep = existed.back();  // a failure before the second pass leaves it as it was
    fs::create_directories(staging);
    guards->push_back(std::move(guard));
    if (!existed.back() || !args.resume) continue;
    const std::string plan_marker = ReadSmallFile(staging / kStagingMarker);
    if (plan_marker.empty()) {
      // A staging folder without its plan (emptied, or the old report a kill left after the
      // swap): nothing to resume.
      existed.back() = false;
      continue;
    }
    if (plan_marker != StagingMarkerText(suites[i].name, targets[i].plan, targets[i].inputs)) {
      const std::string changed = ChangedInputs(plan_marker, targets[i].inputs);
      if (!changed.empty()) {
        throw InputError("--resume", 0, staging.string(),
                         "holds an unfinished run over other input files: " + changed +
                             "; nothing to resume: run without --resume to discard it");
      }
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
    // The marker stays (replaced atomically below), so a kill here leaves a folder still ours.
    std::set<std::string> keep = {kStagingMarker};
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
      TestKillPoint("run-clearing-staging");
    }
    WriteFileAtomically((staging / kStagingMarker).string(), [&](std::ostream& out) {
      out << StagingMarkerText(suites[i].name, targets[i].plan, targets[i].inputs);
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
  if (args.verbose && !args.quiet && Ranks::root()) std::printf("%s\n", DataRootLine().c_str());
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
                         fs::path(out.string() + ".partial"),
                         HashInputFiles(SuiteInputFiles(suite))};
      if (args.sharded) {
        CheckShardOutput(out.string(), args.shard);
        target.written = out / kShardsFolder / ShardFolderName(args.shard);
        // Beside the report folder, not in it, so that a killed shard leaves nothing in
        // DIR/shards.
        target.staging = out.string() + ".shard-" + ShardFolderName(args.shard) + ".partial";
      } else {
        CheckReportOutput(out);
      }
      CheckStagingOutput(target.staging);
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
  if (Ranks::root()) TestKillPoint("run-claimed");
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
  RunTally tally;  // rank 0's
  for (size_t i = 0; i < suites.size(); ++i) {
    SuiteOutcome outcome =
        RunOneSuite(suites[i], plans[i], targets[i], args, &libraries, finished[i], &kill);
    failed += outcome.failed_required;
    TallyMerge(outcome.tally, &tally);
  }
  RunAgreed([&] {
    if (!Ranks::root()) return;
    TestKillPoint("run-staged");
    for (size_t i = 0; i < suites.size(); ++i) {
      const fs::path& written = targets[i].written;
      const fs::path& staging = targets[i].staging;
      // In one step (the old report, checked ours at planning, goes to the staging folder and is
      // removed), still under the lock.
      ReplaceFolder(staging, written);
      staged[i]->keep = true;
      TestKillPoint("run-replaced");
      // The markers served the resume only: the report is as it always was.
      for (const fs::directory_entry& entry : fs::directory_iterator(written)) {
        if (entry.is_directory()) fs::remove(entry.path() / kRunMarker);
      }
      fs::remove(written / kStagingMarker);
      WriteInventory(written);
    }
  });
  if (Ranks::root() && !args.quiet) std::printf("%s\n", VerdictLine(tally).c_str());
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
  cmd->add_option(
         "suites", args->suites,
         std::string("Suite files (TOML; default: ") + kDefaultSuite + " below the data root)")
      ->default_str("");  // not "[]"
  cmd->add_option(
      "--out,-o", args->out,
      "Report folder to write (one suite; default: reports/<suite name>), or the parent of "
      "the suites' report folders (several)");
  cmd->add_option("--jobs,-j", args->jobs,
                  "Threads per process (0: all cores, shared by the MPI ranks of a machine)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--filter", args->filter,
                  "Run only scenarios whose name matches this regex (default: all)");
  cmd->add_option("--params", args->params,
                  "Parameter overlay (TOML [params], e.g. a tuning job's best.toml) over every "
                  "scenario's settings (default: none)");
  cmd->add_option("--gaits", args->gaits,
                  "Gait database (folder with reference/, networks/, walker.csv) for every walker "
                  "scenario (default: the one each scenario names)");
  cmd->add_option(
      "--shard", args->shard_text,
      "Run only shard I of N (e.g. 2/8): the jobs i of each suite with i mod N = I-1, "
      "into DIR/shards/I-of-N/; rabbit report DIR merges the N shards (default: all jobs)");
  cmd->add_flag("--resume", args->resume,
                "Continue a run that was killed: keep the runs it finished (in DIR.partial) and "
                "run only the rest, for the same suites, --out, --params and --filter");
  cmd->add_option("--gnuplot", args->report.gnuplot,
                  "gnuplot executable for the figures (searched on PATH without a '/')")
      ->check(RunnableExecutable());
  cmd->add_option("--family-details", args->report.family_details,
                  "Figures, steps and replays for the first N members of each family only "
                  "(-1: every member)")
      ->check(IntegerIn(-1, kMaxFamilyDetails));
  cmd->add_option("--survival-bin", args->report.survival_bin_n_s,
                  "Width in N s of the impulse bins of survival against push impulse "
                  "(push_survival.csv and its charts, for the families with pushes)")
      ->check(NumberIn(1e-3, 1000.0, "N s"));
  cmd->add_flag(
      "--no-html", [args](std::int64_t) { args->html = false; },
      "Write the CSV files only (summary.csv, comparison.csv, push_survival.csv, the runs')");
  cmd->add_flag("--quiet,-q", args->quiet, "Print nothing but errors and warnings");
  cmd->add_flag("--verbose,-v", args->verbose,
                "Print the data root and every run in the table (default: a family's failed "
                "runs and its success rates only)");
  return {cmd, [args] { return RunRun(*args); }};
}

}  // namespace rabbit::cli
