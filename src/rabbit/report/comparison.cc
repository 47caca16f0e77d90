// The head-to-head comparison of a batch run's variants (comparison.h).
#include "rabbit/report/comparison.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"

namespace rabbit {
namespace {

using report_internal::IsMainRun;
using report_internal::SummaryRow;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

double Mean(const std::vector<double>& values) {
  if (values.empty()) return kNan;
  double sum = 0.0;
  for (double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

double Median(std::vector<double> values) {
  if (values.empty()) return kNan;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// The rows of one group and variant, while they are collected.
struct VariantRuns {
  VariantComparison row;
  int main_runs = 0;
  std::vector<std::string> controllers;
  std::vector<double> speed_errors, costs;
  bool memory_known = true;
  double memory = 0.0;
};

}  // namespace

ProportionInterval WilsonInterval(int successes, int trials, double z) {
  ProportionInterval ci;
  if (trials <= 0 || successes < 0 || successes > trials || !(z > 0.0)) return ci;
  const double n = trials, p = successes / n, z2 = z * z;
  const double denominator = 1.0 + z2 / n;
  const double centre = (p + z2 / (2.0 * n)) / denominator;
  const double half = z / denominator * std::sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n));
  ci.low = successes == 0 ? 0.0 : std::max(0.0, centre - half);
  ci.high = successes == trials ? 1.0 : std::min(1.0, centre + half);
  return ci;
}

SuccessTargets ReadTargets(const std::string& dir) {
  const std::string path = (std::filesystem::path(dir) / kTargetsFile).string();
  SuccessTargets targets;
  if (!std::filesystem::exists(path)) return targets;
  const CsvTable table = CsvTable::Read(path);
  const size_t group = table.Column("group"), rate = table.Column("target_success_rate");
  for (size_t row = 0; row < table.num_rows(); ++row) {
    const double value = table.Number(row, rate);
    if (table.Cell(row, group).empty() || !(value > 0.0 && value <= 1.0)) {
      throw InputError(path, table.line(row), "target_success_rate",
                       "expected a group and a rate in (0, 1]");
    }
    targets.emplace_back(table.Text(row, group), value);
  }
  return targets;
}

std::vector<VariantComparison> CompareVariants(const std::vector<SummaryRow>& rows,
                                               const SuccessTargets& targets) {
  // Groups in order of first appearance; a family and a plain scenario of the same name apart.
  struct Group {
    std::string name;
    bool family = false;
    std::vector<std::string> scenarios;
    std::vector<VariantRuns> variants;
  };
  std::vector<Group> groups;
  for (const SummaryRow& r : rows) {
    auto g = std::find_if(groups.begin(), groups.end(), [&r](const Group& x) {
      return x.name == r.group && x.family == r.is_family_member;
    });
    if (g == groups.end()) {
      groups.push_back({r.group, r.is_family_member, {}, {}});
      g = groups.end() - 1;
    }
    if (std::find(g->scenarios.begin(), g->scenarios.end(), r.scenario) == g->scenarios.end()) {
      g->scenarios.push_back(r.scenario);
    }
    auto v = std::find_if(g->variants.begin(), g->variants.end(),
                          [&r](const VariantRuns& c) { return c.row.variant == r.variant; });
    if (v == g->variants.end()) {
      g->variants.emplace_back();
      v = g->variants.end() - 1;
      v->row.suite = r.suite;
      v->row.group = r.group;
      v->row.family = r.is_family_member;
      v->row.variant = r.variant;
    }
    VariantComparison& c = v->row;
    ++c.runs;
    c.passed += r.passed ? 1 : 0;
    v->main_runs += IsMainRun(r) ? 1 : 0;
    if (std::find(v->controllers.begin(), v->controllers.end(), r.controller) ==
        v->controllers.end()) {
      v->controllers.push_back(r.controller);
    }
    if (r.outcome == "completed") {
      ++c.completed;
      if (std::isfinite(r.mean_speed_error)) v->speed_errors.push_back(r.mean_speed_error);
      if (std::isfinite(r.cost_of_transport)) v->costs.push_back(r.cost_of_transport);
    } else if (r.outcome == "fell") {
      ++c.fell;
    } else if (r.outcome == "tripped") {
      ++c.tripped;
    } else if (r.outcome == "stalled") {
      ++c.stalled;
    } else if (r.outcome == "diverged") {
      ++c.diverged;
    } else if (r.outcome == "timeout") {
      ++c.timeout;
    } else {
      ++c.other_outcome;
    }
    if (std::isnan(r.pattern_memory_bytes)) {
      v->memory_known = false;
    } else {
      v->memory = std::max(v->memory, r.pattern_memory_bytes);
    }
  }
  std::vector<VariantComparison> out;
  for (Group& g : groups) {
    // The main variant first (summary order has it first per scenario; a group's first row may
    // still be a baseline when its main runs were filtered out).
    std::stable_partition(g.variants.begin(), g.variants.end(),
                          [](const VariantRuns& c) { return c.main_runs > 0; });
    for (VariantRuns& v : g.variants) {
      VariantComparison c = v.row;
      c.members = static_cast<int>(g.scenarios.size());
      for (const std::string& name : v.controllers) {
        c.controller += (c.controller.empty() ? "" : ";") + name;
      }
      c.role = v.main_runs == c.runs ? "main" : v.main_runs == 0 ? "baseline" : "mixed";
      c.success_rate = static_cast<double>(c.passed) / static_cast<double>(c.runs);
      c.ci = WilsonInterval(c.passed, c.runs);
      c.speed_error_runs = static_cast<int>(v.speed_errors.size());
      c.speed_error_mean = Mean(v.speed_errors);
      c.speed_error_median = Median(v.speed_errors);
      c.cot_runs = static_cast<int>(v.costs.size());
      c.cot_mean = Mean(v.costs);
      c.cot_median = Median(v.costs);
      c.pattern_memory_bytes = v.memory_known ? v.memory : kNan;
      if (c.role == "main") {
        for (const auto& [group, rate] : targets) {
          if (group == c.group) {
            c.target = rate;
            c.target_gap = c.success_rate - rate;
          }
        }
      }
      out.push_back(std::move(c));
    }
  }
  return out;
}

std::string ComparisonHeader() {
  return "suite,group,group_kind,members,variant,controller,role,runs,passed,success_rate,ci_low,"
         "ci_high,completed,fell,tripped,stalled,diverged,timeout,other_outcome,speed_error_runs,"
         "speed_error_mean_m_s,speed_error_median_m_s,cot_runs,cot_mean,cot_median,"
         "pattern_memory_bytes,target_success_rate,target_gap";
}

std::string ComparisonCsv(const std::vector<VariantComparison>& rows) {
  std::string out = ComparisonHeader() + "\n";
  for (const VariantComparison& c : rows) {
    out += FormatCsvCell(c.suite) + ',' + FormatCsvCell(c.group) + ',' +
           (c.family ? "family" : "scenario") + ',' + std::to_string(c.members) + ',' +
           FormatCsvCell(c.variant) + ',' + FormatCsvCell(c.controller) + ',' + c.role + ',' +
           std::to_string(c.runs) + ',' + std::to_string(c.passed) + ',' +
           FormatCsvNumber(c.success_rate) + ',' + FormatCsvNumber(c.ci.low) + ',' +
           FormatCsvNumber(c.ci.high) + ',' + std::to_string(c.completed) + ',' +
           std::to_string(c.fell) + ',' + std::to_string(c.tripped) + ',' +
           std::to_string(c.stalled) + ',' + std::to_string(c.diverged) + ',' +
           std::to_string(c.timeout) + ',' + std::to_string(c.other_outcome) + ',' +
           std::to_string(c.speed_error_runs) + ',' + FormatCsvNumber(c.speed_error_mean) + ',' +
           FormatCsvNumber(c.speed_error_median) + ',' + std::to_string(c.cot_runs) + ',' +
           FormatCsvNumber(c.cot_mean) + ',' + FormatCsvNumber(c.cot_median) + ',' +
           FormatCsvNumber(c.pattern_memory_bytes) + ',' + FormatCsvNumber(c.target) + ',' +
           FormatCsvNumber(c.target_gap) + '\n';
  }
  return out;
}

std::string WriteComparison(const std::string& dir) {
  const std::filesystem::path root(dir);
  const std::string csv = ComparisonCsv(CompareVariants(
      report_internal::ReadSummary((root / "summary.csv").string()), ReadTargets(dir)));
  const std::string path = (root / "comparison.csv").string();
  WriteFileAtomically(path, [&csv](std::ostream& out) { out << csv; });
  return path;
}

}  // namespace rabbit
