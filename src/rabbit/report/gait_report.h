// The report of a gait database: per gait its figures, a stick diagram of 2.8 s of walking (as the
// chapter's figure 8) and its swing-leg trajectories against e; and all gaits' trajectories
// together. A self-contained HTML page (inline SVG).
#ifndef RABBIT_REPORT_GAIT_REPORT_H_
#define RABBIT_REPORT_GAIT_REPORT_H_

#include <string>

namespace rabbit {

// Reads dir/index.csv and its gaits, re-walks each, and writes out_dir/index.html (atomically).
// Returns the page's path. Throws InputError for a malformed database.
std::string WriteGaitReport(const std::string& dir, const std::string& out_dir);

}  // namespace rabbit

#endif  // RABBIT_REPORT_GAIT_REPORT_H_
