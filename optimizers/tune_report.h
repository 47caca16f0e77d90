// The HTML page of a tuning job's folder (placeholder until the report lands).
#ifndef RABBIT_OPTIMIZERS_TUNE_REPORT_H_
#define RABBIT_OPTIMIZERS_TUNE_REPORT_H_

#include <string>
#include <vector>

namespace rabbit {

struct TuneReportOptions {
  std::string gnuplot = "gnuplot";
  double timeout = 60.0;
};
void WriteTuneReport(const std::string& dir, const TuneReportOptions& options,
                     std::vector<std::string>* warnings);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_TUNE_REPORT_H_
