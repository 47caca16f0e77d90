// The files a suite reads, by content: what resume and shard fingerprints cover, so that a run is
// never resumed or merged over inputs that changed since it started.
#ifndef RABBIT_SCENARIO_SUITE_INPUTS_H_
#define RABBIT_SCENARIO_SUITE_INPUTS_H_

#include <string>
#include <vector>

#include "rabbit/scenario/suite.h"

namespace rabbit {

struct InputFile {
  std::string path;
  std::string sha256;  // Sha256OfFile
};

// Every file the suite reads: the suite file, each scenario's model file and, for the walkers, the
// FLL file and every file at the root of the networks folder and of the gait database (index,
// networks, gaits, manifest). Sorted by path, each once.
std::vector<std::string> SuiteInputFiles(const Suite& suite);

// The files' content hashes, in the given order. Throws InputError naming a file that cannot be
// read.
std::vector<InputFile> HashInputFiles(const std::vector<std::string>& paths);

// Marker lines, one per file: "input = <sha256> <path>\n".
std::string InputLines(const std::vector<InputFile>& inputs);

// Compares the "input = ..." lines of a marker's text with the inputs now: empty when they agree,
// else a message naming the first file that changed, appeared or disappeared.
std::string ChangedInputs(const std::string& marker_text, const std::vector<InputFile>& now);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_SUITE_INPUTS_H_
