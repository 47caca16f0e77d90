// rabbit report DIR [--gnuplot PATH]: rebuilds DIR/comparison.csv, DIR/push_survival.csv and
// DIR/index.html from the CSV files a batch run wrote (summary.csv and each run's folder), or a
// tuning job's page (rabbit tune), without re-running anything. When DIR holds the shards of a
// sharded run (DIR/shards/I-of-N), first merges them into DIR (rabbit/report/shards.h).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/flag_checks.h"
#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/report/shards.h"
#include "rabbit/report/suite_report.h"
#include "rabbit/report/tune_report.h"
#include "rabbit/scenario/ranks.h"

namespace rabbit::cli {
namespace {

namespace fs = std::filesystem;

struct ReportArgs {
  std::string dir;
  SuiteReportOptions options;
  bool quiet = false;
};

int Report(const ReportArgs& args) {
  std::string error;
  if (!args.options.IsValid(&error)) {
    std::cerr << "rabbit report: " << error << "\n";
    return 2;
  }
  std::vector<std::string> warnings;
  // One writer per folder; only a folder rabbit run or rabbit tune wrote is written into.
  const OutputLock lock(args.dir, "dir");
  if (!HasMarker(args.dir, {kReportMarker, kTuneMarker}) && !HasShards(args.dir)) {
    throw InputError(args.dir, 0, "",
                     std::string("is not a report of rabbit run or rabbit tune (no ") +
                         kReportMarker + ", " + kTuneMarker + " or shards/): nothing written");
  }
  // A file a user added to the report stops a rewrite of it.
  CheckInventory("dir", args.dir);
  // What a killed merge left beside the folder (its runs are still in the shards, or already in
  // the report): removed.
  if (HasShards(args.dir) || HasMarker(MergeStagingFolder(args.dir), {kReportMarker})) {
    ClearMergeStaging(args.dir);
  }
  if (fs::exists(fs::path(args.dir) / ".rabbit-tune")) {  // a tuning job's folder
    if (!fs::exists(fs::path(args.dir) / "meta.csv")) {
      throw InputError(args.dir, 0, "",
                       "a tuning job that has not finished (or only its shards): "
                       "finish it with rabbit tune JOB --resume");
    }
    TuneReportOptions options;
    options.gnuplot = args.options.gnuplot;
    WriteTuneReport(args.dir, options, &warnings);
    for (const std::string& w : warnings) std::cerr << "rabbit report: warning: " << w << "\n";
    if (!args.quiet) std::printf("wrote %s\n", (fs::path(args.dir) / "index.html").c_str());
    return 0;
  }
  if (HasShards(args.dir)) {
    std::string label = fs::path(args.dir).lexically_normal().string();
    if (label.size() > 1 && label.back() == '/') label.pop_back();
    const MergedShards merged = MergeShards(args.dir, [&](const std::string& staging) {
      SuiteReportOptions options = args.options;
      options.source_label = label;
      WriteSuiteReport(staging, options, &warnings);
    });
    for (const std::string& w : warnings) std::cerr << "rabbit report: warning: " << w << "\n";
    if (!args.quiet) {
      std::printf("merged %d shard(s) of suite %s: %zu runs\nwrote %s\n", merged.count,
                  merged.suite.c_str(), merged.runs, (fs::path(label) / "index.html").c_str());
    }
    // The verdict rabbit run would have given the whole suite.
    if (merged.failed_required > 0) {
      std::cerr << "rabbit report: " << merged.failed_required
                << " required scenario(s) failed their criteria\n";
      return 1;
    }
    return 0;
  }
  // The inventory goes while the pages are rewritten (a kill meanwhile leaves a folder that is
  // replaced as one made before inventories, not one that refuses its own new pages), and comes
  // back listing them.
  fs::remove(fs::path(args.dir) / kInventory);
  const std::string page = WriteSuiteReport(args.dir, args.options, &warnings);
  WriteInventory(args.dir);
  for (const std::string& w : warnings) std::cerr << "rabbit report: warning: " << w << "\n";
  if (!args.quiet) std::printf("wrote %s\n", page.c_str());
  return 0;
}

// Under mpirun every rank would write the same files: rank 0 does the work, the others take its
// exit code.
int RunReport(const ReportArgs& args) {
  int code = 2;
  RunAgreed([&] {
    if (Ranks::root()) code = Report(args);
  });
  return std::stoi(Ranks::Broadcast(std::to_string(code)));
}

}  // namespace

Command RegisterReport(CLI::App* app) {
  auto args = std::make_shared<ReportArgs>();
  CLI::App* cmd = app->add_subcommand(
      "report",
      "Rebuild the HTML report of a batch run or a tuning job (DIR/index.html) from its CSV "
      "files, merging the shards of a sharded run (DIR/shards) first");
  cmd->add_option("dir", args->dir,
                  "Report directory written by `rabbit run` (has summary.csv, or shards/ to merge)")
      ->required();
  cmd->add_option("--gnuplot", args->options.gnuplot,
                  "gnuplot executable for the figures (searched on PATH without a '/'); without it "
                  "the page has tables and replays only")
      ->check(RunnableExecutable());
  cmd->add_option("--replay-fps", args->options.replay_fps, "Frames per second of the replays");
  cmd->add_option("--stick-window", args->options.stick_window,
                  "Seconds of walking per stick diagram");
  cmd->add_option("--stick-every", args->options.stick_every,
                  "Seconds between the figures of a stick diagram");
  cmd->add_option("--family-details", args->options.family_details,
                  "Figures, steps and replays for the first N members of each family only "
                  "(-1: every member)")
      ->check(IntegerIn(-1, kMaxFamilyDetails));
  cmd->add_option("--survival-bin", args->options.survival_bin_n_s,
                  "Width in N s of the impulse bins of survival against push impulse "
                  "(push_survival.csv and its charts, for the families with pushes)")
      ->check(NumberIn(1e-3, 1000.0, "N s"));
  cmd->add_flag("--quiet,-q", args->quiet, "Print nothing but warnings and errors");
  return {cmd, [args] { return RunReport(*args); }};
}

}  // namespace rabbit::cli
