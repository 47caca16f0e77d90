#include "rabbit/scenario/trajectory_csv.h"

#include <iomanip>

#include "rabbit/io/atomic_file.h"

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
  out << std::setprecision(12);
  for (const SimSample& s : result.samples) {
    out << s.t;
    for (int i = 0; i < kNq; ++i) out << ',' << s.q[i];
    for (int i = 0; i < kNq; ++i) out << ',' << s.qd[i];
    for (int j = 0; j < kNumJoints; ++j) out << ',' << s.tau_cmd[j];
    for (int j = 0; j < kNumJoints; ++j) out << ',' << s.tau[j];
    for (int leg = 0; leg < kNumLegs; ++leg) {
      out << ',' << s.foot_pos[leg].x() << ',' << s.foot_pos[leg].y() << ',' << s.foot_force[leg].fn
          << ',' << s.foot_force[leg].ft << ',' << (s.foot_force[leg].fn > 0.0 ? 1 : 0) << ','
          << ContactModeName(s.foot_mode[leg]);
    }
    out << ',' << s.kinetic << ',' << s.potential << ',' << s.elastic << ',' << TotalEnergy(s)
        << '\n';
  }
}

void WriteTrajectoryCsvFile(const SimResult& result, const std::string& path) {
  WriteFileAtomically(path, [&result](std::ostream& out) { WriteTrajectoryCsv(result, out); });
}

}  // namespace rabbit
