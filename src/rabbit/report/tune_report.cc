// The tuning job's report page (tune_report.h): the header, the sections around the three
// figures and the tables, over the job's files as tune_report_data.h reads them.
#include "rabbit/report/tune_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/report/gnuplot.h"
#include "rabbit/report/report_figures.h"
#include "rabbit/report/report_page.h"
#include "rabbit/report/suite_report.h"
#include "rabbit/report/svg.h"
#include "rabbit/report/tune_report_data.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;
using namespace tune_report_internal;  // NOLINT: the report's own parts

const char kTuneStyle[] = R"css(
table.meta th{text-align:left;background:#f6f7f9;font-weight:600;width:170px}
table.meta td{text-align:left;white-space:normal}
table.meta{margin:10px 0;font-size:13.5px;min-width:600px}
.headline{font-size:17px;margin:14px 0 4px}
.headline .value{font-weight:700;font-variant-numeric:tabular-nums}
.better{color:#16652a}
.worse{color:#a3150f}
tr.best td{background:#e7f0fa;font-weight:600}
tr.invalid td{color:#8a1c14;background:#fdf3f2}
tr.guard td{background:#fff6e0}
td.guard{text-align:left;white-space:normal;min-width:140px}
td.num{font-variant-numeric:tabular-nums}
td.error{text-align:left;white-space:normal;min-width:180px}
td.pass{background:var(--pass);color:#16652a;font-weight:700}
td.fail{background:var(--fail);color:#a3150f;font-weight:700}
pre.toml{background:#f6f7f9;border:1px solid #e3e6ea;border-radius:4px;padding:10px 12px;
  font-size:13px;overflow-x:auto}
ul.suites{margin:0;padding-left:18px}
)css";

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[64];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M UTC", &tm);
  return buffer;
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ';')) {
    item = Trim(item);
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

// "a → b", b marked better or worse than a (lower is better: every term is minimised).
std::string Change(double a, double b, int sig = 4) {
  std::string cls;
  if (std::isfinite(a) && std::isfinite(b) && a != b) cls = b < a ? "better" : "worse";
  return Cell(a, sig) + " &rarr; " +
         (cls.empty() ? Cell(b, sig) : "<span class=\"" + cls + "\">" + Cell(b, sig) + "</span>");
}

std::string PassText(int passed) {
  return passed < 0 ? "&ndash;" : passed ? "&#10003;&nbsp;pass" : "&#10007;&nbsp;fail";
}

// The outcomes of a scenario's runs: "completed", or "fell ×2, completed" for several runs.
std::string OutcomeText(const Outcomes& outcomes, const ComparisonRow& row) {
  const auto it = outcomes.find({row.suite, row.scenario});
  if (it == outcomes.end() || it->second.empty()) return "&ndash;";
  std::vector<std::pair<std::string, int>> counts;
  for (const std::string& o : it->second) {
    auto c =
        std::find_if(counts.begin(), counts.end(), [&](const auto& p) { return p.first == o; });
    if (c == counts.end()) {
      counts.emplace_back(o, 1);
    } else {
      ++c->second;
    }
  }
  std::string out;
  for (const auto& [o, n] : counts) {
    out += (out.empty() ? "" : ", ") + HtmlEscape(o.empty() ? "?" : o) +
           (n > 1 ? "&nbsp;&times;" + std::to_string(n) : "");
  }
  return out;
}

std::string HeaderHtml(const TuneData& data, const std::string& source) {
  const Meta& m = data.meta;
  const Evaluation* initial = FindEval(data, m.initial_eval);
  const Evaluation* best = FindEval(data, m.best_eval);
  const double initial_objective = std::isnan(m.initial_objective) && initial != nullptr
                                       ? initial->objective
                                       : m.initial_objective;
  const double best_objective =
      std::isnan(m.best_objective) && best != nullptr ? best->objective : m.best_objective;
  std::ostringstream html;
  html << "<h1>Tuning job <em>" << HtmlEscape(m.job.empty() ? "(unnamed)" : m.job)
       << "</em></h1>\n";
  if (!m.description.empty()) html << "<p>" << HtmlEscape(m.description) << "</p>\n";
  html << "<p class=\"note\">Rebuilt from the CSV files in <code>" << HtmlEscape(source)
       << "</code> (rabbit " << RABBIT_VERSION << ") on " << UtcNow() << ".</p>\n";
  if (!m.complete) {
    html << "<p class=\"warning\">The job has not completed (stopped, or still running): the page "
            "shows its "
         << data.evaluations.size() << " evaluations so far.</p>\n";
  }
  html << "<p class=\"headline\">Best objective <span class=\"value\" id=\"best-objective\">"
       << Cell(best_objective) << "</span>";
  if (m.best_eval) html << " (evaluation " << *m.best_eval << ")";
  html << " against the initial <span class=\"value\" id=\"initial-objective\">"
       << Cell(initial_objective) << "</span>";
  if (m.initial_eval) html << " (evaluation " << *m.initial_eval << ")";
  if (std::isfinite(initial_objective) && std::isfinite(best_objective) &&
      initial_objective != 0.0) {
    const double improvement = (initial_objective - best_objective) / std::abs(initial_objective);
    html << ": <span class=\"value " << (improvement >= 0.0 ? "better" : "worse")
         << "\" id=\"improvement\">" << Format("%.2f", 100.0 * improvement)
         << "&nbsp;%</span> relative improvement";
  }
  html << ".</p>\n";

  double wall = 0.0;
  for (const Evaluation& e : data.evaluations) wall += std::isfinite(e.wall) ? e.wall : 0.0;
  std::ostringstream budget;
  budget << data.evaluations.size() << " evaluated of at most " << HtmlEscape(m.max_evaluations);
  if (m.evaluations != std::to_string(data.evaluations.size())) {
    budget << " (meta.csv counts " << HtmlEscape(m.evaluations) << ")";
  }
  budget << "; " << (m.complete ? "complete" : "not complete") << "; " << Cell(wall, 4)
         << " s of evaluation wall time in all";
  std::string weights;
  const auto parsed = ParseWeights(m.weights);
  if (!parsed.empty()) {
    for (const auto& [name, w] : parsed) {
      weights += (weights.empty() ? "" : " + ") + Format("%g", w) + "&nbsp;&times;&nbsp;<code>" +
                 HtmlEscape(name) + "</code>";
    }
    weights += " <span class=\"note\">(" + HtmlEscape(m.weights) + ")</span>";
  } else {
    weights = m.weights.empty() ? "&ndash;" : HtmlEscape(m.weights);
  }
  std::string suites;
  for (const std::string& s : SplitList(m.suites))
    suites += "<li><code>" + HtmlEscape(s) + "</code></li>";
  suites = suites.empty() ? "&ndash;" : "<ul class=\"suites\">" + suites + "</ul>";
  std::string guards;
  for (const std::string& s : SplitList(m.guards)) {
    guards += "<li><code>" + HtmlEscape(s) + "</code></li>";
  }
  guards = guards.empty() ? "none"
                          : "<ul class=\"suites\">" + guards +
                                "</ul><span class=\"note\">the best must keep their required "
                                "scenarios passing</span>";
  const std::pair<const char*, std::string> rows[] = {
      {"algorithm", "<code>" + HtmlEscape(m.algorithm) + "</code>"},
      {"seed", HtmlEscape(m.seed)},
      {"starts", HtmlEscape(m.starts)},
      {"budget", budget.str()},
      {"objective form", "<code>" + HtmlEscape(m.form) + "</code>"},
      {"weights", weights},
      {"suites", suites},
      {"guards", guards},
      {"job file", "<code>" + HtmlEscape(m.job_file) + "</code>"},
      {"fingerprint", "<code>" + HtmlEscape(m.fingerprint) + "</code>"},
  };
  html << "<table class=\"meta\"><tbody>\n";
  for (const auto& [name, value] : rows) {
    html << "<tr><th>" << name << "</th><td>" << value << "</td></tr>\n";
  }
  html << "</tbody></table>\n";
  return html.str();
}

std::string ParametersTable(const TuneData& data) {
  std::ostringstream html;
  html << "<div class=\"table-wrap\"><table class=\"parameters\"><thead><tr><th>parameter</th>"
          "<th>lower</th><th>upper</th><th>initial</th><th>best</th><th>change</th>"
          "<th>note</th></tr></thead><tbody>\n";
  for (const Parameter& p : data.parameters) {
    const double range = p.upper - p.lower;
    std::string change = "&ndash;";
    if (std::isfinite(p.initial) && std::isfinite(p.best)) {
      change = Cell(p.best - p.initial);
      if (std::isfinite(range) && range > 0.0) {
        change +=
            " (" + Format("%+.1f", 100.0 * (p.best - p.initial) / range) + "&nbsp;% of the range)";
      }
    }
    // A best on its bound suggests the bound, not the objective, stopped the search.
    std::string note;
    const double tolerance = std::isfinite(range) && range > 0.0 ? 1e-6 * range : 0.0;
    if (std::isfinite(p.best) && std::isfinite(p.lower) && p.best <= p.lower + tolerance) {
      note = "at the lower bound";
    } else if (std::isfinite(p.best) && std::isfinite(p.upper) && p.best >= p.upper - tolerance) {
      note = "at the upper bound";
    }
    html << "<tr><td class=\"text\"><code>" << HtmlEscape(p.path)
         << "</code></td><td class=\"num\">" << Cell(p.lower) << "</td><td class=\"num\">"
         << Cell(p.upper) << "</td><td class=\"num\">" << Cell(p.initial)
         << "</td><td class=\"num\"><b>" << Cell(p.best) << "</b></td><td class=\"num\">" << change
         << "</td><td class=\"text\">" << note << "</td></tr>\n";
  }
  html << "</tbody></table></div>\n";
  return html.str();
}

std::string ComparisonTable(const TuneData& data) {
  const auto weights = ParseWeights(data.meta.weights);
  std::vector<int> terms;
  for (int k = 0; k < kTerms; ++k) {
    for (const ComparisonRow& r : data.comparison) {
      if (std::isfinite(r.initial[k]) || std::isfinite(r.best[k])) {
        terms.push_back(k);
        break;
      }
    }
  }
  int initial_passed = 0, best_passed = 0;
  for (const ComparisonRow& r : data.comparison) {
    initial_passed += r.initial_passed == 1 ? 1 : 0;
    best_passed += r.best_passed == 1 ? 1 : 0;
  }
  std::ostringstream html;
  html << "<p>Passed: <b>" << initial_passed << "</b> of " << data.comparison.size()
       << (data.comparison.size() == 1 ? " scenario" : " scenarios")
       << " with the initial parameters, <b id=\"best-passed\">" << best_passed
       << "</b> with the best.</p>\n";
  html << "<div class=\"table-wrap\"><table class=\"comparison\"><thead><tr><th>suite</th>"
          "<th>scenario</th><th>initial</th><th>best</th><th>outcome<br>initial &rarr; best</th>";
  for (int k : terms) {
    const double w = TermWeight(weights, k);
    html << "<th>" << kTermNames[k];
    if (std::isfinite(w))
      html << "<br><span class=\"note\">weight " << Format("%g", w) << "</span>";
    html << "</th>";
  }
  html << "</tr></thead><tbody>\n";
  for (const ComparisonRow& r : data.comparison) {
    auto pass_cell = [](int passed) {
      return std::string("<td class=\"") +
             (passed < 0 ? "text"
              : passed   ? "pass"
                         : "fail") +
             "\">" + PassText(passed) + "</td>";
    };
    html << "<tr><td class=\"text\">" << HtmlEscape(r.suite) << "</td><td class=\"text\">"
         << HtmlEscape(r.scenario) << "</td>" << pass_cell(r.initial_passed)
         << pass_cell(r.best_passed) << "<td class=\"text\">"
         << OutcomeText(data.initial_outcomes, r) << " &rarr; "
         << OutcomeText(data.best_outcomes, r) << "</td>";
    for (int k : terms) html << "<td class=\"num\">" << Change(r.initial[k], r.best[k]) << "</td>";
    html << "</tr>\n";
  }
  html << "</tbody></table></div>\n";
  return html.str();
}

// The candidates that broke a guard (could not be the best): each with the required guard
// scenarios it failed, linked to its row of the log.
std::string GuardsSection(const TuneData& data) {
  if (SplitList(data.meta.guards).empty()) return "";
  int run = 0;
  std::vector<const Evaluation*> broke;
  for (const Evaluation& e : data.evaluations) {
    run += e.guards_run == 1 ? 1 : 0;
    if (e.broke_guard()) broke.push_back(&e);
  }
  std::ostringstream html;
  html << "<section id=\"guards\"><h2>Guards</h2>\n<p>The guard suites ran for " << run
       << (run == 1 ? " candidate" : " candidates")
       << " (each one that beat its search's best eligible objective so far); " << broke.size()
       << " broke a required scenario and could not be the best";
  if (!data.meta.best_eval) html << "; <strong>no candidate kept them</strong>";
  html << ".</p>\n";
  if (!broke.empty()) {
    html << "<div class=\"table-wrap\"><table class=\"log\"><thead><tr><th>eval</th>"
            "<th>objective</th><th>broke</th></tr></thead><tbody>\n";
    for (const Evaluation* e : broke) {
      html << "<tr class=\"guard\"><td><a href=\"#eval-" << e->eval << "\">" << e->eval
           << "</a></td><td class=\"num\">" << Cell(e->objective) << "</td><td class=\"guard\">"
           << HtmlEscape(e->guard_broken) << "</td></tr>\n";
    }
    html << "</tbody></table></div>\n";
  }
  html << "</section>\n";
  return html.str();
}

std::string EvaluationLog(const TuneData& data) {
  std::vector<int> terms;
  for (int k = 0; k < kTerms; ++k) {
    for (const Evaluation& e : data.evaluations) {
      if (std::isfinite(e.terms[k])) {
        terms.push_back(k);
        break;
      }
    }
  }
  std::ostringstream table;
  table << "<div class=\"table-wrap\"><table class=\"log\"><thead><tr><th>eval</th><th>round</th>"
           "<th>start</th><th>seq</th><th>objective</th><th>new<br>best</th>";
  for (int k : terms) table << "<th>" << kTermNames[k] << "</th>";
  table << "<th>runs</th><th>failed</th>";
  for (const Parameter& p : data.parameters) table << "<th>" << HtmlEscape(p.path) << "</th>";
  bool any_guards = false;
  for (const Evaluation& e : data.evaluations) any_guards = any_guards || e.guards_run == 1;
  if (any_guards) table << "<th>guards</th>";
  table << "<th>wall<br>s</th><th>error</th></tr></thead><tbody>\n";
  const std::vector<int> starts = Starts(data.evaluations);
  double best_so_far = std::numeric_limits<double>::infinity();
  for (const Evaluation& e : data.evaluations) {
    const bool is_best = data.meta.best_eval && e.eval == *data.meta.best_eval;
    // In evaluation order, as the search saw them (the convergence plot's black line).
    const bool improved = !e.invalid() && std::isfinite(e.objective) && e.objective < best_so_far;
    if (improved) best_so_far = e.objective;
    table << "<tr id=\"eval-" << e.eval << "\""
          << (is_best           ? " class=\"best\""
              : e.invalid()     ? " class=\"invalid\""
              : e.broke_guard() ? " class=\"guard\""
                                : "")
          << "><td>" << e.eval << "</td><td>" << e.round << "</td><td><span class=\"swatch\" "
          << "style=\"background:" << StartColor(starts, e.start) << "\"></span>" << e.start
          << "</td><td>" << e.seq << "</td><td class=\"num\">" << Cell(e.objective) << "</td><td>"
          << (improved ? "&#9660;" : "") << "</td>";
    for (int k : terms) table << "<td class=\"num\">" << Cell(e.terms[k], 4) << "</td>";
    table << "<td>" << e.runs << "</td><td>" << e.failed << "</td>";
    for (double v : e.params) table << "<td class=\"num\">" << Cell(v) << "</td>";
    if (any_guards) {
      table << "<td class=\"guard\">"
            << (e.guards_run != 1 ? ""
                : e.broke_guard() ? "broke: " + HtmlEscape(e.guard_broken)
                                  : std::string("kept"))
            << "</td>";
    }
    table << "<td class=\"num\">" << Cell(e.wall, 3) << "</td><td class=\"error\">"
          << HtmlEscape(e.error) << "</td></tr>\n";
  }
  table << "</tbody></table></div>\n";
  std::ostringstream html;
  html << "<p class=\"note\">Every candidate in evaluation order; &#9660; marks a new best so far, "
          "the best candidate is in bold, invalid candidates in red, candidates that broke a guard "
          "in amber.</p>\n";
  if (data.evaluations.size() > kOpenLogRows) {
    html << "<details class=\"log\"><summary>All " << data.evaluations.size()
         << " evaluations</summary>\n"
         << table.str() << "</details>\n";
  } else {
    html << table.str();
  }
  return html.str();
}

}  // namespace

bool TuneReportOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (gnuplot.empty() || gnuplot.find_first_of(std::string("\n\r\0", 3)) != std::string::npos) {
    return fail("gnuplot must be a non-empty executable name or path");
  }
  if (!(timeout > 0.0) || !std::isfinite(timeout)) {
    return fail("timeout must be a positive number of seconds");
  }
  return true;
}

void WriteTuneReport(const std::string& dir, const TuneReportOptions& options,
                     std::vector<std::string>* warnings) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("tune report options: " + error);
  const fs::path root(dir);
  const TuneData data = ReadTuneData(root);

  // The batch report's figure machinery: one gnuplot process for the three figures.
  SuiteReportOptions figure_options;
  figure_options.gnuplot = options.gnuplot;
  figure_options.gnuplot_timeout = options.timeout;
  FigureSet figures(figure_options);
  ConvergenceInfo convergence;
  const std::optional<size_t> f_convergence = ConvergenceFigure(data, &convergence, &figures);
  const std::optional<size_t> f_traces = TracesFigure(data, &figures);
  const std::vector<int> shown_terms = ShownTerms(data);
  const std::optional<size_t> f_comparison = ComparisonFigure(data, shown_terms, &figures);
  std::string figure_error;
  const bool have_figures = figures.Render(&figure_error);
  if (!have_figures) {
    figure_error =
        "figures left out: gnuplot (" + options.gnuplot + ") could not draw them: " + figure_error;
    if (warnings != nullptr) warnings->push_back(figure_error);
  }
  auto figure = [&](const std::optional<size_t>& k) {
    return have_figures && k ? figures.figure(*k).html : std::string();
  };

  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
       << "<title>rabbit-gait: tuning job " << HtmlEscape(data.meta.job) << "</title><script>"
       << report_internal::kErrorCounter << "</script><style>" << report_internal::kStyle
       << kTuneStyle << "</style></head><body><main>\n";
  html << HeaderHtml(data, dir);
  if (!have_figures) html << "<p class=\"warning\">" << HtmlEscape(figure_error) << "</p>\n";

  html << "<section id=\"convergence\"><h2>Convergence</h2>\n" << figure(f_convergence);
  if (!convergence.left_out.empty()) {
    html << "<p class=\"note\" id=\"invalid-note\">" << convergence.left_out.size()
         << (convergence.left_out.size() == 1 ? " invalid candidate" : " invalid candidates")
         << " (an error, or the objective 1e6) not plotted: evaluation"
         << (convergence.left_out.size() == 1 ? " " : "s ");
    const size_t kListed = 20;
    for (size_t i = 0; i < convergence.left_out.size() && i < kListed; ++i) {
      html << (i == 0 ? "" : ", ") << "<a href=\"#eval-" << convergence.left_out[i] << "\">"
           << convergence.left_out[i] << "</a>";
    }
    if (convergence.left_out.size() > kListed) html << ", &hellip;";
    html << ".</p>\n";
  }
  if (!f_convergence) html << "<p class=\"note\">No valid evaluation to plot.</p>\n";
  html << "</section>\n";

  html << GuardsSection(data);

  html << "<section id=\"parameters\"><h2>Parameters</h2>\n"
       << figure(f_traces) << ParametersTable(data) << "</section>\n";

  html << "<section id=\"scenarios\"><h2>Per scenario: best against initial</h2>\n"
       << figure(f_comparison) << ComparisonTable(data) << "</section>\n";

  html << "<section id=\"best-toml\"><h2>Best parameters (<code>best.toml</code>)</h2>\n";
  if (data.best_toml) {
    html << "<pre class=\"toml\">" << HtmlEscape(*data.best_toml) << "</pre>\n";
  } else {
    html << "<p class=\"note\">Not written (yet).</p>\n";
  }
  html << "</section>\n";

  html << "<section id=\"log\"><h2>Evaluation log</h2>\n" << EvaluationLog(data) << "</section>\n";
  html << "</main></body></html>\n";

  const std::string page = html.str();
  WriteFileAtomically((root / "index.html").string(), [&page](std::ostream& out) { out << page; });
}

}  // namespace rabbit
