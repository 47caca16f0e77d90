// The head-to-head comparison of a batch run's variants (the Fuzzy-CMAC walker and its
// baselines), built from summary.csv alone, per group and variant. A group is a family (all its
// members together: obstacle_anywhere-000, -001, ...) or a plain scenario (itself).
//
// DIR/comparison.csv, one row per group and variant (groups in summary order, variants in their
// order of first appearance in the group: the main variant first):
//   suite, group, group_kind      the suite; the family's or the scenario's name; "family" or
//                                 "scenario"
//   members                       scenarios in the group (a family's members)
//   variant, controller, role     as in summary.csv; role "main", "baseline" (or "mixed" when
//                                 the variant is the main one of some members only)
//   runs, passed                  the variant's runs in the group and those that passed their
//                                 criteria
//   success_rate, ci_low, ci_high passed / runs and its 95% Wilson score interval (below)
//   completed, fell, tripped, stalled, diverged, timeout, other_outcome   runs per outcome
//   speed_error_runs              completed runs with a measured speed error ...
//   speed_error_mean_m_s          ... the mean and the median over them of summary.csv's
//   speed_error_median_m_s        mean_abs_speed_error_m_s (|V_M - V_d| averaged over a run's
//                                 measured steps). Completed runs only: a run that fell ends on a
//                                 step whose V_M means nothing (6 m/s has been seen).
//   cot_runs, cot_mean, cot_median  the same for cost_of_transport (energy / (m g distance)),
//                                 completed runs with a value (it needs 0.1 m of travel)
//   pattern_memory_bytes          the gait pattern's memory (its CMAC weights; 0 for the
//                                 pragmatic rules): the largest over the runs (one gait pattern
//                                 gives one value); nan when summary.csv has no such column
//   target_success_rate           the suite's target for the group ([suite.targets], from
//                                 DIR/targets.csv), on the main variant's row only (else nan)
//   target_gap                    success_rate - target: >= 0 met, < 0 missed by that much
// Numbers as summary.csv writes them (10 significant digits, `nan` for none).
#ifndef RABBIT_REPORT_COMPARISON_H_
#define RABBIT_REPORT_COMPARISON_H_

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/report/report_data.h"

namespace rabbit {

// z_{0.975}: the standard normal quantile of a two-sided 95% interval.
constexpr double kZ95 = 1.959963984540054;

struct ProportionInterval {
  double low = std::numeric_limits<double>::quiet_NaN();
  double high = std::numeric_limits<double>::quiet_NaN();
};

// The Wilson score interval of a proportion: k successes in n trials, p = k / n,
//   centre    = (p + z^2 / (2 n)) / (1 + z^2 / n)
//   half      = z / (1 + z^2 / n) * sqrt(p (1 - p) / n + z^2 / (4 n^2))
//   [low, high] = [centre - half, centre + half]
// (the p' with |p - p'| = z sqrt(p' (1 - p') / n): the score test's acceptance region). It stays
// within [0, 1] and is not degenerate at k = 0 or k = n (0/10: [0, 0.278]), unlike p +- z sqrt(p
// (1 - p) / n). low is exactly 0 for k = 0 and high exactly 1 for k = n. NaN for n = 0, or for k
// outside 0..n.
ProportionInterval WilsonInterval(int successes, int trials, double z = kZ95);

// One row of comparison.csv.
struct VariantComparison {
  std::string suite, group;
  bool family = false;  // group_kind "family" (else "scenario")
  int members = 0;
  std::string variant, controller, role;
  int runs = 0, passed = 0;
  double success_rate = std::numeric_limits<double>::quiet_NaN();
  ProportionInterval ci;
  int completed = 0, fell = 0, tripped = 0, stalled = 0, diverged = 0, timeout = 0,
      other_outcome = 0;
  int speed_error_runs = 0;
  double speed_error_mean = std::numeric_limits<double>::quiet_NaN();
  double speed_error_median = std::numeric_limits<double>::quiet_NaN();
  int cot_runs = 0;
  double cot_mean = std::numeric_limits<double>::quiet_NaN();
  double cot_median = std::numeric_limits<double>::quiet_NaN();
  double pattern_memory_bytes = std::numeric_limits<double>::quiet_NaN();
  double target = std::numeric_limits<double>::quiet_NaN();  // main variant's target, or nan
  double target_gap = std::numeric_limits<double>::quiet_NaN();
};

// A report folder's success targets: DIR/targets.csv, `group,target_success_rate`, one row per
// group (written by rabbit run from the suite's [suite.targets]).
constexpr const char* kTargetsFile = "targets.csv";
using SuccessTargets = std::vector<std::pair<std::string, double>>;
// Reads DIR/targets.csv; none (empty) when the file does not exist. Throws InputError for a
// malformed one.
SuccessTargets ReadTargets(const std::string& dir);

// The rows of comparison.csv for summary rows (any order; grouped as described above).
std::vector<VariantComparison> CompareVariants(const std::vector<report_internal::SummaryRow>& rows,
                                               const SuccessTargets& targets = {});

// comparison.csv's header line and its text (header and rows, each line ending in "\n").
std::string ComparisonHeader();
std::string ComparisonCsv(const std::vector<VariantComparison>& rows);

// Reads DIR/summary.csv and writes DIR/comparison.csv atomically; returns its path. Throws
// InputError for a missing or malformed summary.
std::string WriteComparison(const std::string& dir);

}  // namespace rabbit

#endif  // RABBIT_REPORT_COMPARISON_H_
