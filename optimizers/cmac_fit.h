// Fitting a SISO CMAC with Ceres. The output is linear in the weights, so fitting a
// CMAC to samples (x_i, y_i) is a sparse linear least-squares problem: one residual per sample,
// O(x_i) - y_i, touching its N_l active weights; optional smoothness residuals
// sqrt(smoothness) (w_a - w_b) between neighbouring detectors of the same layer; and a tiny ridge
// sqrt(ridge) w on every weight so that detectors no sample reaches stay at 0. Solved with a
// sparse normal Cholesky factorisation (SuiteSparse when Ceres has it, else Eigen).
#ifndef RABBIT_OPTIMIZERS_CMAC_FIT_H_
#define RABBIT_OPTIMIZERS_CMAC_FIT_H_

#include <string>
#include <vector>

#include "rabbit/learn/cmac.h"

namespace rabbit {

struct CmacFitOptions {
  double smoothness = 1e-4;  // weight of the neighbour-difference residuals
  double ridge = 1e-10;      // weight of the per-weight residuals
  bool IsValid(std::string* error) const;
};

struct CmacFitSummary {
  double rms = 0.0;  // RMS of O(x_i) - y_i after the fit
  double seconds = 0.0;
  std::string brief;  // Ceres' BriefReport
};

// Replaces cmac's weights with the least-squares fit.
CmacFitSummary FitCmacCeres(const std::vector<double>& x, const std::vector<double>& y,
                            const CmacFitOptions& options, Cmac* cmac);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_CMAC_FIT_H_
