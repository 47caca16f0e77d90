#include "cmac_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>

#include "rabbit/learn/cmac_training.h"

namespace rabbit {
namespace {

// r = sum_i c_i w_i - target over the distinct active weights (c_i > 1 only where hashing put two
// layers' detectors on one weight). Linear: the Jacobian is written out, not differentiated.
class SampleResidual final : public ceres::CostFunction {
 public:
  SampleResidual(std::vector<double> coefficients, double target)
      : coefficients_(std::move(coefficients)), target_(target) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->assign(coefficients_.size(), 1);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    double sum = -target_;
    for (size_t i = 0; i < coefficients_.size(); ++i) sum += coefficients_[i] * parameters[i][0];
    residuals[0] = sum;
    if (jacobians != nullptr) {
      for (size_t i = 0; i < coefficients_.size(); ++i) {
        if (jacobians[i] != nullptr) jacobians[i][0] = coefficients_[i];
      }
    }
    return true;
  }

 private:
  std::vector<double> coefficients_;
  double target_;
};

// r = sqrt(weight) (w_a - w_b), or sqrt(weight) w_a with one block.
class DifferenceResidual final : public ceres::CostFunction {
 public:
  DifferenceResidual(int blocks, double weight) : scale_(std::sqrt(weight)) {
    set_num_residuals(1);
    mutable_parameter_block_sizes()->assign(blocks, 1);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const bool pair = parameter_block_sizes().size() == 2;
    residuals[0] = scale_ * (parameters[0][0] - (pair ? parameters[1][0] : 0.0));
    if (jacobians != nullptr) {
      if (jacobians[0] != nullptr) jacobians[0][0] = scale_;
      if (pair && jacobians[1] != nullptr) jacobians[1][0] = -scale_;
    }
    return true;
  }

 private:
  double scale_;
};

}  // namespace

bool CmacFitOptions::IsValid(std::string* error) const {
  if (!(std::isfinite(smoothness) && smoothness >= 0.0 && std::isfinite(ridge) && ridge >= 0.0)) {
    *error = "smoothness and ridge must be finite and >= 0";
    return false;
  }
  return true;
}

CmacFitSummary FitCmacCeres(const std::vector<double>& x, const std::vector<double>& y,
                            const CmacFitOptions& options, Cmac* cmac) {
  const auto start = std::chrono::steady_clock::now();
  std::string error;
  if (!options.IsValid(&error)) throw std::invalid_argument("CMAC fit: " + error);
  if (x.size() != y.size()) throw std::invalid_argument("CMAC fit: x and y differ in size");
  std::vector<double>& w = *cmac->mutable_weights();
  const int layers = cmac->options().layers;
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  CmacActive active;
  for (size_t i = 0; i < x.size(); ++i) {
    cmac->Active(x[i], &active);
    if (active.count == 0 || !std::isfinite(y[i])) continue;  // NaN sample: nothing to fit
    std::vector<double*> blocks;
    std::vector<double> coefficients;
    for (int j = 0; j < layers; ++j) {
      double* block = &w[active.index[j]];
      const auto it = std::find(blocks.begin(), blocks.end(), block);
      if (it == blocks.end()) {
        blocks.push_back(block);
        coefficients.push_back(1.0);
      } else {
        coefficients[it - blocks.begin()] += 1.0;
      }
    }
    problem.AddResidualBlock(new SampleResidual(std::move(coefficients), y[i]), nullptr, blocks);
  }
  // Neighbouring detectors of each layer (d and d + 1), by address; a pair that hashing put on
  // one weight has nothing to smooth.
  if (options.smoothness > 0.0) {
    std::set<std::pair<int, int>> pairs;
    for (int j = 0; j < layers; ++j) {
      for (int d = 0; d + 1 < cmac->NumDetectorsInLayer(j); ++d) {
        const int a = cmac->Address(j, d), b = cmac->Address(j, d + 1);
        if (a != b) pairs.insert({std::min(a, b), std::max(a, b)});
      }
    }
    for (const auto& [a, b] : pairs) {
      problem.AddResidualBlock(new DifferenceResidual(2, options.smoothness), nullptr,
                               {&w[a], &w[b]});
    }
  }
  if (options.ridge > 0.0) {
    for (double& weight : w) {
      problem.AddResidualBlock(new DifferenceResidual(1, options.ridge), nullptr, &weight);
    }
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.sparse_linear_algebra_library_type =
      ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE) ? ceres::SUITE_SPARSE
                                                                            : ceres::EIGEN_SPARSE;
  solver.max_num_iterations = 10;  // linear: one Gauss-Newton step solves it
  solver.function_tolerance = 1e-14;
  solver.num_threads = 1;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  if (!summary.IsSolutionUsable()) {
    throw std::runtime_error("CMAC fit failed: " + summary.BriefReport());
  }
  for (double weight : w) {
    if (!std::isfinite(weight)) throw std::runtime_error("CMAC fit produced non-finite weights");
  }
  CmacFitSummary result;
  result.rms = CmacRmsError(*cmac, x, y);
  result.brief = summary.BriefReport();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace rabbit
