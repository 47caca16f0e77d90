// Reading a report folder: the CSV files a batch run wrote (summary.csv and per run meta.csv,
// trajectory.csv, steps.csv, tracking.csv, terrain.csv, ground.csv) parsed into RunData, grouped by
// scenario; plus what the figures and the page share about runs (variant names and colours,
// sampling the trajectory). Implementation details of WriteSuiteReport (suite_report.h).
#ifndef RABBIT_REPORT_REPORT_DATA_H_
#define RABBIT_REPORT_REPORT_DATA_H_

#include <array>
#include <cstddef>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "rabbit/contact/terrain.h"
#include "rabbit/report/suite_report.h"

namespace rabbit {
namespace report_internal {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------------
// What the run wrote.

struct SummaryRow {
  int line = 0;
  std::string suite, scenario, variant, run, controller, outcome, reason;
  // The head-to-head group: the scenario's family (the `family` column), or the scenario itself
  // when it is a plain one. Summaries without the column (written before it) take the family from
  // a member's name, <family>-<3 or more digits>.
  std::string group;
  bool is_family_member = false;
  bool passed = false;
  std::vector<std::string> failed;
  double duration = kNan, distance = kNan, steps = kNan, mean_speed_error = kNan,
         final_speed_error = kNan, l_mean = kNan, l_min = kNan, l_max = kNan, l_spread = kNan,
         saturation = kNan, energy = kNan, cost_of_transport = kNan, wall = kNan,
         real_time_factor = kNan;
  double pattern_memory_bytes = kNan;  // nan: a summary without the column
};

struct Trajectory {
  std::vector<double> t;
  std::vector<std::array<double, 7>> q;
  std::vector<int> contact;  // bit 0: foot 1 on the ground, bit 1: foot 2 (empty: not recorded)
};

struct Step {
  int step = 0, leg = 0;
  double t = 0.0, v_d = kNan, v_m = kNan, l_step = kNan, t_step = kNan, d_obs = kNan,
         q0_d_deg = kNan;
  std::vector<double> w;
  std::string rules;
};

struct Tracking {
  std::vector<double> t, hip_d, hip, knee_d, knee, q0_d, q0;
  std::vector<int> stance;
};

struct RunData {
  SummaryRow row;
  std::string folder;
  std::string description;
  LinkLengths lengths;
  Trajectory trajectory;
  std::vector<Step> steps;
  // The weights' legends: the reference gaits' names from meta.csv's weight_gaits, or the
  // columns' names (w_O1, ...) in a folder written without it.
  std::vector<std::string> weight_names;
  std::vector<std::string> weight_gaits;  // meta.csv's weight_gaits (empty: none, or absent)
  Tracking tracking;
  Terrain terrain;  // obstacles (terrain.csv) and ground profile (ground.csv)
};

// The run a scenario's figures are drawn for (its main variant: the run named after the scenario,
// whatever its controller); baselines are overlaid on it.
bool IsMainRun(const SummaryRow& row);

struct ScenarioGroup {
  std::string name;
  std::vector<size_t> runs;  // into the runs; the main variant first
};

// DIR/summary.csv, one row per run; throws InputError for a malformed file or row (an unsafe or
// repeated run folder name included).
std::vector<SummaryRow> ReadSummary(const std::string& path);

// The files of the run in dir / row.run; a warning per trajectory with rows left out (`nan`
// coordinates) is appended to *warnings (may be null).
RunData ReadRun(const std::filesystem::path& dir, const SummaryRow& row,
                std::vector<std::string>* warnings);

// The runs grouped by scenario, in order of first appearance; the main variant first in each.
std::vector<ScenarioGroup> GroupByScenario(const std::vector<RunData>& runs);

// ---------------------------------------------------------------------------------------------
// Naming and colouring variants.

std::string VariantLabel(const std::string& variant);
// A run's label: the variant's, without "(baseline)" for a scenario's main run.
std::string RunLabel(const SummaryRow& row);
std::string RunShortLabel(const SummaryRow& row);
// The same without "(baseline)", for the summary table (where baselines are in italics).
std::string VariantShortLabel(const std::string& variant);
std::string VariantColor(const std::string& variant);

// ---------------------------------------------------------------------------------------------
// Sampling a run.

// q at time t, linearly interpolated between the samples around it (clamped to the ends); tr
// must not be empty. *hint is the sample index to search from (updated); *contact (may be null)
// gets the contact bits of the sample used.
std::array<double, 7> QAt(const Trajectory& tr, double t, size_t* hint, int* contact);

}  // namespace report_internal
}  // namespace rabbit

#endif  // RABBIT_REPORT_REPORT_DATA_H_
