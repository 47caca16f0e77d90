#include "rabbit/learn/cmac_training.h"

#include <cmath>

namespace rabbit {

double CmacRmsError(const Cmac& cmac, const std::vector<double>& x, const std::vector<double>& y) {
  if (x.empty()) return 0.0;
  double sum = 0.0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double d = cmac.Query(x[i]) - y[i];
    sum += d * d;
  }
  return std::sqrt(sum / static_cast<double>(x.size()));
}

double TrainCmacLms(const std::vector<double>& x, const std::vector<double>& y,
                    const LmsOptions& options, Cmac* cmac) {
  for (int epoch = 0; epoch < options.epochs; ++epoch) {
    for (size_t i = 0; i < x.size(); ++i) cmac->Update(x[i], y[i], options.beta);
  }
  return CmacRmsError(*cmac, x, y);
}

}  // namespace rabbit
