// rabbit run's table and verdict (cli/run_summary.h).
#include "cli/run_summary.h"

#include <cmath>
#include <map>
#include <string>

#include "rabbit/report/comparison.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"

namespace rabbit::cli {
namespace {

bool IsMain(const BatchJob& job, const RunBrief& run) { return run.run == job.scenario->name; }

// The table's pass column: yes; NO for a required scenario that failed (fails the run); no for
// an optional run that failed (an optional scenario, or a baseline).
const char* PassMark(const BatchJob& job, const RunBrief& run) {
  if (run.passed) return "yes";
  return IsMain(job, run) && job.scenario->required ? "NO" : "no";
}

void PrintRow(std::FILE* out, const BatchJob& job, const RunBrief& r, bool reasons) {
  std::fprintf(out, "%-34s %-10s %-6s %6d %8.2f %9.3f %8.3f\n", r.run.c_str(),
               OutcomeName(r.outcome), PassMark(job, r), r.metrics.steps, r.metrics.distance,
               r.metrics.mean_abs_speed_error, r.metrics.l_step_mean);
  if (!reasons) return;
  for (const std::string& f : r.failures) std::fprintf(out, "    - %s\n", f.c_str());
}

// A proportion in percent, rounded to a whole number ("nan" for none).
std::string Percent(double x) {
  if (!std::isfinite(x)) return "nan";
  char buffer[16];
  std::snprintf(buffer, sizeof buffer, "%.0f", 100.0 * x);
  return buffer;
}

// "12/20 passed (60%, 95% CI 39-78%)"
std::string Rate(int passed, int runs) {
  const ProportionInterval ci = WilsonInterval(passed, runs);
  const double rate = runs > 0 ? static_cast<double>(passed) / runs : NAN;
  return std::to_string(passed) + "/" + std::to_string(runs) + " passed (" + Percent(rate) +
         "%, 95% CI " + Percent(ci.low) + "-" + Percent(ci.high) + "%)";
}

}  // namespace

void TallyRuns(const std::string& suite, const std::vector<BatchJob>& jobs,
               const std::vector<RunBrief>& runs, RunTally* tally) {
  for (size_t k = 0; k < jobs.size() && k < runs.size(); ++k) {
    const BatchJob& job = jobs[k];
    const RunBrief& r = runs[k];
    if (!IsMain(job, r)) {
      ++(r.passed ? tally->baseline_passed : tally->baseline_failed);
    } else if (job.scenario->required) {
      ++(r.passed ? tally->required_passed : tally->required_failed);
    } else {
      ++(r.passed ? tally->optional_passed : tally->optional_failed);
    }
    if (job.scenario->family.empty()) continue;
    const std::string variant = IsMain(job, r) ? "" : job.variant;
    FamilyTally* found = nullptr;
    for (FamilyTally& f : tally->families) {
      if (f.suite == suite && f.family == job.scenario->family && f.variant == variant) found = &f;
    }
    if (found == nullptr) {
      tally->families.push_back({suite, job.scenario->family, variant, 0, 0});
      found = &tally->families.back();
    }
    ++found->runs;
    found->passed += r.passed ? 1 : 0;
  }
}

void TallyMerge(const RunTally& from, RunTally* into) {
  into->required_passed += from.required_passed;
  into->required_failed += from.required_failed;
  into->optional_passed += from.optional_passed;
  into->optional_failed += from.optional_failed;
  into->baseline_passed += from.baseline_passed;
  into->baseline_failed += from.baseline_failed;
  into->families.insert(into->families.end(), from.families.begin(), from.families.end());
}

void PrintRunTable(std::FILE* out, const std::string& suite, const std::vector<BatchJob>& jobs,
                   const std::vector<RunBrief>& runs, bool verbose) {
  std::fprintf(out, "%-34s %-10s %-6s %6s %8s %9s %8s\n", "run", "outcome", "pass", "steps",
               "dist m", "|V-Vd| m/s", "L_step m");
  std::map<std::string, int> shown, hidden;  // per family: failed main runs listed, left out
  bool families = false;
  for (size_t k = 0; k < jobs.size() && k < runs.size(); ++k) {
    const BatchJob& job = jobs[k];
    const RunBrief& r = runs[k];
    const std::string& family = job.scenario->family;
    families = families || !family.empty();
    if (!verbose && !family.empty()) {
      if (r.passed || !IsMain(job, r)) continue;
      if (shown[family] >= kFamilyFailuresShown) {
        ++hidden[family];
        continue;
      }
      ++shown[family];
    }
    PrintRow(out, job, r, verbose || family.empty());
  }
  for (const auto& [family, count] : hidden) {
    std::fprintf(out, "    ... and %d more failed runs of family %s (-v lists every run)\n", count,
                 family.c_str());
  }
  RunTally tally;
  TallyRuns(suite, jobs, runs, &tally);
  // One line per family: the main variant's rate and interval, then its baselines' counts.
  for (const FamilyTally& f : tally.families) {
    if (!f.variant.empty()) continue;
    std::string line = "family     " + f.family + ": " + Rate(f.passed, f.runs);
    std::string baselines;
    for (const FamilyTally& b : tally.families) {
      if (b.family != f.family || b.variant.empty()) continue;
      baselines += (baselines.empty() ? "; baselines " : ", ") + b.variant + " " +
                   std::to_string(b.passed) + "/" + std::to_string(b.runs);
    }
    std::fprintf(out, "%s%s\n", line.c_str(), baselines.c_str());
  }
  std::fprintf(out,
               "legend     pass: yes = met its criteria; NO = a required scenario failed (the run "
               "exits 1);\n           no = failed, but optional (a scenario with required = false, "
               "or a baseline): reported only%s\n",
               families && !verbose ? ";\n           a family's passed runs and its baselines' "
                                      "runs: in its family line, its failures' reasons with -v"
                                    : "");
}

std::string VerdictLine(const RunTally& t) {
  const int required = t.required_passed + t.required_failed;
  const int optional = t.optional_passed + t.optional_failed;
  const int baselines = t.baseline_passed + t.baseline_failed;
  std::string line =
      std::string("verdict    ") + (t.required_failed > 0 ? "FAILED" : "PASSED") + ": required " +
      (required == 0
           ? std::string("none")
           : std::to_string(t.required_passed) + "/" + std::to_string(required) + " passed");
  if (t.required_failed > 0) line += " (" + std::to_string(t.required_failed) + " failed)";
  line += "; optional " + std::to_string(t.optional_passed) + "/" + std::to_string(optional) +
          " passed";
  if (baselines > 0) {
    line += "; baselines " + std::to_string(t.baseline_passed) + "/" + std::to_string(baselines) +
            " passed";
  }
  for (const FamilyTally& f : t.families) {
    if (!f.variant.empty()) continue;  // the main variant's success: the family's
    line += "; family " + f.family + " " + Rate(f.passed, f.runs);
  }
  return line;
}

}  // namespace rabbit::cli
