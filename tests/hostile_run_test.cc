// Hostile input to `rabbit run`'s flags, end to end through the built binary in a scratch folder:
// a --filter pattern that backtracks exponentially in a backtracking engine, and a gnuplot that
// floods its output. (The table of bad inputs per reader is hostile_input_test.cc.)
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "cli_fixture.h"
#include "hostile_fixture.h"

namespace {

namespace fs = std::filesystem;
using rabbit::testing::CliRun;
using rabbit::testing::kDropInSuite;
using rabbit::testing::RunCli;
using rabbit::testing::WriteText;

// A pattern that backtracks exponentially in a backtracking engine ((a|aa)*c on 60 a's: about
// 1.5e12 paths) is matched in linear time by RE2: the run selects nothing and says so.
TEST(HostileFilterTest, ExponentialPatternOnALongNameEndsAtOnce) {
  const fs::path dir =
      fs::temp_directory_path() / ("rabbit_hostile_filter_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  WriteText(dir / "s.toml", "[suite]\nname = \"f\"\n[[scenario]]\nname = \"" +
                                std::string(60, 'a') + "\"\n" + kDropInSuite);
  const CliRun run = RunCli("run " + (dir / "s.toml").string() + " --filter '(a|aa)*c' --out " +
                            (dir / "out").string());
  EXPECT_EQ(run.code, 2) << run.output;
  EXPECT_NE(run.output.find("--filter"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // And a pattern that does match selects the scenario.
  const CliRun match = RunCli("run " + (dir / "s.toml").string() + " --filter '^(a|aa)*$' -q " +
                              "--no-html --out " + (dir / "out").string());
  EXPECT_EQ(match.code, 0) << match.output;
  EXPECT_TRUE(fs::exists(dir / "out/summary.csv"));
  fs::remove_all(dir);
}

// A gnuplot that prints 20 MB: the warning quotes a bounded part of it, with a note.
TEST(HostileGnuplotTest, HugeOutputIsCutInTheWarning) {
  const fs::path dir =
      fs::temp_directory_path() / ("rabbit_hostile_gnuplot_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  WriteText(dir / "s.toml",
            "[suite]\nname = \"g\"\n[[scenario]]\nname = \"drop\"\n" + kDropInSuite);
  WriteText(dir / "gnuplot.sh", "#!/bin/sh\nyes x | head -c 20000000 | tr -d '\\n' >&2\nexit 1\n");
  fs::permissions(dir / "gnuplot.sh", fs::perms::owner_all);
  const CliRun run = RunCli("run " + (dir / "s.toml").string() + " -q --gnuplot " +
                            (dir / "gnuplot.sh").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(run.code, 0) << run.output.substr(0, 2000);
  EXPECT_NE(run.output.find("warning"), std::string::npos) << run.output.substr(0, 2000);
  EXPECT_NE(run.output.find("more bytes left out"), std::string::npos)
      << run.output.substr(0, 2000);
  EXPECT_LT(run.output.size(), 20000u);
  fs::remove_all(dir);
}

}  // namespace
