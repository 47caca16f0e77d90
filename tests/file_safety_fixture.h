// The file-safety tests' fixture (file_safety_test, interrupted_writers_test): a scratch folder
// with a small gait database, a small walking suite and a small tuning job to write from, and a
// snapshot of a folder to compare before and after.
#ifndef RABBIT_TESTS_FILE_SAFETY_FIXTURE_H_
#define RABBIT_TESTS_FILE_SAFETY_FIXTURE_H_

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "cli_fixture.h"

namespace rabbit::testing {

// Every file below `root` (or `root` itself) with its content, and every folder: what "untouched"
// compares.
std::map<std::string, std::string> TreeSnapshot(const std::filesystem::path& root);

class FileSafetyTest : public ScratchDirTest {
 protected:
  FileSafetyTest() : ScratchDirTest("rabbit_file_safety") {}
  // A gait database of two shipped gaits (quick to train), at `name`.
  std::filesystem::path SmallDatabase(const std::string& name) {
    const std::filesystem::path db = dir_ / name,
                                shipped = std::string(RABBIT_SOURCE_DIR) + "/gaits/reference";
    std::filesystem::create_directories(db);
    std::stringstream index(ReadText(shipped / "index.csv"));
    std::string line, text;
    std::getline(index, line);
    text = line + "\n";
    while (std::getline(index, line)) {
      if (line.rfind("vm_0.30,", 0) == 0 || line.rfind("vm_0.40,", 0) == 0) {
        text += line + "\n";
        const std::string file = line.substr(line.find(',') + 1);
        std::filesystem::copy_file(shipped / file.substr(0, file.find(',')),
                                   db / file.substr(0, file.find(',')));
      }
    }
    std::ofstream(db / "index.csv") << text;
    return db;
  }
  // A two-scenario walking suite on the shipped database (a few seconds).
  std::filesystem::path SmallSuite() {
    return Write("small.toml",
                 "[suite]\nname = \"small\"\n[defaults]\nexpect_outcome = \"completed\"\n"
                 "[defaults.simulation]\nduration = 3.0\nrecord_every = 20\n"
                 "[defaults.velocity]\nvalue = 0.6\n"
                 "[defaults.controller]\ntype = \"fuzzy_cmac\"\nfll = \"" +
                     std::string(RABBIT_SOURCE_DIR) + "/gaits/gait_pattern.fll\"\nnetworks = \"" +
                     std::string(RABBIT_SOURCE_DIR) + "/gaits/networks\"\ngaits = \"" +
                     std::string(RABBIT_SOURCE_DIR) + "/gaits/reference\"\n" +
                     "[[scenario]]\nname = \"walk\"\n[[scenario]]\nname = \"second\"\n");
  }
  // The small suite on a copy of the shipped gaits in dir_/gaits (to change one), as local.toml.
  std::filesystem::path SmallSuiteOnACopyOfTheGaits() {
    const std::string root = RABBIT_SOURCE_DIR;
    std::filesystem::copy(root + "/gaits", dir_ / "gaits",
                          std::filesystem::copy_options::recursive);
    std::string text = ReadText(SmallSuite());
    for (size_t at; (at = text.find(root + "/gaits")) != std::string::npos;) {
      text.replace(at, root.size() + 6, (dir_ / "gaits").string());
    }
    return Write("local.toml", text);
  }
  std::filesystem::path TuneJob() {
    return Write("job.toml", "[job]\nsuites = [\"" + std::string(RABBIT_SOURCE_DIR) +
                                 "/scenarios/tune_ramp.toml\"]\nfilter = \"^ramp_up$\"\n"
                                 "max_evaluations = 4\n[objective]\nspeed_error = 1.0\n"
                                 "[[parameter]]\npath = \"controller.k_p\"\nlower = 0.0\n"
                                 "upper = 0.6\n[[parameter]]\npath = \"controller.k_v\"\n"
                                 "lower = 0.0\nupper = 0.4\n");
  }
  std::filesystem::path MakeFifo(const std::string& name) {
    const std::filesystem::path path = dir_ / name;
    EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0);
    return path;
  }
};

}  // namespace rabbit::testing

#endif  // RABBIT_TESTS_FILE_SAFETY_FIXTURE_H_
