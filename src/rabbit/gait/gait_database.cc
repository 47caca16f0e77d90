#include "rabbit/gait/gait_database.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>
#include <tuple>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"

namespace rabbit {
namespace {

constexpr double kDeg = M_PI / 180.0;
const char* const kColumns[] = {"e_rad", "q_i1_rad", "q_i2_rad", "qd_i1_rad_s", "qd_i2_rad_s"};
// The index's columns; an index written before gaits had roles has the first kOldIndexColumns.
const char* const kIndexColumns[] = {"name",     "file",           "target_v_m", "measured_v_m",
                                     "l_step_m", "t_step_s",       "steps",      "source",
                                     "role",     "target_l_step_m"};
constexpr std::size_t kOldIndexColumns = 8;

std::string IndexHeader() {
  std::string out;
  for (const char* c : kIndexColumns) out += (out.empty() ? "" : ",") + std::string(c);
  return out;
}

// The gait's metadata as ordered key/value pairs (angles in degrees at the edge).
std::vector<std::pair<std::string, double>> NumericMetadata(const GaitRecord& g) {
  const PragmaticParams& r = g.spec.rules;
  return {{"target_v_m", g.target_v_m},
          {"target_l_step_m", g.target_l_step},
          {"measured_v_m", g.measured.v_m},
          {"measured_l_step_m", g.measured.l_step},
          {"measured_t_step_s", g.measured.t_step},
          {"l_step_spread_m", g.measured.l_step_spread},
          {"v_m_spread_m_s", g.measured.v_m_spread},
          {"steps", static_cast<double>(g.measured.steps)},
          {"saturation_time_s", g.measured.saturation_time},
          {"qr1_dsw_deg", r.qr1_dsw / kDeg},
          {"qi2_dsw_deg", r.qi2_dsw / kDeg},
          {"q0_d_deg", r.q0_d / kDeg},
          {"pulse_torque_nm", r.pulse_torque},
          {"pulse_start_s", r.pulse_start},
          {"pulse_duration_s", r.pulse_duration},
          {"hip_kp", r.hip_kp},
          {"hip_kd", r.hip_kd},
          {"trunk_kp", r.trunk_kp},
          {"trunk_kd", r.trunk_kd},
          {"knee_kp", r.knee_kp},
          {"knee_kd", r.knee_kd},
          {"start_speed_m_s", g.spec.start_speed},
          {"start_angle_deg", g.spec.start_angle / kDeg},
          {"seed", static_cast<double>(g.seed)}};
}

}  // namespace

const char* GaitRoleName(GaitRole role) { return role == GaitRole::kLibrary ? "library" : "speed"; }

bool ParseGaitRole(const std::string& text, GaitRole* role) {
  if (text == "speed") {
    *role = GaitRole::kSpeed;
  } else if (text == "library") {
    *role = GaitRole::kLibrary;
  } else {
    return false;
  }
  return true;
}

std::vector<GaitIndexEntry> GaitsOfRole(const std::vector<GaitIndexEntry>& index, GaitRole role) {
  std::vector<GaitIndexEntry> out;
  for (const GaitIndexEntry& e : index) {
    if (e.role == role) out.push_back(e);
  }
  return out;
}

std::string ModelHash(const ModelParams& p) {
  std::ostringstream text;
  text << std::setprecision(17) << p.trunk_mass << ' ' << p.trunk_com << ' ' << p.trunk_inertia
       << ' ' << p.thigh_mass << ' ' << p.thigh_length << ' ' << p.thigh_com << ' '
       << p.thigh_inertia << ' ' << p.shin_mass << ' ' << p.shin_length << ' ' << p.shin_com << ' '
       << p.shin_inertia << ' ' << p.rotor_inertia << ' ' << p.gear_ratio << ' ' << p.gravity << ' '
       << p.slope;
  // FNV-1a, 64 bit: stable across platforms and runs (std::hash is not).
  unsigned long long h = 1469598103934665603ULL;
  for (unsigned char c : text.str()) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", h);
  return buffer;
}

void WriteGaitFile(const GaitRecord& g, const std::string& path) {
  const std::string text = GaitFileText(g);
  WriteFileAtomically(path, [&text](std::ostream& out) { out << text; });
}

std::string GaitFileText(const GaitRecord& g) {
  std::ostringstream out;
  {
    out << "# format = " << kGaitFormat << "\n";
    out << "# name = " << g.name << "\n";
    out << std::setprecision(17);  // exact round trip: the gait is re-walked from these
    for (const auto& [key, value] : NumericMetadata(g))
      out << "# " << key << " = " << value << "\n";
    out << "# model_hash = " << g.model_hash << "\n";
    out << "# generator = rabbit " << RABBIT_VERSION << "\n";
    out << "# source = " << g.source << "\n";
    // Speed gaits (the default) carry no role line: their files are as before roles existed.
    if (g.role != GaitRole::kSpeed) out << "# role = " << GaitRoleName(g.role) << "\n";
    for (size_t i = 0; i < std::size(kColumns); ++i) out << (i ? "," : "") << kColumns[i];
    out << "\n" << std::setprecision(12);
    for (const SwingSample& s : g.swing) {
      out << s.e << ',' << s.q1 << ',' << s.q2 << ',' << s.qd1 << ',' << s.qd2 << "\n";
    }
  }
  return out.str();
}

GaitRecord ReadGaitFile(const std::string& path) {
  std::istringstream in(ReadBoundedFile(path, kGaitFileLimits));
  std::map<std::string, std::pair<std::string, int>> meta;  // key -> value, line
  std::string line;
  int number = 0;
  bool header_seen = false;
  GaitRecord g;
  std::vector<int> column_of(std::size(kColumns), -1);
  size_t columns = 0;
  while (std::getline(in, line)) {
    ++number;
    if (Trim(line).empty()) continue;
    if (line[0] == '#') {
      if (header_seen) throw InputError(path, number, "", "comment after the column header");
      const size_t eq = line.find('=');
      if (eq == std::string::npos) continue;  // free comment
      const std::string key = Trim(line.substr(1, eq - 1));
      const auto [it, inserted] = meta.insert({key, {Trim(line.substr(eq + 1)), number}});
      if (!inserted) {
        throw InputError(
            path, number, key,
            "metadata key given twice (first on line " + std::to_string(it->second.second) + ")");
      }
      continue;
    }
    if (!header_seen) {
      header_seen = true;
      const auto format = meta.find("format");
      if (format == meta.end()) {
        throw InputError(path, 1, "format",
                         "missing '# format = " + std::string(kGaitFormat) + "'");
      }
      if (format->second.first != kGaitFormat) {
        throw InputError(
            path, format->second.second, "format",
            "unsupported format \"" + format->second.first + "\" (expected " + kGaitFormat + ")");
      }
      const std::vector<std::string> names = SplitCsv(line);
      columns = names.size();
      for (size_t c = 0; c < std::size(kColumns); ++c) {
        const auto it = std::find(names.begin(), names.end(), kColumns[c]);
        if (it == names.end()) {
          throw InputError(path, number, kColumns[c], "missing column");
        }
        column_of[c] = static_cast<int>(it - names.begin());
      }
      continue;
    }
    const std::vector<std::string> cells = SplitCsv(line);
    if (cells.size() != columns) {
      throw InputError(
          path, number, "",
          "expected " + std::to_string(columns) + " cells, got " + std::to_string(cells.size()));
    }
    double v[5];
    for (size_t c = 0; c < std::size(kColumns); ++c) {
      v[c] = ParseFiniteNumber(cells[column_of[c]], path, number, kColumns[c]);
      // Angles within a turn, rates within 100 rad/s: anything else is not a gait.
      const double bound = c < 3 ? 2 * M_PI : 100.0;
      if (std::abs(v[c]) > bound) {
        throw InputError(path, number, kColumns[c],
                         "value out of range (|x| <= " + std::to_string(bound) + ")");
      }
    }
    if (!g.swing.empty() && !(v[0] > g.swing.back().e)) {
      throw InputError(path, number, "e_rad", "e must increase strictly from row to row");
    }
    g.swing.push_back({v[0], v[1], v[2], v[3], v[4]});
  }
  if (!header_seen) throw InputError(path, number, "", "no column header and no data");
  if (g.swing.size() < 2) throw InputError(path, number, "", "fewer than 2 trajectory rows");

  auto number_of = [&](const std::string& key) {
    const auto it = meta.find(key);
    if (it == meta.end()) throw InputError(path, 0, key, "missing metadata '# " + key + " = ...'");
    return ParseFiniteNumber(it->second.first, path, it->second.second, key);
  };
  auto count_of = [&](const std::string& key, double max) {
    const double v = number_of(key);
    if (!(v >= 0.0 && v <= max && v == std::floor(v))) {
      throw InputError(
          path, meta[key].second, key,
          "expected a whole number in [0, " + std::to_string(static_cast<long>(max)) + "]");
    }
    return v;
  };
  auto text_of = [&](const std::string& key) {
    const auto it = meta.find(key);
    return it == meta.end() ? std::string() : it->second.first;
  };
  g.name = text_of("name");
  if (g.name.empty()) g.name = std::filesystem::path(path).stem().string();
  g.model_hash = text_of("model_hash");
  g.source = text_of("source");
  if (meta.count("role") != 0 && !ParseGaitRole(meta["role"].first, &g.role)) {
    throw InputError(path, meta["role"].second, "role",
                     "unknown role \"" + meta["role"].first + "\" (speed or library)");
  }
  g.target_v_m = number_of("target_v_m");
  g.target_l_step = number_of("target_l_step_m");
  g.measured.v_m = number_of("measured_v_m");
  g.measured.l_step = number_of("measured_l_step_m");
  g.measured.t_step = number_of("measured_t_step_s");
  g.measured.l_step_spread = number_of("l_step_spread_m");
  g.measured.v_m_spread = number_of("v_m_spread_m_s");
  g.measured.steps = static_cast<int>(count_of("steps", 1e6));
  g.measured.saturation_time = number_of("saturation_time_s");
  PragmaticParams& r = g.spec.rules;
  r.qr1_dsw = number_of("qr1_dsw_deg") * kDeg;
  r.qi2_dsw = number_of("qi2_dsw_deg") * kDeg;
  r.q0_d = number_of("q0_d_deg") * kDeg;
  r.pulse_torque = number_of("pulse_torque_nm");
  r.pulse_start = number_of("pulse_start_s");
  r.pulse_duration = number_of("pulse_duration_s");
  r.hip_kp = number_of("hip_kp");
  r.hip_kd = number_of("hip_kd");
  r.trunk_kp = number_of("trunk_kp");
  r.trunk_kd = number_of("trunk_kd");
  r.knee_kp = number_of("knee_kp");
  r.knee_kd = number_of("knee_kd");
  g.spec.start_speed = number_of("start_speed_m_s");
  g.spec.start_angle = number_of("start_angle_deg") * kDeg;
  g.seed = static_cast<unsigned>(count_of("seed", 4294967295.0));
  std::string error;
  if (!g.spec.IsValid(&error)) throw InputError(path, 0, "", "invalid gait parameters: " + error);
  return g;
}

void WriteGaitIndex(const std::vector<GaitIndexEntry>& entries, const std::string& path) {
  WriteFileAtomically(path, [&entries](std::ostream& out) {
    out << IndexHeader() << "\n";
    out << std::setprecision(6);
    for (const GaitIndexEntry& e : entries) {
      out << e.name << ',' << e.file << ',' << e.target_v_m << ',' << e.measured_v_m << ','
          << e.l_step << ',' << e.t_step << ',' << e.steps << ',' << e.source << ','
          << GaitRoleName(e.role) << ',' << e.target_l_step << "\n";
    }
  });
}

std::vector<GaitIndexEntry> ReadGaitIndex(const std::string& path) {
  std::vector<GaitIndexEntry> entries;
  std::istringstream in(ReadBoundedFile(path, kIndexFileLimits));
  std::string line;
  int number = 0;
  bool header_seen = false;
  std::size_t columns = std::size(kIndexColumns);
  std::map<std::string, int> line_of_name, line_of_file;
  while (std::getline(in, line)) {
    ++number;
    if (Trim(line).empty()) continue;
    const std::vector<std::string> c = SplitCsv(line);
    if (!header_seen) {
      header_seen = true;
      const std::vector<std::string> all(std::begin(kIndexColumns), std::end(kIndexColumns));
      const std::vector<std::string> old(all.begin(), all.begin() + kOldIndexColumns);
      if (c != all && c != old) {
        throw InputError(
            path, number, "",
            "expected the header row \"" + IndexHeader() + "\", got \"" + Trim(line) + "\"");
      }
      columns = c.size();
      continue;
    }
    if (c.size() != columns) {
      throw InputError(path, number, "",
                       "expected " + std::to_string(columns) + " cells (" + IndexHeader() +
                           "), got " + std::to_string(c.size()));
    }
    for (auto [seen, value, key] :
         {std::tuple(&line_of_name, c[0], "name"), std::tuple(&line_of_file, c[1], "file")}) {
      const auto [it, inserted] = seen->insert({value, number});
      if (!inserted) {
        throw InputError(path, number, key,
                         "gait \"" + value + "\" listed twice (first on line " +
                             std::to_string(it->second) + ")");
      }
    }
    GaitIndexEntry e;
    e.name = c[0];
    e.file = c[1];
    e.target_v_m = ParseFiniteNumber(c[2], path, number, "target_v_m");
    e.measured_v_m = ParseFiniteNumber(c[3], path, number, "measured_v_m");
    e.l_step = ParseFiniteNumber(c[4], path, number, "l_step_m");
    e.t_step = ParseFiniteNumber(c[5], path, number, "t_step_s");
    const double steps = ParseFiniteNumber(c[6], path, number, "steps");
    if (!(steps >= 0.0 && steps <= 1e6)) throw InputError(path, number, "steps", "out of range");
    e.steps = static_cast<int>(steps);
    e.source = c[7];
    if (c.size() == 10) {
      if (!ParseGaitRole(c[8], &e.role)) {
        throw InputError(path, number, "role", "unknown role \"" + c[8] + "\" (speed or library)");
      }
      e.target_l_step = ParseFiniteNumber(c[9], path, number, "target_l_step_m");
    }
    entries.push_back(e);
  }
  if (!header_seen)
    throw InputError(path, 0, "", "empty file: expected the header row \"" + IndexHeader() + "\"");
  return entries;
}

}  // namespace rabbit
