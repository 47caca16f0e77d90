#include "rabbit/control/step_map_control.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace rabbit {

namespace {
constexpr double kDeg = M_PI / 180.0;
}  // namespace

std::vector<StepMapBand> StepMapParams::DefaultStepMapBands() {
  // {V m/s, q* deg, a, b m/s per deg}: bench/identify_step_map on the training walks of
  // scenarios/train/speed.toml (docs/design/velocity-control.md, "The step-to-step map").
  const double table[][4] = {{0.3, -10.21, 0.550, 0.00593}, {0.4, -6.76, 0.550, 0.00593},
                             {0.5, -3.21, 0.550, 0.00593},  {0.6, 7.85, 0.550, 0.00593},
                             {0.7, 13.13, 0.550, 0.00593},  {0.8, 17.68, 0.550, 0.00593},
                             {0.9, 24.42, 0.550, 0.00593},  {1.0, 27.46, 0.550, 0.00593}};
  std::vector<StepMapBand> bands;
  for (const auto& row : table) bands.push_back({row[0], row[1] * kDeg, row[2], row[3] / kDeg});
  return bands;
}

bool StepMapParams::IsValid(std::string* error) const {
  if (bands.empty()) {
    *error = "velocity_control.step_map.bands: at least one band";
    return false;
  }
  for (size_t i = 0; i < bands.size(); ++i) {
    const StepMapBand& band = bands[i];
    const bool ordered = i == 0 || band.v > bands[i - 1].v;
    if (!(std::isfinite(band.v) && band.v > 0.0 && band.v < 3.0 && ordered &&
          std::abs(band.q_star) < M_PI / 4 && band.a >= 0.0 && band.a < 1.0 && band.b > 0.0 &&
          std::isfinite(band.b))) {
      *error = "velocity_control.step_map.bands: band " + std::to_string(i + 1) +
               " needs V in (0, 3) m/s ascending, |q*| < 45 deg, a in [0, 1), b > 0";
      return false;
    }
  }
  if (!(decay >= 0.0 && decay < 1.0)) {
    *error = "velocity_control.step_map.decay must be in [0, 1)";
    return false;
  }
  if (!(offset_gain >= 0.0 && offset_gain <= 1.0)) {
    *error = "velocity_control.step_map.offset_gain must be in [0, 1]";
    return false;
  }
  if (!(offset_max >= 0.0 && offset_max <= 1.0)) {
    *error = "velocity_control.step_map.offset_max must be in [0, 1] m/s";
    return false;
  }
  if (!(fis_gain >= 0.0 && fis_gain <= 2.0 && fis_max >= 0.0 && fis_max <= 1.0)) {
    *error = "velocity_control.step_map: fis_gain must be in [0, 2], fis_max in [0, 1] m/s";
    return false;
  }
  if (!(max_change > 0.0 && max_change <= M_PI / 4)) {
    *error = "velocity_control.step_map.max_change_deg must be in (0, 45]";
    return false;
  }
  return true;
}

StepMapBand StepMapAt(const std::vector<StepMapBand>& bands, double v) {
  if (bands.empty()) return {};
  if (v <= bands.front().v) return bands.front();
  for (size_t i = 1; i < bands.size(); ++i) {
    if (v < bands[i].v) {
      const StepMapBand& lo = bands[i - 1];
      const StepMapBand& hi = bands[i];
      const double f = (v - lo.v) / (hi.v - lo.v);
      return {v, lo.q_star + f * (hi.q_star - lo.q_star), lo.a + f * (hi.a - lo.a),
              lo.b + f * (hi.b - lo.b)};
    }
  }
  return bands.back();
}

StepMapControl::StepMapControl(const StepMapParams& params)
    : p_(params), predicted_(std::numeric_limits<double>::quiet_NaN()) {
  std::string error;
  if (!p_.IsValid(&error)) throw std::invalid_argument(error);
}

double StepMapControl::Update(double s, double v_c, double q0_d, double q0_d_min, double q0_d_max) {
  if (std::isfinite(predicted_)) {
    offset_ =
        std::clamp(offset_ + p_.offset_gain * (s - predicted_), -p_.offset_max, p_.offset_max);
  }
  const StepMapBand m = StepMapAt(p_.bands, v_c);
  // The next stride, which the pitch in force still decides.
  predicted_ = v_c + m.a * (s - v_c) + m.b * (q0_d - m.q_star) + offset_;
  const double e1 = predicted_ - v_c;
  const double wanted = m.q_star + ((p_.decay - m.a) * e1 - offset_) / m.b;
  const double q = std::clamp(std::clamp(wanted, q0_d - p_.max_change, q0_d + p_.max_change),
                              q0_d_min, q0_d_max);
  const double withheld = wanted - std::clamp(wanted, q0_d_min, q0_d_max);  // the range's part
  fis_offset_ = std::clamp(p_.fis_gain * m.b / (1.0 - m.a) * withheld, -p_.fis_max, p_.fis_max);
  return q;
}

bool IdentifyStepMap(const std::vector<StepMapSample>& samples, const std::vector<double>& centres,
                     int min_samples, bool pooled, StepMapFit* fit, std::string* error) {
  for (size_t i = 1; i < centres.size(); ++i) {
    if (!(centres[i] > centres[i - 1])) {
      *error = "the bands' centres must ascend";
      return false;
    }
  }
  if (centres.empty()) {
    *error = "no band to fit";
    return false;
  }
  std::vector<std::vector<const StepMapSample*>> members(centres.size());
  for (const StepMapSample& sample : samples) {
    size_t best = 0;
    for (size_t i = 1; i < centres.size(); ++i) {
      if (std::abs(sample.v_c - centres[i]) < std::abs(sample.v_c - centres[best])) best = i;
    }
    members[best].push_back(&sample);
  }
  *fit = StepMapFit{};
  const size_t n_bands = centres.size();
  const auto name = [&centres](size_t i) {
    char text[64];
    std::snprintf(text, sizeof text, "band %zu (V = %.2f m/s)", i + 1, centres[i]);
    return std::string(text);
  };
  for (size_t i = 0; i < n_bands; ++i) {
    if (static_cast<int>(members[i].size()) < std::max(min_samples, 3)) {
      *error = name(i) + ": " + std::to_string(members[i].size()) + " samples, need " +
               std::to_string(std::max(min_samples, 3));
      return false;
    }
  }
  // Pooled: one a and b for every band, an intercept c_i per band; else all three per band.
  const size_t n = samples.size();
  const size_t cols = pooled ? 2 + n_bands : 3;
  std::vector<Eigen::Vector3d> coef(n_bands);  // per band (c, a, b)
  if (pooled) {
    Eigen::MatrixXd x = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), cols);
    Eigen::VectorXd y(n);
    Eigen::Index row = 0;
    for (size_t i = 0; i < n_bands; ++i) {
      for (const StepMapSample* m : members[i]) {
        x(row, 0) = m->s;
        x(row, 1) = m->q0_d;
        x(row, 2 + static_cast<Eigen::Index>(i)) = 1.0;
        y[row++] = m->s_next;
      }
    }
    const Eigen::VectorXd c = x.colPivHouseholderQr().solve(y);
    for (size_t i = 0; i < n_bands; ++i) coef[i] << c[2 + static_cast<Eigen::Index>(i)], c[0], c[1];
  } else {
    for (size_t i = 0; i < n_bands; ++i) {
      const auto& m = members[i];
      Eigen::MatrixXd x(m.size(), 3);
      Eigen::VectorXd y(m.size());
      for (size_t j = 0; j < m.size(); ++j) {
        x.row(static_cast<Eigen::Index>(j)) << 1.0, m[j]->s, m[j]->q0_d;
        y[static_cast<Eigen::Index>(j)] = m[j]->s_next;
      }
      coef[i] = x.colPivHouseholderQr().solve(y);
    }
  }
  for (size_t i = 0; i < n_bands; ++i) {
    const Eigen::Vector3d& c = coef[i];
    if (!(c[2] > 0.0) || !c.allFinite()) {
      *error = name(i) + ": the pitch's effect b is not positive (the samples do not excite it)";
      return false;
    }
    double sum = 0.0;
    for (const StepMapSample* m : members[i]) {
      const double r = c[0] + c[1] * m->s + c[2] * m->q0_d - m->s_next;
      sum += r * r;
    }
    const double v = centres[i];
    fit->bands.push_back({v, (v * (1.0 - c[1]) - c[0]) / c[2], c[1], c[2]});
    fit->samples.push_back(static_cast<int>(members[i].size()));
    fit->rms.push_back(std::sqrt(sum / static_cast<double>(members[i].size())));
  }
  return true;
}

}  // namespace rabbit
