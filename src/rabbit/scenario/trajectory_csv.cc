#include "rabbit/scenario/trajectory_csv.h"

#include <algorithm>
#include <cstring>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv.h"

namespace rabbit {

void WriteTrajectoryCsv(const SimResult& result, std::ostream& out) {
  static const char* kCoords[] = {"x_m",     "y_m",     "q0_rad", "q11_rad",
                                  "q12_rad", "q21_rad", "q22_rad"};
  static const char* kRates[] = {"xd_m_s",     "yd_m_s",     "q0d_rad_s", "q11d_rad_s",
                                 "q12d_rad_s", "q21d_rad_s", "q22d_rad_s"};
  static const char* kJoints[] = {"hip1", "knee1", "hip2", "knee2"};
  out << "t_s";
  for (const char* c : kCoords) out << ',' << c;
  for (const char* c : kRates) out << ',' << c;
  for (const char* j : kJoints) out << ",tau_cmd_" << j << "_nm";
  for (const char* j : kJoints) out << ",tau_" << j << "_nm";
  for (int leg = 1; leg <= kNumLegs; ++leg) {
    out << ",foot" << leg << "_x_m,foot" << leg << "_y_m,foot" << leg << "_fn_n,foot" << leg
        << "_ft_n,foot" << leg << "_contact,foot" << leg << "_mode";
  }
  out << ",kinetic_j,potential_j,elastic_j,total_energy_j\n";
  // Each row is formatted into one buffer (shortest round-trip numbers, no stream formatting)
  // and written in one call: this file is the bulk of a run's output.
  constexpr int kNumbers = 1 + 2 * kNq + 2 * kNumJoints + 5 * kNumLegs + 4;
  char row[kNumbers * (kMaxCsvNumberChars + 1) + kNumLegs * 16 + 2];
  for (const SimSample& s : result.samples) {
    char* p = row;
    auto number = [&p](double v) {
      *p++ = ',';
      p = WriteCsvNumber(p, v);
    };
    p = WriteCsvNumber(p, s.t);
    for (int i = 0; i < kNq; ++i) number(s.q[i]);
    for (int i = 0; i < kNq; ++i) number(s.qd[i]);
    for (int j = 0; j < kNumJoints; ++j) number(s.tau_cmd[j]);
    for (int j = 0; j < kNumJoints; ++j) number(s.tau[j]);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      number(s.foot_pos[leg].x());
      number(s.foot_pos[leg].y());
      number(s.foot_force[leg].fn);
      number(s.foot_force[leg].ft);
      *p++ = ',';
      *p++ = s.foot_force[leg].fn > 0.0 ? '1' : '0';
      *p++ = ',';
      const char* mode = ContactModeName(s.foot_mode[leg]);
      const size_t length = std::strlen(mode);
      std::memcpy(p, mode, std::min<size_t>(length, 15));
      p += std::min<size_t>(length, 15);
    }
    number(s.kinetic);
    number(s.potential);
    number(s.elastic);
    number(TotalEnergy(s));
    *p++ = '\n';
    out.write(row, p - row);
  }
}

void WriteTrajectoryCsvFile(const SimResult& result, const std::string& path) {
  WriteFileAtomically(path, [&result](std::ostream& out) { WriteTrajectoryCsv(result, out); });
}

}  // namespace rabbit
