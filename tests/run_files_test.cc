// The run files' summary row does not depend on what is recorded: metrics and criteria come from
// the full control rate, so a walk recorded at every period, every 7th, every 10th, every 50th or
// not at all gives the same row (wall-time columns aside); and a recorded trajectory's numbers
// read back as the simulated doubles.
#include "rabbit/scenario/run_files.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "rabbit/io/csv.h"
#include "rabbit/scenario/suite.h"
#include "rabbit/scenario/trajectory_csv.h"

namespace rabbit {
namespace {

const std::string kRoot = RABBIT_SOURCE_DIR;

const Suite& Paper() {
  static const Suite suite = LoadSuite(kRoot + "/scenarios/paper.toml");
  return suite;
}

Scenario Named(const std::string& name) {
  for (const Scenario& s : Paper().scenarios) {
    if (s.name == name) return s;
  }
  throw std::runtime_error("no scenario " + name);
}

std::string Row(Scenario scenario, const std::string& variant, int record_every,
                const GaitLibrary* library) {
  scenario.options.record_every = record_every;
  RunOutput run = RunScenario(scenario, variant, library);
  run.wall = 0.0;  // the only figure that is not deterministic
  return SummaryRow("paper", run);
}

TEST(SummaryRow, SameAtAnyRecordingRate) {
  Scenario flat = Named("flat");
  // Long enough for the warm-up, the switch to the Fuzzy-CMAC and measured steps; 8.0037 s ends
  // between two samples of every recording rate below.
  flat.options.duration = 8.0037;
  const std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(flat.pattern);
  for (const char* variant : {"fuzzy_cmac", "pragmatic"}) {
    const std::string full = Row(flat, variant, 1, library.get());
    EXPECT_NE(full.find(",completed,"), std::string::npos) << full;
    for (int every : {7, 10, 50, 0}) {
      EXPECT_EQ(Row(flat, variant, every, library.get()), full)
          << variant << ", record_every " << every;
    }
  }
}

TEST(SummaryRow, SameAtAnyRecordingRateWhenTheRunEndsEarly) {
  // The passive fall ends between samples of a coarse recording.
  Scenario fall = LoadScenario(kRoot + "/scenarios/passive_fall.toml");
  const std::string full = Row(fall, ScenarioVariants(fall)[0], 1, nullptr);
  EXPECT_NE(full.find(",fell,"), std::string::npos) << full;
  for (int every : {7, 50, 0}) {
    EXPECT_EQ(Row(fall, ScenarioVariants(fall)[0], every, nullptr), full)
        << "record_every " << every;
  }
}

TEST(TrajectoryCsv, NumbersReadBackExactly) {
  Scenario fall = LoadScenario(kRoot + "/scenarios/passive_fall.toml");
  fall.options.record_every = 25;
  const RunOutput run = RunScenario(fall, ScenarioVariants(fall)[0], nullptr);
  ASSERT_GE(run.sim.samples.size(), 3u);
  std::ostringstream out;
  WriteTrajectoryCsv(run.sim, out);
  const std::vector<std::string> lines = SplitLines(out.str());
  ASSERT_EQ(lines.size(), run.sim.samples.size() + 1);
  const std::vector<std::string> header = SplitCsv(lines[0]);
  for (size_t k = 0; k < run.sim.samples.size(); ++k) {
    const SimSample& s = run.sim.samples[k];
    const std::vector<std::string> cells = SplitCsv(lines[k + 1]);
    ASSERT_EQ(cells.size(), header.size()) << lines[k + 1];
    EXPECT_EQ(std::strtod(cells[0].c_str(), nullptr), s.t);
    for (int i = 0; i < kNq; ++i) {
      EXPECT_EQ(std::strtod(cells[1 + i].c_str(), nullptr), s.q[i]) << header[1 + i];
      EXPECT_EQ(std::strtod(cells[1 + kNq + i].c_str(), nullptr), s.qd[i]) << header[1 + kNq + i];
    }
    EXPECT_EQ(std::strtod(cells.back().c_str(), nullptr), TotalEnergy(s));
    EXPECT_EQ(cells[header.size() - 5], ContactModeName(s.foot_mode[1]));
  }
}

}  // namespace
}  // namespace rabbit
