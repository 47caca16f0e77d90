// The report's figures (report_figures.h).
#include "rabbit/report/report_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>

#include "rabbit/report/svg.h"

namespace rabbit {
namespace report_internal {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
const char* const kLegColors[2] = {"#0072B2", "#D55E00"};  // leg 1, leg 2 (as in the replay script)
const char* const kTrunkColor = "#404040";
// Fuzzy weights w_O1, w_O2, ...: the reference gaits from slow to fast, eight steps of viridis
// (ordered, and readable with the common colour-vision deficiencies).
const char* const kWeightColors[] = {"#440154", "#46327e", "#365c8d", "#277f8e",
                                     "#1fa187", "#4ac16d", "#a0da39", "#fde725"};

std::string Printf(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

// A number for gnuplot's data files (NaN for missing and infinite values).
std::string DataNumber(double v) { return std::isfinite(v) ? Printf("%.7g", v) : "NaN"; }

std::string Base64(const std::string& data) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < data.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(data[i]) << 16 |
                       static_cast<unsigned char>(data[i + 1]) << 8 |
                       static_cast<unsigned char>(data[i + 2]);
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += kAlphabet[v >> 6 & 63];
    out += kAlphabet[v & 63];
  }
  if (i + 1 == data.size()) {
    const unsigned v = static_cast<unsigned char>(data[i]) << 16;
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += "==";
  } else if (i + 2 == data.size()) {
    const unsigned v =
        static_cast<unsigned char>(data[i]) << 16 | static_cast<unsigned char>(data[i + 1]) << 8;
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += kAlphabet[v >> 6 & 63];
    out += '=';
  }
  return out;
}

// The SVG element without the XML prolog, DOCTYPE and comments before it.
std::string StripSvgProlog(const std::string& svg) {
  const size_t start = svg.find("<svg");
  return start == std::string::npos ? svg : svg.substr(start);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Windows of a run.

Window StartWindow(const Trajectory& tr, double width) {
  return {tr.t.front(), std::min(tr.t.front() + width, tr.t.back()), "start"};
}

Window LastWindow(const Trajectory& tr, double width) {
  return {std::max(tr.t.front(), tr.t.back() - width), tr.t.back(), "end of the run"};
}

namespace {

// Centred on the first sample where the hip reaches x (else the last window).
Window WindowAtX(const Trajectory& tr, double x, double width, const std::string& what) {
  for (size_t j = 0; j < tr.t.size(); ++j) {
    if (tr.q[j][0] >= x) {
      double t0 = tr.t[j] - 0.5 * width;
      t0 = std::max(tr.t.front(), std::min(t0, tr.t.back() - width));
      return {t0, std::min(t0 + width, tr.t.back()), "around " + what};
    }
  }
  Window w = LastWindow(tr, width);
  w.what = "end of the run (the hip never reached " + what + ")";
  return w;
}

}  // namespace

Window ObstacleWindow(const Trajectory& tr, const Obstacle& o, double width) {
  return WindowAtX(tr, o.x_start + 0.5 * o.length, width, "the first obstacle");
}

Window SlopeWindow(const Trajectory& tr, double x, double width) {
  return WindowAtX(tr, x, width, "the first change of slope");
}

// ---------------------------------------------------------------------------------------------
// Figures.

size_t FigureSet::Begin(int width, int height, const std::string& caption, const std::string& alt) {
  const size_t k = figures_.size();
  figures_.push_back({caption, alt, width, height, ""});
  const std::string out = "fig" + std::to_string(k) + ".svg";
  job_.outputs.push_back(out);
  script_ << "reset\nset terminal svg size " << width << ',' << height
          << " dynamic enhanced font 'sans,11' background '#ffffff'\nset output '" << out
          << "'\nset encoding utf8\nset border 3 lw 1 lc rgb '#333333'\n"
             "set xtics nomirror out\nset ytics nomirror out\n"
             "set grid lw 1 lc rgb '#e6e6e6' dt 1\n"
             "set key opaque box lc rgb '#cccccc' samplen 2.5 spacing 1.1\n";
  return k;
}

std::string FigureSet::AddData(const std::string& contents) {
  const std::string name = "data" + std::to_string(job_.files.size()) + ".dat";
  job_.files.push_back({name, contents});
  return "'" + name + "'";
}

bool FigureSet::Render(std::string* error) {
  if (figures_.empty()) return true;
  job_.script = script_.str() + "unset output\n";
  const GnuplotResult result = RunGnuplot(options_.gnuplot, job_, options_.gnuplot_timeout);
  if (!result.ok) {
    *error = result.error;
    return false;
  }
  for (size_t k = 0; k < figures_.size(); ++k) {
    Figure& f = figures_[k];
    f.html = "<figure class=\"gp\"><img class=\"fig\" width=\"" + std::to_string(f.width) +
             "\" height=\"" + std::to_string(f.height) + "\" alt=\"" + HtmlEscape(f.alt) +
             "\" src=\"data:image/svg+xml;base64," + Base64(StripSvgProlog(result.outputs[k])) +
             "\"><figcaption>" + f.caption + "</figcaption></figure>\n";
  }
  return true;
}

// The chapter's figures 12, 14, 15: the robot every `every` seconds over a window of walking.
size_t StickDiagramFigure(const RunData& run, const Window& w, const SuiteReportOptions& options,
                          FigureSet* figures) {
  const Trajectory& tr = run.trajectory;
  std::ostringstream trunk, leg[2], path;
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_hi = 0.0;
  auto extend = [&](const StickPoint& p) {
    x_lo = std::min(x_lo, p.x);
    x_hi = std::max(x_hi, p.x);
    y_hi = std::max(y_hi, p.y);
  };
  size_t hint = 0;
  int frames = 0;
  const int count = static_cast<int>(std::floor((w.t1 - w.t0) / options.stick_every + 1e-9)) + 1;
  for (int k = 0; k < count; ++k) {
    const double t = w.t0 + k * options.stick_every;
    const StickFigure f = StickPoints(QAt(tr, t, &hint, nullptr), run.lengths);
    trunk << DataNumber(f.trunk_top.x) << ' ' << DataNumber(f.trunk_top.y) << '\n'
          << DataNumber(f.hip.x) << ' ' << DataNumber(f.hip.y) << "\n\n";
    for (int i = 0; i < 2; ++i) {
      leg[i] << DataNumber(f.hip.x) << ' ' << DataNumber(f.hip.y) << '\n'
             << DataNumber(f.knee[i].x) << ' ' << DataNumber(f.knee[i].y) << '\n'
             << DataNumber(f.foot[i].x) << ' ' << DataNumber(f.foot[i].y) << "\n\n";
      extend(f.knee[i]);
      extend(f.foot[i]);
    }
    extend(f.hip);
    extend(f.trunk_top);
    ++frames;
  }
  for (size_t j = 0; j < tr.t.size(); ++j) {
    if (tr.t[j] < w.t0 - 1e-9 || tr.t[j] > w.t1 + 1e-9) continue;
    path << DataNumber(tr.q[j][0]) << ' ' << DataNumber(tr.q[j][1]) << '\n';
  }
  x_lo -= 0.15;
  x_hi += 0.15;
  // The ground in the window: its vertices (the window's ends and the profile's breakpoints).
  const Terrain& terrain = run.terrain;
  const std::vector<Eigen::Vector2d> outline = terrain.ground.Outline(x_lo, x_hi);
  double ground_lo = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& p : outline) ground_lo = std::min(ground_lo, p.y());
  const double y_lo = ground_lo - 0.08;
  y_hi = std::max(y_hi, ground_lo + 0.5) + 0.08;
  // Equal scales on both axes, at most kPixelsPerMetre so that a short window is not blown up.
  const double kPixelsPerMetre = 300.0, kMarginX = 95.0, kMarginY = 80.0;
  const double scale = std::min(kPixelsPerMetre, (options.figure_width - kMarginX) / (x_hi - x_lo));
  const int width = static_cast<int>(std::lround((x_hi - x_lo) * scale + kMarginX));
  const int height = static_cast<int>(std::lround((y_hi - y_lo) * scale + kMarginY));
  char caption[400];
  std::snprintf(caption, sizeof caption,
                "Stick diagram, %s: t = %.2f&ndash;%.2f s, a figure every %.2f s (%d figures); "
                "leg 1 <span style=\"color:%s\">&#9632;</span>, leg 2 "
                "<span style=\"color:%s\">&#9632;</span>, trunk "
                "<span style=\"color:%s\">&#9632;</span>, hip path dotted.",
                w.what.c_str(), w.t0, w.t1, options.stick_every, frames, kLegColors[0],
                kLegColors[1], kTrunkColor);
  const size_t k =
      figures->Begin(width, height, caption, "stick diagram of " + run.row.run + ", " + w.what);
  std::ostringstream& s = figures->script();
  const std::string d_trunk = figures->AddData(trunk.str()),
                    d_leg1 = figures->AddData(leg[0].str()),
                    d_leg2 = figures->AddData(leg[1].str()), d_path = figures->AddData(path.str());
  s << "set size ratio -1\nset xrange [" << x_lo << ':' << x_hi << "]\nset yrange [" << y_lo << ':'
    << y_hi << "]\nset xlabel 'x (m)'\nset ylabel 'y (m)'\nunset grid\n"
    << "unset key\n";
  if (terrain.ground.is_flat_zero()) {
    s << "set object 1 rect from " << x_lo << ',' << y_lo << " to " << x_hi
      << ",0 fc rgb '#efe8dc' fs solid 1.0 noborder behind\n"
      << "set arrow 1 from " << x_lo << ",0 to " << x_hi
      << ",0 nohead lw 2 lc rgb '#555555' back\n";
  } else {
    s << "set object 1 polygon from " << x_lo << ',' << y_lo;
    for (const Eigen::Vector2d& p : outline) s << " to " << p.x() << ',' << p.y();
    s << " to " << x_hi << ',' << y_lo << " to " << x_lo << ',' << y_lo
      << " fc rgb '#efe8dc' fs solid 1.0 noborder behind\n";
    for (size_t i = 0; i + 1 < outline.size(); ++i) {
      s << "set arrow " << i + 1 << " from " << outline[i].x() << ',' << outline[i].y() << " to "
        << outline[i + 1].x() << ',' << outline[i + 1].y()
        << " nohead lw 2 lc rgb '#555555' back\n";
    }
  }
  int object = 2;
  for (size_t i = 0; i < terrain.obstacles.size(); ++i) {
    const Obstacle& o = terrain.obstacles[i];
    if (o.x_end() < x_lo || o.x_start > x_hi) continue;
    const double base = terrain.ObstacleBase(static_cast<int>(i));
    s << "set object " << object++ << " rect from " << o.x_start << ',' << base << " to "
      << o.x_end() << ',' << base + o.height
      << " fc rgb '#9a9a9a' fs solid 1.0 border lc rgb '#555555' behind\n";
  }
  s << "plot " << d_path << " with lines dt 3 lw 1.2 lc rgb '#888888' title 'hip path', \\\n  "
    << d_leg2 << " with lines lw 1.6 lc rgb '" << kLegColors[1] << "' title 'leg 2', \\\n  "
    << d_leg1 << " with lines lw 1.6 lc rgb '" << kLegColors[0] << "' title 'leg 1', \\\n  "
    << d_trunk << " with lines lw 2 lc rgb '" << kTrunkColor << "' title 'trunk'\n";
  return k;
}

size_t StepsFigure(const std::vector<const RunData*>& runs, bool with_obstacles,
                   const SuiteReportOptions& options, FigureSet* figures) {
  const RunData& main = *runs.front();
  // 64 bits: a step index may be INT_MAX in a hand-written steps.csv.
  std::int64_t step_lo = std::numeric_limits<std::int64_t>::max();
  std::int64_t step_hi = std::numeric_limits<std::int64_t>::min();
  for (const RunData* run : runs) {
    for (const Step& s : run->steps) {
      step_lo = std::min<std::int64_t>(step_lo, s.step);
      step_hi = std::max<std::int64_t>(step_hi, s.step);
    }
  }
  if (step_hi <= step_lo) step_hi = step_lo + 1;
  const int panels = with_obstacles ? 3 : 2;
  const int height = 170 + 190 * panels;
  const size_t k = figures->Begin(
      options.figure_width, height,
      "Per step: the desired velocity V<sub>d</sub> and the measured V<sub>M</sub> = "
      "L<sub>step</sub> / t<sub>step</sub> (top), the step length L<sub>step</sub>" +
          std::string(with_obstacles ? ", and the distance d<sub>obs</sub> to the next obstacle "
                                       "at each step (bottom)"
                                     : "") +
          ". Baselines overlaid.",
      "V_d, V_M and L_step per step");
  std::vector<std::string> data;
  for (const RunData* run : runs) {
    std::ostringstream d;
    for (const Step& s : run->steps) {
      // V_M is measured only when the leg's take-off was seen (t_step > 0).
      const double v_m = s.t_step > 0.0 ? s.v_m : kNan;
      d << s.step << ' ' << DataNumber(s.v_d) << ' ' << DataNumber(v_m) << ' '
        << DataNumber(s.l_step) << ' ' << DataNumber(s.d_obs) << '\n';
    }
    data.push_back(figures->AddData(d.str()));
  }
  std::ostringstream& s = figures->script();
  s << "set multiplot layout " << panels << ",1 margins 0.08,0.73,0.11,0.96 spacing 0,0.07\n"
    << "set xrange [" << static_cast<double>(step_lo) - 0.5 << ':'
    << static_cast<double>(step_hi) + 0.5 << "]\n"
    << "set key outside right top vertical\nset format x '%g'\n";
  // The main variant drawn last (on top of its baselines, which share its first steps); the key,
  // inverted, lists it first and the baselines in summary order.
  auto series = [&](int column, const char* what) {
    for (size_t v = runs.size(); v-- > 0;) {
      s << data[v] << " using 1:" << column << " with linespoints pt 7 ps 0.45 lw 1.4 lc rgb '"
        << VariantColor(runs[v]->row.variant) << "' title "
        << GnuplotQuote(std::string(what) + ", " + RunLabel(runs[v]->row)) << " noenhanced"
        << (v == 0 ? "" : ", \\\n  ");
    }
  };
  s << "set key invert\nset ylabel 'velocity (m/s)'\nunset xlabel\nplot ";
  series(3, "V_M");
  s << ", \\\n  " << data[0] << " using 1:2 with steps lw 1.6 dt 2 lc rgb '#000000' title "
    << GnuplotQuote("V_d, " + RunLabel(main.row)) << " noenhanced\n";
  s << "set ylabel 'L_{step} (m)'\n" << (panels == 2 ? "set xlabel 'step'\n" : "") << "plot ";
  series(4, "L_step");
  s << '\n';
  if (with_obstacles) {
    s << "set ylabel 'd_{obs} (m)'\nset xlabel 'step'\nset yrange [0:*]\nplot " << data[0]
      << " using 1:5 with linespoints pt 7 ps 0.45 lw 1.4 lc rgb '"
      << VariantColor(main.row.variant) << "' title "
      << GnuplotQuote("d_obs, " + RunLabel(main.row)) << " noenhanced\n";
  }
  s << "unset multiplot\n";
  return k;
}

size_t TrackingFigure(const RunData& run, const Window& w, const SuiteReportOptions& options,
                      FigureSet* figures) {
  const Tracking& tr = run.tracking;
  std::ostringstream d;
  int previous = -1;
  for (size_t j = 0; j < tr.t.size(); ++j) {
    if (tr.t[j] < w.t0 - 1e-9 || tr.t[j] > w.t1 + 1e-9) continue;
    const int swing = tr.stance[j] == 0 ? 0 : 3 - tr.stance[j];  // 0: no leg in support
    if (previous >= 0 && swing != previous) d << '\n';  // a support exchange breaks the lines
    previous = swing;
    auto actual = [&](double v, int leg) {
      return DataNumber(swing == leg ? v * kRadToDeg : kNan);
    };
    d << DataNumber(tr.t[j]) << ' ' << DataNumber(tr.hip_d[j] * kRadToDeg) << ' '
      << actual(tr.hip[j], 1) << ' ' << actual(tr.hip[j], 2) << ' '
      << DataNumber(tr.knee_d[j] * kRadToDeg) << ' ' << actual(tr.knee[j], 1) << ' '
      << actual(tr.knee[j], 2) << ' ' << DataNumber(tr.q0_d[j] * kRadToDeg) << ' '
      << DataNumber(tr.q0[j] * kRadToDeg) << '\n';
  }
  char caption[400];
  std::snprintf(caption, sizeof caption,
                "Joint tracking, %s (t = %.2f&ndash;%.2f s): the swing leg's hip and knee and the "
                "trunk pitch, reference (dashed) and actual, coloured by the leg that swings.",
                w.what.c_str(), w.t0, w.t1);
  const size_t k =
      figures->Begin(options.figure_width, 680, caption, "joint tracking of " + run.row.run);
  const std::string data = figures->AddData(d.str());
  std::ostringstream& s = figures->script();
  const std::string leg1 = std::string("lc rgb '") + kLegColors[0] + "'",
                    leg2 = std::string("lc rgb '") + kLegColors[1] + "'";
  s << "set multiplot layout 3,1 margins 0.08,0.73,0.09,0.97 spacing 0,0.06\n"
    << "set xrange [" << w.t0 << ':' << w.t1 << "]\nset key outside right top vertical\n"
    << "unset xlabel\nset ylabel 'swing hip (deg)'\n"
    << "plot " << data << " using 1:2 with lines dt 2 lw 1.5 lc rgb '#000000' title 'reference', "
    << data << " using 1:3 with lines lw 1.6 " << leg1 << " title 'leg 1 swinging', " << data
    << " using 1:4 with lines lw 1.6 " << leg2 << " title 'leg 2 swinging'\n"
    << "set ylabel 'swing knee (deg)'\n"
    << "plot " << data << " using 1:5 with lines dt 2 lw 1.5 lc rgb '#000000' title 'reference', "
    << data << " using 1:6 with lines lw 1.6 " << leg1 << " title 'leg 1 swinging', " << data
    << " using 1:7 with lines lw 1.6 " << leg2 << " title 'leg 2 swinging'\n"
    << "set ylabel 'trunk pitch q_0 (deg)'\nset xlabel 't (s)'\n"
    << "plot " << data << " using 1:8 with lines dt 2 lw 1.5 lc rgb '#000000' title 'q_0^d', "
    << data << " using 1:9 with lines lw 1.6 lc rgb '" << kTrunkColor << "' title 'q_0'\n"
    << "unset multiplot\n";
  return k;
}

size_t WeightsFigure(const RunData& run, const SuiteReportOptions& options, FigureSet* figures) {
  const size_t n = run.weight_names.size();
  std::ostringstream d;
  // 64 bits: a step index may be INT_MAX in a hand-written steps.csv.
  std::int64_t step_lo = std::numeric_limits<std::int64_t>::max();
  std::int64_t step_hi = std::numeric_limits<std::int64_t>::min();
  for (const Step& s : run.steps) {
    d << s.step;
    double sum = 0.0;
    for (size_t k = 0; k < n; ++k) {
      sum += std::isfinite(s.w[k]) ? s.w[k] : 0.0;
      d << ' ' << DataNumber(sum);
    }
    d << '\n';
    step_lo = std::min<std::int64_t>(step_lo, s.step);
    step_hi = std::max<std::int64_t>(step_hi, s.step);
  }
  const size_t k = figures->Begin(
      options.figure_width, 330,
      "Fuzzy-CMAC weights per step: w<sub>Ok</sub>, the share of reference gait O<sub>k</sub> in "
      "the gait pattern (eq. 12), stacked.",
      "fuzzy weights per step of " + run.row.run);
  const std::string data = figures->AddData(d.str());
  std::ostringstream& s = figures->script();
  s << "set xrange [" << static_cast<double>(step_lo) - 0.5 << ':'
    << static_cast<double>(step_hi) + 0.5 << "]\nset yrange [0:1.02]\n"
    << "set lmargin at screen 0.08\nset rmargin at screen 0.73\n"
    << "set key outside right top vertical\nset boxwidth 0.9 relative\n"
    << "set style fill solid 1.0 noborder\nset xlabel 'step'\nset ylabel 'weight w_{Ok}'\n"
    << "set grid noxtics\nplot ";
  // Topmost cumulative sum first, so that each lower one is drawn over it.
  for (size_t j = n; j-- > 0;) {
    s << (j + 1 == n ? "" : ", \\\n  ") << data << " using 1:" << j + 2 << " with boxes lc rgb '"
      << kWeightColors[j % std::size(kWeightColors)] << "' title "
      << GnuplotQuote(run.weight_names[j]) << " noenhanced";
  }
  s << '\n';
  return k;
}

// ---------------------------------------------------------------------------------------------
// The head-to-head.

namespace {

// A variant's colour as gnuplot's `lc rgb variable` takes it (0xRRGGBB).
long ColorNumber(const std::string& variant) {
  return std::strtol(VariantColor(variant).c_str() + 1, nullptr, 16);
}

// The upper end of a panel's y range: above the largest finite value, 1 when there is none.
double PanelTop(const std::vector<double>& values) {
  double top = 0.0;
  for (double v : values) {
    if (std::isfinite(v)) top = std::max(top, v);
  }
  return top > 0.0 ? 1.18 * top : 1.0;
}

}  // namespace

size_t GroupComparisonFigure(const std::vector<const VariantComparison*>& variants,
                             const SuiteReportOptions& options, FigureSet* figures) {
  const VariantComparison& first = *variants.front();
  const size_t k = figures->Begin(
      options.figure_width, 320,
      "Head-to-head, " + std::string(first.family ? "family " : "scenario ") +
          HtmlEscape(first.group) +
          ": success rate (passed / runs) with its 95% Wilson interval; the mean |V<sub>M</sub> "
          "&minus; V<sub>d</sub>| of a run and the cost of transport, over the completed runs: "
          "median (bar) and mean (&#9670;).",
      "head-to-head of " + first.group);
  std::ostringstream d, tics;
  std::vector<double> speed, cost;
  for (size_t v = 0; v < variants.size(); ++v) {
    const VariantComparison& c = *variants[v];
    d << v << ' ' << DataNumber(c.success_rate) << ' ' << DataNumber(c.ci.low) << ' '
      << DataNumber(c.ci.high) << ' ' << ColorNumber(c.variant) << ' '
      << DataNumber(c.speed_error_median) << ' ' << DataNumber(c.speed_error_mean) << ' '
      << DataNumber(c.cot_median) << ' ' << DataNumber(c.cot_mean) << '\n';
    tics << (v == 0 ? "" : ", ") << GnuplotQuote(VariantShortLabel(c.variant)) << ' ' << v;
    speed.insert(speed.end(), {c.speed_error_median, c.speed_error_mean});
    cost.insert(cost.end(), {c.cot_median, c.cot_mean});
  }
  const std::string data = figures->AddData(d.str());
  // Room for three bars at least, so that one or two are not drawn as wide as a panel.
  const double pad = 0.5 * std::max(0.0, 3.0 - static_cast<double>(variants.size()));
  std::ostringstream& s = figures->script();
  s << "set multiplot layout 1,3 margins 0.06,0.99," << (variants.size() > 3 ? "0.27" : "0.16")
    << ",0.88 spacing 0.07,0\n"
    << "set xrange [" << -0.6 - pad << ':' << static_cast<double>(variants.size()) - 0.4 + pad
    << "]\n"
    << "set xtics noenhanced (" << tics.str() << ")"
    << (variants.size() > 3 ? " rotate by -25" : "") << "\nset grid noxtics ytics\n"
    << "set style fill solid 0.85 border lc rgb '#555555'\nset boxwidth 0.6 absolute\n"
    << "unset key\nset yrange [0:1.05]\nset title 'success rate (95% Wilson interval)'\n"
    << "plot " << data << " using 1:2:5 with boxes lc rgb variable, " << data
    << " using 1:3:(0):($4-$3) with vectors heads size screen 0.012,90 lw 1.5 lc rgb '#222222'\n";
  auto panel = [&](const char* title, int median, int mean, double top) {
    s << "set title " << GnuplotQuote(title) << "\nset yrange [0:" << top << "]\n"
      << "plot " << data << " using 1:" << median << ":5 with boxes lc rgb variable, " << data
      << " using 1:" << mean << " with points pt 13 ps 1.3 lc rgb '#222222'\n";
  };
  panel("|V_M - V_d| (m/s), completed runs", 6, 7, PanelTop(speed));
  panel("cost of transport, completed runs", 8, 9, PanelTop(cost));
  s << "unset multiplot\n";
  return k;
}

size_t OverviewComparisonFigure(const std::vector<VariantComparison>& rows,
                                const SuiteReportOptions& options, FigureSet* figures) {
  // Groups in order, variants in order of first appearance over the groups.
  std::vector<std::pair<std::string, bool>> groups;
  std::vector<std::string> variants;
  for (const VariantComparison& c : rows) {
    const std::pair<std::string, bool> g{c.group, c.family};
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
    if (std::find(variants.begin(), variants.end(), c.variant) == variants.end()) {
      variants.push_back(c.variant);
    }
  }
  const double slot = 0.8 / static_cast<double>(variants.size());
  std::vector<std::ostringstream> data(variants.size());
  std::ostringstream tics;
  size_t longest = 0;
  for (size_t g = 0; g < groups.size(); ++g) {
    tics << (g == 0 ? "" : ", ") << GnuplotQuote(groups[g].first) << ' ' << g;
    longest = std::max(longest, groups[g].first.size());
  }
  for (const VariantComparison& c : rows) {
    const size_t g = static_cast<size_t>(
        std::find(groups.begin(), groups.end(), std::make_pair(c.group, c.family)) -
        groups.begin());
    const size_t v = static_cast<size_t>(std::find(variants.begin(), variants.end(), c.variant) -
                                         variants.begin());
    const double x =
        static_cast<double>(g) +
        (static_cast<double>(v) - 0.5 * static_cast<double>(variants.size() - 1)) * slot;
    data[v] << DataNumber(x) << ' ' << DataNumber(c.success_rate) << ' ' << DataNumber(c.ci.low)
            << ' ' << DataNumber(c.ci.high) << '\n';
  }
  const bool rotate = groups.size() * std::max<size_t>(longest, 6) * 7 >
                      static_cast<size_t>(options.figure_width) * 7 / 10;
  const size_t k = figures->Begin(
      options.figure_width, rotate ? 420 : 340,
      "Success rate of every group and variant (passed / runs; a family's members together), "
      "with 95% Wilson intervals.",
      "success rate per group and variant");
  std::vector<std::string> names;
  for (std::ostringstream& d : data) names.push_back(figures->AddData(d.str()));
  std::ostringstream& s = figures->script();
  s << "set lmargin at screen 0.07\nset rmargin at screen 0.80\n"
    << (rotate ? "set bmargin 9\n" : "")
    << "set xrange [-0.6:" << static_cast<double>(groups.size()) - 0.4 << "]\nset yrange [0:1.05]\n"
    << "set xtics noenhanced (" << tics.str() << ")" << (rotate ? " rotate by -30" : "")
    << "\nset grid noxtics ytics\nset ylabel 'success rate'\n"
    << "set style fill solid 0.85 border lc rgb '#555555'\nset boxwidth " << 0.9 * slot
    << " absolute\nset key outside right top vertical\nplot ";
  for (size_t v = 0; v < variants.size(); ++v) {
    s << (v == 0 ? "" : ", \\\n  ") << names[v] << " using 1:2 with boxes lc rgb '"
      << VariantColor(variants[v]) << "' title " << GnuplotQuote(VariantShortLabel(variants[v]))
      << " noenhanced, " << names[v]
      << " using 1:3:(0):($4-$3) with vectors heads size screen 0.006,90 lw 1.3 lc rgb '#222222' "
         "notitle";
  }
  s << '\n';
  return k;
}

size_t PushSurvivalFigure(const std::vector<const SurvivalBin*>& bins,
                          const SuiteReportOptions& options, FigureSet* figures) {
  // One data block per variant (in order of first appearance), backward bins at negative J; a
  // blank line between the directions so that no line is drawn across J = 0. Each variant's
  // points are set a little apart within the bin, so that the intervals do not hide each other.
  std::vector<std::string> variants;
  for (const SurvivalBin* b : bins) {
    if (std::find(variants.begin(), variants.end(), b->variant) == variants.end()) {
      variants.push_back(b->variant);
    }
  }
  const double width = bins.front()->impulse_max - bins.front()->impulse_min;
  const double dodge = 0.5 * width / static_cast<double>(variants.size() + 1);
  double reach = 0.0;
  std::vector<std::ostringstream> data(variants.size());
  std::vector<bool> started(variants.size(), false), last_forward(variants.size(), false);
  for (const SurvivalBin* b : bins) {
    const size_t v = std::find(variants.begin(), variants.end(), b->variant) - variants.begin();
    if (started[v] && b->forward && !last_forward[v]) data[v] << '\n';
    started[v] = true;
    last_forward[v] = b->forward;
    const double sign = b->forward ? 1.0 : -1.0;
    const double shift = (static_cast<double>(v) - 0.5 * static_cast<double>(variants.size() - 1));
    data[v] << DataNumber(sign * 0.5 * (b->impulse_min + b->impulse_max) + shift * dodge) << ' '
            << DataNumber(b->success_rate) << ' ' << DataNumber(b->ci.low) << ' '
            << DataNumber(b->ci.high) << '\n';
    reach = std::max(reach, b->impulse_max);
  }
  const size_t k = figures->Begin(
      options.figure_width, 340,
      "Survival against push impulse, family " + HtmlEscape(bins.front()->group) +
          ": success rate per " + DataNumber(width) +
          " N s bin of the runs' horizontal impulse J (backward pushes at J &lt; 0, forward at "
          "J &gt; 0), with 95% Wilson intervals; the bins' counts are in push_survival.csv.",
      "survival against push impulse, " + bins.front()->group);
  std::vector<std::string> names;
  for (std::ostringstream& d : data) names.push_back(figures->AddData(d.str()));
  std::ostringstream& s = figures->script();
  s << "set lmargin at screen 0.07\nset rmargin at screen 0.80\nset xrange [" << -reach << ':'
    << reach << "]\nset yrange [-0.02:1.05]\nset xzeroaxis lt 1 lc rgb '#999999'\n"
    << "set xlabel 'push impulse J (N s): backward < 0 < forward'\nset ylabel 'success rate'\n"
    << "set key outside right top vertical\nplot ";
  for (size_t v = 0; v < variants.size(); ++v) {
    s << (v == 0 ? "" : ", \\\n  ") << names[v] << " using 1:2:3:4 with yerrorlines lw 1.6 pt 7 "
      << "ps 0.8 lc rgb '" << VariantColor(variants[v]) << "' title "
      << GnuplotQuote(VariantShortLabel(variants[v])) << " noenhanced";
  }
  s << '\n';
  return k;
}

}  // namespace report_internal
}  // namespace rabbit
