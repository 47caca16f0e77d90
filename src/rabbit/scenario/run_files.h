// The CSV files of a batch run (the report's data; the HTML page is built from them afterwards):
//   DIR/summary.csv          one row per run (SummaryColumns())
//   DIR/<run>/meta.csv       key,value: scenario, variant, description, link lengths, period,
//                            velocity profile, start gait, seed, pushes, noise, outcome
//   DIR/<run>/trajectory.csv the recorded samples (rabbit/scenario/trajectory_csv.h)
//   DIR/<run>/steps.csv      step,leg,t_s,x_m,v_d_m_s,v_m_m_s,v_m_used_m_s,l_step_m,t_step_s,
//                            d_obs_m,q0_d_deg,w_O1..w_ON,rules,warmup
//   DIR/<run>/tracking.csv   t_s,stance_leg,e_rad,q_sw1_d_rad,q_sw1_rad,q_sw2_d_rad,q_sw2_rad,
//                            q0_d_rad,q0_rad (legs 1-based; references nan when none)
//   DIR/<run>/terrain.csv    x_start_m,length_m,height_m,base_m: the obstacles (base_m: the
//                            ground's height under them)
//   DIR/<run>/ground.csv     x_start_m,slope_deg,height_m: the ground profile's breakpoints
//                            (slope from x_start on, positive descending; height at x_start);
//                            no rows: flat ground y = 0
#ifndef RABBIT_SCENARIO_RUN_FILES_H_
#define RABBIT_SCENARIO_RUN_FILES_H_

#include <string>
#include <vector>

#include "rabbit/scenario/run.h"

namespace rabbit {

// Writes the run's folder DIR/<run.run>/ (each file atomically).
void WriteRunFiles(const Scenario& scenario, const RunOutput& run, const std::string& dir);

// One summary.csv row of a run (no newline), and the header.
std::string SummaryHeader();
std::string SummaryRow(const std::string& suite, const RunOutput& run);
// Columns that are not deterministic (excluded when comparing runs).
const std::vector<std::string>& WallTimeColumns();

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_RUN_FILES_H_
