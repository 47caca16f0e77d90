// Running gnuplot once for many figures: the data files and the script go into a fresh temporary
// directory (removed afterwards), gnuplot runs on the script with stdin closed and no shell, and
// the files the script wrote are read back.
#ifndef RABBIT_REPORT_GNUPLOT_H_
#define RABBIT_REPORT_GNUPLOT_H_

#include <string>
#include <utility>
#include <vector>

namespace rabbit {

struct GnuplotJob {
  // The script; it runs with the temporary directory as gnuplot's working directory, so it names
  // its data and output files relative to it.
  std::string script;
  std::vector<std::pair<std::string, std::string>> files;  // plain file name, contents
  std::vector<std::string> outputs;                        // plain file names the script writes
};

struct GnuplotResult {
  bool ok = false;                   // gnuplot ran and exited 0, and every output exists
  std::string error;                 // else why (cannot start, exit status and its messages...)
  std::vector<std::string> outputs;  // contents of job.outputs, in order (empty when !ok)
};

// Runs `executable script.gp` (executable searched on PATH when it has no '/'), killing it after
// timeout seconds. Never throws for gnuplot's failures: they are in the result.
GnuplotResult RunGnuplot(const std::string& executable, const GnuplotJob& job, double timeout);

// Whether `executable` names a file this process may run: with a '/', that file; else a file of
// that name in a folder of PATH (posix_spawnp's search; "/bin:/usr/bin" when PATH is unset).
bool IsRunnableExecutable(const std::string& executable);

// text as a gnuplot single-quoted string (a quote doubled; newlines become spaces).
std::string GnuplotQuote(const std::string& text);

}  // namespace rabbit

#endif  // RABBIT_REPORT_GNUPLOT_H_
