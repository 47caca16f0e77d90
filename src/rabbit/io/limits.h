// The limits on what the readers accept, in one place (docs/bad-input.md lists them): every file
// a user hands to rabbit is read through ReadBoundedFile with one of these, so that a huge file, a
// device such as /dev/zero or a FIFO that never ends stops with an InputError naming the file and
// the limit instead of exhausting memory. The values leave at least a hundredfold margin over the
// largest file the tool writes or ships of each kind.
#ifndef RABBIT_IO_LIMITS_H_
#define RABBIT_IO_LIMITS_H_

#include <cstddef>

namespace rabbit {

struct FileLimits {
  const char* what;       // the kind of file, plural, in messages: "TOML files", ...
  size_t max_bytes;       // the whole file
  size_t max_lines;       // lines (rows, comments and blank lines included)
  size_t max_line_bytes;  // one line, without its line break
};

constexpr size_t kKiB = 1024, kMiB = 1024 * 1024;

// Configuration: scenarios, suites, tuning jobs, gait targets, parameter overlays, model files.
constexpr FileLimits kTomlFileLimits = {"TOML files", 4 * kMiB, 100000, 64 * kKiB};
// Fuzzy systems in fuzzylite's FLL language.
constexpr FileLimits kFllFileLimits = {"FLL files", 4 * kMiB, 100000, 64 * kKiB};
// One reference gait (a few hundred rows ship; the writer averages one swing).
constexpr FileLimits kGaitFileLimits = {"gait files", 16 * kMiB, 200000, 64 * kKiB};
// gaits/<set>/index.csv and gaits/networks/index.csv.
constexpr FileLimits kIndexFileLimits = {"index files", 4 * kMiB, 10000, 64 * kKiB};
// One CMAC network: up to the 2^22 weights of the largest hashed table, one per row.
constexpr FileLimits kNetworkFileLimits = {"network files", 256 * kMiB, 5000000, 64 * kKiB};
// The CSV tables rabbit reads back (run files, summaries, tuning logs): a run records at most
// kMaxRecordedSamples samples, about 560 bytes each in trajectory.csv (a 1 GB file is refused).
constexpr FileLimits kCsvTableLimits = {"CSV files", 768 * kMiB, 2000000, 1 * kMiB};

// What rabbit writes for itself and reads back: the markers of its folders (report staging
// folders, tuning jobs, shards; a staging marker lists every input file with its hash).
constexpr FileLimits kMarkerFileLimits = {"marker files", 1 * kMiB, 20000, 64 * kKiB};
// The inventory of a finished output folder (one line per file rabbit wrote in it: a report of a
// suite of 20,000 scenarios holds about 150,000).
constexpr FileLimits kInventoryFileLimits = {"inventory files", 64 * kMiB, 2000000, 8 * kKiB};
// A gait database's manifest.csv (one row per file of the database).
constexpr FileLimits kManifestFileLimits = {"manifest files", 4 * kMiB, 20000, 64 * kKiB};
// A gait database's walker.csv (one row per gait).
constexpr FileLimits kWalkerFileLimits = {"walker settings files", 4 * kMiB, 10000, 64 * kKiB};

// A run keeps at most this many samples (duration / (control period * record_every)): a distance
// run's default 600 s time limit at 1 kHz, every sample, fits.
constexpr double kMaxRecordedSamples = 1e6;
// The longest simulated run, s (an hour of walking; the default time limit of a distance run is
// 600 s).
constexpr double kMaxDurationS = 3600.0;
// Names a user gives (gaits, scenarios, sets): at most this many characters.
constexpr size_t kMaxNameChars = 100;
// What an external program (gnuplot) may print into one warning before it is cut.
constexpr size_t kMaxQuotedOutputBytes = 2000;

}  // namespace rabbit

#endif  // RABBIT_IO_LIMITS_H_
