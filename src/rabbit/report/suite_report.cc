#include "rabbit/report/suite_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "rabbit/contact/terrain.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/report/gnuplot.h"
#include "rabbit/report/svg.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kRadToDeg = 180.0 / M_PI;
const char* const kMainVariant = "fuzzy_cmac";
const char* const kLegColors[2] = {"#1f77b4", "#d62728"};  // leg 1, leg 2: figures and replay
const char* const kTrunkColor = "#404040";
// Fuzzy weights w_O1, w_O2, ...: the reference gaits from slow to fast (viridis), then others.
const char* const kWeightColors[] = {"#440154", "#3b528b", "#21918c", "#5ec962",
                                     "#fde725", "#e7298a", "#a6761d", "#666666"};

// ---------------------------------------------------------------------------------------------
// What the run wrote.

struct SummaryRow {
  int line = 0;
  std::string suite, scenario, variant, run, controller, outcome, reason;
  bool passed = false;
  std::vector<std::string> failed;
  double duration = kNan, distance = kNan, steps = kNan, mean_speed_error = kNan,
         final_speed_error = kNan, l_mean = kNan, l_min = kNan, l_max = kNan, l_spread = kNan,
         saturation = kNan, energy = kNan, cost_of_transport = kNan, wall = kNan,
         real_time_factor = kNan;
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
  std::vector<std::string> weight_names;  // w_O1, ...
  Tracking tracking;
  std::vector<Obstacle> obstacles;
};

// The variant a scenario's figures are drawn for: the walker, or "main" (a scenario whose
// controller is not the walker); baselines are overlaid on it.
bool IsMainVariant(const std::string& variant) {
  return variant == kMainVariant || variant == "main";
}

struct ScenarioGroup {
  std::string name;
  std::vector<size_t> runs;  // into the runs; the main variant first
};

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
    const std::string passed = table.Text(r, c_passed);
    if (passed == "1" || passed == "true") {
      row.passed = true;
    } else if (passed == "0" || passed == "false") {
      row.passed = false;
    } else {
      throw InputError(path, row.line, "passed", "expected 1 or 0, got \"" + passed + "\"");
    }
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
    rows.push_back(row);
  }
  return rows;
}

void ReadMeta(const std::string& path, RunData* run) {
  const CsvTable table = CsvTable::Read(path);
  const size_t c_key = table.Column("key"), c_value = table.Column("value");
  std::map<std::string, std::pair<std::string, int>> meta;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    meta[table.Text(r, c_key)] = {table.Text(r, c_value), table.line(r)};
  }
  auto length = [&](const char* key) {
    const auto it = meta.find(key);
    if (it == meta.end()) throw InputError(path, 0, key, "missing key");
    const double value = ParseFiniteNumber(it->second.first, path, it->second.second, key);
    if (!(value > 0.0)) throw InputError(path, it->second.second, key, "must be positive");
    return value;
  };
  run->lengths.thigh = length("thigh_length_m");
  run->lengths.shin = length("shin_length_m");
  run->lengths.trunk = length("trunk_length_m");
  const auto description = meta.find("description");
  if (description != meta.end()) run->description = description->second.first;
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
  run->weight_names.clear();
  for (size_t c : c_w) run->weight_names.push_back(table.header()[c]);
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
  ReadTerrain((folder / "terrain.csv").string(), &run.obstacles);
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
                          [&runs](size_t k) { return IsMainVariant(runs[k].row.variant); });
  }
  return groups;
}

// ---------------------------------------------------------------------------------------------
// Formatting.

std::string Printf(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

// A number for gnuplot's data files (NaN for missing and infinite values).
std::string DataNumber(double v) { return std::isfinite(v) ? Printf("%.7g", v) : "NaN"; }

// A number for the replay's JSON: fixed decimals, trailing zeros dropped.
std::string JsonNumber(double v, int decimals) {
  if (!std::isfinite(v)) return "null";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  std::string s = buffer;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

// A table cell's number: "-" for missing, infinity spelled out.
std::string CellNumber(double v, int decimals) {
  if (std::isnan(v)) return "&ndash;";
  if (std::isinf(v)) return v > 0 ? "&infin;" : "&minus;&infin;";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

std::string Base64(const std::string& data) {
  static const char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < data.size(); i += 3) {
    const unsigned v = static_cast<unsigned char>(data[i]) << 16 |
                       static_cast<unsigned char>(data[i + 1]) << 8 |
                       static_cast<unsigned char>(data[i + 2]);
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += kAlphabet[v >> 6 & 63];
    out += kAlphabet[v & 63];
  }
  if (i + 1 == data.size()) {
    const unsigned v = static_cast<unsigned char>(data[i]) << 16;
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += "==";
  } else if (i + 2 == data.size()) {
    const unsigned v =
        static_cast<unsigned char>(data[i]) << 16 | static_cast<unsigned char>(data[i + 1]) << 8;
    out += kAlphabet[v >> 18 & 63];
    out += kAlphabet[v >> 12 & 63];
    out += kAlphabet[v >> 6 & 63];
    out += '=';
  }
  return out;
}

// The SVG element without the XML prolog, DOCTYPE and comments before it.
std::string StripSvgProlog(const std::string& svg) {
  const size_t start = svg.find("<svg");
  return start == std::string::npos ? svg : svg.substr(start);
}

std::string VariantLabel(const std::string& variant) {
  if (variant == "fuzzy_cmac") return "Fuzzy-CMAC";
  if (variant == "main") return "main controller";
  if (variant == "pragmatic") return "pragmatic (baseline)";
  if (variant == "nearest_gait") return "nearest gait (baseline)";
  return variant;
}

// The same without "(baseline)", for the summary table (where baselines are in italics).
std::string VariantShortLabel(const std::string& variant) {
  if (variant == "pragmatic") return "pragmatic";
  if (variant == "nearest_gait") return "nearest gait";
  return VariantLabel(variant);
}

std::string VariantColor(const std::string& variant) {
  if (variant == "fuzzy_cmac" || variant == "main") return "#1b9e77";
  if (variant == "pragmatic") return "#d95f02";
  if (variant == "nearest_gait") return "#7570b3";
  static const char* const kOthers[] = {"#e7298a", "#66a61e", "#a6761d", "#e6ab02"};
  size_t h = 0;
  for (char c : variant) h = h * 31 + static_cast<unsigned char>(c);
  return kOthers[h % std::size(kOthers)];
}

// ---------------------------------------------------------------------------------------------
// Sampling a run.

// q at time t, linearly interpolated between the samples around it (clamped to the ends).
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

struct Window {
  double t0 = 0.0, t1 = 0.0;
  std::string what;
};

// A window of `width` seconds within the run: centred on the first obstacle (when the hip reaches
// its middle; else the last window), or the start, or the end.
Window StartWindow(const Trajectory& tr, double width) {
  return {tr.t.front(), std::min(tr.t.front() + width, tr.t.back()), "start"};
}

Window LastWindow(const Trajectory& tr, double width) {
  return {std::max(tr.t.front(), tr.t.back() - width), tr.t.back(), "end of the run"};
}

Window ObstacleWindow(const Trajectory& tr, const Obstacle& o, double width) {
  const double centre = o.x_start + 0.5 * o.length;
  for (size_t j = 0; j < tr.t.size(); ++j) {
    if (tr.q[j][0] >= centre) {
      double t0 = tr.t[j] - 0.5 * width;
      t0 = std::max(tr.t.front(), std::min(t0, tr.t.back() - width));
      return {t0, std::min(t0 + width, tr.t.back()), "around the first obstacle"};
    }
  }
  Window w = LastWindow(tr, width);
  w.what = "end of the run (the hip never reached the first obstacle)";
  return w;
}

// ---------------------------------------------------------------------------------------------
// Figures: gnuplot scripts, all rendered by one process.

struct Figure {
  std::string caption;
  std::string alt;
  int width = 0, height = 0;
  std::string html;  // filled after rendering
};

class FigureSet {
 public:
  explicit FigureSet(const SuiteReportOptions& options) : options_(options) {}

  // Starts a figure; returns its index. The caller appends its commands to script().
  size_t Begin(int width, int height, const std::string& caption, const std::string& alt) {
    const size_t k = figures_.size();
    figures_.push_back({caption, alt, width, height, ""});
    const std::string out = "fig" + std::to_string(k) + ".svg";
    job_.outputs.push_back(out);
    script_ << "reset\nset terminal svg size " << width << ',' << height
            << " dynamic enhanced font 'sans,11' background '#ffffff'\nset output '" << out
            << "'\nset encoding utf8\nset border 3 lw 1 lc rgb '#333333'\n"
               "set xtics nomirror out\nset ytics nomirror out\n"
               "set grid lw 1 lc rgb '#e6e6e6' dt 1\n"
               "set key opaque box lc rgb '#cccccc' samplen 2.5 spacing 1.1\n";
    return k;
  }
  std::ostringstream& script() { return script_; }
  // Adds a data file for the current figure and returns its (quoted) name.
  std::string AddData(const std::string& contents) {
    const std::string name = "data" + std::to_string(job_.files.size()) + ".dat";
    job_.files.push_back({name, contents});
    return "'" + name + "'";
  }
  size_t size() const { return figures_.size(); }
  const Figure& figure(size_t k) const { return figures_[k]; }

  // Renders every figure; false (and *error) when gnuplot could not.
  bool Render(std::string* error) {
    if (figures_.empty()) return true;
    job_.script = script_.str() + "unset output\n";
    const GnuplotResult result = RunGnuplot(options_.gnuplot, job_, options_.gnuplot_timeout);
    if (!result.ok) {
      *error = result.error;
      return false;
    }
    for (size_t k = 0; k < figures_.size(); ++k) {
      Figure& f = figures_[k];
      f.html = "<figure class=\"gp\"><img class=\"fig\" width=\"" + std::to_string(f.width) +
               "\" height=\"" + std::to_string(f.height) + "\" alt=\"" + HtmlEscape(f.alt) +
               "\" src=\"data:image/svg+xml;base64," + Base64(StripSvgProlog(result.outputs[k])) +
               "\"><figcaption>" + f.caption + "</figcaption></figure>\n";
    }
    return true;
  }

 private:
  const SuiteReportOptions& options_;
  std::vector<Figure> figures_;
  GnuplotJob job_;
  std::ostringstream script_;
};

// The chapter's figures 12, 14, 15: the robot every `every` seconds over a window of walking.
size_t StickDiagramFigure(const RunData& run, const Window& w, const SuiteReportOptions& options,
                          FigureSet* figures) {
  const Trajectory& tr = run.trajectory;
  std::ostringstream trunk, leg[2], path;
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_hi = 0.0;
  auto extend = [&](const StickPoint& p) {
    x_lo = std::min(x_lo, p.x);
    x_hi = std::max(x_hi, p.x);
    y_hi = std::max(y_hi, p.y);
  };
  size_t hint = 0;
  int frames = 0;
  const int count = static_cast<int>(std::floor((w.t1 - w.t0) / options.stick_every + 1e-9)) + 1;
  for (int k = 0; k < count; ++k) {
    const double t = w.t0 + k * options.stick_every;
    const StickFigure f = StickPoints(QAt(tr, t, &hint, nullptr), run.lengths);
    trunk << DataNumber(f.trunk_top.x) << ' ' << DataNumber(f.trunk_top.y) << '\n'
          << DataNumber(f.hip.x) << ' ' << DataNumber(f.hip.y) << "\n\n";
    for (int i = 0; i < 2; ++i) {
      leg[i] << DataNumber(f.hip.x) << ' ' << DataNumber(f.hip.y) << '\n'
             << DataNumber(f.knee[i].x) << ' ' << DataNumber(f.knee[i].y) << '\n'
             << DataNumber(f.foot[i].x) << ' ' << DataNumber(f.foot[i].y) << "\n\n";
      extend(f.knee[i]);
      extend(f.foot[i]);
    }
    extend(f.hip);
    extend(f.trunk_top);
    ++frames;
  }
  for (size_t j = 0; j < tr.t.size(); ++j) {
    if (tr.t[j] < w.t0 - 1e-9 || tr.t[j] > w.t1 + 1e-9) continue;
    path << DataNumber(tr.q[j][0]) << ' ' << DataNumber(tr.q[j][1]) << '\n';
  }
  x_lo -= 0.15;
  x_hi += 0.15;
  const double y_lo = -0.08;
  y_hi = std::max(y_hi, 0.5) + 0.08;
  // Equal scales on both axes, at most kPixelsPerMetre so that a short window is not blown up.
  const double kPixelsPerMetre = 300.0, kMarginX = 95.0, kMarginY = 80.0;
  const double scale = std::min(kPixelsPerMetre, (options.figure_width - kMarginX) / (x_hi - x_lo));
  const int width = static_cast<int>(std::lround((x_hi - x_lo) * scale + kMarginX));
  const int height = static_cast<int>(std::lround((y_hi - y_lo) * scale + kMarginY));
  char caption[400];
  std::snprintf(caption, sizeof caption,
                "Stick diagram, %s: t = %.2f&ndash;%.2f s, a figure every %.2f s (%d figures); "
                "leg 1 <span style=\"color:%s\">&#9632;</span>, leg 2 "
                "<span style=\"color:%s\">&#9632;</span>, trunk "
                "<span style=\"color:%s\">&#9632;</span>, hip path dotted.",
                w.what.c_str(), w.t0, w.t1, options.stick_every, frames, kLegColors[0],
                kLegColors[1], kTrunkColor);
  const size_t k =
      figures->Begin(width, height, caption, "stick diagram of " + run.row.run + ", " + w.what);
  std::ostringstream& s = figures->script();
  const std::string d_trunk = figures->AddData(trunk.str()),
                    d_leg1 = figures->AddData(leg[0].str()),
                    d_leg2 = figures->AddData(leg[1].str()), d_path = figures->AddData(path.str());
  s << "set size ratio -1\nset xrange [" << x_lo << ':' << x_hi << "]\nset yrange [" << y_lo << ':'
    << y_hi << "]\nset xlabel 'x (m)'\nset ylabel 'y (m)'\nunset grid\n"
    << "unset key\n"
    << "set object 1 rect from " << x_lo << ',' << y_lo << " to " << x_hi
    << ",0 fc rgb '#efe8dc' fs solid 1.0 noborder behind\n"
    << "set arrow 1 from " << x_lo << ",0 to " << x_hi << ",0 nohead lw 2 lc rgb '#555555' back\n";
  int object = 2;
  for (const Obstacle& o : run.obstacles) {
    if (o.x_end() < x_lo || o.x_start > x_hi) continue;
    s << "set object " << object++ << " rect from " << o.x_start << ",0 to " << o.x_end() << ','
      << o.height << " fc rgb '#9a9a9a' fs solid 1.0 border lc rgb '#555555' behind\n";
  }
  s << "plot " << d_path << " with lines dt 3 lw 1.2 lc rgb '#888888' title 'hip path', \\\n  "
    << d_leg2 << " with lines lw 1.6 lc rgb '" << kLegColors[1] << "' title 'leg 2', \\\n  "
    << d_leg1 << " with lines lw 1.6 lc rgb '" << kLegColors[0] << "' title 'leg 1', \\\n  "
    << d_trunk << " with lines lw 2 lc rgb '" << kTrunkColor << "' title 'trunk'\n";
  return k;
}

// The chapter's figures 13 and 16: V_d, V_M and L_step against the step index, per variant.
size_t StepsFigure(const std::vector<const RunData*>& runs, bool with_obstacles,
                   const SuiteReportOptions& options, FigureSet* figures) {
  const RunData& main = *runs.front();
  int step_lo = std::numeric_limits<int>::max(), step_hi = std::numeric_limits<int>::min();
  for (const RunData* run : runs) {
    for (const Step& s : run->steps) {
      step_lo = std::min(step_lo, s.step);
      step_hi = std::max(step_hi, s.step);
    }
  }
  if (step_hi <= step_lo) step_hi = step_lo + 1;
  const int panels = with_obstacles ? 3 : 2;
  const int height = 170 + 190 * panels;
  const size_t k = figures->Begin(
      options.figure_width, height,
      "Per step: the desired velocity V<sub>d</sub> and the measured V<sub>M</sub> = "
      "L<sub>step</sub> / t<sub>step</sub> (top), the step length L<sub>step</sub>" +
          std::string(with_obstacles ? ", and the distance d<sub>obs</sub> to the next obstacle "
                                       "at each step (bottom)"
                                     : "") +
          ". Baselines overlaid.",
      "V_d, V_M and L_step per step");
  std::vector<std::string> data;
  for (const RunData* run : runs) {
    std::ostringstream d;
    for (const Step& s : run->steps) {
      // V_M is measured only when the leg's take-off was seen (t_step > 0).
      const double v_m = s.t_step > 0.0 ? s.v_m : kNan;
      d << s.step << ' ' << DataNumber(s.v_d) << ' ' << DataNumber(v_m) << ' '
        << DataNumber(s.l_step) << ' ' << DataNumber(s.d_obs) << '\n';
    }
    data.push_back(figures->AddData(d.str()));
  }
  std::ostringstream& s = figures->script();
  s << "set multiplot layout " << panels << ",1 margins 0.08,0.73,0.11,0.96 spacing 0,0.07\n"
    << "set xrange [" << step_lo - 0.5 << ':' << step_hi + 0.5 << "]\n"
    << "set key outside right top vertical\nset format x '%g'\n";
  // The main variant drawn last (on top of its baselines, which share its first steps); the key,
  // inverted, lists it first and the baselines in summary order.
  auto series = [&](int column, const char* what) {
    for (size_t v = runs.size(); v-- > 0;) {
      s << data[v] << " using 1:" << column << " with linespoints pt 7 ps 0.45 lw 1.4 lc rgb '"
        << VariantColor(runs[v]->row.variant) << "' title "
        << GnuplotQuote(std::string(what) + ", " + VariantLabel(runs[v]->row.variant))
        << " noenhanced" << (v == 0 ? "" : ", \\\n  ");
    }
  };
  s << "set key invert\nset ylabel 'velocity (m/s)'\nunset xlabel\nplot ";
  series(3, "V_M");
  s << ", \\\n  " << data[0] << " using 1:2 with steps lw 1.6 dt 2 lc rgb '#000000' title "
    << GnuplotQuote("V_d, " + VariantLabel(main.row.variant)) << " noenhanced\n";
  s << "set ylabel 'L_{step} (m)'\n" << (panels == 2 ? "set xlabel 'step'\n" : "") << "plot ";
  series(4, "L_step");
  s << '\n';
  if (with_obstacles) {
    s << "set ylabel 'd_{obs} (m)'\nset xlabel 'step'\nset yrange [0:*]\nplot " << data[0]
      << " using 1:5 with linespoints pt 7 ps 0.45 lw 1.4 lc rgb '"
      << VariantColor(main.row.variant) << "' title "
      << GnuplotQuote("d_obs, " + VariantLabel(main.row.variant)) << " noenhanced\n";
  }
  s << "unset multiplot\n";
  return k;
}

// Swing hip, swing knee and trunk: reference (dashed) against actual, coloured by the swing leg.
size_t TrackingFigure(const RunData& run, const Window& w, const SuiteReportOptions& options,
                      FigureSet* figures) {
  const Tracking& tr = run.tracking;
  std::ostringstream d;
  int previous = -1;
  for (size_t j = 0; j < tr.t.size(); ++j) {
    if (tr.t[j] < w.t0 - 1e-9 || tr.t[j] > w.t1 + 1e-9) continue;
    const int swing = tr.stance[j] == 0 ? 0 : 3 - tr.stance[j];  // 0: no leg in support
    if (previous >= 0 && swing != previous) d << '\n';  // a support exchange breaks the lines
    previous = swing;
    auto actual = [&](double v, int leg) {
      return DataNumber(swing == leg ? v * kRadToDeg : kNan);
    };
    d << DataNumber(tr.t[j]) << ' ' << DataNumber(tr.hip_d[j] * kRadToDeg) << ' '
      << actual(tr.hip[j], 1) << ' ' << actual(tr.hip[j], 2) << ' '
      << DataNumber(tr.knee_d[j] * kRadToDeg) << ' ' << actual(tr.knee[j], 1) << ' '
      << actual(tr.knee[j], 2) << ' ' << DataNumber(tr.q0_d[j] * kRadToDeg) << ' '
      << DataNumber(tr.q0[j] * kRadToDeg) << '\n';
  }
  char caption[400];
  std::snprintf(caption, sizeof caption,
                "Joint tracking, %s (t = %.2f&ndash;%.2f s): the swing leg's hip and knee and the "
                "trunk pitch, reference (dashed) and actual, coloured by the leg that swings.",
                w.what.c_str(), w.t0, w.t1);
  const size_t k =
      figures->Begin(options.figure_width, 680, caption, "joint tracking of " + run.row.run);
  const std::string data = figures->AddData(d.str());
  std::ostringstream& s = figures->script();
  const std::string leg1 = std::string("lc rgb '") + kLegColors[0] + "'",
                    leg2 = std::string("lc rgb '") + kLegColors[1] + "'";
  s << "set multiplot layout 3,1 margins 0.08,0.73,0.09,0.97 spacing 0,0.06\n"
    << "set xrange [" << w.t0 << ':' << w.t1 << "]\nset key outside right top vertical\n"
    << "unset xlabel\nset ylabel 'swing hip (deg)'\n"
    << "plot " << data << " using 1:2 with lines dt 2 lw 1.5 lc rgb '#000000' title 'reference', "
    << data << " using 1:3 with lines lw 1.6 " << leg1 << " title 'leg 1 swinging', " << data
    << " using 1:4 with lines lw 1.6 " << leg2 << " title 'leg 2 swinging'\n"
    << "set ylabel 'swing knee (deg)'\n"
    << "plot " << data << " using 1:5 with lines dt 2 lw 1.5 lc rgb '#000000' title 'reference', "
    << data << " using 1:6 with lines lw 1.6 " << leg1 << " title 'leg 1 swinging', " << data
    << " using 1:7 with lines lw 1.6 " << leg2 << " title 'leg 2 swinging'\n"
    << "set ylabel 'trunk pitch q_0 (deg)'\nset xlabel 't (s)'\n"
    << "plot " << data << " using 1:8 with lines dt 2 lw 1.5 lc rgb '#000000' title 'q_0^d', "
    << data << " using 1:9 with lines lw 1.6 lc rgb '" << kTrunkColor << "' title 'q_0'\n"
    << "unset multiplot\n";
  return k;
}

// The fuzzy system's per-gait weights w_Ok of every step, stacked (they sum to 1).
size_t WeightsFigure(const RunData& run, const SuiteReportOptions& options, FigureSet* figures) {
  const size_t n = run.weight_names.size();
  std::ostringstream d;
  int step_lo = std::numeric_limits<int>::max(), step_hi = std::numeric_limits<int>::min();
  for (const Step& s : run.steps) {
    d << s.step;
    double sum = 0.0;
    for (size_t k = 0; k < n; ++k) {
      sum += std::isfinite(s.w[k]) ? s.w[k] : 0.0;
      d << ' ' << DataNumber(sum);
    }
    d << '\n';
    step_lo = std::min(step_lo, s.step);
    step_hi = std::max(step_hi, s.step);
  }
  const size_t k = figures->Begin(
      options.figure_width, 330,
      "Fuzzy-CMAC weights per step: w<sub>Ok</sub>, the share of reference gait O<sub>k</sub> in "
      "the gait pattern (eq. 12), stacked.",
      "fuzzy weights per step of " + run.row.run);
  const std::string data = figures->AddData(d.str());
  std::ostringstream& s = figures->script();
  s << "set xrange [" << step_lo - 0.5 << ':' << step_hi + 0.5 << "]\nset yrange [0:1.02]\n"
    << "set lmargin at screen 0.08\nset rmargin at screen 0.73\n"
    << "set key outside right top vertical\nset boxwidth 0.9 relative\n"
    << "set style fill solid 1.0 noborder\nset xlabel 'step'\nset ylabel 'weight w_{Ok}'\n"
    << "set grid noxtics\nplot ";
  // Topmost cumulative sum first, so that each lower one is drawn over it.
  for (size_t j = n; j-- > 0;) {
    s << (j + 1 == n ? "" : ", \\\n  ") << data << " using 1:" << j + 2 << " with boxes lc rgb '"
      << kWeightColors[j % std::size(kWeightColors)] << "' title "
      << GnuplotQuote(run.weight_names[j]) << " noenhanced";
  }
  s << '\n';
  return k;
}

// ---------------------------------------------------------------------------------------------
// The page.

const char kStyle[] = R"css(
:root{--fg:#1d1f23;--muted:#5f6670;--line:#d5d9de;--pass:#e2f3e5;--fail:#fbe2df}
*{box-sizing:border-box}
body{font:15px/1.5 "DejaVu Sans",system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;color:var(--fg);margin:0;background:#eef0f3}
main{max-width:1360px;margin:0 auto;padding:28px 30px 64px;background:#fff;min-height:100vh}
h1{font-size:27px;margin:0 0 4px;font-weight:650}
h2{font-size:21px;margin:44px 0 6px;padding-top:14px;border-top:2px solid #e3e6ea}
h3{font-size:16px;margin:26px 0 6px;color:#2c3440}
p{margin:6px 0}
.note{color:var(--muted);font-size:13.5px}
.warning{background:#fff4d6;border:1px solid #f0d48a;padding:8px 12px;border-radius:4px;font-size:14px}
table{border-collapse:collapse;font-size:12.5px}
th,td{border:1px solid var(--line);padding:4px 6px;text-align:right;vertical-align:top}
th{background:#f1f3f6;font-weight:600;text-align:center}
td.text{text-align:left}
td.scenario{text-align:left;font-weight:600;background:#fafbfc}
td{white-space:nowrap}
td.criteria{text-align:left;white-space:normal;font-size:12.5px;color:#8a1c14;background:#fdf3f2;border-top:0}
td.criteria ul{display:inline;margin:0;padding:0}
td.criteria li{display:inline;margin-left:10px}
td.criteria li+li:before{content:"\2022\00a0";color:#c0a0a0}
td.variant{text-align:left;white-space:nowrap}
td.variant.baseline{font-style:italic;color:#4a5058}
td.status{white-space:nowrap}
.reason{font-size:12px;color:var(--muted);white-space:normal;min-width:160px;max-width:240px}
tr.pass td.status{background:var(--pass);color:#16652a;font-weight:700}
tr.fail td.status{background:var(--fail);color:#a3150f;font-weight:700}
tr.group-start td{border-top:2px solid #9aa3ad}
.swatch{display:inline-block;width:11px;height:11px;border-radius:2px;margin-right:6px;vertical-align:-1px}
.table-wrap{overflow-x:auto}
figure{margin:10px 0 22px}
figure img{display:block;max-width:100%;height:auto;border:1px solid #e6e8eb;border-radius:3px}
figcaption{font-size:13px;color:var(--muted);max-width:1000px;margin-top:4px}
details{margin:10px 0}
summary{cursor:pointer;color:#2c3440;font-weight:600}
.replay{margin:8px 0 24px;max-width:1000px}
.replay h4{margin:0 0 4px;font-size:14.5px}
.replay canvas{display:block;width:100%;height:auto;border:1px solid #d9dde2;border-radius:4px;background:#fff}
.controls{display:flex;gap:10px;align-items:center;margin-top:6px;font-size:13.5px}
.controls button{min-width:82px;padding:3px 10px;font:inherit;cursor:pointer}
.controls input[type=range]{flex:1}
.controls .time{font-variant-numeric:tabular-nums;min-width:150px;text-align:right;color:var(--muted)}
code{background:#f3f4f6;padding:0 3px;border-radius:3px}
)css";

// First in <head>: counts uncaught errors, before anything else can throw.
const char kErrorCounter[] =
    "document.documentElement.dataset.jsErrors='0';"
    "function rabbitCountError(){var d=document.documentElement.dataset;"
    "d.jsErrors=String((parseInt(d.jsErrors,10)||0)+1);}"
    "window.addEventListener('error',rabbitCountError);"
    "window.addEventListener('unhandledrejection',rabbitCountError);";

// The replays: each .replay element holds a canvas, controls and its frames as JSON
// {fps, t: [...], p: [12 numbers per frame: hip, trunk top, knee 1, foot 1, knee 2, foot 2],
//  c: [contact bits per frame], obs: [[x_start, length, height], ...]}.
const char kReplayScript[] = R"js(
(function(){
  var root=document.documentElement;
  var LEG=['#1f77b4','#d62728'], TRUNK='#404040';
  function Replay(el){
    var d=JSON.parse(el.querySelector('script.replay-data').textContent);
    var canvas=el.querySelector('canvas'), ctx=canvas.getContext('2d');
    var button=el.querySelector('button.play'), slider=el.querySelector('input.seek');
    var speed=el.querySelector('select.speed'), label=el.querySelector('.time');
    var n=d.t.length, frame=0, playing=false, last=0, clock=0;
    var W=canvas.width, H=canvas.height, ratio=window.devicePixelRatio||1;
    canvas.width=Math.round(W*ratio); canvas.height=Math.round(H*ratio);
    slider.max=String(Math.max(0,n-1));
    var yLo=-0.14, yHi=1.76, s=H/(yHi-yLo);
    function draw(){
      ctx.setTransform(ratio,0,0,ratio,0,0);
      ctx.fillStyle='#ffffff'; ctx.fillRect(0,0,W,H);
      if(n===0){ctx.fillStyle='#555';ctx.font='15px sans-serif';ctx.fillText('no trajectory recorded',20,30);return;}
      var p=d.p, o=12*frame, hx=p[o];
      var left=hx-0.42*W/s;
      function X(x){return (x-left)*s;} function Y(y){return (yHi-y)*s;}
      ctx.fillStyle='#efe8dc'; ctx.fillRect(0,Y(0),W,H-Y(0));
      ctx.strokeStyle='#555'; ctx.lineWidth=2; ctx.beginPath(); ctx.moveTo(0,Y(0)); ctx.lineTo(W,Y(0)); ctx.stroke();
      ctx.lineWidth=1; ctx.fillStyle='#6b6256'; ctx.font='11px sans-serif'; ctx.textAlign='center';
      for(var m=Math.ceil(left*4)/4; m<=left+W/s; m+=0.25){
        var big=Math.abs(m-Math.round(m))<1e-6, half=Math.abs(2*m-Math.round(2*m))<1e-6;
        ctx.beginPath(); ctx.moveTo(X(m),Y(0)); ctx.lineTo(X(m),Y(0)+(big?9:half?6:3)); ctx.stroke();
        if(big) ctx.fillText(Math.round(m)+' m',X(m),Y(0)+20);
      }
      for(var k=0;k<d.obs.length;k++){
        var b=d.obs[k];
        if(X(b[0]+b[1])<0||X(b[0])>W) continue;
        ctx.fillStyle='#9a9a9a'; ctx.fillRect(X(b[0]),Y(b[2]),b[1]*s,b[2]*s);
        ctx.strokeStyle='#555'; ctx.strokeRect(X(b[0]),Y(b[2]),b[1]*s,b[2]*s);
      }
      ctx.lineCap='round';
      function seg(i,j,color,width){ctx.strokeStyle=color;ctx.lineWidth=width;ctx.beginPath();
        ctx.moveTo(X(p[o+i]),Y(p[o+i+1]));ctx.lineTo(X(p[o+j]),Y(p[o+j+1]));ctx.stroke();}
      function dot(i,r,fill,color){ctx.beginPath();ctx.arc(X(p[o+i]),Y(p[o+i+1]),r,0,2*Math.PI);
        ctx.fillStyle=fill;ctx.fill();ctx.strokeStyle=color;ctx.lineWidth=1.5;ctx.stroke();}
      var contact=d.c.length?d.c[frame]:0;
      for(var leg=1;leg>=0;leg--){
        var kn=4+4*leg, ft=6+4*leg;
        seg(0,kn,LEG[leg],6); seg(kn,ft,LEG[leg],5);
        dot(kn,3.5,'#fff',LEG[leg]);
        dot(ft,4.5,(contact>>leg)&1?LEG[leg]:'#fff',LEG[leg]);
      }
      seg(0,2,TRUNK,8); dot(0,4.5,'#fff',TRUNK);
      ctx.textAlign='left'; ctx.fillStyle='#333'; ctx.font='13px sans-serif';
      var text='t = '+d.t[frame].toFixed(2)+' s    x = '+hx.toFixed(2)+' m';
      ctx.fillText(text,10,20);
      ctx.fillStyle='#777'; ctx.font='11px sans-serif';
      ctx.fillText('filled foot: on the ground',10,36);
      var st=-1; for(var j=0;4*j<d.s.length&&d.s[4*j]<=d.t[frame]+1e-9;j++) st=j;
      if(st>=0){
        var v=function(x,k){return x===null?'\u2013':x.toFixed(k);};
        ctx.textAlign='right'; ctx.fillStyle='#333'; ctx.font='13px sans-serif';
        ctx.fillText('step '+(st+1)+' of '+(d.s.length/4)+':  V_d '+v(d.s[4*st+1],2)+'  V_M '+
          v(d.s[4*st+2],3)+' m/s  L_step '+v(d.s[4*st+3],3)+' m',W-10,20);
      }
      label.textContent='t = '+d.t[frame].toFixed(2)+' / '+d.t[n-1].toFixed(2)+' s';
      slider.value=String(frame);
    }
    function setButton(){button.textContent=playing?'\u275a\u275a Pause':'\u25b6 Play';}
    function tick(now){
      if(!playing) return;
      // The frame's timestamp may precede the click's performance.now(): never step back.
      clock+=Math.max(0,now-last)/1000*(parseFloat(speed.value)||1); last=Math.max(last,now);
      var f=Math.max(0,Math.min(n-1,Math.floor(clock*d.fps+1e-9)));
      if(f>=n-1){playing=false;setButton();}
      if(f!==frame){frame=f;draw();}
      if(playing) requestAnimationFrame(tick);
    }
    button.addEventListener('click',function(){
      if(playing){playing=false;}else{
        if(frame>=n-1) frame=0;
        clock=frame/d.fps; last=performance.now(); playing=n>1;
        if(playing) requestAnimationFrame(tick);
      }
      setButton();
    });
    slider.addEventListener('input',function(){frame=parseInt(slider.value,10)||0;clock=frame/d.fps;draw();});
    setButton(); draw();
  }
  var all=document.querySelectorAll('.replay'), drawn=0;
  for(var i=0;i<all.length;i++){
    try{Replay(all[i]);drawn++;}catch(e){rabbitCountError();if(window.console)console.error(e);}
  }
  root.dataset.replayCount=String(drawn);
  root.dataset.replay=drawn===all.length?'ready':'failed';
})();
)js";

std::string ReplayJson(const RunData& run, const SuiteReportOptions& options) {
  const Trajectory& tr = run.trajectory;
  const int dec = options.replay_decimals;
  std::string t, p, c;
  size_t hint = 0;
  int frames = 0;
  if (!tr.t.empty()) {
    const double t0 = tr.t.front(), span = tr.t.back() - t0;
    const int count = static_cast<int>(std::floor(span * options.replay_fps + 1e-9)) + 1;
    for (int k = 0; k < count; ++k) {
      const double time = t0 + static_cast<double>(k) / options.replay_fps;
      int contact = 0;
      const StickFigure f = StickPoints(QAt(tr, time, &hint, &contact), run.lengths);
      const StickPoint points[6] = {f.hip, f.trunk_top, f.knee[0], f.foot[0], f.knee[1], f.foot[1]};
      if (k > 0) {
        t += ',';
        p += ',';
        c += ',';
      }
      t += JsonNumber(time, dec);
      for (int i = 0; i < 6; ++i) {
        p +=
            (i == 0 ? "" : ",") + JsonNumber(points[i].x, dec) + ',' + JsonNumber(points[i].y, dec);
      }
      c += std::to_string(contact);
      ++frames;
    }
  }
  std::string obs;
  for (const Obstacle& o : run.obstacles) {
    obs += (obs.empty() ? "[" : ",[") + JsonNumber(o.x_start, dec) + ',' +
           JsonNumber(o.length, dec) + ',' + JsonNumber(o.height, dec) + ']';
  }
  // Per step: touchdown time, V_d, V_M, L_step (for the overlay).
  std::string steps;
  for (const Step& s : run.steps) {
    const double v_m = s.t_step > 0.0 ? s.v_m : kNan;
    steps += (steps.empty() ? "" : ",") + JsonNumber(s.t, dec) + ',' + JsonNumber(s.v_d, 3) + ',' +
             JsonNumber(v_m, 3) + ',' + JsonNumber(s.l_step, 3);
  }
  return "{\"fps\":" + std::to_string(options.replay_fps) +
         ",\"frames\":" + std::to_string(frames) + ",\"t\":[" + t + "],\"p\":[" + p + "],\"c\":[" +
         (tr.contact.empty() ? "" : c) + "],\"obs\":[" + obs + "],\"s\":[" + steps + "]}";
}

std::string ReplayHtml(const RunData& run, size_t index, const SuiteReportOptions& options) {
  std::ostringstream html;
  html << "<div class=\"replay\" id=\"replay-" << index << "\"><h4><span class=\"swatch\" "
       << "style=\"background:" << VariantColor(run.row.variant) << "\"></span>"
       << HtmlEscape(VariantLabel(run.row.variant)) << " &mdash; run <code>"
       << HtmlEscape(run.row.run) << "</code>, " << HtmlEscape(run.row.outcome) << "</h4>"
       << "<canvas width=\"1000\" height=\"360\"></canvas><div class=\"controls\">"
       << "<button type=\"button\" class=\"play\">Play</button>"
       << "<input type=\"range\" class=\"seek\" min=\"0\" max=\"0\" step=\"1\" value=\"0\" "
          "aria-label=\"time\">"
       << "<label>speed <select class=\"speed\"><option value=\"0.1\">0.1&times;</option>"
          "<option value=\"0.25\">0.25&times;</option><option value=\"0.5\">0.5&times;</option>"
          "<option value=\"1\" selected>1&times;</option><option value=\"2\">2&times;</option>"
          "<option value=\"4\">4&times;</option></select></label>"
       << "<span class=\"time\"></span></div>"
       << "<script type=\"application/json\" class=\"replay-data\">" << ReplayJson(run, options)
       << "</script></div>\n";
  return html.str();
}

std::string SummaryTable(const std::vector<RunData>& runs,
                         const std::vector<ScenarioGroup>& groups) {
  const int kColumns = 14;
  std::ostringstream html;
  html << "<div class=\"table-wrap\"><table class=\"summary\"><thead><tr>"
          "<th>scenario</th><th>variant</th><th>result</th><th>outcome</th>"
          "<th>duration<br>s</th><th>distance<br>m</th><th>steps</th>"
          "<th>|V<sub>M</sub>&minus;V<sub>d</sub>| m/s<br>mean / final</th>"
          "<th>L<sub>step</sub> m<br>mean (min&ndash;max)</th>"
          "<th>L<sub>step</sub><br>spread mm</th><th>saturation<br>s</th><th>energy<br>J</th>"
          "<th>cost of<br>transport</th><th>wall "
          "s<br>(&times;&nbsp;real&nbsp;time)</th></tr></thead>"
          "<tbody>\n";
  for (size_t g = 0; g < groups.size(); ++g) {
    const ScenarioGroup& group = groups[g];
    size_t rows = 0;
    for (size_t k : group.runs) rows += runs[k].row.failed.empty() ? 1 : 2;
    for (size_t i = 0; i < group.runs.size(); ++i) {
      const SummaryRow& r = runs[group.runs[i]].row;
      const char* result = r.passed ? "pass" : "fail";
      html << "<tr class=\"" << result << (i == 0 ? " group-start" : "") << "\">";
      if (i == 0) {
        html << "<td class=\"scenario\" rowspan=\"" << rows << "\"><a href=\"#scenario-" << g
             << "\">" << HtmlEscape(group.name) << "</a></td>";
      }
      html << "<td class=\"variant" << (IsMainVariant(r.variant) ? "" : " baseline")
           << "\"><span class=\"swatch\" style=\"background:" << VariantColor(r.variant)
           << "\"></span>" << HtmlEscape(VariantShortLabel(r.variant))
           << "</td><td class=\"status\">"
           << (r.passed ? "&#10003;&nbsp;pass" : "&#10007;&nbsp;fail") << "</td><td class=\"text\">"
           << HtmlEscape(r.outcome);
      if (!r.reason.empty()) html << "<div class=\"reason\">" << HtmlEscape(r.reason) << "</div>";
      html << "</td><td>" << CellNumber(r.duration, 2) << "</td><td>" << CellNumber(r.distance, 2)
           << "</td><td>" << CellNumber(r.steps, 0) << "</td><td>"
           << CellNumber(r.mean_speed_error, 3) << " / " << CellNumber(r.final_speed_error, 3)
           << "</td><td>" << CellNumber(r.l_mean, 3) << " (" << CellNumber(r.l_min, 3) << "&ndash;"
           << CellNumber(r.l_max, 3) << ")</td><td>" << CellNumber(r.l_spread * 1000.0, 1)
           << "</td><td>" << CellNumber(r.saturation, 2) << "</td><td>" << CellNumber(r.energy, 1)
           << "</td><td>" << CellNumber(r.cost_of_transport, 3) << "</td><td>"
           << CellNumber(r.wall, 2) << " (" << CellNumber(r.real_time_factor, 0)
           << "&times;)</td></tr>\n";
      if (!r.failed.empty()) {
        html << "<tr class=\"criteria-row\"><td class=\"criteria\" colspan=\"" << kColumns - 1
             << "\"><b>failed criteria:</b><ul>";
        for (const std::string& f : r.failed) html << "<li>" << HtmlEscape(f) << "</li>";
        html << "</ul></td></tr>\n";
      }
    }
  }
  html << "</tbody></table></div>\n";
  return html.str();
}

std::string StepsTable(const RunData& run) {
  std::ostringstream html;
  html << "<details><summary>Steps of " << HtmlEscape(VariantLabel(run.row.variant)) << " ("
       << run.steps.size() << ")</summary><div class=\"table-wrap\"><table><thead><tr>"
       << "<th>step</th><th>leg</th><th>t<br>s</th><th>V<sub>d</sub><br>m/s</th>"
       << "<th>V<sub>M</sub><br>m/s</th><th>L<sub>step</sub><br>m</th>"
       << "<th>t<sub>step</sub><br>s</th><th>d<sub>obs</sub><br>m</th>"
       << "<th>q<sub>0</sub><sup>d</sup><br>deg</th>";
  for (const std::string& w : run.weight_names) html << "<th>" << HtmlEscape(w) << "</th>";
  html << "<th>rules fired</th></tr></thead><tbody>";
  for (const Step& s : run.steps) {
    html << "<tr><td>" << s.step << "</td><td>" << s.leg << "</td><td>" << CellNumber(s.t, 2)
         << "</td><td>" << CellNumber(s.v_d, 3) << "</td><td>" << CellNumber(s.v_m, 3)
         << "</td><td>" << CellNumber(s.l_step, 3) << "</td><td>" << CellNumber(s.t_step, 3)
         << "</td><td>" << CellNumber(s.d_obs, 3) << "</td><td>" << CellNumber(s.q0_d_deg, 1)
         << "</td>";
    for (double w : s.w) html << "<td>" << CellNumber(w, 3) << "</td>";
    html << "<td class=\"text\">" << HtmlEscape(s.rules) << "</td></tr>";
  }
  html << "</tbody></table></div></details>\n";
  return html.str();
}

std::string TerrainText(const std::vector<Obstacle>& obstacles) {
  if (obstacles.empty()) return "flat ground";
  std::string out =
      std::to_string(obstacles.size()) + (obstacles.size() == 1 ? " obstacle: " : " obstacles: ");
  for (size_t k = 0; k < obstacles.size(); ++k) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, "%sx = %.2f&ndash;%.2f m, %.0f mm high",
                  k == 0 ? "" : "; ", obstacles[k].x_start, obstacles[k].x_end(),
                  obstacles[k].height * 1000.0);
    out += buffer;
  }
  return out;
}

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[64];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%d %H:%M UTC", &tm);
  return buffer;
}

bool HasFiniteWeights(const RunData& run) {
  for (const Step& s : run.steps) {
    for (double w : s.w) {
      if (std::isfinite(w)) return true;
    }
  }
  return false;
}

bool HasSamplesIn(const std::vector<double>& t, const Window& w) {
  for (double v : t) {
    if (v >= w.t0 - 1e-9 && v <= w.t1 + 1e-9) return true;
  }
  return false;
}

}  // namespace

bool SuiteReportOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (gnuplot.empty() || gnuplot.find_first_of(std::string("\n\r\0", 3)) != std::string::npos) {
    return fail("gnuplot must be a non-empty executable name or path");
  }
  if (!(gnuplot_timeout > 0.0) || !std::isfinite(gnuplot_timeout)) {
    return fail("gnuplot_timeout must be a positive number of seconds");
  }
  if (replay_fps < 1 || replay_fps > 240) return fail("replay_fps must be within 1..240");
  if (replay_decimals < 1 || replay_decimals > 9) {
    return fail("replay_decimals must be within 1..9");
  }
  for (const auto& [name, value] : {std::pair<const char*, double>{"stick_every", stick_every},
                                    {"stick_window", stick_window},
                                    {"tracking_window", tracking_window}}) {
    if (!(value > 0.0) || !std::isfinite(value) || value > 1e6) {
      return fail(std::string(name) + " must be a positive number of seconds");
    }
  }
  if (stick_window / stick_every > 1000.0) {
    return fail("stick_window / stick_every must be at most 1000 figures per diagram");
  }
  if (figure_width < 300 || figure_width > 4000) {
    return fail("figure_width must be within 300..4000 px");
  }
  return true;
}

StickFigure StickPoints(const std::array<double, 7>& q, const LinkLengths& lengths) {
  StickFigure f;
  f.hip = {q[0], q[1]};
  const double q0 = q[2];
  f.trunk_top = {f.hip.x + lengths.trunk * std::sin(q0), f.hip.y + lengths.trunk * std::cos(q0)};
  for (int leg = 0; leg < 2; ++leg) {
    const double thigh = q[3 + 2 * leg] - q0;
    const double shin = thigh + q[4 + 2 * leg];
    f.knee[leg] = {f.hip.x + lengths.thigh * std::sin(thigh),
                   f.hip.y - lengths.thigh * std::cos(thigh)};
    f.foot[leg] = {f.knee[leg].x + lengths.shin * std::sin(shin),
                   f.knee[leg].y - lengths.shin * std::cos(shin)};
  }
  return f;
}

std::string WriteSuiteReport(const std::string& dir, const SuiteReportOptions& options,
                             std::vector<std::string>* warnings) {
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("report options: " + error);
  const fs::path root(dir);
  const std::string summary_path = (root / "summary.csv").string();
  const std::vector<SummaryRow> rows = ReadSummary(summary_path);
  std::vector<RunData> runs;
  for (const SummaryRow& row : rows) runs.push_back(ReadRun(root, row, warnings));
  const std::vector<ScenarioGroup> groups = GroupByScenario(runs);

  // Figures of every scenario, rendered together.
  FigureSet figures(options);
  std::vector<std::vector<size_t>> scenario_figures(groups.size());
  for (size_t g = 0; g < groups.size(); ++g) {
    const RunData& main = runs[groups[g].runs.front()];
    std::vector<size_t>& mine = scenario_figures[g];
    const Trajectory& tr = main.trajectory;
    if (!tr.t.empty()) {
      mine.push_back(
          StickDiagramFigure(main, StartWindow(tr, options.stick_window), options, &figures));
      if (!main.obstacles.empty()) {
        mine.push_back(StickDiagramFigure(
            main, ObstacleWindow(tr, main.obstacles.front(), options.stick_window), options,
            &figures));
      }
    }
    std::vector<const RunData*> with_steps;
    for (size_t k : groups[g].runs) {
      if (!runs[k].steps.empty()) with_steps.push_back(&runs[k]);
    }
    if (!with_steps.empty() && with_steps.front() == &main) {
      mine.push_back(StepsFigure(with_steps, !main.obstacles.empty(), options, &figures));
    }
    if (!tr.t.empty() && !main.tracking.t.empty()) {
      const Window w = main.obstacles.empty()
                           ? LastWindow(tr, options.tracking_window)
                           : ObstacleWindow(tr, main.obstacles.front(), options.tracking_window);
      if (HasSamplesIn(main.tracking.t, w)) {
        mine.push_back(TrackingFigure(main, w, options, &figures));
      }
    }
    if (HasFiniteWeights(main)) mine.push_back(WeightsFigure(main, options, &figures));
  }
  std::string figure_error;
  const bool have_figures = figures.Render(&figure_error);
  if (!have_figures) {
    const std::string warning =
        "figures left out: gnuplot (" + options.gnuplot + ") could not draw them: " + figure_error;
    if (warnings != nullptr) warnings->push_back(warning);
    figure_error = warning;
  }

  // The page.
  std::string suite;
  for (const SummaryRow& r : rows) {
    if (suite.find(r.suite) == std::string::npos) suite += (suite.empty() ? "" : ", ") + r.suite;
  }
  if (suite.empty()) suite = root.filename().string();
  int passed = 0;
  for (const SummaryRow& r : rows) passed += r.passed ? 1 : 0;
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
       << "<title>rabbit-gait: suite " << HtmlEscape(suite) << "</title><script>" << kErrorCounter
       << "</script><style>" << kStyle << "</style></head><body><main>\n";
  html << "<h1>Suite <em>" << HtmlEscape(suite) << "</em>: batch report</h1>\n";
  html << "<p class=\"note\">" << rows.size() << (rows.size() == 1 ? " run" : " runs") << " in "
       << groups.size() << (groups.size() == 1 ? " scenario" : " scenarios") << ", <b>" << passed
       << " passed</b>, <b>" << rows.size() - static_cast<size_t>(passed)
       << " failed</b>. Rebuilt from the CSV files in <code>"
       << HtmlEscape(options.source_label.empty() ? dir : options.source_label)
       << "</code> by <code>rabbit report</code> (rabbit " << RABBIT_VERSION << ") on " << UtcNow()
       << ". Variants: the Fuzzy-CMAC walker, and as baselines the pragmatic rules at the "
          "nearest reference gait and the Fuzzy-CMAC with its weights rounded to the strongest "
          "rule.</p>\n";
  if (!have_figures) html << "<p class=\"warning\">" << HtmlEscape(figure_error) << "</p>\n";
  html << "<h2 style=\"border:0;margin-top:20px\">Summary</h2>\n<p class=\"note\">One row per run, "
          "grouped by scenario, baselines in italics below their scenario's main variant; "
          "&ndash; marks a value the run could not measure.</p>\n"
       << SummaryTable(runs, groups);

  size_t replay_index = 0;
  for (size_t g = 0; g < groups.size(); ++g) {
    const ScenarioGroup& group = groups[g];
    const RunData& main = runs[group.runs.front()];
    html << "<section id=\"scenario-" << g << "\"><h2>" << HtmlEscape(group.name) << "</h2>\n";
    if (!main.description.empty()) html << "<p>" << HtmlEscape(main.description) << "</p>\n";
    html << "<p class=\"note\">Terrain: " << TerrainText(main.obstacles) << ". Runs: ";
    for (size_t i = 0; i < group.runs.size(); ++i) {
      const SummaryRow& r = runs[group.runs[i]].row;
      html << (i == 0 ? "" : "; ") << HtmlEscape(VariantLabel(r.variant)) << " <code>"
           << HtmlEscape(r.run) << "</code> " << (r.passed ? "passed" : "failed") << " ("
           << HtmlEscape(r.outcome) << ")";
    }
    html << ".</p>\n";
    if (have_figures) {
      for (size_t k : scenario_figures[g]) html << figures.figure(k).html;
    }
    if (!main.steps.empty()) html << StepsTable(main);
    html << "<h3>Replay</h3>\n";
    for (size_t k : group.runs) html << ReplayHtml(runs[k], replay_index++, options);
    html << "</section>\n";
  }
  html << "</main><script>" << kReplayScript << "</script></body></html>\n";

  const std::string path = (root / "index.html").string();
  const std::string page = html.str();
  WriteFileAtomically(path, [&page](std::ostream& out) { out << page; });
  return path;
}

}  // namespace rabbit
