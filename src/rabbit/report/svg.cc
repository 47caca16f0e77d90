#include "rabbit/report/svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <vector>

namespace rabbit {
namespace {

// The Okabe-Ito palette (distinct for the common colour-vision deficiencies), yellow last: eight
// colours, one per reference gait of the shipped database. Legs 1 and 2 are the first two.
const char* const kColors[] = {"#0072B2", "#D55E00", "#009E73", "#E69F00",
                               "#CC79A7", "#56B4E9", "#000000", "#F0E442"};

std::string Fmt(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

// "Nice" tick spacing for a range.
double TickStep(double span) {
  const double raw = span / 5.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double f = raw / mag;
  return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * mag;
}

}  // namespace

std::string HtmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string StickDiagramSvg(const Model& model, const std::vector<SimSample>& samples,
                            const Terrain& terrain, double t0, double t1, double every) {
  std::vector<const SimSample*> frames;
  double next = t0;
  for (const SimSample& s : samples) {
    if (s.t + 1e-9 < next || s.t > t1 + 1e-9) continue;
    frames.push_back(&s);
    next = s.t + every;
  }
  if (frames.empty()) return "<p>(no samples in range)</p>";
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  for (const SimSample* s : frames) {
    const Pose p = ComputePose(model, s->q);
    for (const Vec2& v : {p.hip, p.trunk_top, p.foot[0], p.foot[1]}) {
      x_lo = std::min(x_lo, v.x());
      x_hi = std::max(x_hi, v.x());
    }
  }
  x_lo -= 0.1;
  x_hi += 0.1;
  // The vertical range from the ground under the figures (flat ground: y = 0).
  const std::vector<Eigen::Vector2d> outline = terrain.ground.Outline(x_lo, x_hi);
  double ground_lo = 0.0, ground_hi = 0.0;
  if (!terrain.ground.is_flat_zero()) {
    ground_lo = std::numeric_limits<double>::infinity();
    ground_hi = -ground_lo;
    for (const Eigen::Vector2d& p : outline) {
      ground_lo = std::min(ground_lo, p.y());
      ground_hi = std::max(ground_hi, p.y());
    }
  }
  const double y_lo = ground_lo - 0.05, y_hi = ground_hi + 1.6;
  const double scale = 300.0;  // px per m
  const double left = 70.0, right = 70.0, bottom = 50.0,
               top_margin = 30.0;  // px of the axes' labels
  const double w = (x_hi - x_lo) * scale, h = (y_hi - y_lo) * scale;
  auto X = [&](double x) { return Fmt(left + (x - x_lo) * scale); };
  auto Y = [&](double y) { return Fmt(top_margin + (y_hi - y) * scale); };
  std::ostringstream svg;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='"
      << Fmt(std::min(w + left + right, 1400.0)) << "' viewBox='0 0 " << Fmt(w + left + right)
      << ' ' << Fmt(top_margin + h + bottom) << "' style='background:#fff'>";
  // The axes, in metres: x along the ground, y up (the world frame of the simulation).
  svg << "<g stroke='#333' stroke-width='1.5' font-size='20' font-family='sans-serif' "
         "fill='#333'>";
  svg << "<line x1='" << X(x_lo) << "' y1='" << Fmt(top_margin + h + 4) << "' x2='" << X(x_hi)
      << "' y2='" << Fmt(top_margin + h + 4) << "'/>";
  const double x_step = TickStep(x_hi - x_lo);
  for (double x = std::ceil(x_lo / x_step) * x_step; x <= x_hi + 1e-9; x += x_step) {
    svg << "<line x1='" << X(x) << "' y1='" << Fmt(top_margin + h + 4) << "' x2='" << X(x)
        << "' y2='" << Fmt(top_margin + h + 12) << "'/><text stroke='none' text-anchor='middle' x='"
        << X(x) << "' y='" << Fmt(top_margin + h + 34) << "'>" << Fmt(std::abs(x) < 1e-9 ? 0.0 : x)
        << "</text>";
  }
  svg << "<text stroke='none' x='" << Fmt(left + w + 10) << "' y='" << Fmt(top_margin + h + 11)
      << "'>x (m)</text>";
  svg << "<line x1='" << Fmt(left - 4) << "' y1='" << Y(y_lo) << "' x2='" << Fmt(left - 4)
      << "' y2='" << Y(y_hi) << "'/>";
  const double y_step = TickStep(y_hi - y_lo);
  for (double y = std::ceil(y_lo / y_step) * y_step; y <= y_hi + 1e-9; y += y_step) {
    svg << "<line x1='" << Fmt(left - 12) << "' y1='" << Y(y) << "' x2='" << Fmt(left - 4)
        << "' y2='" << Y(y) << "'/><text stroke='none' text-anchor='end' x='" << Fmt(left - 16)
        << "' y='" << Y(y) << "' dy='7'>" << Fmt(std::abs(y) < 1e-9 ? 0.0 : y) << "</text>";
  }
  svg << "<text stroke='none' x='" << Fmt(left + 6) << "' y='22'>y (m)</text></g>";
  if (terrain.ground.is_flat_zero()) {
    svg << "<line x1='" << X(x_lo) << "' y1='" << Y(0) << "' x2='" << X(x_hi) << "' y2='" << Y(0)
        << "' stroke='#555' stroke-width='2'/>";
  } else {
    svg << "<polyline fill='none' stroke='#555' stroke-width='2' points='";
    for (const Eigen::Vector2d& p : outline) svg << X(p.x()) << ',' << Y(p.y()) << ' ';
    svg << "'/>";
  }
  for (size_t i = 0; i < terrain.obstacles.size(); ++i) {
    const Obstacle& o = terrain.obstacles[i];
    const double top = terrain.ObstacleTop(static_cast<int>(i));
    svg << "<rect x='" << X(o.x_start) << "' y='" << Y(top) << "' width='" << Fmt(o.length * scale)
        << "' height='" << Fmt(o.height * scale) << "' fill='#888'/>";
  }
  for (size_t i = 0; i < frames.size(); ++i) {
    const Pose p = ComputePose(model, frames[i]->q);
    const double shade = frames.size() > 1 ? 0.25 + 0.75 * static_cast<double>(i) /
                                                        static_cast<double>(frames.size() - 1)
                                           : 1.0;
    svg << "<g stroke-width='3' stroke-linecap='round' opacity='" << Fmt(shade) << "'>";
    auto line = [&](const Vec2& a, const Vec2& b, const char* color) {
      svg << "<line x1='" << X(a.x()) << "' y1='" << Y(a.y()) << "' x2='" << X(b.x()) << "' y2='"
          << Y(b.y()) << "' stroke='" << color << "'/>";
    };
    line(p.hip, p.trunk_top, "#333");
    line(p.hip, p.knee[0], kColors[0]);
    line(p.knee[0], p.foot[0], kColors[0]);
    line(p.hip, p.knee[1], kColors[1]);
    line(p.knee[1], p.foot[1], kColors[1]);
    svg << "</g>";
  }
  svg << "</svg>";
  return svg.str();
}

std::string LinePlotSvg(const std::string& title, const std::string& x_label,
                        const std::string& y_label, const std::vector<PlotSeries>& series) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  for (const PlotSeries& s : series) {
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x_lo = std::min(x_lo, s.x[i]);
      x_hi = std::max(x_hi, s.x[i]);
      y_lo = std::min(y_lo, s.y[i]);
      y_hi = std::max(y_hi, s.y[i]);
    }
  }
  if (!(x_hi > x_lo)) x_hi = x_lo + 1.0;
  if (!(y_hi > y_lo)) y_hi = y_lo + 1.0;
  const double pad = 0.05 * (y_hi - y_lo);
  y_lo -= pad;
  y_hi += pad;
  const double W = 640, H = 360, L = 70, R = 150, T = 30, B = 50;
  auto X = [&](double x) { return Fmt(L + (x - x_lo) / (x_hi - x_lo) * (W - L - R)); };
  auto Y = [&](double y) { return Fmt(H - B - (y - y_lo) / (y_hi - y_lo) * (H - T - B)); };
  std::ostringstream svg;
  svg << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
      << "' font-family='sans-serif' font-size='12' style='background:#fff'>";
  svg << "<text x='" << W / 2 << "' y='18' text-anchor='middle' font-size='14'>"
      << HtmlEscape(title) << "</text>";
  svg << "<rect x='" << L << "' y='" << T << "' width='" << W - L - R << "' height='" << H - T - B
      << "' fill='none' stroke='#333'/>";
  const double xs = TickStep(x_hi - x_lo), ys = TickStep(y_hi - y_lo);
  // Ticks by count (at most a dozen), so that huge or degenerate ranges cannot loop forever.
  const double x_first = std::ceil(x_lo / xs) * xs, y_first = std::ceil(y_lo / ys) * ys;
  for (int i = 0; i < 12; ++i) {
    const double x = x_first + i * xs;
    if (!(x <= x_hi + 1e-12 * std::abs(x_hi))) break;
    svg << "<line x1='" << X(x) << "' y1='" << Fmt(H - B) << "' x2='" << X(x) << "' y2='"
        << Fmt(H - B + 5) << "' stroke='#333'/><text x='" << X(x) << "' y='" << Fmt(H - B + 18)
        << "' text-anchor='middle'>" << Fmt(x) << "</text>";
  }
  for (int i = 0; i < 12; ++i) {
    const double y = y_first + i * ys;
    if (!(y <= y_hi + 1e-12 * std::abs(y_hi))) break;
    svg << "<line x1='" << Fmt(L - 5) << "' y1='" << Y(y) << "' x2='" << Fmt(L) << "' y2='" << Y(y)
        << "' stroke='#333'/><text x='" << Fmt(L - 8) << "' y='" << Y(y)
        << "' text-anchor='end' dominant-baseline='middle'>" << Fmt(y) << "</text>";
  }
  svg << "<text x='" << Fmt((L + W - R) / 2) << "' y='" << Fmt(H - 10) << "' text-anchor='middle'>"
      << HtmlEscape(x_label) << "</text>";
  svg << "<text transform='translate(16," << Fmt((T + H - B) / 2)
      << ") rotate(-90)' text-anchor='middle'>" << HtmlEscape(y_label) << "</text>";
  for (size_t k = 0; k < series.size(); ++k) {
    const PlotSeries& s = series[k];
    const char* color = kColors[k % std::size(kColors)];
    svg << "<polyline fill='none' stroke='" << color << "' stroke-width='1.5' points='";
    for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i]))
        svg << X(s.x[i]) << ',' << Y(s.y[i]) << ' ';
    }
    svg << "'/>";
    const double ly = T + 15 + 18.0 * static_cast<double>(k);
    svg << "<line x1='" << Fmt(W - R + 10) << "' y1='" << Fmt(ly) << "' x2='" << Fmt(W - R + 30)
        << "' y2='" << Fmt(ly) << "' stroke='" << color << "' stroke-width='2'/><text x='"
        << Fmt(W - R + 35) << "' y='" << Fmt(ly) << "' dominant-baseline='middle'>"
        << HtmlEscape(s.name) << "</text>";
  }
  svg << "</svg>";
  return svg.str();
}

}  // namespace rabbit
