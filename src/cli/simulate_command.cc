// rabbit simulate SCENARIO.toml [--out traj.csv]: one run, full time series.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/gait/database_layout.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/model/model.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/run.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/scenario/trajectory_csv.h"
#include "rabbit/sim/simulator.h"

namespace rabbit::cli {
namespace {

struct SimulateArgs {
  std::string scenario;
  std::string out;
  std::string integrator;
  std::string params;
  std::string gaits;
  bool quiet = false;
};

int RunSimulate(const SimulateArgs& args) {
  ParamOverlay overlay;
  if (!args.params.empty()) overlay = LoadParamOverlay(args.params);
  if (!args.gaits.empty()) overlay.gait_database = GaitDatabaseRoot(args.gaits);
  Scenario scenario = LoadScenario(args.scenario, &overlay);
  if (!args.integrator.empty()) {
    ParseIntegratorName(args.integrator, &scenario.options.integrator.kind);  // checked by CLI11
    std::string error;
    if (!scenario.options.integrator.IsValid(&error)) {
      std::cerr << "rabbit simulate: --integrator " << args.integrator << ": " << error << " ("
                << scenario.file << " sets the order)\n";
      return 2;
    }
  }
  const std::string out =
      args.out.empty() ? "reports/" + scenario.name + "/trajectory.csv" : args.out;
  if (!IsStandardOutput(out)) {  // before the work: a new file, or a trajectory to replace
    CheckOwnedFile("--out", out, "t_s,", "a trajectory CSV of rabbit simulate");
  }
  // Walker scenarios need their gait pattern (loaded before the clock starts).
  std::shared_ptr<const GaitLibrary> library;
  if (scenario.controller == ControllerKind::kFuzzyCmac)
    library = LoadGaitLibrary(scenario.pattern);
  const auto start = std::chrono::steady_clock::now();
  const RunOutput run = RunScenario(scenario, ScenarioVariants(scenario).front(), library.get());
  const SimResult& result = run.sim;
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  WriteOutputFile(out, [&result](std::ostream& o) { WriteTrajectoryCsv(result, o); });

  if (!args.quiet) {
    // With --out -, the CSV is standard output: the summary goes to standard error.
    FILE* talk = IsStandardOutput(out) ? stderr : stdout;
    const double period = scenario.options.control_period;
    std::fprintf(talk, "scenario   %s (%s)\n", scenario.name.c_str(), scenario.file.c_str());
    std::fprintf(talk, "outcome    %s%s%s\n", OutcomeName(result.outcome),
                 result.reason.empty() ? "" : ": ", result.reason.c_str());
    std::fprintf(talk, "simulated  %.3f s in %.3f s wall (%.0fx real time), integrator %s\n",
                 result.t_end, wall, wall > 0 ? result.t_end / wall : 0.0,
                 IntegratorName(scenario.options.integrator.kind));
    std::fprintf(talk, "steps      %ld internal, %ld rhs evals, %ld contact events\n",
                 result.integrator.steps, result.integrator.rhs_evals, result.num_events);
    std::fprintf(talk, "saturation hip1 %.3f s, knee1 %.3f s, hip2 %.3f s, knee2 %.3f s\n",
                 result.saturation_time(0, period), result.saturation_time(1, period),
                 result.saturation_time(2, period), result.saturation_time(3, period));
    if (!run.steps.empty()) {
      std::fprintf(talk,
                   "walking    %zu steps, %.2f m, mean L_step %.3f m, mean |V_M - V_d| %.3f m/s\n",
                   run.steps.size(), run.metrics.distance, run.metrics.l_step_mean,
                   run.metrics.mean_abs_speed_error);
    }
    std::fprintf(talk, "wrote      %s (%zu rows)\n", out.c_str(), result.samples.size());
  }
  if (!scenario.expected_outcome.empty() &&
      scenario.expected_outcome != OutcomeName(result.outcome)) {
    std::cerr << "rabbit simulate: expected outcome '" << scenario.expected_outcome << "', got '"
              << OutcomeName(result.outcome) << "'\n";
    return 1;
  }
  return 0;
}

}  // namespace

Command RegisterSimulate(CLI::App* app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd =
      app->add_subcommand("simulate", "Run one scenario and write its full time series");
  cmd->add_option("scenario", args->scenario, "Scenario file (TOML)")->required();
  cmd->add_option("--out,-o", args->out,
                  "Trajectory CSV file to write (default: reports/<scenario name>/trajectory.csv; "
                  "-: standard output)");
  cmd->add_option("--integrator", args->integrator,
                  "Override the scenario's integrator (default: the scenario's)")
      ->check(CLI::IsMember({"arkode", "cvode", "cvode-adams"}));
  cmd->add_option("--params", args->params,
                  "Parameter overlay (TOML [params], e.g. a tuning job's best.toml) over the "
                  "scenario's settings (default: none)");
  cmd->add_option("--gaits", args->gaits,
                  "Gait database for a walker scenario (folder; default: the one it names)");
  cmd->add_flag("--quiet,-q", args->quiet, "Print nothing but errors");
  return {cmd, [args] { return RunSimulate(*args); }};
}

}  // namespace rabbit::cli
