// `rabbit run` and `rabbit report` end to end on the built binary: a family's head-to-head table,
// shards merged by `rabbit report` and the shard set's checks.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "rabbit/io/csv_table.h"

namespace {

namespace fs = std::filesystem;
using rabbit::testing::CliRun;
using rabbit::testing::CliTest;
using rabbit::testing::ReadText;
using rabbit::testing::RunCli;
using rabbit::testing::SmallWalkerSuite;
using rabbit::testing::WithoutWallTime;

}  // namespace

namespace {

// The cells of a CSV line (RFC 4180 quotes; no cell spans lines in rabbit's files).
std::vector<std::string> CsvCells(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      cells.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

// Occurrences of needle in text.
int Count(const std::string& text, const std::string& needle) {
  int n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// A CSV file as rows of column name -> cell.
std::vector<std::map<std::string, std::string>> CsvRows(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  const std::vector<std::string> header = CsvCells(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = CsvCells(line);
    EXPECT_EQ(cells.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (size_t k = 0; k < header.size() && k < cells.size(); ++k) row[header[k]] = cells[k];
    rows.push_back(row);
  }
  return rows;
}

// SmallSuite and a family of four pushed walks beside the pragmatic rules: 11 runs.
std::string SuiteWithAFamily() {
  return SmallWalkerSuite("") +
         "[[family]]\nname = \"pushed\"\ncount = 4\nseed = 3\n[family.scenario]\n"
         "required = false\n[family.scenario.controller]\nbaselines = [\"pragmatic\"]\n"
         "[[family.scenario.push]]\nstart = 4.0\nduration = 0.1\nforce_x = 0.0\nheight = 0.2\n"
         "[family.vary]\n\"push.1.force_x\" = [-250.0, 250.0]\n";
}

}  // namespace

TEST_F(CliTest, HeadToHeadOfAFamilyIsTheSummarysAndRabbitReportRebuildsIt) {
  const std::string suite = Write("family.toml", SuiteWithAFamily());
  const fs::path out = dir_ / "out", csv_only = dir_ / "csv_only";
  const CliRun run = RunCli("run " + suite + " -q --out " + out.string());
  ASSERT_EQ(run.code, 0) << run.output;
  const std::string comparison = ReadText(out / "comparison.csv");
  const auto summary = CsvRows(ReadText(out / "summary.csv"));
  ASSERT_EQ(summary.size(), 11u);

  // The same figures computed here from summary.csv: per group (family, or plain scenario) and
  // variant, the counts, passed / runs with the Wilson interval (as the roots of the score
  // test's quadratic), and the speed error over the completed runs.
  struct Expected {
    int runs = 0, passed = 0, completed = 0, fell = 0, tripped = 0;
    std::vector<double> speed_errors;
  };
  std::map<std::string, Expected> expected;  // "group/kind/variant"
  for (const auto& r : summary) {
    const bool member = !r.at("family").empty();
    const std::string key = (member ? r.at("family") : r.at("scenario")) + "/" +
                            (member ? "family" : "scenario") + "/" + r.at("variant");
    Expected& e = expected[key];
    ++e.runs;
    e.passed += r.at("passed") == "1" ? 1 : 0;
    e.completed += r.at("outcome") == "completed" ? 1 : 0;
    e.fell += r.at("outcome") == "fell" ? 1 : 0;
    e.tripped += r.at("outcome") == "tripped" ? 1 : 0;
    if (r.at("outcome") == "completed") {
      e.speed_errors.push_back(std::stod(r.at("mean_abs_speed_error_m_s")));
    }
    EXPECT_EQ(r.at("pattern_memory_bytes") == "0", r.at("variant") == "pragmatic");
  }
  EXPECT_EQ(expected.count("pushed/family/fuzzy_cmac"), 1u);
  EXPECT_EQ(expected.at("pushed/family/fuzzy_cmac").runs, 4);
  const auto rows = CsvRows(comparison);
  ASSERT_EQ(rows.size(), expected.size());  // walk x 2, second, pushed x 2
  const double kTolerance = 1e-9;           // the files' 10 significant digits
  const double z = 1.959963984540054;
  for (const auto& c : rows) {
    const std::string key = c.at("group") + "/" + c.at("group_kind") + "/" + c.at("variant");
    ASSERT_EQ(expected.count(key), 1u) << key;
    const Expected& e = expected.at(key);
    EXPECT_EQ(std::stoi(c.at("runs")), e.runs) << key;
    EXPECT_EQ(std::stoi(c.at("passed")), e.passed) << key;
    EXPECT_EQ(std::stoi(c.at("completed")), e.completed) << key;
    EXPECT_EQ(std::stoi(c.at("fell")), e.fell) << key;
    EXPECT_EQ(std::stoi(c.at("tripped")), e.tripped) << key;
    const double n = e.runs, p = e.passed / n;
    EXPECT_NEAR(std::stod(c.at("success_rate")), p, kTolerance) << key;
    const double a = 1.0 + z * z / n, b = -(2.0 * p + z * z / n);
    const double root = std::sqrt(b * b - 4.0 * a * p * p);
    EXPECT_NEAR(std::stod(c.at("ci_low")), (-b - root) / (2.0 * a), kTolerance) << key;
    EXPECT_NEAR(std::stod(c.at("ci_high")), (-b + root) / (2.0 * a), kTolerance) << key;
    EXPECT_EQ(std::stoi(c.at("speed_error_runs")), static_cast<int>(e.speed_errors.size()));
    if (!e.speed_errors.empty()) {
      double mean = 0.0;
      for (double v : e.speed_errors) mean += v / static_cast<double>(e.speed_errors.size());
      EXPECT_NEAR(std::stod(c.at("speed_error_mean_m_s")), mean, kTolerance) << key;
    } else {
      EXPECT_EQ(c.at("speed_error_mean_m_s"), "nan") << key;
    }
  }
  // The family's outcomes are mixed (else this test would check little).
  const Expected& walker = expected.at("pushed/family/fuzzy_cmac");
  const Expected& rules = expected.at("pushed/family/pragmatic");
  EXPECT_LT(walker.completed + rules.completed, 8);
  EXPECT_GT(walker.completed + rules.completed, 0);

  // The page opens with the head-to-head: a table per group, the family's chart.
  const std::string page = ReadText(out / "index.html");
  EXPECT_NE(page.find("<section id=\"head-to-head\">"), std::string::npos);
  EXPECT_EQ(Count(page, "<table class=\"comparison\">"), 3);
  if (run.output.find("figures left out") == std::string::npos) {
    EXPECT_EQ(Count(page, "alt=\"head-to-head of pushed\""), 1);
  }
  // rabbit report rebuilds comparison.csv from summary.csv alone; --no-html writes it too.
  fs::remove(out / "comparison.csv");
  fs::remove(out / "index.html");
  ASSERT_EQ(RunCli("report -q " + out.string()).code, 0);
  EXPECT_EQ(ReadText(out / "comparison.csv"), comparison);
  EXPECT_TRUE(fs::exists(out / "index.html"));
  ASSERT_EQ(RunCli("run " + suite + " --no-html -q --out " + csv_only.string()).code, 0);
  EXPECT_EQ(ReadText(csv_only / "comparison.csv"), comparison);
  EXPECT_FALSE(fs::exists(csv_only / "index.html"));
}

TEST_F(CliTest, ShardsMergedByReportEqualAnUnshardedRun) {
  const std::string suite = Write("small.toml", SmallWalkerSuite(""));
  const fs::path one = dir_ / "one", merged = dir_ / "merged";
  ASSERT_EQ(RunCli("run " + suite + " --no-html -q --out " + one.string()).code, 0);
  // Shard 1 of 2 takes jobs 0 and 2 (walk, second), shard 2 job 1 (walk+nearest_gait).
  const CliRun first = RunCli("run " + suite + " --shard 1/2 --out " + merged.string());
  ASSERT_EQ(first.code, 0) << first.output;
  EXPECT_NE(first.output.find("shard 1/2, 2 of 3 runs"), std::string::npos) << first.output;
  const fs::path shard1 = merged / "shards" / "1-of-2";
  for (const char* file : {".rabbit-shard", "summary.csv", "walk/steps.csv", "second/meta.csv"}) {
    EXPECT_TRUE(fs::exists(shard1 / file)) << file;
  }
  EXPECT_FALSE(fs::exists(shard1 / "walk+nearest_gait"));
  EXPECT_FALSE(fs::exists(shard1 / "index.html"));
  EXPECT_FALSE(fs::exists(merged / "summary.csv"));  // the main report is not touched
  const std::string marker = ReadText(shard1 / ".rabbit-shard");
  EXPECT_EQ(marker.rfind("rabbit-shard/1\nsuite = small\nshard = 1/2\nplan = ", 0), 0u) << marker;
  EXPECT_NE(marker.find("\njobs = 3\nruns = 2\n"), std::string::npos) << marker;
  EXPECT_EQ(ReadText(shard1 / "summary.csv").find("\n1,"), std::string::npos);  // not its job
  ASSERT_EQ(RunCli("run " + suite + " --shard 2/2 -q --out " + merged.string() + "/").code, 0);
  EXPECT_TRUE(fs::exists(shard1 / "walk")) << "shard 2 touched shard 1";

  const CliRun report = RunCli("report " + merged.string());
  ASSERT_EQ(report.code, 0) << report.output;
  EXPECT_NE(report.output.find("merged 2 shard(s) of suite small: 3 runs"), std::string::npos)
      << report.output;
  EXPECT_EQ(WithoutWallTime(ReadText(one / "summary.csv")),
            WithoutWallTime(ReadText(merged / "summary.csv")));
  for (const char* run : {"walk", "walk+nearest_gait", "second"}) {
    for (const char* file : {"steps.csv", "trajectory.csv", "meta.csv", "tracking.csv"}) {
      EXPECT_EQ(ReadText(one / run / file), ReadText(merged / run / file)) << run << "/" << file;
    }
  }
  EXPECT_FALSE(fs::exists(merged / "shards"));
  EXPECT_TRUE(fs::exists(merged / "index.html"));
  EXPECT_EQ(ReadText(one / "comparison.csv"), ReadText(merged / "comparison.csv"));
  EXPECT_EQ(ReadText(merged / ".rabbit-report"), ReadText(one / ".rabbit-report"));
  for (const auto& entry : fs::directory_iterator(dir_)) {
    EXPECT_EQ(entry.path().filename().string().find(".partial"), std::string::npos);
  }
  // The merged folder is a report again: rebuilt by rabbit report, replaced by rabbit run.
  EXPECT_EQ(RunCli("report -q " + merged.string()).code, 0);
  EXPECT_EQ(RunCli("run " + suite + " --no-html -q --out " + merged.string()).code, 0);
}

TEST_F(CliTest, ShardBadInputExitsTwoAndWritesNothing) {
  const std::string suite = Write("small.toml", SmallWalkerSuite(""));
  const fs::path out = dir_ / "report";
  for (const char* shard : {"3/2", "0/2", "1/0", "2", "a/b", "1/2/3"}) {
    const CliRun r = RunCli("run " + suite + " --shard " + shard + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << shard << r.output;
    EXPECT_NE(r.output.find("--shard expects I/N"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out)) << shard;
  }
  // A folder that is neither a report nor a folder of shards is not written into.
  fs::create_directories(dir_ / "precious");
  std::ofstream(dir_ / "precious" / "thesis.tex") << "keep me";
  const CliRun refused =
      RunCli("run " + suite + " --shard 1/2 --out " + (dir_ / "precious").string());
  EXPECT_EQ(refused.code, 2) << refused.output;
  EXPECT_FALSE(fs::exists(dir_ / "precious" / "shards"));
  // An unsharded run does not replace a folder of shards: merge it first.
  ASSERT_EQ(RunCli("run " + suite + " --shard 1/2 -q --out " + out.string()).code, 0);
  const CliRun unsharded = RunCli("run " + suite + " --no-html --out " + out.string());
  EXPECT_EQ(unsharded.code, 2) << unsharded.output;
  EXPECT_NE(unsharded.output.find("rabbit report"), std::string::npos) << unsharded.output;
  EXPECT_TRUE(fs::exists(out / "shards" / "1-of-2" / "walk"));
}

TEST_F(CliTest, ReportRefusesAnIncompleteOrMixedSetOfShards) {
  const std::string suite = Write("small.toml", SmallWalkerSuite(""));
  const fs::path out = dir_ / "report";
  ASSERT_EQ(RunCli("run " + suite + " --shard 1/3 -q --out " + out.string()).code, 0);
  ASSERT_EQ(RunCli("run " + suite + " --shard 3/3 -q --out " + out.string()).code, 0);
  const CliRun missing = RunCli("report " + out.string());
  EXPECT_EQ(missing.code, 2) << missing.output;
  EXPECT_NE(missing.output.find("missing shard(s) 2-of-3"), std::string::npos) << missing.output;
  // Nothing changed.
  EXPECT_TRUE(fs::exists(out / "shards" / "1-of-3" / "walk" / "steps.csv"));
  EXPECT_TRUE(fs::exists(out / "shards" / "3-of-3" / "second" / "steps.csv"));
  EXPECT_FALSE(fs::exists(out / "summary.csv"));
  EXPECT_FALSE(fs::exists(out / "index.html"));
  // Shard 2 of another plan (another --filter) does not complete the set; nor does another N.
  ASSERT_EQ(RunCli("run " + suite + " --filter walk --shard 2/3 -q --out " + out.string()).code, 0);
  const CliRun mixed = RunCli("report " + out.string());
  EXPECT_EQ(mixed.code, 2) << mixed.output;
  EXPECT_NE(mixed.output.find("another plan"), std::string::npos) << mixed.output;
  ASSERT_EQ(RunCli("run " + suite + " --shard 2/2 -q --out " + out.string()).code, 0);
  const CliRun counts = RunCli("report " + out.string());
  EXPECT_EQ(counts.code, 2) << counts.output;
  EXPECT_NE(counts.output.find("different counts"), std::string::npos) << counts.output;
  EXPECT_FALSE(fs::exists(out / "summary.csv"));
  // With the stray shards gone and shard 2 run again, the set merges.
  fs::remove_all(out / "shards" / "2-of-2");
  ASSERT_EQ(RunCli("run " + suite + " --shard 2/3 -q --out " + out.string()).code, 0);
  const CliRun complete = RunCli("report -q " + out.string());
  EXPECT_EQ(complete.code, 0) << complete.output;
  EXPECT_TRUE(fs::exists(out / "walk+nearest_gait" / "steps.csv"));
}

// A gnuplot the user names that cannot be run is a usage error before any work (run, report and
// tune; with a '/' a file that is not executable, without one no such name on PATH); a gnuplot
// that runs and fails is a warning, and the page is written without its figures.
TEST_F(CliTest, AGnuplotThatCannotBeRunIsAUsageError) {
  const std::string suite = Write("small.toml", SmallWalkerSuite(""));
  const fs::path out = dir_ / "report";
  const std::string not_executable = Write("gnuplot", "#!/bin/sh\nexit 0\n");  // mode 644
  for (const std::string& gnuplot : {std::string("rabbit-no-such-gnuplot"),
                                     (dir_ / "missing").string(), not_executable, dir_.string()}) {
    SCOPED_TRACE(gnuplot);
    for (const std::string& command : {"run " + suite + " -q --out " + out.string(),
                                       "report -q " + out.string(), "tune " + suite + " -q"}) {
      const CliRun r = RunCli(command + " --gnuplot " + gnuplot);
      EXPECT_EQ(r.code, 2) << command << r.output;
      EXPECT_NE(r.output.find("--gnuplot: cannot run '" + gnuplot + "'"), std::string::npos)
          << r.output;
      EXPECT_FALSE(fs::exists(out)) << command;
    }
  }
  const CliRun fails =
      RunCli("run " + suite + " -q --out " + out.string() + " --gnuplot /bin/false");
  EXPECT_EQ(fails.code, 0) << fails.output;
  EXPECT_NE(fails.output.find("warning: figures left out"), std::string::npos) << fails.output;
  EXPECT_TRUE(fs::exists(out / "index.html"));
}
