// Reading a report folder into RunData (report_data.h).
#include "rabbit/report/report_data.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <regex>
#include <sstream>
#include <utility>

#include "rabbit/io/csv.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/io/key_value_csv.h"

namespace rabbit {
namespace report_internal {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> SplitOn(const std::string& text, char separator) {
  std::vector<std::string> out;
  std::string cell;
  std::istringstream in(text);
  while (std::getline(in, cell, separator)) {
    cell = Trim(cell);
    if (!cell.empty()) out.push_back(cell);
  }
  return out;
}

bool IsSafeFolderName(const std::string& name) {
  return !name.empty() && name != "." && name != ".." &&
         name.find_first_of("/\\") == std::string::npos && name.find('\0') == std::string::npos;
}

}  // namespace

bool IsMainRun(const SummaryRow& row) { return row.run == row.scenario; }

std::vector<SummaryRow> ReadSummary(const std::string& path) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_suite = table.Column("suite"), c_scenario = table.Column("scenario"),
               c_variant = table.Column("variant"), c_run = table.Column("run"),
               c_controller = table.Column("controller"), c_outcome = table.Column("outcome"),
               c_reason = table.Column("reason"), c_passed = table.Column("passed"),
               c_failed = table.Column("failed_criteria");
  const char* const kNumbers[] = {"duration_s",
                                  "distance_m",
                                  "steps",
                                  "mean_abs_speed_error_m_s",
                                  "final_abs_speed_error_m_s",
                                  "l_step_mean_m",
                                  "l_step_min_m",
                                  "l_step_max_m",
                                  "l_step_spread_m",
                                  "saturation_s",
                                  "energy_j",
                                  "cost_of_transport",
                                  "wall_s",
                                  "real_time_factor"};
  std::vector<size_t> numbers;
  for (const char* name : kNumbers) numbers.push_back(table.Column(name));
  // Columns added later: optional, so that older reports still rebuild.
  const bool has_family = table.HasColumn("family");
  const size_t c_family = has_family ? table.Column("family") : 0;
  const bool has_memory = table.HasColumn("pattern_memory_bytes");
  const size_t c_memory = has_memory ? table.Column("pattern_memory_bytes") : 0;
  static const std::regex kMemberName("(.+)-[0-9]{3,}");
  std::vector<SummaryRow> rows;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    SummaryRow row;
    row.line = table.line(r);
    row.suite = table.Text(r, c_suite);
    row.scenario = table.Text(r, c_scenario);
    row.variant = table.Text(r, c_variant);
    row.run = table.Text(r, c_run);
    row.controller = table.Text(r, c_controller);
    row.outcome = table.Text(r, c_outcome);
    row.reason = table.Text(r, c_reason);
    row.failed = SplitOn(table.Text(r, c_failed), ';');
    row.passed = table.Flag(r, c_passed) == 1;
    if (row.scenario.empty()) throw InputError(path, row.line, "scenario", "empty scenario name");
    if (row.variant.empty()) throw InputError(path, row.line, "variant", "empty variant");
    if (!IsSafeFolderName(row.run)) {
      throw InputError(path, row.line, "run",
                       "\"" + row.run + "\" is not a folder name inside the report directory");
    }
    for (const SummaryRow& seen : rows) {
      if (seen.run == row.run) {
        throw InputError(path, row.line, "run",
                         "run \"" + row.run + "\" also on line " + std::to_string(seen.line));
      }
    }
    double* const fields[] = {&row.duration,
                              &row.distance,
                              &row.steps,
                              &row.mean_speed_error,
                              &row.final_speed_error,
                              &row.l_mean,
                              &row.l_min,
                              &row.l_max,
                              &row.l_spread,
                              &row.saturation,
                              &row.energy,
                              &row.cost_of_transport,
                              &row.wall,
                              &row.real_time_factor};
    for (size_t k = 0; k < numbers.size(); ++k) {
      *fields[k] = table.Number(r, numbers[k], CsvNumber::kAny);
    }
    if (has_memory) {
      row.pattern_memory_bytes = table.Number(r, c_memory, CsvNumber::kFiniteOrNan);
      if (row.pattern_memory_bytes < 0.0) {
        throw InputError(path, row.line, "pattern_memory_bytes", "must not be negative");
      }
    }
    std::smatch member;
    const std::string family = has_family ? table.Text(r, c_family)
                               : std::regex_match(row.scenario, member, kMemberName)
                                   ? member[1].str()
                                   : "";
    row.is_family_member = !family.empty();
    row.group = row.is_family_member ? family : row.scenario;
    rows.push_back(row);
  }
  return rows;
}

namespace {

void ReadMeta(const std::string& path, RunData* run) {
  const KeyValueCsv meta = KeyValueCsv::Read(path);
  auto length = [&](const char* key) {
    const double value = meta.Number(key);
    if (!(value > 0.0)) throw InputError(path, meta.line(key), key, "must be positive");
    return value;
  };
  run->lengths.thigh = length("thigh_length_m");
  run->lengths.shin = length("shin_length_m");
  run->lengths.trunk = length("trunk_length_m");
  if (meta.Has("description")) run->description = meta.Text("description");
  run->weight_gaits.clear();
  if (meta.Has("weight_gaits")) {
    std::stringstream list(meta.Text("weight_gaits"));
    for (std::string name; std::getline(list, name, ';');) run->weight_gaits.push_back(name);
  }
}

// Rows whose coordinates are missing (`nan`: a run that diverged) are left out and counted.
int ReadTrajectory(const std::string& path, Trajectory* trajectory) {
  const CsvTable table = CsvTable::Read(path);
  const char* const kCoords[] = {"x_m",     "y_m",     "q0_rad", "q11_rad",
                                 "q12_rad", "q21_rad", "q22_rad"};
  const size_t c_t = table.Column("t_s");
  std::array<size_t, 7> c_q{};
  for (int i = 0; i < 7; ++i) c_q[i] = table.Column(kCoords[i]);
  const bool has_contact = table.HasColumn("foot1_contact") && table.HasColumn("foot2_contact");
  const size_t c_contact1 = has_contact ? table.Column("foot1_contact") : 0;
  const size_t c_contact2 = has_contact ? table.Column("foot2_contact") : 0;
  int skipped = 0;
  double previous = -std::numeric_limits<double>::infinity();
  for (size_t r = 0; r < table.num_rows(); ++r) {
    const double t = table.Number(r, c_t);
    if (t < previous) throw InputError(path, table.line(r), "t_s", "time decreases");
    previous = t;
    std::array<double, 7> q;
    bool finite = true;
    for (int i = 0; i < 7; ++i) {
      q[i] = table.Number(r, c_q[i], CsvNumber::kFiniteOrNan);
      finite = finite && std::isfinite(q[i]);
    }
    if (!finite) {
      ++skipped;
      continue;
    }
    trajectory->t.push_back(t);
    trajectory->q.push_back(q);
    if (has_contact) {
      trajectory->contact.push_back((table.Number(r, c_contact1) > 0.0 ? 1 : 0) |
                                    (table.Number(r, c_contact2) > 0.0 ? 2 : 0));
    }
  }
  return skipped;
}

void ReadSteps(const std::string& path, RunData* run) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_step = table.Column("step"), c_leg = table.Column("leg"),
               c_t = table.Column("t_s"), c_v_d = table.Column("v_d_m_s"),
               c_v_m = table.Column("v_m_m_s"), c_l = table.Column("l_step_m"),
               c_t_step = table.Column("t_step_s"), c_d_obs = table.Column("d_obs_m");
  const bool has_q0_d = table.HasColumn("q0_d_deg"), has_rules = table.HasColumn("rules");
  const size_t c_q0_d = has_q0_d ? table.Column("q0_d_deg") : 0;
  const size_t c_rules = has_rules ? table.Column("rules") : 0;
  const std::vector<size_t> c_w = table.ColumnsWithPrefix("w_O");
  // The gaits' names when meta.csv lists one per weight column, else the columns' own.
  const bool named = run->weight_gaits.size() == c_w.size();
  run->weight_names.clear();
  for (size_t k = 0; k < c_w.size(); ++k) {
    run->weight_names.push_back(named ? run->weight_gaits[k] : table.header()[c_w[k]]);
  }
  for (size_t r = 0; r < table.num_rows(); ++r) {
    Step s;
    s.step = table.Integer(r, c_step);
    s.leg = table.Integer(r, c_leg);
    if (s.leg != 1 && s.leg != 2) {
      throw InputError(path, table.line(r), "leg", "expected 1 or 2, got " + table.Text(r, c_leg));
    }
    s.t = table.Number(r, c_t);
    s.v_d = table.Number(r, c_v_d, CsvNumber::kFiniteOrNan);
    s.v_m = table.Number(r, c_v_m, CsvNumber::kFiniteOrNan);
    s.l_step = table.Number(r, c_l, CsvNumber::kFiniteOrNan);
    s.t_step = table.Number(r, c_t_step, CsvNumber::kFiniteOrNan);
    s.d_obs = table.Number(r, c_d_obs, CsvNumber::kAny);  // inf: no obstacle ahead
    if (has_q0_d) s.q0_d_deg = table.Number(r, c_q0_d, CsvNumber::kFiniteOrNan);
    for (size_t c : c_w) s.w.push_back(table.Number(r, c, CsvNumber::kFiniteOrNan));
    if (has_rules) s.rules = table.Text(r, c_rules);
    run->steps.push_back(std::move(s));
  }
}

void ReadTracking(const std::string& path, Tracking* tracking) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_stance = table.Column("stance_leg");
  table.Column("e_rad");  // required by the format, not drawn
  struct Field {
    const char* name;
    std::vector<double>* values;
  };
  const Field fields[] = {{"q_sw1_d_rad", &tracking->hip_d},  {"q_sw1_rad", &tracking->hip},
                          {"q_sw2_d_rad", &tracking->knee_d}, {"q_sw2_rad", &tracking->knee},
                          {"q0_d_rad", &tracking->q0_d},      {"q0_rad", &tracking->q0}};
  tracking->t = table.Numbers("t_s");
  for (size_t r = 1; r < tracking->t.size(); ++r) {
    if (tracking->t[r] < tracking->t[r - 1]) {
      throw InputError(path, table.line(r), "t_s", "time decreases");
    }
  }
  for (const Field& f : fields) *f.values = table.Numbers(f.name, CsvNumber::kFiniteOrNan);
  for (size_t r = 0; r < table.num_rows(); ++r) {
    const int stance = table.Integer(r, c_stance);
    if (stance < 0 || stance > 2) {
      throw InputError(path, table.line(r), "stance_leg",
                       "expected 1, 2 (or 0: none), got " + table.Text(r, c_stance));
    }
    tracking->stance.push_back(stance);
  }
}

// The ground profile: ground.csv (x_start_m, slope_deg, rise_m; height_m is derived), absent in
// reports written before it existed: flat ground.
GroundProfile ReadGround(const std::string& path) {
  if (!fs::exists(path)) return GroundProfile();
  const CsvTable table = CsvTable::Read(path);
  const size_t c_x = table.Column("x_start_m"), c_slope = table.Column("slope_deg");
  const bool has_rise = table.HasColumn("rise_m");  // written since steps exist
  std::vector<SlopeBreak> breaks;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    SlopeBreak b;
    b.x_start = table.Number(r, c_x);
    b.slope = table.Number(r, c_slope) * M_PI / 180.0;
    if (has_rise) b.rise = table.Number(r, table.Column("rise_m"));
    breaks.push_back(b);
  }
  if (breaks.empty()) return GroundProfile();
  GroundProfile ground(std::move(breaks));
  std::string error;
  if (!ground.IsValid(&error)) throw InputError(path, 0, "", error);
  return ground;
}

void ReadTerrain(const std::string& path, std::vector<Obstacle>* obstacles) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_x = table.Column("x_start_m"), c_length = table.Column("length_m"),
               c_height = table.Column("height_m");
  for (size_t r = 0; r < table.num_rows(); ++r) {
    Obstacle o;
    o.x_start = table.Number(r, c_x);
    o.length = table.Number(r, c_length);
    o.height = table.Number(r, c_height);
    if (!(o.length > 0.0)) throw InputError(path, table.line(r), "length_m", "must be positive");
    if (!(o.height > 0.0)) throw InputError(path, table.line(r), "height_m", "must be positive");
    obstacles->push_back(o);
  }
  std::sort(obstacles->begin(), obstacles->end(),
            [](const Obstacle& a, const Obstacle& b) { return a.x_start < b.x_start; });
}

}  // namespace

RunData ReadRun(const fs::path& dir, const SummaryRow& row, std::vector<std::string>* warnings) {
  RunData run;
  run.row = row;
  const fs::path folder = dir / row.run;
  run.folder = folder.string();
  ReadMeta((folder / "meta.csv").string(), &run);
  const std::string trajectory = (folder / "trajectory.csv").string();
  const int skipped = ReadTrajectory(trajectory, &run.trajectory);
  if (skipped > 0 && warnings != nullptr) {
    warnings->push_back(trajectory + ": " + std::to_string(skipped) +
                        " rows with missing coordinates (nan) left out");
  }
  ReadSteps((folder / "steps.csv").string(), &run);
  ReadTracking((folder / "tracking.csv").string(), &run.tracking);
  ReadTerrain((folder / "terrain.csv").string(), &run.terrain.obstacles);
  run.terrain.ground = ReadGround((folder / "ground.csv").string());
  return run;
}

std::vector<ScenarioGroup> GroupByScenario(const std::vector<RunData>& runs) {
  std::vector<ScenarioGroup> groups;
  for (size_t k = 0; k < runs.size(); ++k) {
    const std::string& name = runs[k].row.scenario;
    auto it = std::find_if(groups.begin(), groups.end(),
                           [&name](const ScenarioGroup& g) { return g.name == name; });
    if (it == groups.end()) {
      groups.push_back({name, {}});
      it = groups.end() - 1;
    }
    it->runs.push_back(k);
  }
  for (ScenarioGroup& g : groups) {
    std::stable_partition(g.runs.begin(), g.runs.end(),
                          [&runs](size_t k) { return IsMainRun(runs[k].row); });
  }
  return groups;
}

std::string VariantLabel(const std::string& variant) {
  if (variant == "fuzzy_cmac") return "Fuzzy-CMAC";
  if (variant == "main") return "main controller";
  if (variant == "pragmatic") return "pragmatic (baseline)";
  if (variant == "nearest_gait") return "nearest gait (baseline)";
  if (variant == "multi_cmac") return "multi-input CMAC (baseline)";
  if (variant == "chapter") return "chapter's walker (baseline)";
  return variant;
}

std::string VariantShortLabel(const std::string& variant) {
  if (variant == "pragmatic") return "pragmatic";
  if (variant == "nearest_gait") return "nearest gait";
  if (variant == "multi_cmac") return "multi-input CMAC";
  if (variant == "chapter") return "chapter's walker";
  return VariantLabel(variant);
}

std::string RunLabel(const SummaryRow& row) {
  if (!IsMainRun(row)) return VariantLabel(row.variant);
  if (row.variant == "pragmatic") return "pragmatic rules";
  if (row.variant == "pd_hold") return "PD hold";
  return VariantLabel(row.variant);
}

std::string RunShortLabel(const SummaryRow& row) {
  return IsMainRun(row) ? RunLabel(row) : VariantShortLabel(row.variant);
}

std::string VariantColor(const std::string& variant) {
  // The Okabe-Ito palette: distinct for the common colour-vision deficiencies.
  if (variant == "fuzzy_cmac" || variant == "main") return "#0072B2";
  if (variant == "pragmatic") return "#E69F00";
  if (variant == "nearest_gait") return "#009E73";
  if (variant == "multi_cmac") return "#CC79A7";
  if (variant == "chapter") return "#D55E00";
  static const char* const kOthers[] = {"#56B4E9", "#000000", "#F0E442", "#999999"};
  size_t h = 0;
  for (char c : variant) h = h * 31 + static_cast<unsigned char>(c);
  return kOthers[h % std::size(kOthers)];
}

// ---------------------------------------------------------------------------------------------
// Sampling a run.

std::array<double, 7> QAt(const Trajectory& tr, double t, size_t* hint, int* contact) {
  size_t j = std::min(*hint, tr.t.size() - 1);
  if (tr.t[j] > t) j = 0;
  while (j + 1 < tr.t.size() && tr.t[j + 1] <= t) ++j;
  *hint = j;
  if (contact != nullptr) *contact = tr.contact.empty() ? 0 : tr.contact[j];
  if (j + 1 >= tr.t.size() || t <= tr.t[j]) return tr.q[j];
  const double a = (t - tr.t[j]) / (tr.t[j + 1] - tr.t[j]);
  std::array<double, 7> q;
  for (int i = 0; i < 7; ++i) q[i] = tr.q[j][i] + a * (tr.q[j + 1][i] - tr.q[j][i]);
  return q;
}

}  // namespace report_internal
}  // namespace rabbit
