// The full time series of one run as CSV (one header row, SI units named in the columns).
#ifndef RABBIT_SCENARIO_TRAJECTORY_CSV_H_
#define RABBIT_SCENARIO_TRAJECTORY_CSV_H_

#include <ostream>
#include <string>

#include "rabbit/sim/simulator.h"

namespace rabbit {

void WriteTrajectoryCsv(const SimResult& result, std::ostream& out);
// Atomically writes the CSV to path (creating directories).
void WriteTrajectoryCsvFile(const SimResult& result, const std::string& path);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_TRAJECTORY_CSV_H_
