// The tuning report's parts (tune_report.h): what the job wrote, read strictly
// (tune_report_data.cc), its figures (tune_report_figures.cc) and the page (tune_report.cc).
#ifndef RABBIT_REPORT_TUNE_REPORT_DATA_H_
#define RABBIT_REPORT_TUNE_REPORT_DATA_H_

#include <array>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/report/report_figures.h"

namespace rabbit::tune_report_internal {

using report_internal::FigureSet;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
// The objective the tuner gives an invalid candidate; anything at or above it is left out of the
// convergence plot (it would flatten every real objective against the axis).
constexpr double kInvalidObjective = 1e6;
// Beyond this many evaluations the log is collapsed (the page stays quick to scroll).
constexpr size_t kOpenLogRows = 200;
constexpr int kFigureWidth = 1000;  // px, as the batch report's default

constexpr int kTerms = 7;
const char* const kTermNames[kTerms] = {"failure_rate",   "speed_error",       "step_length_spread",
                                        "energy",         "cost_of_transport", "saturation_time",
                                        "incomplete_rate"};
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
  std::string guards;  // the guard suites, ";"-joined (empty: none, or a log from before guards)
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
  int guards_run = -1;       // 1, 0, or -1: the log has no guard columns
  std::string guard_broken;  // the required guard scenarios it failed (empty: kept, or not run)
  bool broke_guard() const { return guards_run == 1 && !guard_broken.empty(); }
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

// Reads the job's files in root (tune_report.h); throws InputError naming the file, line and
// column.
TuneData ReadTuneData(const std::filesystem::path& root);

// ---------------------------------------------------------------------------------------------
// Shared by the figures and the page.

const Evaluation* FindEval(const TuneData& data, const std::optional<int>& eval);
// `failure_rate=10;speed_error=1` as (term, weight) in order; pairs that do not parse are
// skipped (the page shows the text verbatim anyway).
std::vector<std::pair<std::string, double>> ParseWeights(const std::string& text);
// The weight of term k, NaN when the weights do not name it.
double TermWeight(const std::vector<std::pair<std::string, double>>& weights, int k);
// The distinct search starts in order of first appearance; their colours follow this order.
std::vector<int> Starts(const std::vector<Evaluation>& evaluations);
const char* StartColor(const std::vector<int>& starts, int start);
std::string Format(const char* format, double v);
// A number for gnuplot's data files and scripts (NaN for missing and infinite values).
std::string DataNumber(double v);
// A number on the page: `sig` significant digits, a dash when missing, infinity spelled out.
std::string Cell(double v, int sig = 6);
// A range [lo, hi] with some room around the values, never empty (one value, or all equal).
std::pair<double, double> Padded(double lo, double hi);
// Integer tics over the evaluation axis (a fraction of an evaluation means nothing), about
// `tics` of them: fewer on a small panel, where their labels would run into each other.
std::string EvalAxis(int lo, int hi, double tics);
// A scenario's label: with its suite when the comparison spans several suites.
std::vector<std::string> ScenarioLabels(const std::vector<ComparisonRow>& rows);

// ---------------------------------------------------------------------------------------------
// Figures (tune_report_figures.cc), queued on one FigureSet; each returns its index there, or
// nothing when it has nothing to show.

struct ConvergenceInfo {
  std::vector<int> left_out;  // evaluations not plotted (invalid)
  bool log_y = false;
  double decades = 0.0;
};

// Figure 1: every valid objective as a point, coloured by its search start, the best so far as a
// line, the initial and best candidates marked.
std::optional<size_t> ConvergenceFigure(const TuneData& data, ConvergenceInfo* info,
                                        FigureSet* figures);
// Figure 2: the parameter traces.
std::optional<size_t> TracesFigure(const TuneData& data, FigureSet* figures);
// The terms figure 3 shows: the weighted ones the comparison has values for; else every term it
// has values for (weights that name no term, or none at all).
std::vector<int> ShownTerms(const TuneData& data);
// Figure 3: per scenario, horizontal bars of each shown term, initial above best.
std::optional<size_t> ComparisonFigure(const TuneData& data, const std::vector<int>& terms,
                                       FigureSet* figures);

}  // namespace rabbit::tune_report_internal

#endif  // RABBIT_REPORT_TUNE_REPORT_DATA_H_
