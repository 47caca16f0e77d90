#include "rabbit/gait/gait_walk.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rabbit {

bool GaitSpec::IsValid(std::string* error) const {
  if (!rules.IsValid(error)) return false;
  if (!(std::isfinite(start_speed) && start_speed >= 0.0 && start_speed < 3.0)) {
    *error = "start_speed must be in [0, 3) m/s";
    return false;
  }
  if (!(std::isfinite(start_angle) && std::abs(start_angle) < 0.8)) {
    *error = "start_angle must be within 45 deg";
    return false;
  }
  return true;
}

GaitRun WalkGait(const SimSetup& setup, const GaitSpec& spec, double duration, int window) {
  SimSetup walk = setup;
  walk.terrain = Terrain{};
  walk.options.duration = duration;
  Vec7 q, qd;
  WalkingStartState(*setup.model, spec.rules, spec.start_speed, spec.start_angle, 0, &q, &qd);
  PragmaticController controller(spec.rules, 0);
  GaitRun run;
  run.sim = Simulate(walk, q, qd, &controller);
  run.steps = controller.meter().steps();
  GaitMetrics& m = run.metrics;
  m.fell = run.sim.outcome != Outcome::kCompleted;
  m.walked_time = run.sim.t_end;
  m.reason = run.sim.reason;
  for (int j = 0; j < kNumJoints; ++j) {
    m.saturation_time += run.sim.saturation_time(j, walk.options.control_period);
  }
  // Steps count while legs alternate and each step is a real one (a foot that lands where it
  // took off, or lands again at once, is a stumble: the walk has ended). The first landing of the
  // swing leg, in the air since the start, has no measured take-off (t_step 0): it counts as a
  // step but is never in the measured window.
  for (size_t i = 0; i < run.steps.size(); ++i) {
    const StepRecord& s = run.steps[i];
    if ((i > 0 && s.t_step <= 0.0) || s.l_step < 0.05 || (i > 0 && s.leg == run.steps[i - 1].leg)) {
      break;
    }
    m.steps = static_cast<int>(i) + 1;
  }
  const int n = std::min(window, m.steps - 1);  // never the unmeasured first step
  if (n <= 0) return run;
  double v_min = std::numeric_limits<double>::infinity(), v_max = -v_min;
  double l_min = v_min, l_max = -v_min;
  for (int i = m.steps - n; i < m.steps; ++i) {
    const StepRecord& s = run.steps[i];
    m.v_m += s.v_m / n;
    m.l_step += s.l_step / n;
    m.t_step += s.t_step / n;
    v_min = std::min(v_min, s.v_m);
    v_max = std::max(v_max, s.v_m);
    l_min = std::min(l_min, s.l_step);
    l_max = std::max(l_max, s.l_step);
  }
  m.v_m_spread = v_max - v_min;
  m.l_step_spread = l_max - l_min;
  return run;
}

std::vector<SwingSample> AverageSwingTrajectory(const GaitRun& run, int window, int bins) {
  std::vector<SwingSample> out;
  const int steps = run.metrics.steps;
  const int n = std::min(window, steps - 1);
  if (n <= 0 || bins < 2 || run.sim.samples.empty()) return out;
  const double period =
      run.sim.samples.size() > 1 ? run.sim.samples[1].t - run.sim.samples[0].t : 1.0;
  // The swings of the last n steps: between touchdown k-1 and touchdown k, leg steps[k].leg
  // swings and the other leg stands.
  struct Swing {
    std::vector<SwingSample> samples;  // in time order
  };
  std::vector<Swing> swings;
  double e_lo = -std::numeric_limits<double>::infinity();
  double e_hi = std::numeric_limits<double>::infinity();
  for (int k = steps - n; k < steps; ++k) {
    const StepRecord& from = run.steps[k - 1];
    const StepRecord& to = run.steps[k];
    const int sw = to.leg, st = 1 - sw;
    const auto first = static_cast<size_t>(std::lround(from.t_touchdown / period));
    const auto last = static_cast<size_t>(std::lround(to.t_touchdown / period));
    Swing swing;
    for (size_t i = first; i < last && i < run.sim.samples.size(); ++i) {
      const SimSample& s = run.sim.samples[i];
      swing.samples.push_back(
          {s.q[3 + 2 * st], s.q[3 + 2 * sw], s.q[4 + 2 * sw], s.qd[3 + 2 * sw], s.qd[4 + 2 * sw]});
    }
    if (swing.samples.size() < 2) return out;
    double lo = swing.samples.front().e, hi = lo;
    for (const SwingSample& s : swing.samples) {
      lo = std::min(lo, s.e);
      hi = std::max(hi, s.e);
    }
    e_lo = std::max(e_lo, lo);
    e_hi = std::min(e_hi, hi);
    swings.push_back(std::move(swing));
  }
  if (!(e_hi > e_lo)) return out;
  // e falls monotonically through a swing (the stance leg rotates backward under the hip); each
  // swing is resampled by linear interpolation between the samples that bracket each bin.
  out.resize(bins);
  for (int b = 0; b < bins; ++b) out[b].e = e_lo + (e_hi - e_lo) * b / (bins - 1);
  for (const Swing& swing : swings) {
    for (int b = 0; b < bins; ++b) {
      const double e = out[b].e;
      for (size_t i = 1; i < swing.samples.size(); ++i) {
        const SwingSample& a = swing.samples[i - 1];
        const SwingSample& c = swing.samples[i];
        if ((a.e - e) * (c.e - e) > 0.0 || a.e == c.e) continue;
        const double w = (e - a.e) / (c.e - a.e);
        out[b].q1 += (a.q1 + w * (c.q1 - a.q1)) / n;
        out[b].q2 += (a.q2 + w * (c.q2 - a.q2)) / n;
        out[b].qd1 += (a.qd1 + w * (c.qd1 - a.qd1)) / n;
        out[b].qd2 += (a.qd2 + w * (c.qd2 - a.qd2)) / n;
        break;
      }
    }
  }
  return out;
}

void SplitSwing(const std::vector<SwingSample>& swing, std::vector<double>* e,
                std::array<std::vector<double>, 4>* outputs) {
  e->clear();
  for (std::vector<double>& o : *outputs) o.clear();
  for (const SwingSample& s : swing) {
    e->push_back(s.e);
    (*outputs)[0].push_back(s.q1);
    (*outputs)[1].push_back(s.q2);
    (*outputs)[2].push_back(s.qd1);
    (*outputs)[3].push_back(s.qd2);
  }
}

}  // namespace rabbit
