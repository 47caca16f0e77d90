#include "tune_fixture.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "report_fixture.h"

namespace rabbit::testing {
namespace {

namespace fs = std::filesystem;

// The terms of a log written before incomplete_rate was added: the report reads that term as
// NaN (a log of today's tuner, with all seven, is read in tune_guards_test).
const char kTerms[] =
    "failure_rate,speed_error,step_length_spread,energy,cost_of_transport,saturation_time";
const char kComparisonHeader[] =
    "suite,scenario,initial_passed,best_passed,initial_failure_rate,best_failure_rate,"
    "initial_speed_error,best_speed_error,initial_step_length_spread,best_step_length_spread,"
    "initial_energy,best_energy,initial_cost_of_transport,best_cost_of_transport,"
    "initial_saturation_time,best_saturation_time\n";

std::string Num(double v) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

void Write(const std::string& dir, const std::string& name, const std::string& text) {
  WriteText((fs::path(dir) / name).string(), text);
}

}  // namespace

void WriteTuneFixture(const std::string& dir) {
  fs::create_directories(dir);
  Write(dir, "meta.csv",
        "key,value\n"
        "job,walk_gains\n"
        "description,\"Tune the PD gains <script>alert(1)</script> & check\"\n"
        "job_file,optimizers/jobs/walk_gains.toml\n"
        "algorithm,bobyqa\n"
        "seed,7\n"
        "starts,2\n"
        "max_evaluations,20\n"
        "form,mean\n"
        "weights,failure_rate=10;speed_error=1\n"
        "suites,scenarios/suites/flat.toml;scenarios/suites/push.toml\n"
        "evaluations,6\n"
        "initial_eval,0\n"
        "best_eval,4\n"
        "initial_objective,5.25\n"
        "best_objective,0.0312\n"
        "complete,true\n"
        "fingerprint,3f9a0c1e\n");
  Write(dir, "parameters.csv",
        "path,lower,upper,initial,best\n"
        "controller.k_p,100,1000,600,731.5\n"
        "controller.k_d,5,60,30,22.25\n");
  // objective = 10 failure_rate + speed_error, the means over the two scenarios' runs below.
  Write(dir, "evaluations.csv",
        std::string("eval,round,start,seq,objective,") + kTerms +
            ",runs,failed,controller.k_p,controller.k_d,error,wall_s\n"
            "0,0,0,0,5.25,0.5,0.25,0.012,210.5,0.41,0.8,2,1,600,30,,1.5\n"
            "1,0,1,0,5.15,0.5,0.15,0.011,205,0.4,0.7,2,1,450,45,,1.4\n"
            "2,1,0,1,0.08,0,0.08,0.006,190,0.37,0.2,2,0,700,25,,1.6\n"
            "3,1,1,1,1e6,nan,nan,nan,nan,nan,nan,0,0,1200,45,"
            "\"controller.k_p = 1200 is outside [100, 1000] <b>\",0.01\n"
            "4,2,0,2,0.0312,0,0.0312,0.004,185.25,0.36,0.1,2,0,731.5,22.25,,1.55\n"
            "5,2,1,2,0.045,0,0.045,0.005,188,0.365,0.15,2,0,690,28,,1.45\n");
  Write(dir, "runs.csv",
        std::string("eval,suite,scenario,passed,outcome,") + kTerms +
            "\n"
            "0,flat,walk_0.6,1,completed,0,0.1,0.01,200,0.4,0.5\n"
            "0,push,push & shove,0,fell,1,0.4,0.014,221,0.42,1.1\n"
            "1,flat,walk_0.6,1,completed,0,0.05,0.01,199,0.4,0.4\n"
            "1,push,push & shove,0,tripped,1,0.25,0.012,211,0.4,1.0\n"
            "2,flat,walk_0.6,1,completed,0,0.06,0.005,185,0.36,0.2\n"
            "2,push,push & shove,1,completed,0,0.1,0.007,195,0.38,0.2\n"
            "4,flat,walk_0.6,1,completed,0,0.0224,0.003,180,0.35,0.1\n"
            "4,push,push & shove,1,completed,0,0.04,0.005,190.5,0.37,0.1\n"
            "5,flat,walk_0.6,1,completed,0,0.03,0.004,183,0.355,0.1\n"
            "5,push,push & shove,1,completed,0,0.06,0.006,193,0.375,0.2\n");
  Write(dir, "comparison.csv",
        std::string(kComparisonHeader) +
            "flat,walk_0.6,1,1,0,0,0.1,0.0224,0.01,0.003,200,180,0.4,0.35,0.5,0.1\n"
            "push,push & shove,0,1,1,0,0.4,0.04,0.014,0.005,221,190.5,0.42,0.37,1.1,0.1\n");
  Write(dir, "best.toml",
        "# walk_gains: the best of 6 evaluations (evaluation 4)\n"
        "[controller]\nk_p = 731.5\nk_d = 22.25\n");
}

void WriteSyntheticTuneFixture(const std::string& dir, int evaluations, int parameters,
                               int scenarios) {
  fs::create_directories(dir);
  auto objective = [](int i) { return 0.05 + 2.0 * std::exp(-0.05 * i) + 0.01 * (i % 3); };
  int best = 0;
  for (int i = 1; i < evaluations; ++i) {
    if (objective(i) < objective(best)) best = i;
  }
  // Names of varied length, one far longer than a figure's label.
  auto name = [](int s) {
    return "scenario_" + std::to_string(s) +
           (s == 1 ? "_with_a_very_long_name_that_the_figure_cuts_short" : "");
  };
  auto value = [](int i, int p) { return 5.0 + 4.0 * std::sin(0.3 * i + p) * std::exp(-0.01 * i); };
  std::string params = "path,lower,upper,initial,best\n", columns;
  for (int p = 0; p < parameters; ++p) {
    const std::string path = "controller.gain_" + std::to_string(p);
    params += path + ",0,10," + Num(value(0, p)) + "," + Num(value(best, p)) + "\n";
    columns += "," + path;
  }
  Write(dir, "parameters.csv", params);
  std::string evals = std::string("eval,round,start,seq,objective,") + kTerms + ",runs,failed" +
                      columns + ",error,wall_s\n";
  std::string runs = std::string("eval,suite,scenario,passed,outcome,") + kTerms + "\n";
  for (int i = 0; i < evaluations; ++i) {
    evals += std::to_string(i) + "," + std::to_string(i / 2) + "," + std::to_string(i % 2) + "," +
             std::to_string(i / 2) + "," + Num(objective(i)) + ",0," + Num(objective(i)) +
             ",0.01,200,0.4,0.1," + std::to_string(scenarios) + ",0";
    for (int p = 0; p < parameters; ++p) evals += "," + Num(value(i, p));
    evals += ",,0.5\n";
    for (int s = 0; s < scenarios; ++s) {
      runs += std::to_string(i) + ",synthetic," + name(s) + ",1,completed,0," + Num(objective(i)) +
              ",0.01,200,0.4,0.1\n";
    }
  }
  Write(dir, "evaluations.csv", evals);
  Write(dir, "runs.csv", runs);
  std::string comparison = kComparisonHeader;
  for (int s = 0; s < scenarios; ++s) {
    comparison += "synthetic," + name(s) + ",1,1,0,0," + Num(objective(0) * (1 + 0.1 * s)) + "," +
                  Num(objective(best) * (1 + 0.05 * s)) + ",0.01,0.01,200,200,0.4,0.4,0.1,0.1\n";
  }
  Write(dir, "comparison.csv", comparison);
  Write(dir, "meta.csv",
        "key,value\njob,synthetic\ndescription,a synthetic job\njob_file,synthetic.toml\n"
        "algorithm,sbplx\nseed,1\nstarts,2\nmax_evaluations," +
            std::to_string(evaluations) + "\nform,mean_square\nweights,speed_error=1\n" +
            "suites,synthetic.toml\nevaluations," + std::to_string(evaluations) +
            "\ninitial_eval,0\nbest_eval," + std::to_string(best) + "\ninitial_objective," +
            Num(objective(0)) + "\nbest_objective," + Num(objective(best)) +
            "\ncomplete,true\nfingerprint,0\n");
  Write(dir, "best.toml", "[controller]\ngain_0 = " + Num(value(best, 0)) + "\n");
}

}  // namespace rabbit::testing
