#include "gait_synthesis.h"

#include <nlopt.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;

// The searched parameters, each mapped to [0, 1] between its bounds.
struct Param {
  const char* name;
  double lo, hi;  // default bounds
  // The widest bounds that make sense: the joint's or trunk's physical range for angles (a knee
  // flexes backward only, the trunk falls at 45 deg), twice the actuators' 75 N m for the pulse,
  // positive times, gains and speeds.
  double min, max;
  double scale;  // stored value = value * scale (degrees -> radians)
  double* (*field)(GaitSpec*);
};
const std::array<Param, 10> kParams = {{
    {"qr1_dsw_deg", 10.0, 50.0, -90.0, 90.0, kDeg, [](GaitSpec* s) { return &s->rules.qr1_dsw; }},
    {"qi2_dsw_deg", -30.0, -2.0, -150.0, 0.0, kDeg, [](GaitSpec* s) { return &s->rules.qi2_dsw; }},
    {"q0_d_deg", -5.0, 15.0, -45.0, 45.0, kDeg, [](GaitSpec* s) { return &s->rules.q0_d; }},
    {"pulse_torque_nm", 0.0, 75.0, -150.0, 150.0, 1.0,
     [](GaitSpec* s) { return &s->rules.pulse_torque; }},
    {"pulse_duration_s", 0.02, 0.4, 0.0, 2.0, 1.0,
     [](GaitSpec* s) { return &s->rules.pulse_duration; }},
    {"hip_kp", 50.0, 1500.0, 0.0, 1e5, 1.0, [](GaitSpec* s) { return &s->rules.hip_kp; }},
    {"hip_kd", 2.0, 80.0, 0.0, 1e4, 1.0, [](GaitSpec* s) { return &s->rules.hip_kd; }},
    {"knee_kp", 50.0, 1500.0, 0.0, 1e5, 1.0, [](GaitSpec* s) { return &s->rules.knee_kp; }},
    {"knee_kd", 2.0, 60.0, 0.0, 1e4, 1.0, [](GaitSpec* s) { return &s->rules.knee_kd; }},
    {"start_speed_m_s", 0.1, 1.2, 0.0, 5.0, 1.0, [](GaitSpec* s) { return &s->start_speed; }},
}};
constexpr int kDim = static_cast<int>(kParams.size());

using Bounds = std::array<std::pair<double, double>, kSynthesisParams>;

std::vector<double> ToUnit(GaitSpec spec, const Bounds& b) {
  std::vector<double> x(kDim);
  for (int i = 0; i < kDim; ++i) {
    const double v = *kParams[i].field(&spec) / kParams[i].scale;
    x[i] = std::clamp((v - b[i].first) / (b[i].second - b[i].first), 0.0, 1.0);
  }
  return x;
}
GaitSpec FromUnit(const double* x, GaitSpec spec, const Bounds& b) {
  for (int i = 0; i < kDim; ++i) {
    *kParams[i].field(&spec) = (b[i].first + x[i] * (b[i].second - b[i].first)) * kParams[i].scale;
  }
  return spec;
}

struct Search {
  const SimSetup* setup;
  const SynthesisOptions* options;
  const std::function<void(const SynthesisProgress&)>* progress;
  GaitSpec base;
  int evaluations = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  GaitSpec best_spec;
  GaitMetrics best_metrics;
  const char* stage = "";
};

double Objective(unsigned n, const double* x, double* grad, void* data) {
  (void)n;
  (void)grad;  // derivative-free algorithms only
  auto* s = static_cast<Search*>(data);
  const GaitSpec spec = FromUnit(x, s->base, s->options->bounds);
  const GaitRun run = WalkGait(*s->setup, spec, s->options->walk_duration, s->options->window);
  const double cost = GaitCost(run.metrics, *s->options);
  ++s->evaluations;
  if (cost < s->best_cost) {
    s->best_cost = cost;
    s->best_spec = spec;
    s->best_metrics = run.metrics;
  }
  if (*s->progress) {
    SynthesisProgress p;
    p.evaluation = s->evaluations;
    p.stage = s->stage;
    p.cost = cost;
    p.best_cost = s->best_cost;
    p.best = s->best_metrics;
    (*s->progress)(p);
  }
  return cost;
}

// Runs one NLopt stage from x (in unit coordinates) with at most `budget` evaluations; stops
// early when the criteria are met.
void RunStage(nlopt_algorithm algorithm, const char* name, int budget, std::vector<double>* x,
              Search* search) {
  if (budget <= 0) return;
  nlopt_opt opt = nlopt_create(algorithm, kDim);
  std::vector<double> lo(kDim, 0.0), hi(kDim, 1.0);
  nlopt_set_lower_bounds(opt, lo.data());
  nlopt_set_upper_bounds(opt, hi.data());
  nlopt_set_min_objective(opt, Objective, search);
  nlopt_set_maxeval(opt, budget);
  // Below this the gait meets every criterion (see GaitCost): no need to go on.
  nlopt_set_stopval(opt, 1.0);
  nlopt_set_xtol_abs1(opt, 1e-4);
  std::vector<double> step(kDim, 0.1);
  nlopt_set_initial_step(opt, step.data());
  search->stage = name;
  double f = 0.0;
  nlopt_optimize(opt, x->data(), &f);  // its result code is not needed: the best is tracked
  nlopt_destroy(opt);
}

// Chapter Table 2: V_M -> (qr1_dsw, qi2_dsw, q0_d), degrees.
const double kTable2[5][4] = {{0.4, 20, -7, 0},
                              {0.5, 25, -10, 1.5},
                              {0.6, 30, -14, 4},
                              {0.7, 35, -20, 6.5},
                              {0.8, 40, -25, 10.5}};

}  // namespace

const std::array<const char*, kSynthesisParams> kSynthesisParamNames = [] {
  std::array<const char*, kSynthesisParams> names{};
  for (int i = 0; i < kDim; ++i) names[i] = kParams[i].name;
  return names;
}();

std::array<std::pair<double, double>, kSynthesisParams> DefaultSynthesisBounds() {
  Bounds b{};
  for (int i = 0; i < kDim; ++i) b[i] = {kParams[i].lo, kParams[i].hi};
  return b;
}

bool SynthesisOptions::IsValid(std::string* error) const {
  for (int i = 0; i < kDim; ++i) {
    if (!(std::isfinite(bounds[i].first) && std::isfinite(bounds[i].second) &&
          bounds[i].first < bounds[i].second)) {
      *error = std::string("bounds of ") + kParams[i].name + ": need finite lower < upper";
      return false;
    }
    if (bounds[i].first < kParams[i].min || bounds[i].second > kParams[i].max) {
      char range[64];
      std::snprintf(range, sizeof range, "[%g, %g]", kParams[i].min, kParams[i].max);
      *error = std::string("bounds of ") + kParams[i].name + ": must lie within " + range +
               " (the physically meaningful range)";
      return false;
    }
  }
  if (!(std::isfinite(target_v_m) && target_v_m > 0.05 && target_v_m < 2.0)) {
    *error = "target velocity must be in (0.05, 2) m/s";
    return false;
  }
  if (!(std::isfinite(target_l_step) && target_l_step >= 0.0 && target_l_step < 1.0)) {
    *error = "target step length must be in [0, 1) m (0: none)";
    return false;
  }
  if (budget < 1 || window < 2) {
    *error = "need budget >= 1 and window >= 2";
    return false;
  }
  if (!(walk_duration > 0.5)) {
    *error = "walk_duration must exceed 0.5 s";
    return false;
  }
  if (local_algorithm != "sbplx" && local_algorithm != "bobyqa") {
    *error = "local algorithm must be sbplx or bobyqa";
    return false;
  }
  return true;
}

GaitSpec InitialGaitSpec(double v) {
  int i = 0;
  while (i < 3 && v > kTable2[i + 1][0]) ++i;
  const double w = (v - kTable2[i][0]) / (kTable2[i + 1][0] - kTable2[i][0]);
  auto lerp = [&](int c) { return kTable2[i][c] + w * (kTable2[i + 1][c] - kTable2[i][c]); };
  GaitSpec spec;
  spec.rules.qr1_dsw = std::clamp(lerp(1), 12.0, 58.0) * kDeg;
  spec.rules.qi2_dsw = std::clamp(lerp(2), -28.0, -3.0) * kDeg;
  spec.rules.q0_d = std::clamp(lerp(3), -4.0, 24.0) * kDeg;
  spec.start_speed = v;
  return spec;
}

double GaitCost(const GaitMetrics& m, const SynthesisOptions& o) {
  const int needed = o.window + 2;
  if (m.fell || m.steps < needed) {
    // Did not walk: rank by how long it lasted and how many steps it took.
    return 1000.0 + 500.0 * (1.0 - std::min(1.0, m.walked_time / o.walk_duration)) +
           10.0 * std::max(0, needed - m.steps);
  }
  double cost = std::pow((m.v_m - o.target_v_m) / o.v_tolerance, 2) +
                std::pow(m.l_step_spread / o.max_l_spread, 2);
  if (o.target_l_step > 0.0) cost += std::pow((m.l_step - o.target_l_step) / o.l_tolerance, 2);
  return cost;
}

bool MeetsCriteria(const GaitMetrics& m, const SynthesisOptions& o) {
  return !m.fell && m.steps >= o.window + 2 && std::abs(m.v_m - o.target_v_m) <= o.v_tolerance &&
         m.l_step_spread <= o.max_l_spread &&
         (o.target_l_step <= 0.0 || std::abs(m.l_step - o.target_l_step) <= o.l_tolerance);
}

SynthesisResult SynthesizeGait(const SimSetup& setup, const SynthesisOptions& options,
                               const std::function<void(const SynthesisProgress&)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  Search search;
  search.setup = &setup;
  search.options = &options;
  search.progress = &progress;
  search.base = InitialGaitSpec(options.target_v_m);
  search.best_spec = search.base;
  const nlopt_algorithm local =
      options.local_algorithm == "bobyqa" ? NLOPT_LN_BOBYQA : NLOPT_LN_SBPLX;
  nlopt_srand(options.seed);

  std::vector<double> x = ToUnit(search.base, options.bounds);
  RunStage(local, "local", options.budget / 3, &x, &search);
  if (!MeetsCriteria(search.best_metrics, options)) {
    x = ToUnit(search.best_spec, options.bounds);
    RunStage(NLOPT_GN_CRS2_LM, "global", options.budget / 2, &x, &search);
  }
  if (!MeetsCriteria(search.best_metrics, options)) {
    x = ToUnit(search.best_spec, options.bounds);
    RunStage(local, "polish", options.budget - search.evaluations, &x, &search);
  }
  SynthesisResult result;
  result.spec = search.best_spec;
  result.metrics = search.best_metrics;
  result.cost = search.best_cost;
  result.evaluations = search.evaluations;
  result.success = MeetsCriteria(search.best_metrics, options);
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace rabbit
