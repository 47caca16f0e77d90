// The tuning report's three gnuplot figures (tune_report_data.h), queued on the batch report's
// FigureSet: convergence, parameter traces, best against initial per scenario.
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

namespace rabbit::tune_report_internal {

namespace fs = std::filesystem;

// Figure 1: every valid objective as a point, coloured by its search start, the best so far as a
// line, the initial and best candidates marked.
std::optional<size_t> ConvergenceFigure(const TuneData& data, ConvergenceInfo* info,
                                        FigureSet* figures) {
  const std::vector<int> starts = Starts(data.evaluations);
  std::vector<const Evaluation*> valid;
  for (const Evaluation& e : data.evaluations) {
    if (e.invalid() || !std::isfinite(e.objective)) {
      info->left_out.push_back(e.eval);
    } else {
      valid.push_back(&e);
    }
  }
  if (valid.empty()) return std::nullopt;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  int e_lo = valid.front()->eval, e_hi = e_lo;
  for (const Evaluation& e : data.evaluations) {
    e_lo = std::min(e_lo, e.eval);
    e_hi = std::max(e_hi, e.eval);
  }
  for (const Evaluation* e : valid) {
    lo = std::min(lo, e->objective);
    hi = std::max(hi, e->objective);
  }
  // Two decades or more: a linear axis would crush the late, small improvements to its floor.
  // Only positive objectives have a logarithm.
  info->log_y = lo > 0.0 && hi / lo > 100.0;
  info->decades = lo > 0.0 ? std::log10(hi / lo) : 0.0;

  // The best so far, in evaluation order, carried to the last evaluation.
  std::vector<const Evaluation*> by_eval = valid;
  std::stable_sort(by_eval.begin(), by_eval.end(),
                   [](const Evaluation* a, const Evaluation* b) { return a->eval < b->eval; });
  std::ostringstream best_so_far;
  double best = std::numeric_limits<double>::infinity();
  for (const Evaluation* e : by_eval) {
    best = std::min(best, e->objective);
    best_so_far << e->eval << ' ' << DataNumber(best) << '\n';
  }
  if (by_eval.back()->eval < e_hi) best_so_far << e_hi << ' ' << DataNumber(best) << '\n';

  std::string caption =
      "Figure 1: convergence. The objective of every evaluation (a point, coloured by its "
      "search start) and the best so far (black line)";
  caption += info->log_y ? "; objective on a log scale (it spans " + Format("%.1f", info->decades) +
                               " decades)."
                         : ".";
  const size_t k = figures->Begin(kFigureWidth, 420, caption, "objective per evaluation");
  std::vector<std::string> per_start;
  for (int start : starts) {
    std::ostringstream d;
    for (const Evaluation* e : valid) {
      if (e->start == start) d << e->eval << ' ' << DataNumber(e->objective) << '\n';
    }
    per_start.push_back(d.str());
  }
  std::vector<std::string> names;
  for (size_t s = 0; s < starts.size(); ++s) {
    // A start whose candidates were all invalid has nothing to plot.
    names.push_back(per_start[s].empty() ? "" : figures->AddData(per_start[s]));
  }
  const std::string d_best = figures->AddData(best_so_far.str());
  std::ostringstream marks;
  const Evaluation* initial = FindEval(data, data.meta.initial_eval);
  const Evaluation* best_eval = FindEval(data, data.meta.best_eval);
  std::string d_initial, d_best_mark;
  if (initial != nullptr && !initial->invalid() && std::isfinite(initial->objective)) {
    d_initial = figures->AddData(std::to_string(initial->eval) + ' ' +
                                 DataNumber(initial->objective) + '\n');
  }
  if (best_eval != nullptr && !best_eval->invalid() && std::isfinite(best_eval->objective)) {
    d_best_mark = figures->AddData(std::to_string(best_eval->eval) + ' ' +
                                   DataNumber(best_eval->objective) + '\n');
  }

  std::ostringstream& s = figures->script();
  s << "set lmargin at screen 0.09\nset rmargin at screen 0.78\n"
    << "set key outside right top vertical noenhanced\n"
    << EvalAxis(e_lo, e_hi, 8.0) << "set xlabel 'evaluation'\nset ylabel 'objective'\n";
  if (info->log_y) {
    s << "set logscale y\nset format y '%g'\nset yrange [" << DataNumber(lo / 1.5) << ':'
      << DataNumber(hi * 1.5) << "]\n";
  } else {
    const auto [y_lo, y_hi] = Padded(lo, hi);
    s << "set yrange [" << DataNumber(y_lo) << ':' << DataNumber(y_hi) << "]\n";
  }
  s << "plot ";
  bool first = true;
  auto next = [&]() -> std::ostringstream& {
    if (!first) s << ", \\\n  ";
    first = false;
    return s;
  };
  for (size_t i = 0; i < starts.size(); ++i) {
    if (names[i].empty()) continue;
    const std::string title =
        starts.size() == 1 ? "evaluations" : "start " + std::to_string(starts[i]);
    // Past the palette's colours the key would be a long list of repeated swatches.
    next() << names[i] << " using 1:2 with points pt 7 ps 0.7 lc rgb '"
           << StartColor(starts, starts[i]) << "' "
           << (i < kNumStartColors ? "title " + GnuplotQuote(title) : std::string("notitle"));
  }
  next() << d_best << " using 1:2 with steps lw 1.8 lc rgb '#000000' title 'best so far'";
  if (!d_initial.empty()) {
    next() << d_initial << " using 1:2 with points pt 4 ps 1.8 lw 1.5 lc rgb '#555555' title "
           << GnuplotQuote("initial (eval " + std::to_string(initial->eval) + ")");
  }
  if (!d_best_mark.empty()) {
    next() << d_best_mark << " using 1:2 with points pt 6 ps 2.2 lw 2 lc rgb '#000000' title "
           << GnuplotQuote("best (eval " + std::to_string(best_eval->eval) + ")");
  }
  s << '\n';
  return k;
}

// Figure 2: one panel per parameter, its value against the evaluation, with its bounds dashed,
// invalid candidates as grey crosses and the best candidate circled.
std::optional<size_t> TracesFigure(const TuneData& data, FigureSet* figures) {
  const size_t n = data.parameters.size();
  if (n == 0 || data.evaluations.empty()) return std::nullopt;
  const std::vector<int> starts = Starts(data.evaluations);
  const int cols = n == 1 ? 1 : n <= 4 ? 2 : 3;
  const int rows = static_cast<int>((n + cols - 1) / cols);
  // px: each panel, the room between rows (a row's tic labels, the next row's titles), above
  // the first row's titles and below the last row's tic labels.
  const int panel_height = n == 1 ? 300 : 200, spacing = 58, top = 30, bottom = 34;
  const int height = rows * panel_height + (rows - 1) * spacing + top + bottom;
  int e_lo = data.evaluations.front().eval, e_hi = e_lo;
  for (const Evaluation& e : data.evaluations) {
    e_lo = std::min(e_lo, e.eval);
    e_hi = std::max(e_hi, e.eval);
  }
  const Evaluation* best = FindEval(data, data.meta.best_eval);
  std::string caption =
      "Figure 2: each parameter against the evaluation, coloured by search start as in figure 1";
  if (best != nullptr) {
    caption += "; the best candidate (evaluation " + std::to_string(best->eval) + ") circled";
  }
  caption += "; bounds dashed; invalid candidates as grey crosses.";
  const size_t k = figures->Begin(kFigureWidth, height, caption, "parameter traces");

  // One data file per start (and one of the invalid candidates): eval, then every parameter.
  auto row = [](const Evaluation& e) {
    std::string line = std::to_string(e.eval);
    for (double v : e.params) line += ' ' + DataNumber(v);
    return line + '\n';
  };
  std::vector<std::string> per_start(starts.size());
  std::string invalid;
  for (const Evaluation& e : data.evaluations) {
    if (e.invalid()) {
      invalid += row(e);
    } else {
      per_start[std::find(starts.begin(), starts.end(), e.start) - starts.begin()] += row(e);
    }
  }
  std::vector<std::string> names(starts.size());
  for (size_t i = 0; i < starts.size(); ++i) {
    if (!per_start[i].empty()) names[i] = figures->AddData(per_start[i]);
  }
  const std::string d_invalid = invalid.empty() ? "" : figures->AddData(invalid);
  const std::string d_best = best == nullptr ? "" : figures->AddData(row(*best));

  std::ostringstream& s = figures->script();
  const double h = height;
  s << "unset key\nunset xlabel\n"
    << EvalAxis(e_lo, e_hi,
                cols == 1   ? 8.0
                : cols == 2 ? 6.0
                            : 4.0)
    << "set multiplot layout " << rows << ',' << cols << " margins 0.08,0.98,"
    << DataNumber(bottom / h) << ',' << DataNumber(1.0 - top / h) << " spacing "
    << (cols == 1 ? "0" : "0.07") << ',' << DataNumber(spacing / h) << '\n';
  for (size_t p = 0; p < n; ++p) {
    const Parameter& par = data.parameters[p];
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const Evaluation& e : data.evaluations) {
      if (std::isfinite(e.params[p])) {
        lo = std::min(lo, e.params[p]);
        hi = std::max(hi, e.params[p]);
      }
    }
    for (double b : {par.lower, par.upper, par.best}) {
      if (std::isfinite(b)) {
        lo = std::min(lo, b);
        hi = std::max(hi, b);
      }
    }
    if (!std::isfinite(lo)) lo = hi = 0.0;  // no value at all: an empty, still valid panel
    const auto [y_lo, y_hi] = Padded(lo, hi);
    const size_t column = p + 2;
    s << "set title " << GnuplotQuote(par.path) << " noenhanced\nset yrange [" << DataNumber(y_lo)
      << ':' << DataNumber(y_hi) << "]\n"
      << "plot ";
    bool first = true;
    auto next = [&]() -> std::ostringstream& {
      if (!first) s << ", \\\n  ";
      first = false;
      return s;
    };
    for (double b : {par.lower, par.upper}) {
      if (std::isfinite(b)) next() << DataNumber(b) << " with lines dt 2 lw 1.2 lc rgb '#555555'";
    }
    for (size_t i = 0; i < starts.size(); ++i) {
      if (names[i].empty()) continue;
      next() << names[i] << " using 1:" << column << " with linespoints pt 7 ps 0.5 lw 0.8 lc rgb '"
             << StartColor(starts, starts[i]) << "'";
    }
    if (!d_invalid.empty()) {
      next() << d_invalid << " using 1:" << column << " with points pt 2 ps 0.9 lc rgb '"
             << kInvalidColor << "'";
    }
    if (!d_best.empty()) {
      next() << d_best << " using 1:" << column << " with points pt 6 ps 2 lw 2 lc rgb '#000000'";
    }
    if (first) next() << "NaN notitle";  // nothing at all to draw (no bounds, no values)
    s << '\n';
  }
  s << "unset multiplot\n";
  return k;
}

// The terms figure 3 shows: the weighted ones the comparison has values for; else every term it
// has values for (weights that name no term, or none at all).
std::vector<int> ShownTerms(const TuneData& data) {
  const auto weights = ParseWeights(data.meta.weights);
  auto has_values = [&](int k) {
    for (const ComparisonRow& r : data.comparison) {
      if (std::isfinite(r.initial[k]) || std::isfinite(r.best[k])) return true;
    }
    return false;
  };
  std::vector<int> weighted, present;
  for (int k = 0; k < kTerms; ++k) {
    if (!has_values(k)) continue;
    present.push_back(k);
    const double w = TermWeight(weights, k);
    if (std::isfinite(w) && w != 0.0) weighted.push_back(k);
  }
  return weighted.empty() ? present : weighted;
}

// Figure 3: per scenario, horizontal bars of each shown term, initial above best. Horizontal,
// so that fifty scenario names stay readable down the left; one panel per term, because the
// terms have different units.
std::optional<size_t> ComparisonFigure(const TuneData& data, const std::vector<int>& terms,
                                       FigureSet* figures) {
  const size_t n = data.comparison.size();
  if (n == 0 || terms.empty()) return std::nullopt;
  const auto weights = ParseWeights(data.meta.weights);
  std::vector<std::string> labels = ScenarioLabels(data.comparison);
  size_t longest = 0;
  for (std::string& label : labels) {
    // Cut long names (UTF-8 aware: never inside a character).
    const size_t kMaxChars = 36;
    size_t chars = 0, cut = 0;
    for (size_t i = 0; i < label.size(); ++i) {
      if ((static_cast<unsigned char>(label[i]) & 0xC0) == 0x80) continue;
      if (chars == kMaxChars) cut = i;
      ++chars;
    }
    if (chars > kMaxChars + 1) label = label.substr(0, cut) + "\u2026";
    longest = std::max(longest, std::min(chars, kMaxChars + 1));
  }
  const int cols = std::min<int>(static_cast<int>(terms.size()), 3);
  const int rows = (static_cast<int>(terms.size()) + cols - 1) / cols;
  const double left = std::clamp(7.0 * static_cast<double>(longest) + 24.0, 70.0, 300.0);
  const double right = 20.0, gap = 28.0, title = 30.0, axis = 48.0;
  // px per scenario: roomy bars for a few scenarios, 20 px (a label's height) for many.
  const double row_height = std::clamp(240.0 / static_cast<double>(n), 20.0, 40.0);
  const double bar_rows = static_cast<double>(n) * row_height;
  const double block = title + bar_rows + axis;
  const int width = kFigureWidth;
  const int height = static_cast<int>(std::lround(rows * block + 12.0));
  const double column_width = (width - left - right - gap * (cols - 1)) / cols;

  std::ostringstream d;
  for (size_t i = 0; i < n; ++i) {
    d << i;
    for (int k : terms) {
      d << ' ' << DataNumber(data.comparison[i].initial[k]) << ' '
        << DataNumber(data.comparison[i].best[k]);
    }
    d << '\n';
  }
  char caption[600];
  std::snprintf(caption, sizeof caption,
                "Figure 3: best against initial per scenario, %s: initial "
                "<span style=\"color:%s\">&#9632;</span> above best "
                "<span style=\"color:%s\">&#9632;</span>; the job minimises the weighted "
                "terms, so shorter is better.",
                terms.size() == 1 ? "the term" : "one panel per term", kInitialColor, kBestColor);
  const size_t k = figures->Begin(width, height, caption, "best against initial per scenario");
  const std::string data_file = figures->AddData(d.str());
  std::ostringstream& s = figures->script();
  std::ostringstream ytics;
  ytics << "set ytics noenhanced (";
  for (size_t i = 0; i < n; ++i)
    ytics << (i == 0 ? "" : ", ") << GnuplotQuote(labels[i]) << ' ' << i;
  ytics << ")\n";
  s << "unset key\nset multiplot\nset grid xtics noytics\nset style fill solid 1.0 noborder\n"
    << "set yrange [" << static_cast<double>(n) - 0.5 << ":-0.5]\nset format x '%g'\n";
  for (size_t t = 0; t < terms.size(); ++t) {
    const int term = terms[t];
    const int r = static_cast<int>(t) / cols, c = static_cast<int>(t) % cols;
    const double x0 = left + c * (column_width + gap), x1 = x0 + column_width;
    const double y0 = r * block + title, y1 = y0 + bar_rows;
    double lo = 0.0, hi = 0.0;
    for (const ComparisonRow& row : data.comparison) {
      for (double v : {row.initial[term], row.best[term]}) {
        if (std::isfinite(v)) {
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
      }
    }
    if (hi == lo) hi = lo + 1.0;  // all zero: an axis from 0 to 1
    const double span = hi - lo;
    const double x_lo = lo < 0.0 ? lo - 0.05 * span : 0.0, x_hi = hi > 0.0 ? hi + 0.05 * span : 0.0;
    const double w = TermWeight(weights, term);
    const std::string name = std::string(kTermNames[term]) +
                             (std::isfinite(w) ? " (weight " + Format("%g", w) + ")" : "");
    const int ci = 2 + 2 * static_cast<int>(t), cb = ci + 1;
    s << "set lmargin at screen " << DataNumber(x0 / width) << "\nset rmargin at screen "
      << DataNumber(x1 / width) << "\nset tmargin at screen " << DataNumber(1.0 - y0 / height)
      << "\nset bmargin at screen " << DataNumber(1.0 - y1 / height) << "\nset title "
      << GnuplotQuote(name) << " noenhanced\nset xrange [" << DataNumber(x_lo) << ':'
      << DataNumber(x_hi) << "]\n"
      << (c == 0 ? ytics.str() : "set ytics 1 format ''\n")
      // x y xlow xhigh ylow yhigh: the initial bar in the upper half of the scenario's row.
      << "plot " << data_file << " using (0):($1-0.2):(0):" << ci
      << ":($1-0.4):($1-0.02) with boxxyerror lc rgb '" << kInitialColor << "', \\\n  " << data_file
      << " using (0):($1+0.2):(0):" << cb << ":($1+0.02):($1+0.4) with boxxyerror lc rgb '"
      << kBestColor << "'\n";
  }
  s << "unset multiplot\n";
  return k;
}

}  // namespace rabbit::tune_report_internal
