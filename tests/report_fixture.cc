#include "report_fixture.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "cli_fixture.h"
#include "rabbit/gait/gait_database.h"
#include "rabbit/gait/gait_walk.h"
#include "rabbit/scenario/trajectory_csv.h"

namespace rabbit::testing {
namespace {

namespace fs = std::filesystem;

struct RunSpec {
  std::string run, scenario, variant, gait;
  bool obstacle = false;
  bool passed = true;
  std::string failed;  // the summary's cell, verbatim (may be quoted)
};

const double kObstacleX = 2.0, kObstacleLength = 0.2, kObstacleHeight = 0.02;
const int kDecimation = 10;  // 1 kHz -> 100 Hz, as `rabbit run` writes
// The reference gaits' measured V_M (gaits/reference/index.csv), the centres of the fuzzy V_M triangles.
const double kGaitSpeeds[5] = {0.390, 0.491, 0.585, 0.695, 0.807};

std::string Num(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

// Normalised triangle memberships of v on the reference speeds (shoulders at both ends).
std::vector<double> Weights(double v) {
  std::vector<double> w(5, 0.0);
  if (!(v > kGaitSpeeds[0])) {
    w[0] = 1.0;
  } else if (v >= kGaitSpeeds[4]) {
    w[4] = 1.0;
  } else {
    for (int k = 0; k < 4; ++k) {
      if (v >= kGaitSpeeds[k] && v < kGaitSpeeds[k + 1]) {
        const double a = (v - kGaitSpeeds[k]) / (kGaitSpeeds[k + 1] - kGaitSpeeds[k]);
        w[k] = 1.0 - a;
        w[k + 1] = a;
      }
    }
  }
  return w;
}

void WriteRun(const RunSpec& spec, double duration, const fs::path& dir, std::string* summary) {
  const GaitRecord gait =
      ReadGaitFile(std::string(RABBIT_SOURCE_DIR) + "/gaits/reference/" + spec.gait + ".csv");
  const Model model{ModelParams{}};
  SimSetup setup;
  setup.model = &model;
  const GaitRun walk = WalkGait(setup, gait.spec, duration, 10);
  const bool fuzzy = spec.variant != "pragmatic";
  const double v_d = gait.target_v_m;
  const fs::path run_dir = dir / spec.run;
  fs::create_directories(run_dir);

  SimResult decimated;
  decimated.outcome = walk.sim.outcome;
  for (size_t i = 0; i < walk.sim.samples.size(); i += kDecimation) {
    decimated.samples.push_back(walk.sim.samples[i]);
  }
  std::ostringstream trajectory;
  WriteTrajectoryCsv(decimated, trajectory);
  WriteText((run_dir / "trajectory.csv").string(), trajectory.str());

  const ModelParams& p = model.params();
  WriteText((run_dir / "meta.csv").string(),
            "key,value\nscenario," + spec.scenario + "\nvariant," + spec.variant +
                "\ndescription,\"Walk at " + Num(v_d) + " m/s, re-walked from gait " + spec.gait +
                " (test fixture)\"\nthigh_length_m," + Num(p.thigh_length) + "\nshin_length_m," +
                Num(p.shin_length) + "\ntrunk_length_m," + Num(p.trunk_length) +
                "\ncontrol_period_s,0.001\n");

  std::string terrain = "x_start_m,length_m,height_m\n";
  if (spec.obstacle) {
    terrain += Num(kObstacleX) + "," + Num(kObstacleLength) + "," + Num(kObstacleHeight) + "\n";
  }
  WriteText((run_dir / "terrain.csv").string(), terrain);

  std::string steps =
      "step,leg,t_s,v_d_m_s,v_m_m_s,l_step_m,t_step_s,d_obs_m,q0_d_deg,w_O1,w_O2,w_O3,w_O4,w_O5,"
      "rules\n";
  double l_sum = 0.0, l_min = 1e9, l_max = -1e9, error_sum = 0.0, last_error = NAN;
  int measured = 0;
  for (const StepRecord& s : walk.steps) {
    const double v_m = s.t_step > 0.0 ? s.v_m : NAN;
    // The stance foot's distance to the obstacle's near edge (infinite once past it).
    const double foot_x =
        walk.sim
            .samples[std::min(walk.sim.samples.size() - 1,
                              static_cast<size_t>(std::lround(s.t_touchdown / 0.001)))]
            .foot_pos[s.leg]
            .x();
    const double d_obs = !spec.obstacle         ? INFINITY
                         : foot_x <= kObstacleX ? kObstacleX - foot_x
                                                : INFINITY;
    std::vector<double> w = Weights(std::isfinite(v_m) ? v_m : v_d);
    std::string rules;
    for (int k = 0; k < 5; ++k) {
      if (w[k] > 0.0) {
        static const char* const kSets[5] = {"VerySmall", "Small", "Medium", "Big", "VeryBig"};
        rules += (rules.empty() ? "" : ";") + std::string("VeryBig/") + kSets[k] + ":" +
                 Num(std::round(w[k] * 1000.0) / 1000.0);
      }
    }
    if (!fuzzy) {
      w.assign(5, NAN);
      rules.clear();
    }
    steps += std::to_string(s.index) + "," + std::to_string(s.leg + 1) + "," + Num(s.t_touchdown) +
             "," + Num(v_d) + "," + Num(v_m) + "," + Num(s.l_step) + "," + Num(s.t_step) + "," +
             Num(d_obs) + "," + Num(gait.spec.rules.q0_d * 180.0 / M_PI);
    for (double x : w) steps += "," + Num(x);
    steps += "," + rules + "\n";
    l_sum += s.l_step;
    l_min = std::min(l_min, s.l_step);
    l_max = std::max(l_max, s.l_step);
    if (std::isfinite(v_m)) {
      last_error = std::abs(v_m - v_d);
      error_sum += last_error;
      ++measured;
    }
  }
  WriteText((run_dir / "steps.csv").string(), steps);

  std::string tracking =
      "t_s,stance_leg,e_rad,q_sw1_d_rad,q_sw1_rad,q_sw2_d_rad,q_sw2_rad,q0_d_rad,"
      "q0_rad\n";
  for (const SimSample& s : decimated.samples) {
    const int stance = s.foot_pos[0].y() <= s.foot_pos[1].y() ? 0 : 1;  // the lower foot
    const int swing = 1 - stance;
    const double hip = s.q[3 + 2 * swing], knee = s.q[4 + 2 * swing];
    const double hip_d = fuzzy ? hip + 0.03 * std::sin(7.0 * s.t) : NAN;
    const double knee_d = fuzzy ? knee - 0.04 * std::cos(5.0 * s.t) : NAN;
    tracking += Num(s.t) + "," + std::to_string(stance + 1) + "," + Num(s.q[3 + 2 * stance]) + "," +
                Num(hip_d) + "," + Num(hip) + "," + Num(knee_d) + "," + Num(knee) + "," +
                Num(gait.spec.rules.q0_d) + "," + Num(s.q[2]) + "\n";
  }
  WriteText((run_dir / "tracking.csv").string(), tracking);

  const double n = static_cast<double>(walk.steps.size());
  const double distance = walk.sim.samples.back().q[0] - walk.sim.samples.front().q[0];
  *summary += "suite_fixture," + spec.scenario + "," + spec.variant + "," + spec.run + "," +
              (fuzzy ? "fuzzy_cmac" : "pragmatic") + ",completed,," + (spec.passed ? "1" : "0") +
              "," + spec.failed + "," + Num(walk.sim.t_end) + "," + Num(distance) + "," +
              std::to_string(walk.steps.size()) + "," +
              Num(measured > 0 ? error_sum / measured : NAN) + "," + Num(last_error) + "," +
              Num(l_sum / n) + "," + Num(l_min) + "," + Num(l_max) + "," + Num(l_max - l_min) +
              "," + Num(walk.metrics.saturation_time) + ",123.4,0.21,0.05,240\n";
}

}  // namespace

void WriteText(const std::string& path, const std::string& text) {
  const fs::path p(path);
  if (p.has_parent_path()) fs::create_directories(p.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::string ReadText(const std::string& path) { return ReadText(fs::path(path)); }

int Count(const std::string& text, const std::string& needle) {
  int n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) {
    ++n;
  }
  return n;
}

ReportFixture WriteReportFixture(const std::string& dir, double duration) {
  fs::create_directories(dir);
  const std::vector<RunSpec> specs = {
      {"walk", "walk", "fuzzy_cmac", "vm_0.60", false, true, ""},
      {"walk+pragmatic", "walk", "pragmatic", "vm_0.50", false, false,
       "\"mean speed error 0.09 m/s > 0.03 m/s; L_step spread, last 10 steps, 2 mm\""},
      {"obstacle", "obstacle", "fuzzy_cmac", "vm_0.70", true, true, ""},
  };
  std::string summary =
      "suite,scenario,variant,run,controller,outcome,reason,passed,failed_criteria,duration_s,"
      "distance_m,steps,mean_abs_speed_error_m_s,final_abs_speed_error_m_s,l_step_mean_m,"
      "l_step_min_m,l_step_max_m,l_step_spread_m,saturation_s,energy_j,cost_of_transport,wall_s,"
      "real_time_factor\n";
  ReportFixture fixture;
  fixture.dir = dir;
  for (const RunSpec& spec : specs) {
    WriteRun(spec, duration, dir, &summary);
    fixture.runs.push_back(spec.run);
  }
  WriteText((fs::path(dir) / "summary.csv").string(), summary);
  // walk: stick diagram at the start, per-step plot, tracking, weights; obstacle: the same and a
  // stick diagram around the obstacle; the head-to-head's overview of the two scenarios.
  fixture.expected_figures = 4 + 5 + 1;
  return fixture;
}

}  // namespace rabbit::testing
