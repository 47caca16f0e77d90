// The shipped tuning jobs (optimizers/jobs/): each improves its objective over its initial
// parameters on its shipped budget (which CI runs), and every job file loads.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "rabbit/scenario/suite.h"
#include "tune_job.h"
#include "tune_search.h"
#include "tuner.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

const std::string kJobs = std::string(RABBIT_SOURCE_DIR) + "/optimizers/jobs/";

void ExpectImproves(const std::string& name) {
  const TuneJob job = LoadTuneJob(kJobs + name + ".toml");
  TuneOptions options;
  const fs::path out =
      fs::temp_directory_path() / ("rabbit_tune_jobs_test_" + std::to_string(::getpid()) + name);
  fs::remove_all(out);
  options.out = out.string();
  options.html = false;
  const TuneResult r = RunTune(job, options);
  fs::remove_all(out);
  ASSERT_GE(r.initial, 0);
  ASSERT_GE(r.best, 0);
  // The whole budget (Ceres stops when the next Jacobian would not fit in it).
  EXPECT_LE(static_cast<int>(r.evaluations.size()), job.max_evaluations);
  EXPECT_GT(static_cast<int>(r.evaluations.size()),
            job.max_evaluations - static_cast<int>(job.parameters.size()) - 1);
  const double initial = r.evaluations[r.initial].objective;
  const double best = r.evaluations[r.best].objective;
  EXPECT_LT(best, initial) << name;
  std::printf("%s: objective %.6g -> %.6g (%+.1f%%) in %zu evaluations\n", name.c_str(), initial,
              best, 100.0 * (best - initial) / initial, r.evaluations.size());
}

TEST(TuneJobsTest, EveryShippedJobLoads) {
  int jobs = 0;
  for (const fs::directory_entry& e : fs::directory_iterator(kJobs)) {
    if (e.path().extension() != ".toml") continue;
    EXPECT_NO_THROW(LoadTuneJob(e.path().string())) << e.path();
    ++jobs;
  }
  // robustness_obstacles, robustness_planner, robustness_push, robustness_push_response and
  // robustness_speed run for minutes: loaded, not run.
  EXPECT_EQ(jobs, 8);
}

// Every candidate a shipped job can ask for is a valid walker: each parameter at either bound, the
// others at their initial values, loads every suite of the job. A bound past a key's valid range,
// or past another key the value must stay within (the planner's l_nominal within [l_min, l_max]),
// would be refused at each such candidate, an evaluation of the budget lost.
TEST(TuneJobsTest, EveryBoundOfEveryShippedJobIsAValidSetting) {
  for (const fs::directory_entry& e : fs::directory_iterator(kJobs)) {
    if (e.path().extension() != ".toml") continue;
    const TuneJob job = LoadTuneJob(e.path().string());
    const std::vector<double> initial = tune_internal::StartPoint(job, 0);  // the initial values
    for (size_t i = 0; i < job.parameters.size(); ++i) {
      for (const double bound : {job.parameters[i].lower, job.parameters[i].upper}) {
        std::vector<double> x = initial;
        x[i] = bound;
        const ParamOverlay overlay = job.Overlay(x);
        for (const std::string& suite : job.suites) {
          EXPECT_NO_THROW(LoadSuite(suite, &overlay))
              << job.name << ": " << job.parameters[i].path << " = " << bound << " in " << suite;
        }
      }
    }
  }
}

TEST(TuneJobsTest, VelocityGainsImproveTheRampTracking) { ExpectImproves("velocity_gains"); }
TEST(TuneJobsTest, DObsSetsImproveObstacleClearance) { ExpectImproves("obstacle_d_obs_sets"); }
TEST(TuneJobsTest, PragmaticPdGainsImproveTheReferenceGaits) {
  ExpectImproves("pragmatic_pd_gains");
}

}  // namespace
}  // namespace rabbit
