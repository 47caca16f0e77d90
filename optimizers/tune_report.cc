// The tuning job's report page (tune_report.h): the job's CSV files read strictly (every error
// names the file, line and column), three gnuplot figures rendered by the batch report's
// FigureSet (one gnuplot process, SVG as data: images), and the page around them.
#include "tune_report.h"

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

namespace rabbit {
namespace {

namespace fs = std::filesystem;

using report_internal::FigureSet;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
// The objective the tuner gives an invalid candidate; anything at or above it is left out of the
// convergence plot (it would flatten every real objective against the axis).
constexpr double kInvalidObjective = 1e6;
// Beyond this many evaluations the log is collapsed (the page stays quick to scroll).
constexpr size_t kOpenLogRows = 200;
constexpr int kFigureWidth = 1000;  // px, as the batch report's default

constexpr int kTerms = 6;
const char* const kTermNames[kTerms] = {"failure_rate", "speed_error",       "step_length_spread",
                                        "energy",       "cost_of_transport", "saturation_time"};
using Terms = std::array<double, kTerms>;

// Search starts, in the order of their first appearance (tab10, as matplotlib's default).
const char* const kStartColors[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                    "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
constexpr size_t kNumStartColors = sizeof kStartColors / sizeof kStartColors[0];
const char* const kInitialColor = "#b3b3b3";
const char* const kBestColor = "#1f77b4";
const char* const kInvalidColor = "#9a9a9a";

// ---------------------------------------------------------------------------------------------
// What the job wrote.

struct Meta {
  std::string job, description, job_file, algorithm, seed, starts, max_evaluations, form, weights,
      suites, evaluations, fingerprint;
  std::optional<int> initial_eval, best_eval;
  double initial_objective = kNan, best_objective = kNan;
  bool complete = false;
};

struct Evaluation {
  int line = 0;
  int eval = 0, round = 0, start = 0, seq = 0, runs = 0, failed = 0;
  double objective = kNan, wall = kNan;
  Terms terms{};
  std::vector<double> params;  // in parameters.csv's order
  std::string error;
  // An error, or the tuner's penalty objective (or none at all): not a point of the search.
  bool invalid() const { return !error.empty() || !(objective < kInvalidObjective); }
};

struct Parameter {
  std::string path;
  double lower = kNan, upper = kNan, initial = kNan, best = kNan;
};

struct ComparisonRow {
  std::string suite, scenario;
  int initial_passed = -1, best_passed = -1;  // 1, 0, or -1: not known
  Terms initial{}, best{};
};

// Outcomes of the runs of one candidate, per (suite, scenario), in file order.
using Outcomes = std::map<std::pair<std::string, std::string>, std::vector<std::string>>;

struct TuneData {
  Meta meta;
  std::vector<Parameter> parameters;
  std::vector<Evaluation> evaluations;  // in file (evaluation) order
  std::vector<ComparisonRow> comparison;
  Outcomes initial_outcomes, best_outcomes;
  std::optional<std::string> best_toml;  // absent when the job has not written it
};

// 1/0 (or true/false); -1 for an allowed missing value (empty or nan).
int ReadFlag(const CsvTable& table, size_t row, size_t column, bool allow_missing) {
  const std::string text = table.Text(row, column);
  if (text == "1" || text == "true") return 1;
  if (text == "0" || text == "false") return 0;
  if (allow_missing && (text.empty() || text == "nan")) return -1;
  throw InputError(table.file(), table.line(row), table.header()[column],
                   "expected 1 or 0, got \"" + text + "\"");
}

Terms ReadTerms(const CsvTable& table, size_t row, const std::array<size_t, kTerms>& columns) {
  Terms terms{};
  for (int k = 0; k < kTerms; ++k) {
    terms[k] = table.Number(row, columns[k], CsvNumber::kFiniteOrNan);
  }
  return terms;
}

std::array<size_t, kTerms> TermColumns(const CsvTable& table, const std::string& prefix) {
  std::array<size_t, kTerms> columns{};
  for (int k = 0; k < kTerms; ++k) columns[k] = table.Column(prefix + kTermNames[k]);
  return columns;
}

Meta ReadMeta(const std::string& path) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_key = table.Column("key"), c_value = table.Column("value");
  Meta meta;
  std::map<std::string, size_t> rows;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    const std::string key = table.Text(r, c_key);
    const auto [it, inserted] = rows.emplace(key, r);
    if (!inserted) {
      throw InputError(path, table.line(r), "key",
                       "\"" + key + "\" also on line " + std::to_string(table.line(it->second)));
    }
  }
  auto row_of = [&](const std::string& key) {
    const auto it = rows.find(key);
    if (it == rows.end()) throw InputError(path, 0, key, "missing key");
    return it->second;
  };
  auto text = [&](const std::string& key) { return table.Text(row_of(key), c_value); };
  // An evaluation number, or none yet (empty or nan: a job stopped before its first candidate).
  auto eval = [&](const std::string& key) -> std::optional<int> {
    const size_t r = row_of(key);
    const std::string t = table.Text(r, c_value);
    if (t.empty() || t == "nan") return std::nullopt;
    return table.Integer(r, c_value);
  };
  auto number = [&](const std::string& key) {
    return table.Number(row_of(key), c_value, CsvNumber::kFiniteOrNan);
  };
  meta.job = text("job");
  meta.description = text("description");
  meta.job_file = text("job_file");
  meta.algorithm = text("algorithm");
  meta.seed = text("seed");
  meta.starts = text("starts");
  meta.max_evaluations = text("max_evaluations");
  meta.form = text("form");
  meta.weights = text("weights");
  meta.suites = text("suites");
  meta.evaluations = text("evaluations");
  meta.fingerprint = text("fingerprint");
  meta.initial_eval = eval("initial_eval");
  meta.best_eval = eval("best_eval");
  meta.initial_objective = number("initial_objective");
  meta.best_objective = number("best_objective");
  const std::string complete = text("complete");
  if (complete != "true" && complete != "false") {
    throw InputError(path, table.line(row_of("complete")), "complete",
                     "expected true or false, got \"" + complete + "\"");
  }
  meta.complete = complete == "true";
  return meta;
}

std::vector<Parameter> ReadParameters(const std::string& path) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_path = table.Column("path"), c_lower = table.Column("lower"),
               c_upper = table.Column("upper"), c_initial = table.Column("initial"),
               c_best = table.Column("best");
  std::vector<Parameter> out;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    Parameter p;
    p.path = table.Text(r, c_path);
    if (p.path.empty()) throw InputError(path, table.line(r), "path", "empty parameter path");
    for (const Parameter& seen : out) {
      if (seen.path == p.path) {
        throw InputError(path, table.line(r), "path", "parameter \"" + p.path + "\" repeated");
      }
    }
    // Unbounded sides may be written as inf; a job stopped before its first candidate has no
    // best yet.
    p.lower = table.Number(r, c_lower, CsvNumber::kAny);
    p.upper = table.Number(r, c_upper, CsvNumber::kAny);
    p.initial = table.Number(r, c_initial, CsvNumber::kFiniteOrNan);
    p.best = table.Number(r, c_best, CsvNumber::kFiniteOrNan);
    if (p.lower > p.upper) {
      throw InputError(path, table.line(r), "upper", "the upper bound is below the lower");
    }
    out.push_back(std::move(p));
  }
  return out;
}

std::vector<Evaluation> ReadEvaluations(const std::string& path,
                                        const std::vector<Parameter>& parameters) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_eval = table.Column("eval"), c_round = table.Column("round"),
               c_start = table.Column("start"), c_seq = table.Column("seq"),
               c_objective = table.Column("objective"), c_runs = table.Column("runs"),
               c_failed = table.Column("failed"), c_error = table.Column("error"),
               c_wall = table.Column("wall_s");
  const std::array<size_t, kTerms> c_terms = TermColumns(table, "");
  std::vector<size_t> c_params;
  for (const Parameter& p : parameters) c_params.push_back(table.Column(p.path));
  std::vector<Evaluation> out;
  std::map<int, int> lines;  // eval -> its line
  for (size_t r = 0; r < table.num_rows(); ++r) {
    Evaluation e;
    e.line = table.line(r);
    e.eval = table.Integer(r, c_eval);
    const auto [it, inserted] = lines.emplace(e.eval, e.line);
    if (!inserted) {
      throw InputError(
          path, e.line, "eval",
          "evaluation " + std::to_string(e.eval) + " also on line " + std::to_string(it->second));
    }
    e.round = table.Integer(r, c_round);
    e.start = table.Integer(r, c_start);
    e.seq = table.Integer(r, c_seq);
    e.objective = table.Number(r, c_objective, CsvNumber::kAny);
    e.terms = ReadTerms(table, r, c_terms);
    e.runs = table.Integer(r, c_runs);
    e.failed = table.Integer(r, c_failed);
    for (size_t c : c_params) e.params.push_back(table.Number(r, c, CsvNumber::kFiniteOrNan));
    e.error = table.Text(r, c_error);
    e.wall = table.Number(r, c_wall, CsvNumber::kFiniteOrNan);
    out.push_back(std::move(e));
  }
  return out;
}

// runs.csv, checked whole; the outcomes of the initial and best candidates are kept.
void ReadRuns(const std::string& path, const std::set<int>& evals, const Meta& meta,
              TuneData* data) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_eval = table.Column("eval"), c_suite = table.Column("suite"),
               c_scenario = table.Column("scenario"), c_passed = table.Column("passed"),
               c_outcome = table.Column("outcome");
  const std::array<size_t, kTerms> c_terms = TermColumns(table, "");
  for (size_t r = 0; r < table.num_rows(); ++r) {
    const int eval = table.Integer(r, c_eval);
    if (evals.count(eval) == 0) {
      throw InputError(path, table.line(r), "eval",
                       "evaluation " + std::to_string(eval) + " is not in evaluations.csv");
    }
    ReadFlag(table, r, c_passed, false);
    ReadTerms(table, r, c_terms);
    const std::pair<std::string, std::string> key{table.Text(r, c_suite),
                                                  table.Text(r, c_scenario)};
    const std::string outcome = table.Text(r, c_outcome);
    if (meta.initial_eval && eval == *meta.initial_eval) {
      data->initial_outcomes[key].push_back(outcome);
    }
    if (meta.best_eval && eval == *meta.best_eval) data->best_outcomes[key].push_back(outcome);
  }
}

std::vector<ComparisonRow> ReadComparison(const std::string& path) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_suite = table.Column("suite"), c_scenario = table.Column("scenario"),
               c_initial_passed = table.Column("initial_passed"),
               c_best_passed = table.Column("best_passed");
  const std::array<size_t, kTerms> c_initial = TermColumns(table, "initial_"),
                                   c_best = TermColumns(table, "best_");
  std::vector<ComparisonRow> out;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    ComparisonRow row;
    row.suite = table.Text(r, c_suite);
    row.scenario = table.Text(r, c_scenario);
    row.initial_passed = ReadFlag(table, r, c_initial_passed, true);
    row.best_passed = ReadFlag(table, r, c_best_passed, true);
    row.initial = ReadTerms(table, r, c_initial);
    row.best = ReadTerms(table, r, c_best);
    out.push_back(std::move(row));
  }
  return out;
}

TuneData ReadTuneData(const fs::path& root) {
  TuneData data;
  const std::string meta_path = (root / "meta.csv").string();
  data.meta = ReadMeta(meta_path);
  data.parameters = ReadParameters((root / "parameters.csv").string());
  data.evaluations = ReadEvaluations((root / "evaluations.csv").string(), data.parameters);
  std::set<int> evals;
  for (const Evaluation& e : data.evaluations) evals.insert(e.eval);
  for (const auto& [key, value] :
       {std::pair<const char*, std::optional<int>>{"initial_eval", data.meta.initial_eval},
        {"best_eval", data.meta.best_eval}}) {
    if (value && evals.count(*value) == 0) {
      throw InputError(meta_path, 0, key,
                       "evaluation " + std::to_string(*value) + " is not in evaluations.csv");
    }
  }
  ReadRuns((root / "runs.csv").string(), evals, data.meta, &data);
  data.comparison = ReadComparison((root / "comparison.csv").string());
  std::ifstream toml(root / "best.toml", std::ios::binary);
  if (toml) {
    std::ostringstream text;
    text << toml.rdbuf();
    data.best_toml = text.str();
  }
  return data;
}

// ---------------------------------------------------------------------------------------------
// Shared by the figures and the page.

const Evaluation* FindEval(const TuneData& data, const std::optional<int>& eval) {
  if (!eval) return nullptr;
  for (const Evaluation& e : data.evaluations) {
    if (e.eval == *eval) return &e;
  }
  return nullptr;
}

// `failure_rate=10;speed_error=1` as (term, weight) in order; pairs that do not parse are
// skipped (the page shows the text verbatim anyway).
std::vector<std::pair<std::string, double>> ParseWeights(const std::string& text) {
  std::vector<std::pair<std::string, double>> out;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ';')) {
    const size_t eq = item.find('=');
    if (eq == std::string::npos) continue;
    const std::string name = Trim(item.substr(0, eq)), value = Trim(item.substr(eq + 1));
    char* end = nullptr;
    const double w = std::strtod(value.c_str(), &end);
    if (name.empty() || value.empty() || *end != '\0' || !std::isfinite(w)) continue;
    out.emplace_back(name, w);
  }
  return out;
}

// The weight of term k, NaN when the weights do not name it.
double TermWeight(const std::vector<std::pair<std::string, double>>& weights, int k) {
  for (const auto& [name, w] : weights) {
    if (name == kTermNames[k]) return w;
  }
  return kNan;
}

// The distinct search starts in order of first appearance; their colours follow this order.
std::vector<int> Starts(const std::vector<Evaluation>& evaluations) {
  std::vector<int> out;
  for (const Evaluation& e : evaluations) {
    if (std::find(out.begin(), out.end(), e.start) == out.end()) out.push_back(e.start);
  }
  return out;
}

const char* StartColor(const std::vector<int>& starts, int start) {
  const size_t k = std::find(starts.begin(), starts.end(), start) - starts.begin();
  return kStartColors[k % kNumStartColors];
}

std::string Format(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

// A number for gnuplot's data files and scripts (NaN for missing and infinite values).
std::string DataNumber(double v) { return std::isfinite(v) ? Format("%.10g", v) : "NaN"; }

// A number on the page: `sig` significant digits, a dash when missing, infinity spelled out.
std::string Cell(double v, int sig = 6) {
  if (std::isnan(v)) return "&ndash;";
  if (std::isinf(v)) return v > 0 ? "&infin;" : "&minus;&infin;";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", sig, v);
  return buffer;
}

// A range [lo, hi] with some room around the values, never empty (one value, or all equal).
std::pair<double, double> Padded(double lo, double hi) {
  if (!(hi > lo)) {
    const double pad = lo != 0.0 ? 0.1 * std::abs(lo) : 1.0;
    return {lo - pad, hi + pad};
  }
  const double pad = 0.06 * (hi - lo);
  return {lo - pad, hi + pad};
}

// Integer tics over the evaluation axis (a fraction of an evaluation means nothing), about
// `tics` of them: fewer on a small panel, where their labels would run into each other.
std::string EvalAxis(int lo, int hi, double tics) {
  // In doubles: evaluation numbers of both signs near the int limits would overflow.
  const double span = std::max(1.0, static_cast<double>(hi) - static_cast<double>(lo));
  const double raw = span / tics, mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  const double step = std::max(1.0, (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * mag);
  const double pad = std::max(0.6, 0.02 * span);
  std::ostringstream s;
  s << "set xrange [" << DataNumber(lo - pad) << ':' << DataNumber(hi + pad) << "]\nset xtics "
    << DataNumber(step) << "\nset format x '%.0f'\nunset mxtics\n";
  return s.str();
}

// A scenario's label: with its suite when the comparison spans several suites.
std::vector<std::string> ScenarioLabels(const std::vector<ComparisonRow>& rows) {
  std::set<std::string> suites;
  for (const ComparisonRow& r : rows) suites.insert(r.suite);
  std::vector<std::string> out;
  for (const ComparisonRow& r : rows) {
    out.push_back(suites.size() > 1 ? r.suite + "/" + r.scenario : r.scenario);
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Figures.

struct ConvergenceInfo {
  std::vector<int> left_out;  // evaluations not plotted (invalid)
  bool log_y = false;
  double decades = 0.0;
};

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

// ---------------------------------------------------------------------------------------------
// The page.

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
  const std::pair<const char*, std::string> rows[] = {
      {"algorithm", "<code>" + HtmlEscape(m.algorithm) + "</code>"},
      {"seed", HtmlEscape(m.seed)},
      {"starts", HtmlEscape(m.starts)},
      {"budget", budget.str()},
      {"objective form", "<code>" + HtmlEscape(m.form) + "</code>"},
      {"weights", weights},
      {"suites", suites},
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
  table << "<th>wall<br>s</th><th>error</th></tr></thead><tbody>\n";
  const std::vector<int> starts = Starts(data.evaluations);
  double best_so_far = std::numeric_limits<double>::infinity();
  for (const Evaluation& e : data.evaluations) {
    const bool is_best = data.meta.best_eval && e.eval == *data.meta.best_eval;
    // In evaluation order, as the search saw them (the convergence plot's black line).
    const bool improved = !e.invalid() && std::isfinite(e.objective) && e.objective < best_so_far;
    if (improved) best_so_far = e.objective;
    table << "<tr id=\"eval-" << e.eval << "\""
          << (is_best       ? " class=\"best\""
              : e.invalid() ? " class=\"invalid\""
                            : "")
          << "><td>" << e.eval << "</td><td>" << e.round << "</td><td><span class=\"swatch\" "
          << "style=\"background:" << StartColor(starts, e.start) << "\"></span>" << e.start
          << "</td><td>" << e.seq << "</td><td class=\"num\">" << Cell(e.objective) << "</td><td>"
          << (improved ? "&#9660;" : "") << "</td>";
    for (int k : terms) table << "<td class=\"num\">" << Cell(e.terms[k], 4) << "</td>";
    table << "<td>" << e.runs << "</td><td>" << e.failed << "</td>";
    for (double v : e.params) table << "<td class=\"num\">" << Cell(v) << "</td>";
    table << "<td class=\"num\">" << Cell(e.wall, 3) << "</td><td class=\"error\">"
          << HtmlEscape(e.error) << "</td></tr>\n";
  }
  table << "</tbody></table></div>\n";
  std::ostringstream html;
  html << "<p class=\"note\">Every candidate in evaluation order; &#9660; marks a new best so far, "
          "the best candidate is in bold, invalid candidates in red.</p>\n";
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
