// LMS training of a SISO CMAC on samples (chapter eq. 7), and the fit quality measures shared with
// the Ceres fit (optimizers/cmac_fit.h).
#ifndef RABBIT_LEARN_CMAC_TRAINING_H_
#define RABBIT_LEARN_CMAC_TRAINING_H_

#include <vector>

#include "rabbit/learn/cmac.h"

namespace rabbit {

struct LmsOptions {
  double beta = 0.5;  // learning rate in (0, 1]
  int epochs = 400;   // passes over the samples, in order
};

// RMS of O(x_i) - y_i over the samples.
double CmacRmsError(const Cmac& cmac, const std::vector<double>& x, const std::vector<double>& y);

// Trains by LMS; returns the final RMS error.
double TrainCmacLms(const std::vector<double>& x, const std::vector<double>& y,
                    const LmsOptions& options, Cmac* cmac);

}  // namespace rabbit

#endif  // RABBIT_LEARN_CMAC_TRAINING_H_
