// The integrator's default tolerances on the walking workload: the whole default suite (the
// walker, its baselines and the randomised obstacle family) run at the defaults and again at
// tolerances 10^4 times tighter, the converged reference. Every run must end the same way, pass
// or fail the same criteria, take as many steps, and walk with a mean step length within 1 mm of
// the reference's.
// (The contact-free swing, standing and drop checks of the same defaults: simulator_test.)
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <string>
#include <vector>

#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace {

const std::string kRoot = RABBIT_SOURCE_DIR;

// A failed criterion's message without its figures: which criterion failed, and how it is worded.
std::vector<std::string> Criteria(const std::vector<std::string>& failures) {
  std::vector<std::string> out;
  for (const std::string& f : failures) {
    std::string words;
    for (const char c : f) {
      if (!std::isdigit(static_cast<unsigned char>(c)) && c != '.') words += c;
    }
    out.push_back(words);
  }
  return out;
}

std::vector<RunOutput> RunAll(const Suite& suite) {
  const std::vector<BatchJob> jobs = PlanBatch(suite, "");
  std::vector<RunOutput> runs(jobs.size());
  RunBatch(jobs, 2, nullptr, [&](size_t i, RunOutput&& run) { runs[i] = std::move(run); });
  return runs;
}

TEST(WalkingAccuracyTest, TheDefaultSuiteAtTheDefaultTolerancesIsItsConvergedReference) {
  const Suite suite = LoadSuite(kRoot + "/scenarios/paper.toml");
  Suite reference = suite;
  const IntegratorOptions defaults;
  for (Scenario& s : reference.scenarios) {
    ASSERT_EQ(s.options.integrator.rtol, defaults.rtol) << s.name;  // the suite uses the defaults
    ASSERT_EQ(s.options.integrator.atol, defaults.atol) << s.name;
    s.options.integrator.rtol = 1e-4 * defaults.rtol;
    s.options.integrator.atol = 1e-4 * defaults.atol;
  }
  const std::vector<RunOutput> runs = RunAll(suite);
  const std::vector<RunOutput> converged = RunAll(reference);
  ASSERT_EQ(runs.size(), converged.size());
  ASSERT_GT(runs.size(), 20u);
  int walked = 0;
  for (size_t i = 0; i < runs.size(); ++i) {
    const RunOutput& a = runs[i];
    const RunOutput& b = converged[i];
    SCOPED_TRACE(a.run + " (" + a.controller + ")");
    ASSERT_EQ(a.run, b.run);
    EXPECT_EQ(a.sim.outcome, b.sim.outcome);
    EXPECT_EQ(a.passed, b.passed);
    EXPECT_EQ(Criteria(a.failures), Criteria(b.failures));
    EXPECT_EQ(a.metrics.steps, b.metrics.steps);
    if (a.metrics.steps > 0 && std::isfinite(b.metrics.l_step_mean)) {
      EXPECT_NEAR(a.metrics.l_step_mean, b.metrics.l_step_mean, 1e-3);
      ++walked;
    }
  }
  EXPECT_GT(walked, 15);
}

}  // namespace
}  // namespace rabbit
