// The batch report's orchestration: options, the stick figure's geometry, and WriteSuiteReport,
// which reads the folder (report_data.h), draws the figures (report_figures.h) and assembles the
// page from its pieces (report_page.h).
#include "rabbit/report/suite_report.h"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "rabbit/io/atomic_file.h"
#include "rabbit/report/comparison.h"
#include "rabbit/report/push_survival.h"
#include "rabbit/report/report_data.h"
#include "rabbit/report/report_figures.h"
#include "rabbit/report/report_page.h"
#include "rabbit/report/svg.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

using report_internal::ComparisonTable;
using report_internal::FigureSet;
using report_internal::GroupByScenario;
using report_internal::GroupComparisonFigure;
using report_internal::kErrorCounter;
using report_internal::kReplayScript;
using report_internal::kStyle;
using report_internal::LastWindow;
using report_internal::ObstacleWindow;
using report_internal::OverviewComparisonFigure;
using report_internal::PushSurvivalFigure;
using report_internal::ReadRun;
using report_internal::ReadSummary;
using report_internal::ReplayHtml;
using report_internal::RunData;
using report_internal::RunLabel;
using report_internal::ScenarioGroup;
using report_internal::SlopeWindow;
using report_internal::StartWindow;
using report_internal::Step;
using report_internal::StepsFigure;
using report_internal::StepsTable;
using report_internal::StickDiagramFigure;
using report_internal::SummaryRow;
using report_internal::SummaryTable;
using report_internal::TerrainText;
using report_internal::TrackingFigure;
using report_internal::Trajectory;
using report_internal::WeightsFigure;
using report_internal::Window;

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[64];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M UTC", &tm);
  return buffer;
}

bool HasFiniteWeights(const RunData& run) {
  for (const Step& s : run.steps) {
    for (double w : s.w) {
      if (std::isfinite(w)) return true;
    }
  }
  return false;
}

bool HasSamplesIn(const std::vector<double>& t, const Window& w) {
  for (double v : t) {
    if (v >= w.t0 - 1e-9 && v <= w.t1 + 1e-9) return true;
  }
  return false;
}

}  // namespace

bool SuiteReportOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (gnuplot.empty() || gnuplot.find_first_of(std::string("\n\r\0", 3)) != std::string::npos) {
    return fail("gnuplot must be a non-empty executable name or path");
  }
  if (!(gnuplot_timeout > 0.0) || !std::isfinite(gnuplot_timeout)) {
    return fail("gnuplot_timeout must be a positive number of seconds");
  }
  if (replay_fps < 1 || replay_fps > 240) return fail("replay_fps must be within 1..240");
  if (max_replay_frames < 2 || max_replay_frames > 1000000) {
    return fail("max_replay_frames must be within 2..1000000");
  }
  if (replay_decimals < 1 || replay_decimals > 9) {
    return fail("replay_decimals must be within 1..9");
  }
  for (const auto& [name, value] : {std::pair<const char*, double>{"stick_every", stick_every},
                                    {"stick_window", stick_window},
                                    {"tracking_window", tracking_window}}) {
    if (!(value > 0.0) || !std::isfinite(value) || value > 1e6) {
      return fail(std::string(name) + " must be in (0, 1e6] s");
    }
  }
  if (stick_window / stick_every > 1000.0) {
    return fail("stick_window / stick_every must be at most 1000 figures per diagram");
  }
  if (figure_width < 300 || figure_width > 4000) {
    return fail("figure_width must be within 300..4000 px");
  }
  if (!(survival_bin_n_s > 0.0) || !(survival_bin_n_s <= 1000.0)) {
    return fail("survival_bin_n_s must be within (0, 1000] N s");
  }
  return true;
}

StickFigure StickPoints(const std::array<double, 7>& q, const LinkLengths& lengths) {
  StickFigure f;
  f.hip = {q[0], q[1]};
  const double q0 = q[2];
  f.trunk_top = {f.hip.x + lengths.trunk * std::sin(q0), f.hip.y + lengths.trunk * std::cos(q0)};
  for (int leg = 0; leg < 2; ++leg) {
    const double thigh = q[3 + 2 * leg] - q0;
    const double shin = thigh + q[4 + 2 * leg];
    f.knee[leg] = {f.hip.x + lengths.thigh * std::sin(thigh),
                   f.hip.y - lengths.thigh * std::cos(thigh)};
    f.foot[leg] = {f.knee[leg].x + lengths.shin * std::sin(shin),
                   f.knee[leg].y - lengths.shin * std::cos(shin)};
  }
  return f;
}

namespace {

// The verdict at the top of the page: the main runs and the baselines passed, and each family's
// success rate with its 95% Wilson interval (from the head-to-head).
std::string VerdictHtml(const std::vector<SummaryRow>& rows,
                        const std::vector<VariantComparison>& comparison) {
  int main_runs = 0, main_passed = 0, baselines = 0, baselines_passed = 0;
  for (const SummaryRow& r : rows) {
    const bool main = IsMainRun(r);
    (main ? main_runs : baselines) += 1;
    (main ? main_passed : baselines_passed) += r.passed ? 1 : 0;
  }
  std::ostringstream html;
  html << "<p class=\"verdict " << (main_passed == main_runs ? "pass" : "fail")
       << "\"><b>Verdict</b>: " << main_passed << " of " << main_runs
       << " scenario runs passed their criteria";
  if (main_passed != main_runs) html << " (" << main_runs - main_passed << " failed)";
  if (baselines > 0) {
    html << "; baselines " << baselines_passed << " of " << baselines << " passed";
  }
  for (const VariantComparison& c : comparison) {
    if (!c.family || c.role != "main") continue;
    char rate[96];
    std::snprintf(rate, sizeof rate, "%d/%d passed (%.0f%%, 95%% CI %.0f&ndash;%.0f%%)", c.passed,
                  c.runs, 100.0 * c.success_rate, 100.0 * c.ci.low, 100.0 * c.ci.high);
    html << "; family <a href=\"#head-to-head\">" << HtmlEscape(c.group) << "</a> " << rate;
  }
  html << ".</p>\n<p class=\"note\">A failed run fails <code>rabbit run</code> (exit 1) only "
          "when its scenario is required (the table <code>rabbit run</code> prints marks it "
          "<b>NO</b>; an optional scenario's or a baseline's failure <b>no</b>). Each scenario's "
          "figures, steps and replays are one click away, below the summary.</p>\n";
  return html.str();
}

// The summary: the plain scenarios' runs in one table, then each family's members in a table of
// their own, collapsed under a line with the family's count of passed runs.
std::string SummaryTables(const std::vector<RunData>& runs,
                          const std::vector<ScenarioGroup>& groups) {
  std::vector<size_t> plain;
  std::vector<std::string> families;
  std::map<std::string, std::vector<size_t>> members;
  for (size_t g = 0; g < groups.size(); ++g) {
    const SummaryRow& row = runs[groups[g].runs.front()].row;
    if (!row.is_family_member) {
      plain.push_back(g);
      continue;
    }
    if (members.count(row.group) == 0) families.push_back(row.group);
    members[row.group].push_back(g);
  }
  std::ostringstream html;
  if (!plain.empty()) html << SummaryTable(runs, groups, plain);
  for (const std::string& family : families) {
    int n = 0, passed = 0;
    for (size_t g : members[family]) {
      for (size_t k : groups[g].runs) {
        ++n;
        passed += runs[k].row.passed ? 1 : 0;
      }
    }
    html << "<details class=\"family-table\"><summary>Family " << HtmlEscape(family) << ": "
         << members[family].size() << " members, " << passed << " of " << n
         << " runs passed (every run, one row each)</summary>\n"
         << SummaryTable(runs, groups, members[family]) << "</details>\n";
  }
  return html.str();
}

}  // namespace

std::string WriteSuiteReport(const std::string& dir, const SuiteReportOptions& options,
                             std::vector<std::string>* warnings) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("report options: " + error);
  const fs::path root(dir);
  const std::string summary_path = (root / "summary.csv").string();
  const std::vector<SummaryRow> rows = ReadSummary(summary_path);

  // The head-to-head, from the summary alone.
  const std::vector<VariantComparison> comparison = CompareVariants(rows, ReadTargets(dir));
  std::vector<std::vector<const VariantComparison*>> head_to_head;  // per group, its variants
  std::map<std::string, int> family_size;                           // members per family
  for (const VariantComparison& c : comparison) {
    if (c.family) family_size[c.group] = c.members;
    if (head_to_head.empty() || head_to_head.back().front()->group != c.group ||
        head_to_head.back().front()->family != c.family) {
      head_to_head.emplace_back();
    }
    head_to_head.back().push_back(&c);
  }
  // Survival against push impulse of the pushed families, from every member's meta.csv.
  const std::vector<SurvivalBin> survival =
      ReadPushSurvival(dir, rows, options.survival_bin_n_s, warnings);

  // Which scenarios get their figures, steps and replays: all but the family members beyond the
  // first options.family_details of their family. The others' run files are not read.
  std::set<std::string> detailed;
  {
    std::map<std::string, std::set<std::string>> shown;  // family -> its members shown
    for (const SummaryRow& r : rows) {
      if (!r.is_family_member || options.family_details < 0) {
        detailed.insert(r.scenario);
        continue;
      }
      std::set<std::string>& members = shown[r.group];
      if (members.count(r.scenario) == 0 &&
          members.size() < static_cast<size_t>(options.family_details)) {
        members.insert(r.scenario);
        detailed.insert(r.scenario);
      }
    }
  }
  std::vector<RunData> runs;
  for (const SummaryRow& row : rows) {
    if (detailed.count(row.scenario) != 0) {
      runs.push_back(ReadRun(root, row, warnings));
    } else {
      RunData brief;
      brief.row = row;
      runs.push_back(std::move(brief));
    }
  }
  const std::vector<ScenarioGroup> groups = GroupByScenario(runs);

  // Figures of the head-to-head and of every scenario shown in detail, rendered together.
  FigureSet figures(options);
  const bool overview = head_to_head.size() > 1;
  const size_t overview_figure =
      overview ? OverviewComparisonFigure(comparison, options, &figures) : 0;
  std::vector<size_t> group_figures(head_to_head.size(), figures.size());
  std::vector<std::vector<size_t>> survival_figures(head_to_head.size());
  for (size_t g = 0; g < head_to_head.size(); ++g) {
    // A chart for a family; a plain scenario's one run per variant is its table's row.
    if (!head_to_head[g].front()->family) continue;
    group_figures[g] = GroupComparisonFigure(head_to_head[g], options, &figures);
    std::vector<const SurvivalBin*> bins;
    for (const SurvivalBin& b : survival) {
      if (b.group == head_to_head[g].front()->group) bins.push_back(&b);
    }
    if (!bins.empty()) survival_figures[g].push_back(PushSurvivalFigure(bins, options, &figures));
  }
  std::vector<std::vector<size_t>> scenario_figures(groups.size());
  for (size_t g = 0; g < groups.size(); ++g) {
    if (detailed.count(groups[g].name) == 0) continue;
    const RunData& main = runs[groups[g].runs.front()];
    std::vector<size_t>& mine = scenario_figures[g];
    const Trajectory& tr = main.trajectory;
    if (!tr.t.empty()) {
      mine.push_back(
          StickDiagramFigure(main, StartWindow(tr, options.stick_window), options, &figures));
      if (!main.terrain.obstacles.empty()) {
        mine.push_back(StickDiagramFigure(
            main, ObstacleWindow(tr, main.terrain.obstacles.front(), options.stick_window), options,
            &figures));
      }
      const std::vector<SlopeBreak>& breaks = main.terrain.ground.breaks();
      if (!breaks.empty()) {
        mine.push_back(
            StickDiagramFigure(main, SlopeWindow(tr, breaks.front().x_start, options.stick_window),
                               options, &figures));
      }
    }
    std::vector<const RunData*> with_steps;
    for (size_t k : groups[g].runs) {
      if (!runs[k].steps.empty()) with_steps.push_back(&runs[k]);
    }
    if (!with_steps.empty() && with_steps.front() == &main) {
      mine.push_back(StepsFigure(with_steps, !main.terrain.obstacles.empty(), options, &figures));
    }
    if (!tr.t.empty() && !main.tracking.t.empty()) {
      const Window w =
          main.terrain.obstacles.empty()
              ? LastWindow(tr, options.tracking_window)
              : ObstacleWindow(tr, main.terrain.obstacles.front(), options.tracking_window);
      if (HasSamplesIn(main.tracking.t, w)) {
        mine.push_back(TrackingFigure(main, w, options, &figures));
      }
    }
    if (HasFiniteWeights(main)) mine.push_back(WeightsFigure(main, options, &figures));
  }
  std::string figure_error;
  const bool have_figures = figures.Render(&figure_error);
  if (!have_figures) {
    const std::string warning =
        "figures left out: gnuplot (" + options.gnuplot + ") could not draw them: " + figure_error;
    if (warnings != nullptr) warnings->push_back(warning);
    figure_error = warning;
  }

  // The page.
  std::string suite;
  for (const SummaryRow& r : rows) {
    if (suite.find(r.suite) == std::string::npos) suite += (suite.empty() ? "" : ", ") + r.suite;
  }
  if (suite.empty()) suite = root.filename().string();
  int passed = 0;
  for (const SummaryRow& r : rows) passed += r.passed ? 1 : 0;
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
       << "<title>rabbit-gait: suite " << HtmlEscape(suite) << "</title><script>" << kErrorCounter
       << "</script><style>" << kStyle << "</style></head><body><main>\n";
  html << "<h1>Suite <em>" << HtmlEscape(suite) << "</em>: batch report</h1>\n";
  html << "<p class=\"note\">" << rows.size() << (rows.size() == 1 ? " run" : " runs") << " in "
       << groups.size() << (groups.size() == 1 ? " scenario" : " scenarios") << ", <b>" << passed
       << " passed</b>, <b>" << rows.size() - static_cast<size_t>(passed)
       << " failed</b>. Rebuilt from the CSV files in <code>"
       << HtmlEscape(options.source_label.empty() ? dir : options.source_label)
       << "</code> by <code>rabbit report</code> (rabbit " << RABBIT_VERSION << ") on " << UtcNow()
       << ". Variants: the Fuzzy-CMAC walker, and as baselines the pragmatic rules at the "
          "nearest reference gait and the Fuzzy-CMAC with its weights rounded to the strongest "
          "rule.</p>\n";
  html << VerdictHtml(rows, comparison);
  if (!have_figures) html << "<p class=\"warning\">" << HtmlEscape(figure_error) << "</p>\n";
  html << "<section id=\"head-to-head\"><h2 style=\"border:0;margin-top:20px\">Head-to-head</h2>\n"
       << "<p class=\"note\">Per group (a family: all its members together; a plain scenario: "
          "itself) and variant, from <code>summary.csv</code>, as in <code>comparison.csv</code>. "
          "Success rate = passed / runs (the run met every criterion of its scenario), with the "
          "95% Wilson score interval [(p + z&sup2;/2n &minus; z&radic;(p(1&minus;p)/n + "
          "z&sup2;/4n&sup2;)) / (1 + z&sup2;/n), the same with +], z = 1.96, p = passed / runs, n "
          "= runs. Speed error (a run's mean |V<sub>M</sub> &minus; V<sub>d</sub>| over its "
          "measured steps) and cost of transport (energy / (m g distance)): median and (mean) "
          "over the <em>completed</em> runs only, since a run that fell ends on a step whose "
          "V<sub>M</sub> means nothing. Gait pattern memory: the bytes of its CMAC weights (none "
          "for the pragmatic rules).</p>\n";
  if (overview && have_figures) html << figures.figure(overview_figure).html;
  for (size_t g = 0; g < head_to_head.size(); ++g) {
    const VariantComparison& first = *head_to_head[g].front();
    html << "<div class=\"group\" id=\"group-" << g << "\"><h3>" << HtmlEscape(first.group)
         << "</h3><p class=\"note\">"
         << (first.family ? "Family of " + std::to_string(first.members) + " members"
                          : std::string("Scenario"))
         << ".</p>\n"
         << ComparisonTable(head_to_head[g]);
    if (first.family && have_figures) {
      html << figures.figure(group_figures[g]).html;
      for (size_t k : survival_figures[g]) html << figures.figure(k).html;
    }
    html << "</div>\n";
  }
  html << "</section>\n";
  html << "<h2>Summary</h2>\n<p class=\"note\">One row per run, "
          "grouped by scenario, baselines in italics below their scenario's main variant; "
          "&ndash; marks a value the run could not measure.</p>\n"
       << SummaryTables(runs, groups);

  // Per scenario shown in detail: its section, the figures, steps and replays one click away. The
  // family members not shown in detail get one line per family instead of a section each.
  size_t replay_index = 0;
  std::map<std::string, std::vector<size_t>> brief_members;  // family -> its groups not shown
  std::vector<std::string> family_order;
  for (size_t g = 0; g < groups.size(); ++g) {
    const ScenarioGroup& group = groups[g];
    const RunData& main = runs[group.runs.front()];
    if (detailed.count(group.name) == 0) {
      if (brief_members.count(main.row.group) == 0) family_order.push_back(main.row.group);
      brief_members[main.row.group].push_back(g);
      continue;
    }
    html << "<section id=\"scenario-" << g << "\"><h2>" << HtmlEscape(group.name) << "</h2>\n";
    if (!main.description.empty()) html << "<p>" << HtmlEscape(main.description) << "</p>\n";
    html << "<p class=\"note\">Terrain: " << TerrainText(main.terrain) << ". Runs: ";
    for (size_t i = 0; i < group.runs.size(); ++i) {
      const SummaryRow& r = runs[group.runs[i]].row;
      html << (i == 0 ? "" : "; ") << HtmlEscape(RunLabel(r)) << " <code>" << HtmlEscape(r.run)
           << "</code> " << (r.passed ? "passed" : "failed") << " (" << HtmlEscape(r.outcome)
           << ")";
    }
    html << ".</p>\n<details class=\"run-detail\"><summary>Figures, steps and replays of "
         << HtmlEscape(group.name) << "</summary>\n";
    if (have_figures) {
      for (size_t k : scenario_figures[g]) html << figures.figure(k).html;
    }
    if (!main.steps.empty()) html << StepsTable(main);
    html << "<h3>Replay</h3>\n";
    for (size_t k : group.runs) html << ReplayHtml(runs[k], replay_index++, options);
    html << "</details></section>\n";
  }
  for (const std::string& family : family_order) {
    const std::vector<size_t>& members = brief_members[family];
    html << "<section class=\"family-rest\"><p class=\"note\">";
    for (size_t g : members) html << "<span id=\"scenario-" << g << "\"></span>";
    html << "The other " << members.size() << " members of family <em>" << HtmlEscape(family)
         << "</em> are in the summary table and its head-to-head figure: family <em>"
         << HtmlEscape(family) << "</em> shows the first " << options.family_details << " of its "
         << family_size[family]
         << " members in detail (<code>rabbit report DIR --family-details N</code>; -1: "
            "all).</p></section>\n";
  }
  html << "</main><script>" << kReplayScript << "</script></body></html>\n";

  // The files once everything was read: a malformed run file changes none of them.
  const std::string comparison_csv = ComparisonCsv(comparison);
  WriteFileAtomically((root / "comparison.csv").string(),
                      [&comparison_csv](std::ostream& out) { out << comparison_csv; });
  WritePushSurvivalCsv(dir, survival);
  const std::string path = (root / "index.html").string();
  const std::string page = html.str();
  WriteFileAtomically(path, [&page](std::ostream& out) { out << page; });
  return path;
}

}  // namespace rabbit
