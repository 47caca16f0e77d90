// The log of a tuning job (rabbit tune): evaluations.csv (one row per candidate) and runs.csv (one
// row per run of a candidate), appended as rounds finish and read back by --resume. The columns
// are described in docs/formats/tune-job.md.
#ifndef RABBIT_OPTIMIZERS_TUNE_LOG_H_
#define RABBIT_OPTIMIZERS_TUNE_LOG_H_

#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <utility>

#include "rabbit/io/limits.h"
#include "tune_job.h"
#include "tuner.h"

namespace rabbit::tune_internal {

// A CSV cell: quoted, quotes doubled, line breaks turned into spaces.
std::string CsvText(const std::string& text);

std::string EvaluationsHeader(const TuneJob& job);
std::string RunsHeader();
std::string EvaluationRow(const Evaluation& e);
std::string RunRows(const Evaluation& e);

// The complete lines of a text (a line cut short by a crash is dropped).
std::string CompleteLines(const std::string& text);
std::string ReadText(const std::filesystem::path& path, const FileLimits& limits);

// Evaluations recorded in a log (evaluations.csv and runs.csv texts), keyed by (start, seq).
// Throws InputError naming `file` for a log of other columns or an inconsistent one.
std::map<std::pair<int, int>, Evaluation> ParseLog(const TuneJob& job, const std::string& file,
                                                   const std::string& evaluations,
                                                   const std::string& runs);

class Log {
 public:
  Log() = default;
  Log(const Log&) = delete;
  Log& operator=(const Log&) = delete;
  ~Log();
  // Opens the log files in `dir` for appending (rank 0 only; other ranks log nothing).
  void Open(const std::filesystem::path& dir, const TuneJob& job, const std::string& evaluations,
            const std::string& runs);
  // Runs first, then the evaluation's row: a row in evaluations.csv means its runs are logged.
  void Append(const Evaluation& e);
  void KillAfter(int n) { kill_after_ = n; }

 private:
  std::FILE* evaluations_ = nullptr;
  std::FILE* runs_ = nullptr;
  int kill_after_ = 0, appended_ = 0;
};

}  // namespace rabbit::tune_internal

#endif  // RABBIT_OPTIMIZERS_TUNE_LOG_H_
