// What a tuning job wrote (tune_report_data.h), read strictly: every error names the file, line
// and column.
#include "rabbit/report/tune_report_data.h"

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
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/io/key_value_csv.h"
#include "rabbit/report/gnuplot.h"
#include "rabbit/report/report_figures.h"
#include "rabbit/report/report_page.h"
#include "rabbit/report/suite_report.h"
#include "rabbit/report/svg.h"
#include "rabbit/report/tune_report_data.h"

namespace rabbit::tune_report_internal {

namespace fs = std::filesystem;

namespace {

constexpr size_t kNoColumn = static_cast<size_t>(-1);

Terms ReadTerms(const CsvTable& table, size_t row, const std::array<size_t, kTerms>& columns) {
  Terms terms{};
  for (int k = 0; k < kTerms; ++k) {
    terms[k] =
        columns[k] == kNoColumn ? kNan : table.Number(row, columns[k], CsvNumber::kFiniteOrNan);
  }
  return terms;
}

std::array<size_t, kTerms> TermColumns(const CsvTable& table, const std::string& prefix) {
  std::array<size_t, kTerms> columns{};
  for (int k = 0; k < kTerms; ++k) {
    // incomplete_rate, the last term, came later: a log without it reads NaN there.
    const std::string name = prefix + kTermNames[k];
    columns[k] = k == kTerms - 1 && !table.HasColumn(name) ? kNoColumn : table.Column(name);
  }
  return columns;
}

Meta ReadMeta(const std::string& path) {
  const KeyValueCsv kv = KeyValueCsv::Read(path);
  Meta meta;
  auto text = [&](const std::string& key) { return kv.Text(key); };
  // An evaluation number, or none yet (empty or nan: a job stopped before its first candidate).
  auto eval = [&](const std::string& key) -> std::optional<int> {
    const std::string t = kv.Text(key);
    if (t.empty() || t == "nan") return std::nullopt;
    return kv.Integer(key);
  };
  auto number = [&](const std::string& key) { return kv.Number(key, CsvNumber::kFiniteOrNan); };
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
  if (kv.Has("guards")) meta.guards = text("guards");  // optional: older jobs
  meta.initial_eval = eval("initial_eval");
  meta.best_eval = eval("best_eval");
  meta.initial_objective = number("initial_objective");
  meta.best_objective = number("best_objective");
  const std::string complete = text("complete");
  if (complete != "true" && complete != "false") {
    throw InputError(path, kv.line("complete"), "complete",
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
  // Optional (a log from before guard suites): both or neither.
  std::optional<size_t> c_guards, c_broken;
  if (table.HasColumn("guards_run") || table.HasColumn("guard_broken")) {
    c_guards = table.Column("guards_run");
    c_broken = table.Column("guard_broken");
  }
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
    if (c_guards) {
      e.guards_run = table.Flag(r, *c_guards);
      e.guard_broken = table.Text(r, *c_broken);
    }
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
    table.Flag(r, c_passed);
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
    row.initial_passed = table.Flag(r, c_initial_passed, true);
    row.best_passed = table.Flag(r, c_best_passed, true);
    row.initial = ReadTerms(table, r, c_initial);
    row.best = ReadTerms(table, r, c_best);
    out.push_back(std::move(row));
  }
  return out;
}

}  // namespace

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
  if (fs::exists(root / "best.toml")) {  // optional: a job that has not finished has none
    data.best_toml = ReadBoundedFile((root / "best.toml").string(), kTomlFileLimits);
  }
  return data;
}

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
std::string Cell(double v, int sig) {
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

}  // namespace rabbit::tune_report_internal
