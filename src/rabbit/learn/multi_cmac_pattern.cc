#include "rabbit/learn/multi_cmac_pattern.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

namespace rabbit {
namespace {

constexpr double kMaxTrainingPoints = 2e6;  // grid points (the sparse system's rows)
constexpr int kInputs = 3;                  // e, V_M, d_obs
constexpr int kMaxIterations = 100000;      // of the conjugate-gradient solve

// n points evenly spaced over [lo, hi], both ends included, spacing at most `step`; with
// `midpoints`, the n - 1 midpoints between them instead.
std::vector<double> GridAxis(double lo, double hi, double step, bool midpoints) {
  const int intervals = static_cast<int>(std::max(1.0, std::ceil((hi - lo) / step - 1e-9)));
  std::vector<double> x;
  if (midpoints) {
    for (int i = 0; i < intervals; ++i) x.push_back(lo + (hi - lo) * (i + 0.5) / intervals);
  } else {
    for (int i = 0; i < intervals; ++i) x.push_back(lo + (hi - lo) * i / intervals);
    x.push_back(hi);
  }
  return x;
}

struct Grid {
  std::vector<double> e, v_m, d_obs;
  double size() const {
    return static_cast<double>(e.size()) * static_cast<double>(v_m.size()) *
           static_cast<double>(d_obs.size());
  }
};

Grid MakeGrid(const MultiCmacPatternDomain& d, const MultiCmacPatternOptions& o, bool held_out) {
  return {GridAxis(d.e_min, d.e_max, o.grid_e_step, held_out),
          GridAxis(d.v_m_min, d.v_m_max, o.grid_v_m_step, held_out),
          GridAxis(0.0, d.d_obs_max, o.grid_d_obs_step, held_out)};
}

// Calls f(x, y) for every grid point where the teacher fires, x = {e, V_M, d_obs}, y its outputs.
template <typename F>
void ForEachTeacherPoint(const FuzzyCmac& teacher, bool thigh_frame, const Grid& grid, F f) {
  FuzzyCmac t = teacher;  // SetContext changes it
  std::array<double, kInputs> x;
  for (double v_m : grid.v_m) {
    for (double d_obs : grid.d_obs) {
      if (!t.SetContext(v_m, d_obs)) continue;
      x[1] = v_m;
      x[2] = d_obs;
      for (double e : grid.e) {
        x[0] = e;
        const Eigen::Vector4d y = thigh_frame ? t.QueryThigh(e) : t.Query(e);
        if (y.allFinite()) f(x, y);
      }
    }
  }
}

void CheckTeacher(const FuzzyCmac& teacher, const MultiCmacPatternDomain& domain) {
  if (domain.thigh_frame && teacher.trunk_pitches().empty()) {
    throw std::invalid_argument(
        "multi-input CMAC pattern: the thigh frame needs the teacher's "
        "trunk pitches");
  }
}

bool Positive(double x) { return std::isfinite(x) && x > 0.0; }

}  // namespace

bool MultiCmacPatternOptions::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (layers < 1 || layers > kMaxCmacLayers) {
    return fail("layers must be in [1, " + std::to_string(kMaxCmacLayers) + "]");
  }
  const std::pair<const char*, int> widths[] = {
      {"e_width", e_width}, {"v_m_width", v_m_width}, {"d_obs_width", d_obs_width}};
  for (const auto& [name, width] : widths) {
    if (width < layers)
      return fail(std::string(name) + " must be >= layers (" + std::to_string(layers) +
                  "): offsets would repeat");
  }
  const std::pair<const char*, double> positive[] = {{"e_quantum", e_quantum},
                                                     {"v_m_quantum", v_m_quantum},
                                                     {"d_obs_quantum", d_obs_quantum},
                                                     {"grid_e_step", grid_e_step},
                                                     {"grid_v_m_step", grid_v_m_step},
                                                     {"grid_d_obs_step", grid_d_obs_step},
                                                     {"ridge", ridge}};
  for (const auto& [name, value] : positive) {
    if (!Positive(value)) return fail(std::string(name) + " must be finite and > 0");
  }
  if (!(Positive(tolerance) && tolerance < 1.0)) return fail("tolerance must be in (0, 1)");
  if (max_iterations < 1 || max_iterations > kMaxIterations) {
    return fail("max_iterations must be in [1, " + std::to_string(kMaxIterations) + "]");
  }
  if (!(std::isfinite(v_m_margin) && v_m_margin >= 0.0)) {
    return fail("v_m_margin must be finite and >= 0");
  }
  if (hash_table_size < 1 || hash_table_size > kMaxMultiCmacTable) {
    return fail("hash_table_size must be in [1, " + std::to_string(kMaxMultiCmacTable) + "]");
  }
  return true;
}

bool MultiCmacPatternDomain::IsValid(std::string* error) const {
  auto fail = [error](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(std::isfinite(e_min) && std::isfinite(e_max) && e_min < e_max)) {
    return fail("the e range needs finite e_min < e_max");
  }
  if (!(std::isfinite(v_m_min) && std::isfinite(v_m_max) && v_m_min < v_m_max)) {
    return fail("the V_M range needs finite v_m_min < v_m_max");
  }
  if (!Positive(d_obs_max)) return fail("d_obs_max must be finite and > 0");
  return true;
}

MultiCmacPatternDomain TeacherDomain(const FuzzyCmac& teacher,
                                     const std::vector<double>& gait_velocities, bool thigh_frame,
                                     double d_obs_max, double v_m_margin) {
  if (gait_velocities.empty()) {
    throw std::invalid_argument("multi-input CMAC pattern: no reference gait velocities");
  }
  MultiCmacPatternDomain d;
  d.thigh_frame = thigh_frame;
  const CmacOptions& c = teacher.cmac_options();
  d.e_min = c.x_min;
  d.e_max = c.x_max;
  if (thigh_frame) {
    const std::vector<double>& q0 = teacher.trunk_pitches();
    if (q0.empty()) {
      throw std::invalid_argument(
          "multi-input CMAC pattern: the thigh frame needs the teacher's "
          "trunk pitches");
    }
    d.e_min = c.x_min - *std::max_element(q0.begin(), q0.end());
    d.e_max = c.x_max - *std::min_element(q0.begin(), q0.end());
  }
  d.v_m_min = *std::min_element(gait_velocities.begin(), gait_velocities.end()) - v_m_margin;
  d.v_m_max = *std::max_element(gait_velocities.begin(), gait_velocities.end()) + v_m_margin;
  d.d_obs_max = d_obs_max;
  return d;
}

MultiCmacPattern::MultiCmacPattern(const MultiCmacPatternDomain& domain,
                                   const MultiCmacPatternOptions& options)
    : domain_(domain), options_(options) {
  std::string error;
  if (!options_.IsValid(&error) || !domain_.IsValid(&error)) {
    throw std::invalid_argument("multi-input CMAC pattern: " + error);
  }
  MultiCmacOptions o;
  o.layers = options_.layers;
  o.inputs = {{options_.e_quantum, options_.e_width, domain_.e_min, domain_.e_max},
              {options_.v_m_quantum, options_.v_m_width, domain_.v_m_min, domain_.v_m_max},
              {options_.d_obs_quantum, options_.d_obs_width, 0.0, domain_.d_obs_max}};
  o.hash_table_size = options_.hash_table_size;
  o.hash_seed = options_.hash_seed;
  if (!o.IsValid(&error)) throw std::invalid_argument("multi-input CMAC pattern: " + error);
  cmacs_.assign(kGaitOutputs, MultiCmac(o));
}

Eigen::Vector4d MultiCmacPattern::Query(double e, double v_m, double d_obs) const {
  const double x[kInputs] = {e, v_m, d_obs};
  CmacActive active;
  cmacs_[0].Active(x, &active);  // one structure: the same slots in all four
  if (active.count == 0) return Eigen::Vector4d::Constant(std::nan(""));
  Eigen::Vector4d y;
  for (int o = 0; o < kGaitOutputs; ++o) {
    const std::vector<double>& w = cmacs_[o].weights();
    double sum = 0.0;
    for (int i = 0; i < active.count; ++i) sum += w[active.index[i]];
    y[o] = sum;
  }
  return y;
}

std::size_t MultiCmacPattern::MemoryBytes() const {
  std::size_t bytes = 0;
  for (const MultiCmac& c : cmacs_) bytes += c.MemoryBytes();
  return bytes;
}

std::string MultiCmacTrainingSummary::BriefReport() const {
  char text[320];
  std::snprintf(text, sizeof text,
                "multi-input CMAC pattern: %d grid points, %d weights reached per output "
                "(%.0f virtual detectors, %d in shared slots), training RMS q_i1 %.3g deg, q_i2 "
                "%.3g deg, qd_i1 %.3g deg/s, qd_i2 %.3g deg/s, %.2f s",
                points, unknowns, virtual_detectors, collisions, rms[0] * 180.0 / M_PI,
                rms[1] * 180.0 / M_PI, rms[2] * 180.0 / M_PI, rms[3] * 180.0 / M_PI, seconds);
  return text;
}

MultiCmacPattern TrainMultiCmacPattern(const FuzzyCmac& teacher,
                                       const MultiCmacPatternDomain& domain,
                                       const MultiCmacPatternOptions& options,
                                       MultiCmacTrainingSummary* summary) {
  const auto start = std::chrono::steady_clock::now();
  MultiCmacPattern pattern(domain, options);  // validates
  CheckTeacher(teacher, domain);
  const Grid grid = MakeGrid(domain, options, false);
  if (grid.size() > kMaxTrainingPoints) {
    throw std::invalid_argument("multi-input CMAC pattern: the training grid has " +
                                std::to_string(grid.size()) +
                                " points (at most 2e6): make the grid_* steps coarser");
  }
  const MultiCmac& structure = pattern.cmacs()[0];
  const int layers = options.layers;
  // The grid points' active slots (layers per point), the slots reached, the teacher's outputs.
  std::vector<int> slots;
  std::vector<char> reached(static_cast<size_t>(options.hash_table_size), 0);
  std::vector<double> targets;  // kGaitOutputs per point
  CmacActive active;
  ForEachTeacherPoint(teacher, domain.thigh_frame, grid,
                      [&](const std::array<double, kInputs>& x, const Eigen::Vector4d& y) {
                        structure.Active(x.data(), &active);
                        for (int j = 0; j < layers; ++j) {
                          slots.push_back(active.index[j]);
                          reached[active.index[j]] = 1;
                        }
                        targets.insert(targets.end(), y.data(), y.data() + kGaitOutputs);
                      });
  const int n = static_cast<int>(targets.size() / kGaitOutputs);
  if (n == 0) throw std::runtime_error("multi-input CMAC pattern: the teacher fired nowhere");
  // Unknowns: the slots reached, in slot order.
  std::vector<int> used, column(reached.size(), -1);
  for (size_t slot = 0; slot < reached.size(); ++slot) {
    if (!reached[slot]) continue;
    column[slot] = static_cast<int>(used.size());
    used.push_back(static_cast<int>(slot));
  }
  reached = {};
  const int m = static_cast<int>(used.size());
  // A, row by row: one row per point, 1 per active layer (2 where hashing put two layers on one
  // slot), in column order.
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(n, m);
  a.reserve(Eigen::VectorXi::Constant(n, layers));
  std::array<int, kMaxCmacLayers> row;
  for (int p = 0; p < n; ++p) {
    for (int j = 0; j < layers; ++j) row[j] = column[slots[static_cast<size_t>(p) * layers + j]];
    std::sort(row.begin(), row.begin() + layers);
    for (int j = 0; j < layers; ++j) {
      if (j > 0 && row[j] == row[j - 1]) {
        a.coeffRef(p, row[j]) += 1.0;
      } else {
        a.insert(p, row[j]) = 1.0;
      }
    }
  }
  a.makeCompressed();
  slots = {};
  const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, kGaitOutputs, Eigen::RowMajor>> y(
      targets.data(), n, kGaitOutputs);
  using Sparse = Eigen::SparseMatrix<double>;
  Sparse normal = Sparse(a.transpose() * a);
  for (int i = 0; i < m; ++i) normal.coeffRef(i, i) += options.ridge;
  Eigen::ConjugateGradient<Sparse, Eigen::Lower | Eigen::Upper> solver;
  solver.setTolerance(options.tolerance);
  solver.setMaxIterations(options.max_iterations);
  solver.compute(normal);
  const Eigen::MatrixXd rhs = a.transpose() * y;
  Eigen::MatrixXd w(m, kGaitOutputs);
  int iterations = 0;
  for (int o = 0; o < kGaitOutputs; ++o) {
    w.col(o) = solver.solve(rhs.col(o));
    iterations = std::max(iterations, static_cast<int>(solver.iterations()));
  }
  if (!w.allFinite()) {
    throw std::runtime_error("multi-input CMAC pattern: the least-squares solve failed");
  }
  std::vector<MultiCmac>& cmacs = *pattern.mutable_cmacs();
  for (int o = 0; o < kGaitOutputs; ++o) {
    std::vector<double>& weights = *cmacs[o].mutable_weights();
    for (int i = 0; i < m; ++i) weights[used[i]] = w(i, o);
  }
  if (summary != nullptr) {
    Eigen::Vector4d sum = Eigen::Vector4d::Zero();
    for (int p = 0; p < n; ++p) {
      Eigen::Vector4d r = -y.row(p).transpose();
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(a, p); it; ++it) {
        r += it.value() * w.row(it.col()).transpose();
      }
      sum += r.cwiseProduct(r);
    }
    summary->rms = (sum / n).cwiseSqrt();
    summary->points = n;
    summary->unknowns = m;
    summary->iterations = iterations;
    summary->collisions = structure.NumCollisionsOverRange();
    summary->virtual_detectors = structure.NumVirtualDetectors();
    summary->seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return pattern;
}

MultiCmacPatternError CompareWithTeacher(const MultiCmacPattern& pattern, const FuzzyCmac& teacher,
                                         bool held_out) {
  CheckTeacher(teacher, pattern.domain());
  MultiCmacPatternError error;
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  ForEachTeacherPoint(teacher, pattern.domain().thigh_frame,
                      MakeGrid(pattern.domain(), pattern.options(), held_out),
                      [&](const std::array<double, kInputs>& x, const Eigen::Vector4d& y) {
                        const Eigen::Vector4d d = (pattern.Query(x[0], x[1], x[2]) - y).cwiseAbs();
                        sum += d.cwiseProduct(d);
                        error.max = error.max.cwiseMax(d);
                        ++error.points;
                      });
  if (error.points > 0) error.rms = (sum / error.points).cwiseSqrt();
  return error;
}

MultiCmacSwingPattern::MultiCmacSwingPattern(std::shared_ptr<const MultiCmacPattern> pattern)
    : pattern_(std::move(pattern)),
      v_m_(std::numeric_limits<double>::quiet_NaN()),
      d_obs_(std::numeric_limits<double>::quiet_NaN()) {
  if (pattern_ == nullptr) throw std::invalid_argument("MultiCmacSwingPattern: no pattern");
}

bool MultiCmacSwingPattern::SetContext(double v_m, double d_obs) {
  if (!std::isfinite(v_m) || std::isnan(d_obs)) return false;
  v_m_ = v_m;
  d_obs_ = d_obs;
  return true;
}

Eigen::Vector4d MultiCmacSwingPattern::Query(double e) const {
  if (pattern_->domain().thigh_frame) {
    throw std::logic_error(
        "MultiCmacSwingPattern::Query: the pattern was trained in the thigh "
        "frame");
  }
  return pattern_->Query(e, v_m_, d_obs_);
}

Eigen::Vector4d MultiCmacSwingPattern::QueryThigh(double th_st) const {
  if (!pattern_->domain().thigh_frame) {
    throw std::logic_error(
        "MultiCmacSwingPattern::QueryThigh: the pattern was trained in the "
        "chapter's frame");
  }
  return pattern_->Query(th_st, v_m_, d_obs_);
}

}  // namespace rabbit
