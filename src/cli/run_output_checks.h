// What `rabbit run` may write over: its report folder and the staging folder beside it are
// replaced or emptied only when they are missing, empty, or rabbit run's own (a marker, and an
// inventory that names everything in them); anything else is refused, naming it.
#ifndef RABBIT_CLI_RUN_OUTPUT_CHECKS_H_
#define RABBIT_CLI_RUN_OUTPUT_CHECKS_H_

#include <filesystem>

namespace rabbit::cli {

// A staging folder's marker: which plan it holds, and the content hash of every input file.
constexpr const char* kStagingMarker = ".rabbit-staging";

// Throws InputError unless rabbit run may replace the report folder `out`.
void CheckReportOutput(const std::filesystem::path& out);

// Throws InputError unless the staging folder beside a report is rabbit run's own: missing, empty,
// or holding a staging, report or shard marker (or, from earlier versions, only their lock file).
void CheckStagingOutput(const std::filesystem::path& staging);

}  // namespace rabbit::cli

#endif  // RABBIT_CLI_RUN_OUTPUT_CHECKS_H_
