// A small batch-run report directory for the report tests, written from real walks: the shipped
// reference gaits re-walked with the library (WalkGait), their trajectories decimated to 100 Hz,
// and synthetic steps, tracking and fuzzy weights in the formats `rabbit run` writes.
#ifndef RABBIT_TESTS_REPORT_FIXTURE_H_
#define RABBIT_TESTS_REPORT_FIXTURE_H_

#include <string>
#include <vector>

namespace rabbit::testing {

struct ReportFixture {
  std::string dir;
  std::vector<std::string> runs;  // folder names, in summary order
  int expected_figures = 0;       // gnuplot figures the page should carry
};

// Writes into dir (created): summary.csv and the folders of three runs, "walk" (fuzzy_cmac, flat
// ground), "walk+pragmatic" (its baseline) and "obstacle" (fuzzy_cmac, one 2 cm obstacle); one
// summary cell is RFC 4180 quoted. `duration` seconds of walking per run.
ReportFixture WriteReportFixture(const std::string& dir, double duration = 12.0);

// Writes text to path (creating directories).
void WriteText(const std::string& path, const std::string& text);
// A file's bytes; when it cannot be read, a test failure and "" (cli_fixture.h's ReadText).
std::string ReadText(const std::string& path);
// Occurrences of needle in text.
int Count(const std::string& text, const std::string& needle);

}  // namespace rabbit::testing

#endif  // RABBIT_TESTS_REPORT_FIXTURE_H_
