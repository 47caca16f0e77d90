// The batch-run report from the CSV files of a run: the page has the summary rows, one replay per
// run and the gnuplot figures; without gnuplot a warning and no figures, never a failure;
// malformed input names the file, line and column; the stick-figure geometry at hand-computed
// points and against the model's own kinematics.
#include "rabbit/report/suite_report.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "rabbit/io/error.h"
#include "rabbit/model/model.h"
#include "rabbit/report/report_data.h"
#include "report_fixture.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;
using testing::Count;
using testing::ReadText;
using testing::WriteText;
using report_internal::ReadRun;
using report_internal::ReadSummary;
using report_internal::SummaryRow;

bool OnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string dirs = path == nullptr ? "" : path;
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(start, end - start)) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

class SuiteReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const fs::path dir =
        fs::temp_directory_path() / ("rabbit_suite_report_test_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fixture_ = new testing::ReportFixture(testing::WriteReportFixture(dir.string()));
  }
  static void TearDownTestSuite() {
    fs::remove_all(fixture_->dir);
    delete fixture_;
    fixture_ = nullptr;
  }
  // A copy of the fixture to break, in its own directory.
  static std::string CopyFixture(const std::string& name) {
    const fs::path copy = fs::path(fixture_->dir).parent_path() /
                          (fs::path(fixture_->dir).filename().string() + "_" + name);
    fs::remove_all(copy);
    fs::copy(fixture_->dir, copy, fs::copy_options::recursive);
    fs::remove(copy / "index.html");  // another test's page
    return copy.string();
  }
  static testing::ReportFixture* fixture_;
};
testing::ReportFixture* SuiteReportTest::fixture_ = nullptr;

TEST_F(SuiteReportTest, PageHasSummaryReplaysAndFigures) {
  if (!OnPath("gnuplot")) GTEST_SKIP() << "gnuplot is not on PATH (Debian: gnuplot-nox)";
  std::vector<std::string> warnings;
  const std::string path = WriteSuiteReport(fixture_->dir, SuiteReportOptions{}, &warnings);
  EXPECT_EQ(path, (fs::path(fixture_->dir) / "index.html").string());
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  const std::string page = ReadText(path);
  ASSERT_FALSE(page.empty());
  // Summary: one row per run, pass/fail classes, the quoted criteria split into items.
  EXPECT_EQ(Count(page, "<tr class=\"pass"), 2);
  EXPECT_EQ(Count(page, "<tr class=\"fail"), 1);
  EXPECT_NE(page.find("<code>walk+pragmatic</code>"), std::string::npos);
  EXPECT_NE(page.find("<li>mean speed error 0.09 m/s &gt; 0.03 m/s</li>"), std::string::npos);
  EXPECT_NE(page.find("<li>L_step spread, last 10 steps, 2 mm</li>"), std::string::npos);
  EXPECT_NE(page.find("Suite <em>suite_fixture</em>"), std::string::npos);
  // Baselines grouped with their scenario: the scenario cell spans walk's two runs and the
  // baseline's row of failed criteria.
  EXPECT_NE(page.find("rowspan=\"3\"><a href=\"#scenario-0\">walk</a>"), std::string::npos);
  EXPECT_EQ(Count(page, "<tr class=\"criteria-row\">"), 1);
  // One replay per run, and its frames at replay_fps over the 12 s walks (301 frames).
  EXPECT_EQ(Count(page, "<canvas"), static_cast<int>(fixture_->runs.size()));
  EXPECT_EQ(Count(page, "class=\"replay-data\""), static_cast<int>(fixture_->runs.size()));
  EXPECT_EQ(Count(page, "\"frames\":301,"), 3);
  // The figures, inlined as images, and nothing fetched from elsewhere.
  EXPECT_EQ(Count(page, "<img class=\"fig\""), fixture_->expected_figures);
  EXPECT_EQ(Count(page, "src=\"data:image/svg+xml;base64,"), fixture_->expected_figures);
  EXPECT_EQ(page.find("http:"), std::string::npos);
  EXPECT_EQ(page.find("https:"), std::string::npos);
  // Compact: under 1 MB per run, coordinates rounded to 4 decimals.
  EXPECT_LT(page.size(), fixture_->runs.size() * 1000000);
  const size_t data = page.find("class=\"replay-data\">");
  const std::string json = page.substr(data, page.find("</script>", data) - data);
  EXPECT_FALSE(std::regex_search(json, std::regex("[0-9]\\.[0-9]{5}")));
  EXPECT_TRUE(std::regex_search(json, std::regex("[0-9]\\.[0-9]{4}")));
  // The error counter is installed before any other script.
  EXPECT_LT(page.find("addEventListener('error'"), page.find("<style>"));
}

// The numbers of a JSON array `"key":[...]` in `json` (of its first inner array, if nested).
std::vector<double> JsonArray(const std::string& json, const std::string& key) {
  std::vector<double> out;
  const size_t at = json.find("\"" + key + "\":[");
  if (at == std::string::npos) return out;
  std::stringstream s(json.substr(at + key.size() + 4, json.find(']', at) - at - key.size() - 4));
  std::string cell;
  while (std::getline(s, cell, ',')) {
    cell.erase(0, cell.find_first_not_of('['));  // nested arrays: [[a, b], ...]
    out.push_back(std::atof(cell.c_str()));
  }
  return out;
}

// A replay opens near the first event: the obstacle run a little before its hip reaches the
// obstacle, the walks (completed, nothing ahead) at their start. The page opens on the verdict
// and keeps each scenario's figures, steps and replays in a collapsed block.
TEST_F(SuiteReportTest, ReplaysOpenNearTheObstacleAndDetailIsOneClickAway) {
  const std::string dir = CopyFixture("replay_start");
  SuiteReportOptions options;
  options.gnuplot = "/nonexistent/gnuplot";
  const std::string page = ReadText(WriteSuiteReport(dir, options, nullptr));
  int replays = 0, with_obstacle = 0;
  for (size_t at = page.find("class=\"replay-data\">"); at != std::string::npos;
       at = page.find("class=\"replay-data\">", at + 1)) {
    ++replays;
    const std::string json = page.substr(at, page.find("</script>", at) - at);
    const std::smatch found = [&json] {
      std::smatch m;
      std::regex_search(json, m, std::regex("\"start\":([0-9]+),"));
      return m;
    }();
    ASSERT_FALSE(found.empty()) << json.substr(0, 200);
    const size_t start = std::stoul(found[1].str());
    const std::vector<double> p = JsonArray(json, "p");
    const std::vector<double> obstacle = JsonArray(json, "obs");  // [[x_start, ...]]
    ASSERT_LT(12 * start, p.size());
    if (obstacle.empty()) {
      EXPECT_EQ(start, 0u);
      continue;
    }
    ++with_obstacle;
    // Hip x at the first frame: about 0.6 m plus a second of walking (0.5 to 1.0 m/s) before
    // the obstacle, and the obstacle still ahead.
    const double hip_x = p[12 * start], x_start = obstacle.front();
    EXPECT_GT(start, 0u);
    EXPECT_GT(hip_x, x_start - 0.6 - 1.2) << "opens too early";
    EXPECT_LT(hip_x, x_start - 0.6) << "opens past the approach";
  }
  EXPECT_EQ(replays, 3);
  EXPECT_EQ(with_obstacle, 1);
  EXPECT_LT(page.find("<b>Verdict</b>"), page.find("<section id=\"head-to-head\">"));
  EXPECT_EQ(Count(page, "<details class=\"run-detail\">"), 2);  // walk, obstacle
  EXPECT_LT(page.find("<details class=\"run-detail\">"), page.find("<canvas"));
}

TEST_F(SuiteReportTest, PageOpensWithTheHeadToHeadAndWritesComparisonCsv) {
  const std::string dir = CopyFixture("head_to_head");
  SuiteReportOptions options;
  options.gnuplot = "/nonexistent/gnuplot";
  const std::string page = ReadText(WriteSuiteReport(dir, options, nullptr));
  // The section comes first, one table per group (walk: two variants; obstacle: one).
  const size_t section = page.find("<section id=\"head-to-head\">");
  ASSERT_NE(section, std::string::npos);
  EXPECT_LT(section, page.find("<h2>Summary</h2>"));
  EXPECT_EQ(Count(page, "<table class=\"comparison\">"), 2);
  EXPECT_NE(page.find("<div class=\"group\" id=\"group-1\"><h3>obstacle</h3>"), std::string::npos);
  EXPECT_NE(page.find("Wilson"), std::string::npos);
  // comparison.csv, with the summary's numbers: walk's baseline failed, the walker passed.
  const std::string csv = ReadText((fs::path(dir) / "comparison.csv").string());
  EXPECT_EQ(Count(csv, "\n"), 4);
  EXPECT_NE(csv.find("\nsuite_fixture,walk,scenario,1,fuzzy_cmac,fuzzy_cmac,main,1,1,1,"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\nsuite_fixture,walk,scenario,1,pragmatic,pragmatic,baseline,1,0,0,0,"),
            std::string::npos)
      << csv;
  fs::remove_all(dir);
}

TEST_F(SuiteReportTest, FamilyMembersBeyondTheFirstOnesHaveNoFiguresOrReplays) {
  if (!OnPath("gnuplot")) GTEST_SKIP() << "gnuplot is not on PATH (Debian: gnuplot-nox)";
  // walk and obstacle made members of one family.
  const std::string dir = CopyFixture("family");
  const std::string summary = (fs::path(dir) / "summary.csv").string();
  std::string text = ReadText(summary), with_family;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    with_family += line + (with_family.empty() ? ",family\n" : ",fam\n");
  }
  WriteText(summary, with_family);
  // A run folder of a member not shown is not even read.
  fs::remove(fs::path(dir) / "obstacle" / "steps.csv");
  SuiteReportOptions options;
  options.family_details = 1;
  std::vector<std::string> warnings;
  std::string page = ReadText(WriteSuiteReport(dir, options, &warnings));
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  EXPECT_EQ(Count(page, "<canvas"), 2);  // walk and walk+pragmatic
  // walk's 4 figures and the family's head-to-head chart (no overview of a single group).
  EXPECT_EQ(Count(page, "<img class=\"fig\""), 5);
  EXPECT_EQ(Count(page, "alt=\"head-to-head of fam\""), 1);
  EXPECT_NE(page.find("family <em>fam</em> shows the first 1 of its 2 members in detail"),
            std::string::npos);
  EXPECT_NE(page.find("Family of 2 members."), std::string::npos);
  const std::string csv = ReadText((fs::path(dir) / "comparison.csv").string());
  EXPECT_NE(csv.find("\nsuite_fixture,fam,family,2,fuzzy_cmac,fuzzy_cmac,main,2,2,1,"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find("\nsuite_fixture,fam,family,2,pragmatic,pragmatic,baseline,1,0,0,"),
            std::string::npos)
      << csv;
  // Every member (the missing file is now an error, as for any run shown).
  options.family_details = -1;
  EXPECT_THROW(WriteSuiteReport(dir, options, nullptr), InputError);
  fs::copy(fs::path(fixture_->dir) / "obstacle" / "steps.csv", fs::path(dir) / "obstacle");
  page = ReadText(WriteSuiteReport(dir, options, nullptr));
  EXPECT_EQ(Count(page, "<canvas"), 3);
  EXPECT_EQ(Count(page, "<img class=\"fig\""), 4 + 5 + 1);
  fs::remove_all(dir);
}

TEST_F(SuiteReportTest, WithoutGnuplotWarnsAndKeepsTablesAndReplays) {
  const std::string dir = CopyFixture("nognuplot");
  SuiteReportOptions options;
  options.gnuplot = "/nonexistent/gnuplot";
  std::vector<std::string> warnings;
  const std::string path = WriteSuiteReport(dir, options, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("/nonexistent/gnuplot"), std::string::npos);
  const std::string page = ReadText(path);
  EXPECT_NE(page.find("<table class=\"summary\">"), std::string::npos);
  EXPECT_EQ(Count(page, "<tr class=\"pass") + Count(page, "<tr class=\"fail"), 3);
  EXPECT_EQ(Count(page, "<canvas"), 3);
  EXPECT_EQ(Count(page, "<img"), 0);
  EXPECT_NE(page.find("class=\"warning\""), std::string::npos);
  fs::remove_all(dir);
}

// The weights' legends and the step table's columns name the reference gaits meta.csv lists
// (weight_gaits); a folder without the key, or with a list of another length, keeps w_O1 ...
TEST_F(SuiteReportTest, WeightLegendsNameTheGaitsOfMetaCsv) {
  const std::string dir = CopyFixture("gait_names");
  const std::vector<SummaryRow> rows = ReadSummary(dir + "/summary.csv");
  ASSERT_EQ(rows[0].run, "walk");
  const std::vector<std::string> columns = {"w_O1", "w_O2", "w_O3", "w_O4", "w_O5"};
  EXPECT_EQ(ReadRun(dir, rows[0], nullptr).weight_names, columns);  // no key: the columns
  const std::string meta = dir + "/walk/meta.csv", before = ReadText(meta);
  WriteText(meta, before + "weight_gaits,vm_0.3;vm_0.5;vm_0.6;vm_0.7;vm_0.9\n");
  const std::vector<std::string> gaits = {"vm_0.3", "vm_0.5", "vm_0.6", "vm_0.7", "vm_0.9"};
  EXPECT_EQ(ReadRun(dir, rows[0], nullptr).weight_names, gaits);
  // The page: the step table's header cells and the figure script's legend titles (a gnuplot
  // that keeps its script and fails: the page is still written).
  const std::string script = dir + "/script.gp", plotter = dir + "/keep_script.sh";
  WriteText(plotter, "#!/bin/sh\ncp \"$1\" '" + script + "'\nexit 1\n");
  fs::permissions(plotter, fs::perms::owner_all);
  SuiteReportOptions options;
  options.gnuplot = plotter;
  std::vector<std::string> warnings;
  const std::string page = ReadText(WriteSuiteReport(dir, options, &warnings));
  const std::string plot = ReadText(script);
  for (const std::string& g : gaits) {
    EXPECT_NE(page.find("<th>" + g + "</th>"), std::string::npos) << g;
    EXPECT_NE(plot.find("title '" + g + "' noenhanced"), std::string::npos) << g;
  }
  // walk's figure alone: the other runs' folders have no weight_gaits and keep w_O1 ...
  EXPECT_EQ(Count(plot, "title 'vm_0.3'"), 1);
  EXPECT_GE(Count(plot, "title 'w_O1'"), 1);
  // A list that does not match the columns: the columns' names.
  WriteText(meta, before + "weight_gaits,vm_0.3;vm_0.5\n");
  EXPECT_EQ(ReadRun(dir, rows[0], nullptr).weight_names, columns);
  fs::remove_all(dir);
}

TEST_F(SuiteReportTest, FailingGnuplotIsAWarningToo) {
  const std::string dir = CopyFixture("falsegnuplot");
  SuiteReportOptions options;
  options.gnuplot = "false";  // runs, exits 1
  std::vector<std::string> warnings;
  const std::string page = ReadText(WriteSuiteReport(dir, options, &warnings));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("status 1"), std::string::npos);
  EXPECT_EQ(Count(page, "<img"), 0);
  EXPECT_EQ(Count(page, "<canvas"), 3);
  fs::remove_all(dir);
}

TEST_F(SuiteReportTest, MissingSummaryColumnNamesTheFile) {
  const std::string dir = CopyFixture("nocolumn");
  const std::string summary = (fs::path(dir) / "summary.csv").string();
  std::string text = ReadText(summary);
  text.replace(text.find(",steps,"), 7, ",stepz,");
  WriteText(summary, text);
  try {
    WriteSuiteReport(dir, SuiteReportOptions{}, nullptr);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), summary);
    EXPECT_EQ(e.key(), "steps");
    EXPECT_NE(std::string(e.what()).find("summary.csv"), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(fs::path(dir) / "index.html"));
  fs::remove_all(dir);
}

TEST_F(SuiteReportTest, MalformedRunFilesNameFileLineAndColumn) {
  const std::string dir = CopyFixture("badrun");
  const std::string steps = (fs::path(dir) / "obstacle" / "steps.csv").string();
  std::string text = ReadText(steps);
  const size_t second_row = text.find('\n', text.find('\n') + 1) + 1;
  text.replace(second_row, text.find(',', second_row) - second_row, "one");
  WriteText(steps, text);
  try {
    WriteSuiteReport(dir, SuiteReportOptions{}, nullptr);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), steps);
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.key(), "step");
  }
  // A missing file, and a run name that leaves the directory.
  fs::remove(steps);
  EXPECT_THROW(WriteSuiteReport(dir, SuiteReportOptions{}, nullptr), InputError);
  const std::string summary = (fs::path(dir) / "summary.csv").string();
  std::string s = ReadText(summary);
  s.replace(s.find(",obstacle,", s.find("fuzzy_cmac,obstacle")), 10, ",../obstacle,");
  WriteText(summary, s);
  try {
    WriteSuiteReport(dir, SuiteReportOptions{}, nullptr);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "run");
    EXPECT_EQ(e.line(), 4);
  }
  fs::remove_all(dir);
}

TEST_F(SuiteReportTest, DivergedTrajectoryRowsAreLeftOutWithAWarning) {
  const std::string dir = CopyFixture("diverged");
  const std::string trajectory = (fs::path(dir) / "walk" / "trajectory.csv").string();
  std::string text = ReadText(trajectory);
  // The last row's hip height becomes nan, as a diverged run may write it.
  const size_t last = text.rfind('\n', text.size() - 2) + 1;
  const size_t y = text.find(',', text.find(',', last) + 1) + 1;
  text.replace(y, text.find(',', y) - y, "nan");
  WriteText(trajectory, text);
  SuiteReportOptions options;
  options.gnuplot = "/nonexistent/gnuplot";
  std::vector<std::string> warnings;
  const std::string page = ReadText(WriteSuiteReport(dir, options, &warnings));
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_NE(warnings[0].find("walk/trajectory.csv: 1 rows"), std::string::npos) << warnings[0];
  EXPECT_EQ(Count(page, "\"frames\":301,"), 2);  // walk lost its last 0.01 s (one frame)
  EXPECT_EQ(Count(page, "\"frames\":300,"), 1);
  // Not a number at all is still an error.
  text.replace(y, 3, "abc");
  WriteText(trajectory, text);
  EXPECT_THROW(WriteSuiteReport(dir, options, nullptr), InputError);
  fs::remove_all(dir);
}

TEST_F(SuiteReportTest, AHugeTimeSpanIsReplayedWithBoundedFrames) {
  // The review's case: a last row at t = 1e7 s would ask for 2.5e8 frames at 25 fps. The replay
  // keeps at most max_replay_frames, at a lower frame rate.
  const std::string dir = CopyFixture("huge_span");
  const std::string trajectory = (fs::path(dir) / "walk" / "trajectory.csv").string();
  std::string text = ReadText(trajectory);
  const size_t last = text.rfind('\n', text.size() - 2) + 1;
  text.replace(last, text.find(',', last) - last, "1e7");
  WriteText(trajectory, text);
  SuiteReportOptions options;
  options.gnuplot = "/nonexistent/gnuplot";
  options.max_replay_frames = 5000;
  const std::string page = ReadText(WriteSuiteReport(dir, options, nullptr));
  EXPECT_EQ(Count(page, "\"frames\":5000,"), 1);
  fs::remove_all(dir);
}

// A ground profile in the run folders (ground.csv, as `rabbit run` writes it): the terrain line
// describes it, the replay carries it (breakpoint, height, grade), the stick diagrams gain one
// around the first change of slope, and a malformed profile names its file.
TEST_F(SuiteReportTest, GroundProfileIsDescribedReplayedAndDrawn) {
  const std::string dir = CopyFixture("ground");
  for (const std::string& run : fixture_->runs) {
    WriteText((fs::path(dir) / run / "ground.csv").string(),
              "x_start_m,slope_deg,height_m\n3,-1,0\n7,1,0.06982025971\n");
  }
  SuiteReportOptions options;
  const bool gnuplot = OnPath("gnuplot");
  if (!gnuplot) options.gnuplot = "/nonexistent/gnuplot";
  const std::string page = ReadText(WriteSuiteReport(dir, options, nullptr));
  EXPECT_NE(page.find("ground flat, then up 1.0&deg; from x = 3.00 m, down 1.0&deg; from x = "
                      "7.00 m"),
            std::string::npos);
  // The replay's ground: [x, height, grade] per breakpoint (grade tan 1 deg = 0.017455).
  EXPECT_EQ(Count(page, "\"g\":[3,0,0.017455,7,0.0698,-0.017455]"),
            static_cast<int>(fixture_->runs.size()));
  if (gnuplot) {
    // The walks reach x = 3 m: one more stick diagram per scenario (two scenarios).
    EXPECT_EQ(Count(page, "<img class=\"fig\""), fixture_->expected_figures + 2);
    EXPECT_EQ(Count(page, "around the first change of slope"), 4);  // alt and caption, twice
  }
  const std::string ground = (fs::path(dir) / "walk" / "ground.csv").string();
  WriteText(ground, "x_start_m,slope_deg,height_m\n3,-1,0\n2,1,0\n");
  try {
    WriteSuiteReport(dir, options, nullptr);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), ground);
    EXPECT_NE(std::string(e.what()).find("increasing x_start"), std::string::npos) << e.what();
  }
  fs::remove_all(dir);
}

TEST(SuiteReportOptionsTest, Validation) {
  std::string error;
  EXPECT_TRUE(SuiteReportOptions{}.IsValid(&error)) << error;
  SuiteReportOptions o;
  o.replay_fps = 0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_NE(error.find("replay_fps"), std::string::npos);
  o = SuiteReportOptions{};
  o.stick_every = 0.0;
  EXPECT_FALSE(o.IsValid(&error));
  o = SuiteReportOptions{};
  o.stick_window = 1e4;  // 100000 figures in one diagram
  EXPECT_FALSE(o.IsValid(&error));
  o = SuiteReportOptions{};
  o.gnuplot = "";
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THROW(WriteSuiteReport("/nonexistent", o, nullptr), std::invalid_argument);
}

TEST(StickPointsTest, HandComputedPoses) {
  const double kTolerance = 1e-12;
  const LinkLengths lengths;  // thigh 0.40, shin 0.47, trunk 0.625
  // Upright trunk; thigh 1 horizontal forward with the shin hanging straight down from the
  // knee; leg 2 straight down.
  const StickFigure a = StickPoints({1.0, 0.8, 0.0, M_PI / 2, -M_PI / 2, 0.0, 0.0}, lengths);
  EXPECT_NEAR(a.hip.x, 1.0, kTolerance);
  EXPECT_NEAR(a.hip.y, 0.8, kTolerance);
  EXPECT_NEAR(a.trunk_top.x, 1.0, kTolerance);
  EXPECT_NEAR(a.trunk_top.y, 1.425, kTolerance);
  EXPECT_NEAR(a.knee[0].x, 1.4, kTolerance);
  EXPECT_NEAR(a.knee[0].y, 0.8, kTolerance);
  EXPECT_NEAR(a.foot[0].x, 1.4, kTolerance);
  EXPECT_NEAR(a.foot[0].y, 0.33, kTolerance);
  EXPECT_NEAR(a.knee[1].x, 1.0, kTolerance);
  EXPECT_NEAR(a.knee[1].y, 0.4, kTolerance);
  EXPECT_NEAR(a.foot[1].x, 1.0, kTolerance);
  EXPECT_NEAR(a.foot[1].y, -0.07, kTolerance);
  // Trunk pitched 90 deg forward: its top ahead of the hip; the hips' relative angles equal to
  // the pitch keep the thighs vertical; knee 2 bent back by 90 deg puts shin 2 horizontal, foot
  // behind.
  const StickFigure b =
      StickPoints({0.0, 0.87, M_PI / 2, M_PI / 2, 0.0, M_PI / 2, -M_PI / 2}, lengths);
  EXPECT_NEAR(b.trunk_top.x, 0.625, kTolerance);
  EXPECT_NEAR(b.trunk_top.y, 0.87, kTolerance);
  EXPECT_NEAR(b.foot[0].x, 0.0, kTolerance);
  EXPECT_NEAR(b.foot[0].y, 0.0, kTolerance);
  EXPECT_NEAR(b.knee[1].y, 0.47, kTolerance);
  EXPECT_NEAR(b.foot[1].x, -0.47, kTolerance);
  EXPECT_NEAR(b.foot[1].y, 0.47, kTolerance);
}

TEST(StickPointsTest, AgreesWithTheModelsKinematics) {
  const double kTolerance = 1e-12;
  const Model model{ModelParams{}};
  const LinkLengths lengths{model.params().thigh_length, model.params().shin_length,
                            model.params().trunk_length};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-1.5, 1.5);
  for (int k = 0; k < 100; ++k) {
    Vec7 q;
    q << angle(rng), 0.5 + angle(rng) * 0.1, angle(rng), angle(rng), angle(rng), angle(rng),
        angle(rng);
    const Pose pose = ComputePose(model, q);
    const StickFigure f = StickPoints({q[0], q[1], q[2], q[3], q[4], q[5], q[6]}, lengths);
    EXPECT_NEAR(f.trunk_top.x, pose.trunk_top.x(), kTolerance);
    EXPECT_NEAR(f.trunk_top.y, pose.trunk_top.y(), kTolerance);
    for (int leg = 0; leg < 2; ++leg) {
      EXPECT_NEAR(f.knee[leg].x, pose.knee[leg].x(), kTolerance);
      EXPECT_NEAR(f.knee[leg].y, pose.knee[leg].y(), kTolerance);
      EXPECT_NEAR(f.foot[leg].x, pose.foot[leg].x(), kTolerance);
      EXPECT_NEAR(f.foot[leg].y, pose.foot[leg].y(), kTolerance);
    }
  }
}

}  // namespace
}  // namespace rabbit
