#include "gait_synthesis.h"

#include <nlopt.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <thread>
#include <vector>

#include "rabbit/contact/actuator.h"

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

// One walk's value: what the objective computes for a point.
struct Evaluation {
  double cost = 0.0;
  GaitMetrics metrics;
};

struct Search {
  const SimSetup* setup;
  const SynthesisOptions* options;
  const std::function<void(const SynthesisProgress&)>* progress;
  GaitSpec base;
  int evaluations = 0;
  int walks = 0, walks_ahead = 0;
  double best_cost = std::numeric_limits<double>::infinity();
  GaitSpec best_spec;
  GaitMetrics best_metrics;
  const char* stage = "";
  // Every point walked so far (unit coordinates, exactly): a point asked for again, or walked
  // ahead on other threads, is not walked twice. Its value is the same either way.
  std::map<std::vector<double>, Evaluation> known;
};

Evaluation Walk(const Search& s, const double* x) {
  const GaitSpec spec = FromUnit(x, s.base, s.options->bounds);
  const GaitRun run = WalkGait(*s.setup, spec, s.options->walk_duration, s.options->window);
  return {GaitCost(run.metrics, *s.options), run.metrics};
}

// Walks the points on options.threads threads and keeps their values for the search; the values
// are a function of the points alone, so the search's path does not depend on the threads.
void WalkAhead(const std::vector<std::vector<double>>& points, Search* s) {
  std::vector<std::vector<double>> todo;
  for (const std::vector<double>& x : points) {
    if (s->known.count(x) == 0) todo.push_back(x);
  }
  std::vector<Evaluation> values(todo.size());
  std::atomic<size_t> next{0};
  auto worker = [&] {
    for (size_t i = next++; i < todo.size(); i = next++) values[i] = Walk(*s, todo[i].data());
  };
  const int threads = std::min<int>(s->options->threads, static_cast<int>(todo.size()));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  for (size_t i = 0; i < todo.size(); ++i) s->known.emplace(todo[i], values[i]);
  s->walks += static_cast<int>(todo.size());
  s->walks_ahead += static_cast<int>(todo.size());
}

// The random points NLopt's CRS2 draws for its initial population after the starting point: its
// generator is the standard 32-bit Mersenne Twister seeded with nlopt_srand(seed), drawn in
// 53-bit doubles (two words each), one per coordinate, on [0, 1]. Only a forecast: if NLopt draws
// otherwise, the points are simply not asked for and the search walks its own.
std::vector<std::vector<double>> CrsInitialPoints(unsigned seed, int count) {
  std::mt19937 twister(seed);
  std::vector<std::vector<double>> points(std::max(0, count), std::vector<double>(kDim));
  for (std::vector<double>& x : points) {
    for (double& u : x) {
      const double a = static_cast<double>(twister() >> 5), b = static_cast<double>(twister() >> 6);
      u = (a * 67108864.0 + b) * (1.0 / 9007199254740992.0);
    }
  }
  return points;
}
constexpr int kCrsPopulation = 10 * (kDim + 1);  // NLopt's default for CRS2

double Objective(unsigned n, const double* x, double* grad, void* data) {
  (void)grad;  // derivative-free algorithms only
  auto* s = static_cast<Search*>(data);
  std::vector<double> key(x, x + n);
  auto found = s->known.find(key);
  if (found == s->known.end()) {
    found = s->known.emplace(std::move(key), Walk(*s, x)).first;
    ++s->walks;
  }
  const Evaluation& value = found->second;
  const double cost = value.cost;
  ++s->evaluations;
  if (cost < s->best_cost) {
    s->best_cost = cost;
    s->best_spec = FromUnit(x, s->base, s->options->bounds);
    s->best_metrics = value.metrics;
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
  for (int i = 0; i < kDim; ++i) {
    if (!start[i]) continue;
    if (!(std::isfinite(*start[i]) && *start[i] >= bounds[i].first &&
          *start[i] <= bounds[i].second)) {
      char range[64];
      std::snprintf(range, sizeof range, "[%g, %g]", bounds[i].first, bounds[i].second);
      *error = std::string("start of ") + kParams[i].name + ": must lie within its bounds " + range;
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
  if (budget < 1 || window < 2 || threads < 1 || threads > 1024) {
    *error = "need budget >= 1, window >= 2 and 1 <= threads <= 1024";
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

GaitSpec StartGaitSpec(const SynthesisOptions& options) {
  GaitSpec spec = InitialGaitSpec(options.target_v_m);
  for (int i = 0; i < kDim; ++i) {
    if (options.start[i]) *kParams[i].field(&spec) = *options.start[i] * kParams[i].scale;
  }
  return spec;
}

double SynthesisParamValue(const GaitSpec& spec, int i) {
  GaitSpec copy = spec;
  return *kParams[i].field(&copy) / kParams[i].scale;
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

std::vector<std::string> DiagnoseMiss(const SimSetup& setup, const SynthesisOptions& o,
                                      const SynthesisResult& best) {
  std::vector<std::string> out;
  char text[256];
  const GaitMetrics& m = best.metrics;
  // The criteria the best candidate misses, and by how much.
  if (m.fell || m.steps < o.window + 2) {
    std::snprintf(text, sizeof text,
                  "no candidate walks %d steps: the best took %d steps and %s after %.2f s",
                  o.window + 2, m.steps, m.fell ? "fell" : "stopped stepping", m.walked_time);
    out.push_back(text);
  } else {
    if (std::abs(m.v_m - o.target_v_m) > o.v_tolerance) {
      std::snprintf(text, sizeof text, "V_M %.3f m/s, %.3f %s the target %.3f (tolerance %.3f)",
                    m.v_m, std::abs(m.v_m - o.target_v_m), m.v_m < o.target_v_m ? "below" : "above",
                    o.target_v_m, o.v_tolerance);
      out.push_back(text);
    }
    if (o.target_l_step > 0.0 && std::abs(m.l_step - o.target_l_step) > o.l_tolerance) {
      std::snprintf(text, sizeof text, "L_step %.3f m, %.3f %s the target %.3f (tolerance %.3f)",
                    m.l_step, std::abs(m.l_step - o.target_l_step),
                    m.l_step < o.target_l_step ? "below" : "above", o.target_l_step, o.l_tolerance);
      out.push_back(text);
    }
    if (m.l_step_spread > o.max_l_spread) {
      std::snprintf(text, sizeof text,
                    "L_step varies by %.4f m over the last %d steps (at most %.4f)",
                    m.l_step_spread, o.window, o.max_l_spread);
      out.push_back(text);
    }
  }
  // The search bounds the best candidate lies on (within 1 % of the range).
  GaitSpec spec = best.spec;
  for (int i = 0; i < kDim; ++i) {
    const double v = *kParams[i].field(&spec) / kParams[i].scale;
    const auto [lo, hi] = o.bounds[i];
    const double margin = 0.01 * (hi - lo);
    if (v <= lo + margin || v >= hi - margin) {
      const bool upper = v >= hi - margin;
      std::snprintf(text, sizeof text, "%s at its %s bound %g in the best candidate",
                    kParams[i].name, upper ? "upper" : "lower", upper ? hi : lo);
      out.push_back(text);
    }
  }
  // The actuator limits its walk runs into (share of the walk, per joint kind and limit).
  SimSetup record = setup;
  record.options.record_every = 1;
  const GaitRun run = WalkGait(record, best.spec, o.walk_duration, o.window);
  if (!run.sim.samples.empty()) {
    const char* const joints[2] = {"hip", "knee"};  // joint j: hip (even) or knee (odd)
    const char* const limits[4] = {"", "torque", "power", "speed"};
    long counts[2][4] = {};
    for (const SimSample& sample : run.sim.samples) {
      for (int j = 0; j < kNumJoints; ++j) {
        SaturationRegion region;
        SaturateTorque(setup.actuator, sample.tau_cmd[j], sample.qd[3 + j], &region);
        ++counts[j % 2][static_cast<int>(region)];
      }
    }
    const double samples = 2.0 * static_cast<double>(run.sim.samples.size());  // per joint kind
    for (int k = 0; k < 2; ++k) {
      for (int r = 1; r < 4; ++r) {
        const double share = static_cast<double>(counts[k][r]) / samples;
        if (share < 0.02) continue;  // occasional saturation is normal
        std::snprintf(text, sizeof text, "motor %s limit on the %ss for %.0f %% of the walk",
                      limits[r], joints[k], 100.0 * share);
        out.push_back(text);
      }
    }
  }
  if (best.evaluations >= o.budget) {
    std::snprintf(text, sizeof text, "budget exhausted (%d walks)", o.budget);
  } else {
    std::snprintf(text, sizeof text,
                  "the search converged after %d of its %d walks (no better point nearby)",
                  best.evaluations, o.budget);
  }
  out.push_back(text);
  return out;
}

SynthesisResult SynthesizeGait(const SimSetup& setup, const SynthesisOptions& options,
                               const std::function<void(const SynthesisProgress&)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  Search search;
  search.setup = &setup;
  search.options = &options;
  search.progress = &progress;
  search.base = StartGaitSpec(options);
  search.best_spec = search.base;
  const nlopt_algorithm local =
      options.local_algorithm == "bobyqa" ? NLOPT_LN_BOBYQA : NLOPT_LN_SBPLX;
  nlopt_srand(options.seed);

  // A given start is walked first exactly as given (unit coordinates would round it): when it
  // meets the criteria it is the result, and the stages below do not run.
  const bool has_start = std::any_of(options.start.begin(), options.start.end(),
                                     [](const std::optional<double>& v) { return v.has_value(); });
  if (has_start) {
    const GaitRun run = WalkGait(setup, search.base, options.walk_duration, options.window);
    ++search.walks;
    ++search.evaluations;
    search.stage = "start";
    search.best_cost = GaitCost(run.metrics, options);
    search.best_metrics = run.metrics;
  }
  std::vector<double> x = ToUnit(search.base, options.bounds);
  if (!has_start || !MeetsCriteria(search.best_metrics, options)) {
    RunStage(local, "local", options.budget / 3 - search.evaluations, &x, &search);
  }
  if (!MeetsCriteria(search.best_metrics, options)) {
    x = ToUnit(search.best_spec, options.bounds);
    const int budget = options.budget / 2;
    if (options.threads > 1) {
      WalkAhead(CrsInitialPoints(options.seed, std::min(kCrsPopulation, budget) - 1), &search);
    }
    RunStage(NLOPT_GN_CRS2_LM, "global", budget, &x, &search);
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
  result.walks = search.walks;
  result.walks_ahead = search.walks_ahead;
  result.success = MeetsCriteria(search.best_metrics, options);
  if (!result.success) result.limits = DiagnoseMiss(setup, options, result);
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace rabbit
