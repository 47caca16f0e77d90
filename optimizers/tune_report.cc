#include "tune_report.h"

namespace rabbit {

void WriteTuneReport(const std::string& dir, const TuneReportOptions& options,
                     std::vector<std::string>* warnings) {
  (void)dir;
  (void)options;
  (void)warnings;
}

}  // namespace rabbit
