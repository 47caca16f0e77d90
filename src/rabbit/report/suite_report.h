// The HTML report of a batch run (`rabbit run`), built afterwards from the CSV files the run wrote,
// never from live objects, so it can be rebuilt (`rabbit report DIR`) without re-running.
//
// Input, a report directory DIR:
//   DIR/summary.csv           one row per run (suite, scenario, variant, run, outcome, criteria,
//                             figures); `run` names the run's folder
//   DIR/<run>/meta.csv        key,value: at least thigh_length_m, shin_length_m, trunk_length_m
//   DIR/<run>/trajectory.csv  the time series of WriteTrajectoryCsv (typically decimated)
//   DIR/<run>/steps.csv       one row per step: V_d, V_M, L_step, d_obs, fuzzy weights w_Ok, rules
//   DIR/<run>/tracking.csv    swing hip and knee, reference and actual
//   DIR/<run>/terrain.csv     the obstacles
//   DIR/<run>/ground.csv      the ground profile's breakpoints (optional: flat ground y = 0)
// Output, DIR/comparison.csv (the head-to-head of the variants per family or plain scenario,
// rabbit/report/comparison.h), DIR/push_survival.csv (survival against push impulse of the pushed
// families, rabbit/report/push_survival.h) and DIR/index.html: one self-contained page (inline CSS, JS, and
// figures as data: images): the head-to-head (an overview chart of every group's success rates,
// then per group a table of its variants and, for a family, a chart, and for a pushed family its
// survival against impulse), the summary table grouped
// by scenario (baselines beside the main variant), then per scenario the chapter's figures (stick
// diagrams at the start and around the first obstacle, V_d / V_M / L_step per step with the
// baselines overlaid, joint tracking, fuzzy weights per step), drawn by one gnuplot process, and
// an animated stick-figure replay of every run (for a family, of its first members only).
#ifndef RABBIT_REPORT_SUITE_REPORT_H_
#define RABBIT_REPORT_SUITE_REPORT_H_

#include <array>
#include <string>
#include <vector>

namespace rabbit {

struct SuiteReportOptions {
  std::string gnuplot = "gnuplot";  // the plotter's executable (searched on PATH without a '/')
  double gnuplot_timeout = 60.0;    // s; gnuplot is killed after this and the figures left out
  int replay_fps = 25;              // frames per second of the embedded animation
  int max_replay_frames = 20000;    // per run; longer runs replay at a lower frame rate
  int replay_decimals = 4;          // decimals of the replay's coordinates (m) and times (s)
  double stick_every = 0.1;         // s between drawn figures in stick diagrams
  double stick_window = 3.0;        // s of walking shown per stick diagram (chapter's ~2.8 s)
  double tracking_window = 3.0;     // s of joint tracking shown
  int figure_width = 1000;          // px, width of every figure's SVG canvas
  // Per family, the first `family_details` members (in summary order) get their figures, steps
  // table and replays; the others a line naming their runs' outcomes (their rows stay in the
  // summary table and the head-to-head). Negative: every member.
  int family_details = 3;
  // N s: the width of the impulse bins of survival against push impulse (push_survival.h).
  double survival_bin_n_s = 5.0;
  // The folder the page names as its source (empty: the folder it is built in). `rabbit run`
  // builds in a staging folder and names the final one.
  std::string source_label;
  // Positive finite times, replay_fps 1..240, replay_decimals 1..9, stick_window / stick_every
  // at most 1000 figures, figure_width 300..4000, survival_bin_n_s in (0, 1000], a non-empty
  // gnuplot without newlines.
  bool IsValid(std::string* error) const;
};

// Reads DIR/summary.csv and every run's files, writes DIR/comparison.csv and DIR/index.html
// atomically and returns the page's path. When gnuplot cannot be run (or fails) appends one warning
// to *warnings (may be null) and writes the page with the tables and replays but without figures:
// never a failure for that. Trajectory rows whose coordinates are `nan` (a diverged run) are left
// out with a warning. Throws InputError (file, line, column or key) for a missing or malformed CSV,
// and std::invalid_argument for invalid options.
std::string WriteSuiteReport(const std::string& dir, const SuiteReportOptions& options,
                             std::vector<std::string>* warnings);

// Link lengths for drawing, m.
struct LinkLengths {
  double thigh = 0.40;
  double shin = 0.47;
  double trunk = 0.625;
};

struct StickPoint {
  double x = 0.0, y = 0.0;
};

// The points of the stick figure at q = [x, y, q0, q11, q12, q21, q22] (model.h): the hip at
// (x, y); the trunk's top at hip + trunk (sin q0, cos q0); per leg i the thigh's absolute angle
// th_i = qi1 - q0 from the downward vertical, knee = hip + thigh (sin th_i, -cos th_i), the shin's
// sh_i = th_i + qi2, foot = knee + shin (sin sh_i, -cos sh_i).
struct StickFigure {
  StickPoint hip, trunk_top;
  std::array<StickPoint, 2> knee, foot;  // legs 1 and 2
};
StickFigure StickPoints(const std::array<double, 7>& q, const LinkLengths& lengths);

}  // namespace rabbit

#endif  // RABBIT_REPORT_SUITE_REPORT_H_
