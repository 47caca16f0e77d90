// The HTML pieces of the report page: its CSS, the error counter and replay JavaScript, the
// embedded stick-figure replays, the summary and steps tables and the terrain line.
// Implementation details of WriteSuiteReport (suite_report.h).
#ifndef RABBIT_REPORT_REPORT_PAGE_H_
#define RABBIT_REPORT_REPORT_PAGE_H_

#include <cstddef>
#include <string>
#include <vector>

#include "rabbit/contact/terrain.h"
#include "rabbit/report/comparison.h"
#include "rabbit/report/report_data.h"
#include "rabbit/report/suite_report.h"

namespace rabbit {
namespace report_internal {

// The page's stylesheet (inside <style>).
extern const char kStyle[];
// First in <head>: counts uncaught errors, before anything else can throw.
extern const char kErrorCounter[];
// Last in <body>: animates every .replay element (ReplayHtml).
extern const char kReplayScript[];

// One run's replay: a canvas, its controls and the frames as JSON; index makes its id unique.
std::string ReplayHtml(const RunData& run, size_t index, const SuiteReportOptions& options);

// The summary table: one row per run (and one per run with failed criteria), grouped by scenario;
// the groups listed in `which` only (empty: all). A group's link is #scenario-<its index>.
std::string SummaryTable(const std::vector<RunData>& runs, const std::vector<ScenarioGroup>& groups,
                         const std::vector<size_t>& which = {});

// The head-to-head table of one group: a row per variant (the main one first).
std::string ComparisonTable(const std::vector<const VariantComparison*>& variants);

// A collapsible table of the run's steps.
std::string StepsTable(const RunData& run);

// The ground profile and obstacles in words ("flat ground" when neither).
std::string TerrainText(const Terrain& terrain);

}  // namespace report_internal
}  // namespace rabbit

#endif  // RABBIT_REPORT_REPORT_PAGE_H_
