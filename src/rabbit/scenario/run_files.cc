#include "rabbit/scenario/run_files.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv.h"
#include "rabbit/scenario/trajectory_csv.h"

namespace rabbit {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

// "start_s:duration_s:force_x_n:force_y_n:height_m;..." (empty: none); an event-timed push's
// start is when its event came in the run (nan: never).
std::string PushesText(const std::vector<TrunkPush>& pushes, const std::vector<double>& starts) {
  std::string out;
  for (size_t i = 0; i < pushes.size(); ++i) {
    const TrunkPush& p = pushes[i];
    const double start = i < starts.size() ? starts[i] : p.start;
    if (!out.empty()) out += ';';
    out += FormatCsvNumber(start) + ':' + FormatCsvNumber(p.duration) + ':' +
           FormatCsvNumber(p.force.x()) + ':' + FormatCsvNumber(p.force.y()) + ':' +
           FormatCsvNumber(p.height);
  }
  return out;
}

// The reference gaits of the weights columns, `;`-separated (gait names never hold one).
std::string WeightGaitsText(const std::vector<std::string>& gaits) {
  std::string text;
  for (const std::string& g : gaits) text += (text.empty() ? "" : ";") + g;
  return text;
}

}  // namespace

void WriteRunFiles(const Scenario& scenario, const RunOutput& run, const std::string& dir) {
  namespace fs = std::filesystem;
  const fs::path base = fs::path(dir) / run.run;
  const ModelParams& m = scenario.model;
  WriteFileAtomically((base / "meta.csv").string(), [&](std::ostream& out) {
    out << "key,value\n"
        << "scenario," << FormatCsvCell(run.scenario) << "\nvariant," << run.variant
        << "\ndescription," << FormatCsvCell(scenario.description) << "\nthigh_length_m,"
        << FormatCsvNumber(m.thigh_length) << "\nshin_length_m," << FormatCsvNumber(m.shin_length)
        << "\ntrunk_length_m," << FormatCsvNumber(m.trunk_length) << "\ncontrol_period_s,"
        << FormatCsvNumber(scenario.options.control_period) << "\nvelocity_profile,"
        << VelocityProfileKindName(scenario.velocity.kind) << "\nstart_gait,"
        << FormatCsvCell(scenario.start_gait) << "\nseed," << scenario.seed << "\npushes,"
        << FormatCsvCell(PushesText(scenario.pushes, run.sim.push_starts)) << "\nv_m_noise_std_m_s,"
        << FormatCsvNumber(scenario.walker.v_m_noise) << "\nd_obs_noise_std_m,"
        << FormatCsvNumber(scenario.walker.d_obs_noise) << "\noutcome,"
        << OutcomeName(run.sim.outcome) << "\nreason," << FormatCsvCell(run.sim.reason)
        << "\nweight_gaits," << FormatCsvCell(WeightGaitsText(run.weight_gaits)) << "\n";
  });
  WriteTrajectoryCsvFile(run.sim, (base / "trajectory.csv").string());
  size_t gaits = 0;
  for (const StepRow& s : run.steps) gaits = std::max(gaits, s.weights.size());
  WriteFileAtomically((base / "steps.csv").string(), [&](std::ostream& out) {
    out << "step,leg,t_s,x_m,v_d_m_s,v_m_m_s,v_m_used_m_s,l_step_m,t_step_s,d_obs_m,q0_d_deg";
    for (size_t k = 1; k <= gaits; ++k) out << ",w_O" << k;
    out << ",rules,warmup\n";
    for (const StepRow& s : run.steps) {
      const bool measured = s.step.t_step > 0.0;
      out << s.step.index << ',' << s.step.leg + 1 << ',' << FormatCsvNumber(s.step.t_touchdown)
          << ',' << FormatCsvNumber(s.step.x) << ',' << FormatCsvNumber(s.v_d) << ','
          << (measured ? FormatCsvNumber(s.step.v_m) : "nan") << ','
          << (measured ? FormatCsvNumber(s.v_m_used) : "nan") << ','
          << FormatCsvNumber(s.step.l_step) << ','
          << (measured ? FormatCsvNumber(s.step.t_step) : "nan") << ',' << FormatCsvNumber(s.d_obs)
          << ',' << FormatCsvNumber(s.q0_d * kRadToDeg);
      for (size_t k = 0; k < gaits; ++k) {
        out << ',' << (k < s.weights.size() ? FormatCsvNumber(s.weights[k]) : "nan");
      }
      out << ',' << FormatCsvCell(s.rules) << ',' << (s.warmup ? 1 : 0) << '\n';
    }
  });
  WriteFileAtomically((base / "tracking.csv").string(), [&](std::ostream& out) {
    out << "t_s,stance_leg,e_rad,q_sw1_d_rad,q_sw1_rad,q_sw2_d_rad,q_sw2_rad,q0_d_rad,q0_rad\n";
    for (const WalkerTrack& t : run.tracking) {
      out << FormatCsvNumber(t.t) << ',' << t.stance + 1 << ',' << FormatCsvNumber(t.e) << ','
          << FormatCsvNumber(t.hip_ref) << ',' << FormatCsvNumber(t.hip) << ','
          << FormatCsvNumber(t.knee_ref) << ',' << FormatCsvNumber(t.knee) << ','
          << FormatCsvNumber(t.q0_d) << ',' << FormatCsvNumber(t.q0) << '\n';
    }
  });
  const Terrain& terrain = scenario.terrain;
  WriteFileAtomically((base / "terrain.csv").string(), [&](std::ostream& out) {
    out << "x_start_m,length_m,height_m,base_m\n";
    for (size_t i = 0; i < terrain.obstacles.size(); ++i) {
      const Obstacle& o = terrain.obstacles[i];
      out << FormatCsvNumber(o.x_start) << ',' << FormatCsvNumber(o.length) << ','
          << FormatCsvNumber(o.height) << ','
          << FormatCsvNumber(terrain.ObstacleBase(static_cast<int>(i))) << '\n';
    }
  });
  WriteFileAtomically((base / "ground.csv").string(), [&](std::ostream& out) {
    out << "x_start_m,slope_deg,height_m,rise_m\n";
    for (const SlopeBreak& b : terrain.ground.breaks()) {
      out << FormatCsvNumber(b.x_start) << ',' << FormatCsvNumber(b.slope * 180.0 / M_PI) << ','
          << FormatCsvNumber(terrain.GroundHeight(b.x_start)) << ',' << FormatCsvNumber(b.rise)
          << '\n';
    }
  });
}

std::string SummaryHeader() {
  return "suite,scenario,variant,run,controller,outcome,reason,passed,required,failed_criteria,"
         "duration_s,"
         "distance_m,steps,mean_abs_speed_error_m_s,final_abs_speed_error_m_s,l_step_mean_m,"
         "l_step_min_m,l_step_max_m,l_step_spread_m,saturation_s,energy_j,cost_of_transport,"
         "pattern_memory_bytes,family,wall_s,real_time_factor";
}

const std::vector<std::string>& WallTimeColumns() {
  static const std::vector<std::string> columns = {"wall_s", "real_time_factor"};
  return columns;
}

std::string SummaryRow(const std::string& suite, const RunOutput& run) {
  std::string failed;
  for (const std::string& f : run.failures) failed += (failed.empty() ? "" : ";") + f;
  const RunMetrics& m = run.metrics;
  std::ostringstream out;
  out << FormatCsvCell(suite) << ',' << FormatCsvCell(run.scenario) << ',' << run.variant << ','
      << FormatCsvCell(run.run) << ',' << run.controller << ',' << OutcomeName(run.sim.outcome)
      << ',' << FormatCsvCell(run.sim.reason) << ',' << (run.passed ? 1 : 0) << ','
      << (run.required ? 1 : 0) << ',' << FormatCsvCell(failed) << ',' << FormatCsvNumber(m.duration) << ','
      << FormatCsvNumber(m.distance) << ',' << m.steps << ','
      << FormatCsvNumber(m.mean_abs_speed_error) << ',' << FormatCsvNumber(m.final_abs_speed_error)
      << ',' << FormatCsvNumber(m.l_step_mean) << ',' << FormatCsvNumber(m.l_step_min) << ','
      << FormatCsvNumber(m.l_step_max) << ',' << FormatCsvNumber(m.l_step_spread) << ','
      << FormatCsvNumber(m.saturation) << ',' << FormatCsvNumber(m.energy) << ','
      << FormatCsvNumber(m.cost_of_transport) << ',' << m.pattern_memory_bytes << ','
      << FormatCsvCell(run.family) << ',' << FormatCsvNumber(run.wall) << ','
      << FormatCsvNumber(run.wall > 0.0 ? m.duration / run.wall : std::nan(""));
  return out.str();
}

}  // namespace rabbit
