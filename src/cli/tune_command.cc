// rabbit tune JOB.toml [--out DIR] [--jobs N] [--resume | --force] [--shard I/N]: a tuning job
// (optimizers/tuner.h). Prints one line per evaluation and the best parameters; writes the log,
// best.toml and the report into the job's folder (default reports/<job name>/).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "cli/flag_checks.h"
#include "rabbit/gait/database_layout.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/ranks.h"
#include "tuner.h"

namespace rabbit::cli {
namespace {

struct TuneArgs {
  std::string job;
  std::string shard;
  std::string params;
  std::string gaits;
  TuneOptions options;
};

int RunTuneCommand(TuneArgs args) {
  if (args.options.resume && args.options.force) {
    throw InputError("--force", 0, "", "--resume continues the log, --force discards it: not both");
  }
  if (!args.shard.empty()) {
    std::string error;
    if (!ParseShard(args.shard, &args.options.shard, &error)) {
      throw InputError("--shard", 0, args.shard, error);
    }
  }
  // Every rank loads the job; a rank that fails alone cannot leave the others waiting.
  TuneJob job;
  RunAgreed([&] {
    ParamOverlay overlay;
    if (!args.params.empty()) overlay = LoadParamOverlay(args.params);
    if (!args.gaits.empty()) overlay.gait_database = GaitDatabaseRoot(args.gaits);
    job = LoadTuneJob(args.job, &overlay);
  });
  args.options.threads = ThreadsPerRank(args.options.threads);
  const bool talk = !args.options.quiet && Ranks::root();
  if (talk) {
    std::printf(
        "job        %s (%s): %s, %zu parameters, budget %d evaluations, %d search%s, seed "
        "%llu%s\n",
        job.name.c_str(), job.file.c_str(), TuneAlgorithmName(job.algorithm), job.parameters.size(),
        job.max_evaluations, job.starts, job.starts == 1 ? "" : "es",
        static_cast<unsigned long long>(job.seed),
        Ranks::size() > 1 ? (", " + std::to_string(Ranks::size()) + " ranks").c_str() : "");
    std::fflush(stdout);
  }
  double best = 0.0;
  bool any = false;
  args.options.on_evaluation = [&](const Evaluation& e) {
    if (!talk) return;
    if (EligibleAsBest(job, e) && (!any || e.objective < best)) {
      best = e.objective;
      any = true;
    }
    const std::string guard = !e.guards_run            ? ""
                              : e.guard_broken.empty() ? "  guards kept"
                                                       : "  broke guard: " + e.guard_broken;
    std::printf("eval %4d  search %d  objective %-12.6g best %-12.6g %d/%d runs failed%s%s%s\n",
                e.index, e.start, e.objective, any ? best : std::nan(""), e.failed, e.runs,
                guard.c_str(), e.error.empty() ? "" : "  invalid: ", e.error.c_str());
    std::fflush(stdout);
  };
  const TuneResult result = RunTune(job, args.options);
  if (talk && result.replayed > 0) {
    std::printf("replayed   %d evaluations from the log\n", result.replayed);
  }
  if (!result.complete) {
    if (talk) {
      std::printf("shard      %s done: run `rabbit tune %s --resume` once every shard is done\n",
                  args.shard.c_str(), args.job.c_str());
    }
    return 0;
  }
  // A job with guards none of whose candidates kept them has no result: exit 1, as a required
  // scenario that fails does for `rabbit run`, said even with --quiet (every rank knows the best).
  if (result.best < 0) {
    if (Ranks::root()) {
      // Why. With no best, every valid candidate beat its search's best eligible objective (none
      // yet) and ran the guards, so each that ran them broke one; the others were invalid
      // (settings refused, or an objective that could not be walked) and never reached them.
      int broke = 0;
      for (const Evaluation& e : result.evaluations) broke += e.guards_run ? 1 : 0;
      const int invalid = static_cast<int>(result.evaluations.size()) - broke;
      std::fprintf(stderr,
                   "rabbit tune: no candidate kept the required scenarios of the guard suites "
                   "passing (%d broke a guard, %d invalid): no best.toml written (see "
                   "%s/evaluations.csv, columns guard_broken and error)\n",
                   broke, invalid, result.out.c_str());
    }
    return 1;
  }
  if (talk) {
    const Evaluation& initial = result.evaluations[result.initial];
    const Evaluation& b = result.evaluations[result.best];
    std::printf("best       objective %.6g at evaluation %d (initial %.6g, %+.1f%%)\n", b.objective,
                b.index, initial.objective,
                initial.objective != 0.0
                    ? 100.0 * (b.objective - initial.objective) / std::abs(initial.objective)
                    : 0.0);
    for (size_t i = 0; i < job.parameters.size(); ++i) {
      std::printf("  %-40s %12.6g  (initial %.6g, bounds [%g, %g])\n",
                  job.parameters[i].name.c_str(), b.x[i], initial.x[i], job.parameters[i].lower,
                  job.parameters[i].upper);
    }
    std::printf("wrote      %s/best.toml (rabbit run --params %s/best.toml ...)\n",
                result.out.c_str(), result.out.c_str());
  }
  return 0;
}

}  // namespace

Command RegisterTune(CLI::App* app) {
  auto args = std::make_shared<TuneArgs>();
  CLI::App* cmd = app->add_subcommand(
      "tune", "Tune parameters over scenario suites with NLopt or Ceres (a job file)");
  cmd->add_option("job", args->job,
                  "Tuning job (TOML, docs/formats/tune-job.md; shipped ones: optimizers/jobs/ "
                  "below the data root)")
      ->required();
  cmd->add_option("--out,-o", args->options.out,
                  "Job folder to write: log, best.toml, report (default: reports/<job name>)");
  cmd->add_option("--jobs,-j", args->options.threads, "Threads per process (0: all cores)")
      ->check(CLI::Range(0, 1024));
  cmd->add_option("--params", args->params,
                  "Parameter overlay under the tuned values (over the job's own `params`; default: "
                  "none)");
  cmd->add_option("--gaits", args->gaits,
                  "Gait database for every walker scenario (folder; default: the one each names)");
  cmd->add_option("--gnuplot", args->options.gnuplot,
                  "gnuplot executable for the figures (searched on PATH without a '/')")
      ->check(RunnableExecutable());
  cmd->add_flag("--resume", args->options.resume,
                "Continue the job's log (after an interruption, or to merge shards)");
  cmd->add_flag("--force", args->options.force, "Discard an existing log and start over");
  cmd->add_option(
      "--shard", args->shard,
      "Run only the searches s with s mod N = I - 1 (I/N, for array jobs; default: all)");
  cmd->add_flag(
      "--no-html", [args](std::int64_t) { args->options.html = false; }, "No index.html");
  cmd->add_flag("--quiet,-q", args->options.quiet, "Print nothing but errors and warnings");
  return {cmd, [args] { return RunTuneCommand(*args); }};
}

}  // namespace rabbit::cli
