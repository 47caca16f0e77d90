// rabbit report DIR [--gnuplot PATH]: rebuilds DIR/index.html from the CSV files a batch run wrote
// (summary.csv and each run's folder), without re-running anything.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "rabbit/report/suite_report.h"

namespace rabbit::cli {
namespace {

struct ReportArgs {
  std::string dir;
  SuiteReportOptions options;
  bool quiet = false;
};

int RunReport(const ReportArgs& args) {
  std::string error;
  if (!args.options.IsValid(&error)) {
    std::cerr << "rabbit report: " << error << "\n";
    return 2;
  }
  std::vector<std::string> warnings;
  const std::string page = WriteSuiteReport(args.dir, args.options, &warnings);
  for (const std::string& w : warnings) std::cerr << "rabbit report: warning: " << w << "\n";
  if (!args.quiet) std::printf("wrote %s\n", page.c_str());
  return 0;
}

}  // namespace

Command RegisterReport(CLI::App* app) {
  auto args = std::make_shared<ReportArgs>();
  CLI::App* cmd = app->add_subcommand(
      "report", "Rebuild the HTML report of a batch run (DIR/index.html) from its CSV files");
  cmd->add_option("dir", args->dir, "Report directory written by `rabbit run` (has summary.csv)")
      ->required();
  cmd->add_option("--gnuplot", args->options.gnuplot,
                  "gnuplot executable for the figures (default: gnuplot on PATH); without it "
                  "the page has tables and replays only");
  cmd->add_option("--replay-fps", args->options.replay_fps,
                  "Frames per second of the replays (default 25)");
  cmd->add_option("--stick-window", args->options.stick_window,
                  "Seconds of walking per stick diagram (default 3)");
  cmd->add_option("--stick-every", args->options.stick_every,
                  "Seconds between the figures of a stick diagram (default 0.1)");
  cmd->add_flag("--quiet,-q", args->quiet, "Print nothing but warnings and errors");
  return {cmd, [args] { return RunReport(*args); }};
}

}  // namespace rabbit::cli
