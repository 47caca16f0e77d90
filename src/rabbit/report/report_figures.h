// The report's figures: the time windows they show, and the gnuplot scripts of the stick
// diagrams, the per-step V_d / V_M / L_step plot, the joint tracking and the fuzzy weights, all
// collected in one FigureSet and rendered by one gnuplot process. Implementation details of
// WriteSuiteReport (suite_report.h); the tuning report (tune_report.h) draws its
// figures with FigureSet too.
#ifndef RABBIT_REPORT_REPORT_FIGURES_H_
#define RABBIT_REPORT_REPORT_FIGURES_H_

#include <cstddef>
#include <sstream>
#include <string>
#include <vector>

#include "rabbit/contact/terrain.h"
#include "rabbit/report/comparison.h"
#include "rabbit/report/gnuplot.h"
#include "rabbit/report/push_survival.h"
#include "rabbit/report/report_data.h"
#include "rabbit/report/suite_report.h"

namespace rabbit {
namespace report_internal {

// ---------------------------------------------------------------------------------------------
// Windows of a run.

struct Window {
  double t0 = 0.0, t1 = 0.0;
  std::string what;
};

// A window of `width` seconds within the run: centred on the first obstacle (when the hip reaches
// its middle; else the last window), or the start, or the end. tr must not be empty.
Window StartWindow(const Trajectory& tr, double width);
Window LastWindow(const Trajectory& tr, double width);
Window ObstacleWindow(const Trajectory& tr, const Obstacle& o, double width);
// Centred where the hip reaches x (the ground profile's first breakpoint), else the last window.
Window SlopeWindow(const Trajectory& tr, double x, double width);

// ---------------------------------------------------------------------------------------------
// Figures: gnuplot scripts, all rendered by one process.

struct Figure {
  std::string caption;
  std::string alt;
  int width = 0, height = 0;
  std::string html;  // filled after rendering
};

class FigureSet {
 public:
  explicit FigureSet(const SuiteReportOptions& options) : options_(options) {}

  // Starts a figure; returns its index. The caller appends its commands to script().
  size_t Begin(int width, int height, const std::string& caption, const std::string& alt);
  std::ostringstream& script() { return script_; }
  // Adds a data file for the current figure and returns its (quoted) name.
  std::string AddData(const std::string& contents);
  size_t size() const { return figures_.size(); }
  const Figure& figure(size_t k) const { return figures_[k]; }

  // Renders every figure; false (and *error) when gnuplot could not.
  bool Render(std::string* error);

 private:
  const SuiteReportOptions& options_;
  std::vector<Figure> figures_;
  GnuplotJob job_;
  std::ostringstream script_;
};

size_t StickDiagramFigure(const RunData& run, const Window& w, const SuiteReportOptions& options,
                          FigureSet* figures);

// The chapter's figures 13 and 16: V_d, V_M and L_step against the step index, per variant
// (runs: the main variant first, each with steps).
size_t StepsFigure(const std::vector<const RunData*>& runs, bool with_obstacles,
                   const SuiteReportOptions& options, FigureSet* figures);

// Swing hip, swing knee and trunk: reference (dashed) against actual, coloured by the swing leg.
size_t TrackingFigure(const RunData& run, const Window& w, const SuiteReportOptions& options,
                      FigureSet* figures);

// The fuzzy system's per-gait weights w_Ok of every step, stacked (they sum to 1).
size_t WeightsFigure(const RunData& run, const SuiteReportOptions& options, FigureSet* figures);

// The head-to-head of one group (its comparison rows, the main variant first), three panels with
// a bar per variant: the success rate with its 95% Wilson interval; the speed error and the cost
// of transport over completed runs, median (bar) and mean (diamond).
size_t GroupComparisonFigure(const std::vector<const VariantComparison*>& variants,
                             const SuiteReportOptions& options, FigureSet* figures);

// Every group's success rate per variant (bars side by side) with the Wilson intervals.
size_t OverviewComparisonFigure(const std::vector<VariantComparison>& rows,
                                const SuiteReportOptions& options, FigureSet* figures);

// Survival against push impulse of one family (its push_survival.csv rows, push_survival.h): the
// success rate per impulse bin against the signed impulse, a line per variant with its 95% Wilson
// intervals. bins must not be empty.
size_t PushSurvivalFigure(const std::vector<const SurvivalBin*>& bins,
                          const SuiteReportOptions& options, FigureSet* figures);

}  // namespace report_internal
}  // namespace rabbit

#endif  // RABBIT_REPORT_REPORT_FIGURES_H_
