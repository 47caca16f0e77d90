// The tuning job's report from its CSV files: the page shows the job's numbers, marks the best and
// the invalid candidates, escapes what the files say, and carries the three figures when gnuplot
// is installed; without gnuplot a warning and no figures, never a failure; one evaluation or one
// parameter still draws; a long log is collapsed; malformed or inconsistent files name the file,
// line and column.
#include "rabbit/report/tune_report.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "rabbit/io/error.h"
#include "report_fixture.h"
#include "tune_fixture.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;
using testing::Count;
using testing::ReadText;
using testing::WriteText;

bool OnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  const std::string dirs = path == nullptr ? "" : path;
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = std::min(dirs.find(':', start), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(start, end - start)) / name;
    if (::access(candidate.c_str(), X_OK) == 0) return true;
    start = end + 1;
  }
  return false;
}

bool Contains(const std::string& text, const std::string& needle) {
  return text.find(needle) != std::string::npos;
}

class TuneReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = (fs::temp_directory_path() /
            ("rabbit_tune_report_test_" + std::to_string(::getpid()) + "_" + test->name()))
               .string();
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string File(const std::string& name) const { return (fs::path(dir_) / name).string(); }
  // Replaces the first occurrence of from in the named file.
  void Edit(const std::string& name, const std::string& from, const std::string& to) const {
    std::string text = ReadText(File(name));
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    WriteText(File(name), text);
  }
  static TuneReportOptions NoGnuplot() {
    TuneReportOptions options;
    options.gnuplot = "/nonexistent/gnuplot";
    return options;
  }
  // The InputError of building the page, which must not have been written.
  InputError ErrorOf() const {
    try {
      WriteTuneReport(dir_, NoGnuplot(), nullptr);
    } catch (const InputError& e) {
      EXPECT_FALSE(fs::exists(File("index.html")));
      return e;
    }
    ADD_FAILURE() << "no InputError";
    return InputError("", 0, "", "");
  }
  std::string dir_;
};

TEST_F(TuneReportTest, PageShowsTheJobItsNumbersAndTheBestCandidate) {
  testing::WriteTuneFixture(dir_);
  std::vector<std::string> warnings;
  WriteTuneReport(dir_, NoGnuplot(), &warnings);
  const std::string page = ReadText(File("index.html"));
  ASSERT_FALSE(page.empty());
  // Header: the job, its settings, best against initial and the relative improvement
  // (5.25 - 0.0312) / 5.25 = 99.41 %.
  EXPECT_TRUE(Contains(page, "<h1>Tuning job <em>walk_gains</em></h1>"));
  EXPECT_TRUE(Contains(page, "<code>bobyqa</code>"));
  EXPECT_TRUE(Contains(page, "<tr><th>seed</th><td>7</td></tr>"));
  EXPECT_TRUE(Contains(page, "6 evaluated of at most 20"));
  EXPECT_TRUE(Contains(page, "<code>mean</code>"));
  EXPECT_TRUE(Contains(page,
                       "10&nbsp;&times;&nbsp;<code>failure_rate</code> + "
                       "1&nbsp;&times;&nbsp;<code>speed_error</code>"));
  EXPECT_TRUE(Contains(page, "<li><code>scenarios/suites/push.toml</code></li>"));
  EXPECT_TRUE(Contains(page, "id=\"best-objective\">0.0312</span> (evaluation 4)"));
  EXPECT_TRUE(Contains(page, "id=\"initial-objective\">5.25</span> (evaluation 0)"));
  EXPECT_TRUE(Contains(page, "id=\"improvement\">99.41&nbsp;%</span>"));
  EXPECT_FALSE(Contains(page, "has not completed"));
  // The log: every evaluation, the best in bold, the invalid one in red with its error escaped,
  // the new bests so far (0, 1, 2, 4) marked.
  EXPECT_EQ(Count(page, "<tr id=\"eval-"), 6);
  EXPECT_TRUE(Contains(page, "<tr id=\"eval-4\" class=\"best\">"));
  EXPECT_TRUE(Contains(page, "<tr id=\"eval-3\" class=\"invalid\">"));
  EXPECT_EQ(Count(page, "class=\"invalid\""), 1);
  EXPECT_TRUE(Contains(page, "controller.k_p = 1200 is outside [100, 1000] &lt;b&gt;"));
  EXPECT_EQ(Count(page, "<td>&#9660;</td>"), 4);
  EXPECT_FALSE(Contains(page, "<details class=\"log\">"));  // 6 rows: open
  // The invalid candidate is counted (and linked) in the convergence section.
  EXPECT_TRUE(Contains(page,
                       "1 invalid candidate (an error, or the objective 1e6) not plotted: "
                       "evaluation <a href=\"#eval-3\">3</a>."));
  // Parameters: bounds, initial and best, the change in % of the range.
  EXPECT_TRUE(Contains(page,
                       "<code>controller.k_p</code></td><td class=\"num\">100</td><td "
                       "class=\"num\">1000</td><td class=\"num\">600</td><td "
                       "class=\"num\"><b>731.5</b></td><td class=\"num\">131.5 (+14.6&nbsp;% "
                       "of the range)"));
  EXPECT_TRUE(Contains(page, "<b>22.25</b>"));
  // Per scenario: pass/fail and the outcomes from runs.csv, terms initial -> best.
  EXPECT_TRUE(Contains(page, "Passed: <b>1</b> of 2 scenarios"));
  EXPECT_TRUE(Contains(page, "<b id=\"best-passed\">2</b>"));
  EXPECT_TRUE(Contains(page,
                       "<td class=\"text\">push &amp; shove</td><td class=\"fail\">"
                       "&#10007;&nbsp;fail</td><td class=\"pass\">&#10003;&nbsp;pass</td>"
                       "<td class=\"text\">fell &rarr; completed</td>"));
  EXPECT_TRUE(Contains(page, "0.4 &rarr; <span class=\"better\">0.04</span>"));
  // best.toml verbatim.
  EXPECT_TRUE(Contains(page,
                       "<pre class=\"toml\"># walk_gains: the best of 6 evaluations "
                       "(evaluation 4)\n[controller]\nk_p = 731.5\nk_d = 22.25\n</pre>"));
  // Nothing fetched from elsewhere.
  EXPECT_FALSE(Contains(page, "http:"));
  EXPECT_FALSE(Contains(page, "https:"));
}

TEST_F(TuneReportTest, TextFromTheFilesIsEscaped) {
  testing::WriteTuneFixture(dir_);
  Edit("meta.csv", "job,walk_gains", "job,\"<img src=x onerror=alert(2)>\"");
  Edit("parameters.csv", "controller.k_d,", "\"controller.<k_d>\",");
  Edit("evaluations.csv", ",controller.k_d,", ",\"controller.<k_d>\",");
  WriteTuneReport(dir_, NoGnuplot(), nullptr);
  const std::string page = ReadText(File("index.html"));
  EXPECT_TRUE(
      Contains(page, "Tune the PD gains &lt;script&gt;alert(1)&lt;/script&gt; &amp; check"));
  EXPECT_FALSE(Contains(page, "<script>alert"));
  EXPECT_EQ(Count(page, "<script>"), 1);  // the page's own error counter only
  EXPECT_FALSE(Contains(page, "<img src=x"));
  EXPECT_TRUE(Contains(page, "<em>&lt;img src=x onerror=alert(2)&gt;</em>"));
  EXPECT_TRUE(Contains(page, "<code>controller.&lt;k_d&gt;</code>"));
  EXPECT_FALSE(Contains(page, "<k_d>"));
}

TEST_F(TuneReportTest, FiguresWhenGnuplotIsInstalled) {
  if (!OnPath("gnuplot")) GTEST_SKIP() << "gnuplot is not on PATH (Debian: gnuplot-nox)";
  testing::WriteTuneFixture(dir_);
  std::vector<std::string> warnings;
  WriteTuneReport(dir_, TuneReportOptions{}, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  const std::string page = ReadText(File("index.html"));
  // Convergence, parameter traces, best against initial: inlined SVG images.
  EXPECT_EQ(Count(page, "<img class=\"fig\""), 3);
  EXPECT_EQ(Count(page, "src=\"data:image/svg+xml;base64,"), 3);
  EXPECT_FALSE(Contains(page, "class=\"warning\""));
  // 5.25 / 0.0312 spans 2.2 decades: a log axis; the invalid candidate is left out.
  EXPECT_TRUE(Contains(page, "objective on a log scale (it spans 2.2 decades)"));
  EXPECT_TRUE(Contains(page, "the best candidate (evaluation 4) circled"));
  EXPECT_FALSE(Contains(page, "http:"));
}

TEST_F(TuneReportTest, WithoutGnuplotAWarningAndNoFigures) {
  testing::WriteTuneFixture(dir_);
  std::vector<std::string> warnings;
  WriteTuneReport(dir_, NoGnuplot(), &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(Contains(warnings[0], "/nonexistent/gnuplot")) << warnings[0];
  const std::string page = ReadText(File("index.html"));
  EXPECT_EQ(Count(page, "<img"), 0);
  EXPECT_TRUE(
      Contains(page, "<p class=\"warning\">figures left out: gnuplot (/nonexistent/gnuplot)"));
  // The tables are all there.
  EXPECT_EQ(Count(page, "<tr id=\"eval-"), 6);
  EXPECT_TRUE(Contains(page, "<table class=\"parameters\">"));
  EXPECT_TRUE(Contains(page, "<table class=\"comparison\">"));

  // A gnuplot that runs and fails is a warning too.
  TuneReportOptions failing;
  failing.gnuplot = "false";
  warnings.clear();
  WriteTuneReport(dir_, failing, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(Contains(warnings[0], "status 1")) << warnings[0];
  EXPECT_EQ(Count(ReadText(File("index.html")), "<img"), 0);
}

TEST_F(TuneReportTest, OneEvaluationAndOneParameterStillDraw) {
  testing::WriteSyntheticTuneFixture(dir_, 1, 1, 1);
  std::vector<std::string> warnings;
  WriteTuneReport(dir_, OnPath("gnuplot") ? TuneReportOptions{} : NoGnuplot(), &warnings);
  const std::string page = ReadText(File("index.html"));
  EXPECT_EQ(Count(page, "<tr id=\"eval-"), 1);
  EXPECT_TRUE(Contains(page, "<tr id=\"eval-0\" class=\"best\">"));
  EXPECT_TRUE(Contains(page, "id=\"improvement\">0.00&nbsp;%</span>"));
  if (OnPath("gnuplot")) {
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_EQ(Count(page, "<img class=\"fig\""), 3);
  }
}

TEST_F(TuneReportTest, ALongLogIsCollapsedAndFiftyScenariosDraw) {
  testing::WriteSyntheticTuneFixture(dir_, 250, 5, 50);
  std::vector<std::string> warnings;
  WriteTuneReport(dir_, OnPath("gnuplot") ? TuneReportOptions{} : NoGnuplot(), &warnings);
  const std::string page = ReadText(File("index.html"));
  EXPECT_TRUE(Contains(page, "<details class=\"log\"><summary>All 250 evaluations</summary>"));
  EXPECT_EQ(Count(page, "<tr id=\"eval-"), 250);
  EXPECT_EQ(Count(page, "<td class=\"text\">synthetic</td>"), 50);
  EXPECT_TRUE(Contains(page, "<code>mean_square</code>"));
  if (OnPath("gnuplot")) {
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    EXPECT_EQ(Count(page, "<img class=\"fig\""), 3);
    EXPECT_FALSE(Contains(page, "log scale"));  // 2.05 .. 0.05: under two decades
  }
}

TEST_F(TuneReportTest, AnUnfinishedJobSaysSo) {
  testing::WriteTuneFixture(dir_);
  Edit("meta.csv", "complete,true", "complete,false");
  WriteTuneReport(dir_, NoGnuplot(), nullptr);
  EXPECT_TRUE(Contains(ReadText(File("index.html")),
                       "The job has not completed (stopped, or still running): the page shows its "
                       "6 evaluations so far."));
}

TEST_F(TuneReportTest, AJobStoppedBeforeItsFirstEvaluation) {
  testing::WriteTuneFixture(dir_);
  for (const char* name : {"evaluations.csv", "runs.csv", "comparison.csv"}) {
    const std::string text = ReadText(File(name));
    WriteText(File(name), text.substr(0, text.find('\n') + 1));  // the header only
  }
  Edit("meta.csv", "initial_eval,0", "initial_eval,");
  Edit("meta.csv", "best_eval,4", "best_eval,nan");
  Edit("meta.csv", "initial_objective,5.25", "initial_objective,nan");
  Edit("meta.csv", "best_objective,0.0312", "best_objective,nan");
  Edit("meta.csv", "complete,true", "complete,false");
  std::vector<std::string> warnings;
  WriteTuneReport(dir_, TuneReportOptions{}, &warnings);  // no figure: gnuplot is not run
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  const std::string page = ReadText(File("index.html"));
  EXPECT_TRUE(Contains(page, "No valid evaluation to plot."));
  EXPECT_TRUE(Contains(page, "id=\"best-objective\">&ndash;</span> against"));
  EXPECT_FALSE(Contains(page, "id=\"improvement\""));
  EXPECT_EQ(Count(page, "<tr id=\"eval-"), 0);
  EXPECT_EQ(Count(page, "<img"), 0);
  EXPECT_TRUE(Contains(page, "shows its 0 evaluations so far."));
}

TEST_F(TuneReportTest, AMissingColumnNamesTheFileAndColumn) {
  testing::WriteTuneFixture(dir_);
  Edit("evaluations.csv", ",objective,", ",objectiv,");
  const InputError e = ErrorOf();
  EXPECT_EQ(e.file(), File("evaluations.csv"));
  EXPECT_EQ(e.line(), 1);
  EXPECT_EQ(e.key(), "objective");
  EXPECT_TRUE(Contains(e.what(), "evaluations.csv:1: 'objective': missing column")) << e.what();
}

TEST_F(TuneReportTest, AParameterWithoutItsColumnInTheLog) {
  testing::WriteTuneFixture(dir_);
  Edit("evaluations.csv", ",controller.k_d,", ",controller.kd,");
  const InputError e = ErrorOf();
  EXPECT_EQ(e.file(), File("evaluations.csv"));
  EXPECT_EQ(e.key(), "controller.k_d");
}

TEST_F(TuneReportTest, ABadNumberNamesTheLineAndColumn) {
  testing::WriteTuneFixture(dir_);
  Edit("runs.csv", "1,push,push & shove,0,tripped,1,0.25,",
       "1,push,push & shove,0,tripped,1,fast,");
  const InputError e = ErrorOf();
  EXPECT_EQ(e.file(), File("runs.csv"));
  EXPECT_EQ(e.line(), 5);
  EXPECT_EQ(e.key(), "speed_error");
}

TEST_F(TuneReportTest, AMissingFileOrMetaKeyOrUnknownEvaluation) {
  testing::WriteTuneFixture(dir_);
  fs::remove(File("comparison.csv"));
  InputError e = ErrorOf();
  EXPECT_EQ(e.file(), File("comparison.csv"));
  EXPECT_TRUE(Contains(e.what(), "cannot open")) << e.what();

  testing::WriteTuneFixture(dir_);
  Edit("meta.csv", "best_eval,4\n", "");
  e = ErrorOf();
  EXPECT_EQ(e.file(), File("meta.csv"));
  EXPECT_EQ(e.key(), "best_eval");

  testing::WriteTuneFixture(dir_);
  Edit("meta.csv", "best_eval,4\n", "best_eval,99\n");
  e = ErrorOf();
  EXPECT_EQ(e.key(), "best_eval");
  EXPECT_TRUE(Contains(e.what(), "evaluation 99 is not in evaluations.csv")) << e.what();

  testing::WriteTuneFixture(dir_);
  Edit("runs.csv", "\n5,flat,", "\n7,flat,");
  e = ErrorOf();
  EXPECT_EQ(e.file(), File("runs.csv"));
  EXPECT_EQ(e.key(), "eval");
  EXPECT_EQ(e.line(), 10);

  testing::WriteTuneFixture(dir_);
  Edit("evaluations.csv", "\n5,2,1,2,", "\n4,2,1,2,");
  e = ErrorOf();
  EXPECT_EQ(e.key(), "eval");
  EXPECT_TRUE(Contains(e.what(), "evaluation 4 also on line 6")) << e.what();

  // best.toml is optional: the page says it is not written.
  testing::WriteTuneFixture(dir_);
  fs::remove(File("best.toml"));
  WriteTuneReport(dir_, NoGnuplot(), nullptr);
  EXPECT_TRUE(Contains(ReadText(File("index.html")), "Not written (yet)."));
}

TEST(TuneReportOptionsTest, Validation) {
  std::string error;
  EXPECT_TRUE(TuneReportOptions{}.IsValid(&error)) << error;
  TuneReportOptions o;
  o.timeout = 0.0;
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_TRUE(Contains(error, "timeout"));
  o = TuneReportOptions{};
  o.gnuplot = "gnu\nplot";
  EXPECT_FALSE(o.IsValid(&error));
  EXPECT_THROW(WriteTuneReport("/nonexistent", o, nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace rabbit
