// Survival against push impulse: a run's impulse from meta.csv's pushes against hand-computed
// sums; the binning of hand-built rows (edges, directions, order, counts, the Wilson interval of
// each bin against comparison.h's); push_survival.csv from a report folder; and the report page's
// chart for a pushed family (none for an unpushed one).
#include "rabbit/report/push_survival.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "rabbit/io/error.h"
#include "rabbit/report/suite_report.h"
#include "report_fixture.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;
using report_internal::SummaryRow;
using testing::Count;
using testing::ReadText;
using testing::WriteText;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

TEST(PushImpulseTest, SumsForceTimesDurationOfEveryPush) {
  const double kTolerance = 1e-12;
  EXPECT_EQ(PushImpulse("", "meta.csv", 3), 0.0);
  EXPECT_NEAR(PushImpulse("12:0.1:60:0:0.2", "meta.csv", 3), 6.0, kTolerance);
  // A push whose event never came (start nan) still counts; force_y does not.
  EXPECT_NEAR(PushImpulse("nan:0.2:-50:30:0.2", "meta.csv", 3), -10.0, kTolerance);
  EXPECT_NEAR(PushImpulse("1:0.1:60:0:0.2;5:0.05:-40:0:0.2", "meta.csv", 3), 6.0 - 2.0, kTolerance);
}

TEST(PushImpulseTest, MalformedPushesNameFileLineAndKey) {
  for (const char* bad : {"12:0.1:60:0", "12:0.1:sixty:0:0.2", "12:-0.1:60:0:0.2",
                          "12:0.1:inf:0:0.2", "12:0.1:60:0:0.2;"}) {
    try {
      PushImpulse(bad, "run/meta.csv", 9);
      // A trailing ';' adds no push: not an error.
      EXPECT_EQ(std::string(bad), "12:0.1:60:0:0.2;");
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "run/meta.csv") << bad;
      EXPECT_EQ(e.line(), 9) << bad;
      EXPECT_EQ(e.key(), "pushes") << bad;
    }
  }
}

SummaryRow Row(const std::string& group, const std::string& variant, bool passed,
               bool member = true) {
  SummaryRow r;
  r.suite = "s";
  r.group = group;
  r.scenario = group + "-000";
  r.variant = variant;
  r.passed = passed;
  r.is_family_member = member;
  return r;
}

TEST(PushSurvivalTest, BinsByDirectionAndSizeInOrderWithWilsonIntervals) {
  std::vector<SummaryRow> rows;
  std::vector<double> j;
  auto add = [&](const SummaryRow& r, double impulse) {
    rows.push_back(r);
    j.push_back(impulse);
  };
  add(Row("push", "fuzzy_cmac", true), 3.0);         // forward [0, 5)
  add(Row("push", "chapter", false), 3.0);           // the baseline's own bins
  add(Row("push", "fuzzy_cmac", false), 5.0);        // forward [5, 10): an edge opens its bin
  add(Row("push", "fuzzy_cmac", true), 9.99);        // forward [5, 10)
  add(Row("push", "fuzzy_cmac", true), -4.0);        // backward [0, 5)
  add(Row("push", "fuzzy_cmac", false), -12.0);      // backward [10, 15)
  add(Row("push", "fuzzy_cmac", true), 0.0);         // not pushed: left out
  add(Row("push", "fuzzy_cmac", true), kNan);        // not known: left out
  add(Row("walk", "fuzzy_cmac", true, false), 6.0);  // a plain scenario: left out
  add(Row("quiet", "fuzzy_cmac", true), 0.0);        // a family never pushed: no rows
  const std::vector<SurvivalBin> bins = PushSurvival(rows, j, 5.0);
  struct Want {
    const char* variant;
    bool forward;
    double min, max;
    int runs, passed;
  };
  const std::vector<Want> want = {{"fuzzy_cmac", false, 0, 5, 1, 1},
                                  {"fuzzy_cmac", false, 10, 15, 1, 0},
                                  {"fuzzy_cmac", true, 0, 5, 1, 1},
                                  {"fuzzy_cmac", true, 5, 10, 2, 1},
                                  {"chapter", true, 0, 5, 1, 0}};
  ASSERT_EQ(bins.size(), want.size());
  for (size_t k = 0; k < want.size(); ++k) {
    const SurvivalBin& b = bins[k];
    EXPECT_EQ(b.group, "push");
    EXPECT_EQ(b.variant, want[k].variant) << k;
    EXPECT_EQ(b.forward, want[k].forward) << k;
    EXPECT_EQ(b.impulse_min, want[k].min) << k;
    EXPECT_EQ(b.impulse_max, want[k].max) << k;
    EXPECT_EQ(b.runs, want[k].runs) << k;
    EXPECT_EQ(b.passed, want[k].passed) << k;
    EXPECT_EQ(b.success_rate, static_cast<double>(b.passed) / b.runs) << k;
    const ProportionInterval ci = WilsonInterval(b.passed, b.runs);
    EXPECT_EQ(b.ci.low, ci.low) << k;
    EXPECT_EQ(b.ci.high, ci.high) << k;
  }
  const std::string csv = PushSurvivalCsv(bins);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), PushSurvivalHeader());
  EXPECT_NE(csv.find("\ns,push,fuzzy_cmac,forward,5,10,2,1,0.5,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\ns,push,chapter,forward,0,5,1,0,0,0,"), std::string::npos) << csv;
  EXPECT_THROW(PushSurvival(rows, j, 0.0), std::invalid_argument);
  EXPECT_THROW(PushSurvival(rows, j, kNan), std::invalid_argument);
}

bool OnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path == nullptr ? "" : path);
  for (std::string dir; std::getline(dirs, dir, ':');) {
    if (::access((fs::path(dir) / name).c_str(), X_OK) == 0) return true;
  }
  return false;
}

// The report fixture's three runs made members of family "fam", pushed as given (meta.csv's
// pushes, by run folder).
std::string PushedFixture(const std::string& name,
                          const std::vector<std::pair<std::string, std::string>>& pushes) {
  const fs::path dir = fs::temp_directory_path() /
                       ("rabbit_push_survival_test_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  testing::WriteReportFixture(dir.string(), 4.0);
  const std::string summary = (dir / "summary.csv").string();
  std::istringstream lines(ReadText(summary));
  std::string with_family;
  for (std::string line; std::getline(lines, line);) {
    with_family += line + (with_family.empty() ? ",family\n" : ",fam\n");
  }
  WriteText(summary, with_family);
  for (const auto& [run, text] : pushes) {
    const std::string meta = (dir / run / "meta.csv").string();
    WriteText(meta, ReadText(meta) + "pushes," + text + "\n");
  }
  return dir.string();
}

TEST(PushSurvivalReportTest, WritesTheCsvAndTheChartOfAPushedFamily) {
  const std::string dir =
      PushedFixture("pushed", {{"walk", "12:0.1:60:0:0.2"},            // +6 N s, passed
                               {"walk+pragmatic", "12:0.1:60:0:0.2"},  // +6 N s, failed (baseline)
                               {"obstacle", "12:0.1:-120:0:0.2"}});    // -12 N s, passed
  const std::vector<SurvivalBin> bins = WritePushSurvival(dir, 5.0, nullptr);
  ASSERT_EQ(bins.size(), 3u);
  const std::string csv = ReadText((fs::path(dir) / kPushSurvivalFile).string());
  EXPECT_EQ(csv, PushSurvivalCsv(bins));
  EXPECT_NE(csv.find("\nsuite_fixture,fam,fuzzy_cmac,backward,10,15,1,1,1,"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\nsuite_fixture,fam,fuzzy_cmac,forward,5,10,1,1,1,"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\nsuite_fixture,fam,pragmatic,forward,5,10,1,0,0,"), std::string::npos)
      << csv;
  fs::remove(fs::path(dir) / kPushSurvivalFile);
  if (OnPath("gnuplot")) {
    SuiteReportOptions options;
    std::vector<std::string> warnings;
    const std::string page = ReadText(WriteSuiteReport(dir, options, &warnings));
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_EQ(Count(page, "alt=\"survival against push impulse, fam\""), 1);
    EXPECT_EQ(ReadText((fs::path(dir) / kPushSurvivalFile).string()), csv);
  }
  // A malformed pushes value names its file and key; nothing is written.
  fs::remove(fs::path(dir) / kPushSurvivalFile);
  const std::string meta = (fs::path(dir) / "obstacle" / "meta.csv").string();
  std::string text = ReadText(meta);
  text.replace(text.find("-120"), 4, "lots");
  WriteText(meta, text);
  try {
    WritePushSurvival(dir, 5.0, nullptr);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), meta);
    EXPECT_EQ(e.key(), "pushes");
  }
  EXPECT_FALSE(fs::exists(fs::path(dir) / kPushSurvivalFile));
  fs::remove_all(dir);
}

TEST(PushSurvivalReportTest, AnUnpushedFamilyGetsNoFileAndNoChart) {
  const std::string dir = PushedFixture("quiet", {});
  std::vector<std::string> warnings;
  EXPECT_TRUE(WritePushSurvival(dir, 5.0, &warnings).empty());
  EXPECT_TRUE(warnings.empty());
  EXPECT_FALSE(fs::exists(fs::path(dir) / kPushSurvivalFile));
  if (OnPath("gnuplot")) {
    const std::string page = ReadText(WriteSuiteReport(dir, SuiteReportOptions{}, nullptr));
    EXPECT_EQ(Count(page, "survival against push impulse"), 0);
    EXPECT_EQ(Count(page, "alt=\"head-to-head of fam\""), 1);  // the family's other chart
    EXPECT_FALSE(fs::exists(fs::path(dir) / kPushSurvivalFile));
  }
  // A member whose folder is gone is left out with a warning, not an error.
  fs::remove_all(fs::path(dir) / "obstacle");
  EXPECT_TRUE(WritePushSurvival(dir, 5.0, &warnings).empty());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings.front().find("1 family runs have no meta.csv"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rabbit
