// The head-to-head comparison: the Wilson score interval against published values and against an
// independent computation (the roots of the score test's quadratic); the grouping of summary rows
// into families and plain scenarios, the counts, rates and medians of hand-built rows; the CSV;
// and summaries written before the family column.
#include "rabbit/report/comparison.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "rabbit/io/error.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;
using report_internal::SummaryRow;

// The interval's bounds as the roots in p' of (p - p')^2 = z^2 p' (1 - p') / n, i.e.
// (1 + z^2/n) p'^2 - (2 p + z^2/n) p' + p^2 = 0: another route than WilsonInterval's centre and
// half-width.
ProportionInterval ScoreTestRoots(int k, int n, double z) {
  const double p = static_cast<double>(k) / n, a = 1.0 + z * z / n, b = -(2.0 * p + z * z / n),
               c = p * p;
  const double root = std::sqrt(b * b - 4.0 * a * c);
  return {(-b - root) / (2.0 * a), (-b + root) / (2.0 * a)};
}

TEST(WilsonIntervalTest, PublishedValues) {
  // R: prop.test(k, n, correct = FALSE)$conf.int, 7 digits.
  const double kTolerance = 5e-8;
  struct Case {
    int k, n;
    double low, high;
  };
  for (const Case& c : {Case{0, 10, 0.0, 0.2775328}, Case{10, 10, 0.7224672, 1.0},
                        Case{5, 10, 0.2365931, 0.7634069}, Case{95, 100, 0.8882495, 0.9784563}}) {
    const ProportionInterval ci = WilsonInterval(c.k, c.n);
    EXPECT_NEAR(ci.low, c.low, kTolerance) << c.k << "/" << c.n;
    EXPECT_NEAR(ci.high, c.high, kTolerance) << c.k << "/" << c.n;
  }
  // Exactly 0 and 1 at the ends; the ends are never degenerate (unlike the Wald interval's).
  EXPECT_EQ(WilsonInterval(0, 10).low, 0.0);
  EXPECT_EQ(WilsonInterval(10, 10).high, 1.0);
  EXPECT_GT(WilsonInterval(0, 10).high, 0.2);
  EXPECT_LT(WilsonInterval(10, 10).low, 0.8);
}

TEST(WilsonIntervalTest, AgreesWithTheScoreTestsRootsAndHoldsItsDefinition) {
  const double kTolerance = 1e-12;
  for (int n : {1, 2, 7, 12, 40, 100, 1000}) {
    for (int k = 0; k <= n; ++k) {
      const ProportionInterval ci = WilsonInterval(k, n);
      const ProportionInterval roots = ScoreTestRoots(k, n, kZ95);
      EXPECT_NEAR(ci.low, roots.low, kTolerance) << k << "/" << n;
      EXPECT_NEAR(ci.high, roots.high, kTolerance) << k << "/" << n;
      const double p = static_cast<double>(k) / n;
      EXPECT_LE(ci.low, p);
      EXPECT_GE(ci.high, p);
      // At an inner bound the score statistic |p - p'| / sqrt(p'(1 - p')/n) is z.
      for (double bound : {ci.low, ci.high}) {
        if (bound <= 0.0 || bound >= 1.0) continue;
        const double score = std::abs(p - bound) / std::sqrt(bound * (1.0 - bound) / n);
        EXPECT_NEAR(score, kZ95, 1e-8) << k << "/" << n;
      }
    }
  }
  // Another z: a 90% interval is narrower.
  EXPECT_GT(WilsonInterval(5, 10, 1.644853627).low, WilsonInterval(5, 10).low);
}

TEST(WilsonIntervalTest, UndefinedWithoutTrials) {
  EXPECT_TRUE(std::isnan(WilsonInterval(0, 0).low));
  EXPECT_TRUE(std::isnan(WilsonInterval(0, 0).high));
  EXPECT_TRUE(std::isnan(WilsonInterval(3, 2).low));
  EXPECT_TRUE(std::isnan(WilsonInterval(-1, 2).high));
}

SummaryRow Row(const std::string& scenario, const std::string& family, const std::string& variant,
               bool main, const std::string& outcome, bool passed, double speed_error, double cot,
               double memory) {
  SummaryRow r;
  r.suite = "s";
  r.scenario = scenario;
  r.variant = variant;
  r.controller = variant;
  r.run = main ? scenario : scenario + "+" + variant;
  r.group = family.empty() ? scenario : family;
  r.is_family_member = !family.empty();
  r.outcome = outcome;
  r.passed = passed;
  r.mean_speed_error = speed_error;
  r.cost_of_transport = cot;
  r.pattern_memory_bytes = memory;
  return r;
}

TEST(CompareVariantsTest, CountsRatesAndMediansPerGroupAndVariant) {
  const double kTolerance = 1e-12;
  const double nan = std::nan("");
  // Family f: 4 members, the walker (main) and the pragmatic rules; a plain scenario "f" of the
  // family's name, which is a group of its own; a plain scenario "solo".
  const std::vector<SummaryRow> rows = {
      Row("f-000", "f", "fuzzy_cmac", true, "completed", true, 0.02, 0.25, 38880),
      Row("f-000", "f", "pragmatic", false, "tripped", false, 0.03, 0.30, 0),
      Row("f-001", "f", "fuzzy_cmac", true, "fell", false, 6.0, 0.9, 38880),  // absurd V_M
      Row("f-001", "f", "pragmatic", false, "completed", false, 0.10, 0.18, 0),
      Row("solo", "", "fuzzy_cmac", true, "completed", true, 0.01, 0.20, 38880),
      Row("f-002", "f", "fuzzy_cmac", true, "completed", true, 0.04, 0.27, 38880),
      Row("f-002", "f", "pragmatic", false, "completed", true, 0.05, nan, 0),
      Row("f-003", "f", "fuzzy_cmac", true, "completed", false, 0.03, 0.26, 38880),
      Row("f-003", "f", "pragmatic", false, "diverged", false, nan, nan, 0),
      Row("f", "", "fuzzy_cmac", true, "timeout", false, nan, nan, nan),
  };
  const std::vector<VariantComparison> c = CompareVariants(rows);
  ASSERT_EQ(c.size(), 4u);
  // Groups in order of first appearance, the main variant first.
  EXPECT_EQ(c[0].group, "f");
  EXPECT_TRUE(c[0].family);
  EXPECT_EQ(c[0].variant, "fuzzy_cmac");
  EXPECT_EQ(c[0].role, "main");
  EXPECT_EQ(c[1].variant, "pragmatic");
  EXPECT_EQ(c[1].role, "baseline");
  EXPECT_EQ(c[2].group, "solo");
  EXPECT_FALSE(c[2].family);
  EXPECT_EQ(c[3].group, "f");
  EXPECT_FALSE(c[3].family);

  const VariantComparison& walker = c[0];
  EXPECT_EQ(walker.members, 4);
  EXPECT_EQ(walker.runs, 4);
  EXPECT_EQ(walker.passed, 2);
  EXPECT_NEAR(walker.success_rate, 0.5, kTolerance);
  EXPECT_NEAR(walker.ci.low, WilsonInterval(2, 4).low, kTolerance);
  EXPECT_EQ(walker.completed, 3);
  EXPECT_EQ(walker.fell, 1);
  EXPECT_EQ(walker.tripped + walker.diverged + walker.timeout + walker.other_outcome, 0);
  // Over the completed runs only: the fallen run's 6 m/s does not count.
  EXPECT_EQ(walker.speed_error_runs, 3);
  EXPECT_NEAR(walker.speed_error_mean, (0.02 + 0.04 + 0.03) / 3.0, kTolerance);
  EXPECT_NEAR(walker.speed_error_median, 0.03, kTolerance);
  EXPECT_EQ(walker.cot_runs, 3);
  EXPECT_NEAR(walker.cot_median, 0.26, kTolerance);
  EXPECT_EQ(walker.pattern_memory_bytes, 38880.0);

  const VariantComparison& rules = c[1];
  EXPECT_EQ(rules.runs, 4);
  EXPECT_EQ(rules.passed, 1);
  EXPECT_EQ(rules.completed, 2);
  EXPECT_EQ(rules.tripped, 1);
  EXPECT_EQ(rules.diverged, 1);
  EXPECT_EQ(rules.speed_error_runs, 2);
  EXPECT_NEAR(rules.speed_error_median, 0.075, kTolerance);  // even count: the middle two's mean
  EXPECT_EQ(rules.cot_runs, 1);                              // one completed run has no CoT
  EXPECT_NEAR(rules.cot_mean, 0.18, kTolerance);
  EXPECT_EQ(rules.pattern_memory_bytes, 0.0);

  // No completed run: no speed error; memory unknown (a summary without the column).
  const VariantComparison& plain = c[3];
  EXPECT_EQ(plain.runs, 1);
  EXPECT_EQ(plain.timeout, 1);
  EXPECT_EQ(plain.speed_error_runs, 0);
  EXPECT_TRUE(std::isnan(plain.speed_error_mean));
  EXPECT_TRUE(std::isnan(plain.speed_error_median));
  EXPECT_TRUE(std::isnan(plain.pattern_memory_bytes));
  EXPECT_EQ(plain.success_rate, 0.0);

  // The CSV: the header, then one line per row, numbers in the shortest form that reads back
  // exactly, nan spelled out.
  const std::string csv = ComparisonCsv(c);
  EXPECT_EQ(csv.substr(0, csv.find('\n')), ComparisonHeader());
  EXPECT_NE(csv.find("\ns,f,family,4,fuzzy_cmac,fuzzy_cmac,main,4,2,0.5,0.15003898915214953,"
                     "0.8499610108478505,"),
            std::string::npos)
      << csv;
  // completed, fell, tripped, stalled, diverged, timeout, other_outcome: one timeout.
  EXPECT_NE(csv.find("\ns,f,scenario,1,fuzzy_cmac,fuzzy_cmac,main,1,0,0,0,0.7934506856227626,0,0,0,"
                     "0,0,1,"
                     "0,0,nan,nan,0,nan,nan,nan,nan,nan\n"),
            std::string::npos)
      << csv;
}

TEST(CompareVariantsTest, AStalledRunIsCountedAsStalled) {
  const std::vector<VariantComparison> c =
      CompareVariants({Row("g-000", "g", "fuzzy_cmac", true, "stalled", false, 0.30, 0.5, 0),
                       Row("g-001", "g", "fuzzy_cmac", true, "completed", true, 0.02, 0.25, 0)});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].stalled, 1);
  EXPECT_EQ(c[0].completed, 1);
  EXPECT_EQ(c[0].other_outcome, 0);
  EXPECT_EQ(c[0].speed_error_runs, 1);  // the stalled run's speed error is not a completed run's
}

TEST(CompareVariantsTest, AVariantMainForSomeMembersOnlyIsMixed) {
  const std::vector<VariantComparison> c =
      CompareVariants({Row("g-000", "g", "pragmatic", false, "completed", true, 0.1, 0.2, 0),
                       Row("g-001", "g", "pragmatic", true, "completed", true, 0.1, 0.2, 0)});
  ASSERT_EQ(c.size(), 1u);
  EXPECT_EQ(c[0].role, "mixed");
  EXPECT_EQ(c[0].members, 2);
}

// A suite's success target lands on the main variant's row of its group, with the gap: 3 of 4
// passed against 0.9 is missed by 0.15; the baselines carry none; targets.csv round-trips.
TEST(CompareVariantsTest, TargetsGiveTheMainVariantsGap) {
  const double kTolerance = 1e-12;
  std::vector<SummaryRow> rows;
  for (int i = 0; i < 4; ++i) {
    const std::string name = "g-00" + std::to_string(i);
    rows.push_back(Row(name, "g", "fuzzy_cmac", true, "completed", i < 3, 0.02, 0.5, 100));
    rows.push_back(Row(name, "g", "pragmatic", false, "fell", false, 0.1, 0.2, 0));
  }
  rows.push_back(Row("h", "", "fuzzy_cmac", true, "completed", true, 0.02, 0.5, 100));
  const std::vector<VariantComparison> c = CompareVariants(rows, {{"g", 0.9}, {"h", 0.5}});
  ASSERT_EQ(c.size(), 3u);
  EXPECT_NEAR(c[0].target, 0.9, kTolerance);
  EXPECT_NEAR(c[0].target_gap, 0.75 - 0.9, kTolerance);
  EXPECT_TRUE(std::isnan(c[1].target));  // the baseline
  EXPECT_TRUE(std::isnan(c[1].target_gap));
  EXPECT_NEAR(c[2].target_gap, 0.5, kTolerance);  // met, by 0.5
  const std::string csv = ComparisonCsv(c);
  EXPECT_NE(csv.find(",target_success_rate,target_gap\n"), std::string::npos);
  EXPECT_NE(csv.find(",0.9,-0.15"), std::string::npos) << csv;

  const fs::path dir =
      fs::temp_directory_path() / ("rabbit_targets_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  EXPECT_TRUE(ReadTargets(dir.string()).empty());  // no file: no targets
  std::ofstream(dir / kTargetsFile) << "group,target_success_rate\ng,0.95\npush-x,0.9\n";
  const SuccessTargets read = ReadTargets(dir.string());
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[1].first, "push-x");
  EXPECT_DOUBLE_EQ(read[0].second, 0.95);
  std::ofstream(dir / kTargetsFile) << "group,target_success_rate\ng,1.5\n";
  EXPECT_THROW(ReadTargets(dir.string()), InputError);
  fs::remove_all(dir);
}

TEST(CompareVariantsTest, OlderSummariesTakeTheFamilyFromTheMembersNames) {
  const fs::path dir =
      fs::temp_directory_path() / ("rabbit_comparison_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  // No family and no pattern_memory_bytes column, as rabbit run wrote it before them.
  std::ofstream(dir / "summary.csv")
      << "suite,scenario,variant,run,controller,outcome,reason,passed,failed_criteria,"
         "duration_s,distance_m,steps,mean_abs_speed_error_m_s,final_abs_speed_error_m_s,"
         "l_step_mean_m,l_step_min_m,l_step_max_m,l_step_spread_m,saturation_s,energy_j,"
         "cost_of_transport,wall_s,real_time_factor\n"
         "old,flat,fuzzy_cmac,flat,fuzzy_cmac,completed,,1,,30,17,48,0.02,0.01,0.36,0.3,0.4,"
         "0.01,1,1000,0.2,1,30\n"
         "old,obst-000,fuzzy_cmac,obst-000,fuzzy_cmac,fell,,0,x,10,5,15,3.5,6,0.3,0.2,0.4,0.2,"
         "1,300,0.3,1,10\n"
         "old,obst-001,fuzzy_cmac,obst-001,fuzzy_cmac,completed,,1,,30,17,48,0.03,0.01,0.36,0.3,"
         "0.4,0.01,1,1000,0.2,1,30\n"
         "old,obst-1000,fuzzy_cmac,obst-1000,fuzzy_cmac,completed,,1,,30,17,48,0.05,0.01,0.36,"
         "0.3,0.4,0.01,1,1000,0.2,1,30\n"
         "old,step-12,fuzzy_cmac,step-12,fuzzy_cmac,completed,,1,,30,17,48,0.05,0.01,0.36,"
         "0.3,0.4,0.01,1,1000,0.2,1,30\n";
  const std::string path = WriteComparison(dir.string());
  EXPECT_EQ(path, (dir / "comparison.csv").string());
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], ComparisonHeader());
  EXPECT_EQ(lines[1].rfind("old,flat,scenario,1,", 0), 0u) << lines[1];
  EXPECT_EQ(lines[2].rfind("old,obst,family,3,fuzzy_cmac,fuzzy_cmac,main,3,2,", 0), 0u) << lines[2];
  EXPECT_NE(lines[2].find(",0.04,0.04,"), std::string::npos) << lines[2];   // completed runs
  EXPECT_EQ(lines[2].substr(lines[2].rfind(',')), ",nan");                  // memory: not recorded
  EXPECT_EQ(lines[3].rfind("old,step-12,scenario,1,", 0), 0u) << lines[3];  // 2 digits: no member
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rabbit
