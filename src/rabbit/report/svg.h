// Self-contained SVG figures for the HTML reports: stick diagrams of a walk (as the chapter's
// figures 8, 12, 14, 15) and simple line plots. No plotting dependency: the pages open anywhere.
#ifndef RABBIT_REPORT_SVG_H_
#define RABBIT_REPORT_SVG_H_

#include <string>
#include <vector>

#include "rabbit/contact/terrain.h"
#include "rabbit/model/model.h"
#include "rabbit/sim/simulator.h"

namespace rabbit {

// The robot drawn every `every` seconds over [t0, t1] of a run, on the ground and obstacles.
std::string StickDiagramSvg(const Model& model, const std::vector<SimSample>& samples,
                            const Terrain& terrain, double t0, double t1, double every);

struct PlotSeries {
  std::string name;
  std::vector<double> x, y;
};

// A line plot with axes, ticks and a legend.
std::string LinePlotSvg(const std::string& title, const std::string& x_label,
                        const std::string& y_label, const std::vector<PlotSeries>& series);

// Escapes &, <, > and quotes for HTML text.
std::string HtmlEscape(const std::string& text);

}  // namespace rabbit

#endif  // RABBIT_REPORT_SVG_H_
