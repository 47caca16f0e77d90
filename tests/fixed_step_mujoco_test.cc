// The opt-in fixed step (IntegratorOptions::fixed_step) against MuJoCo's RK4 on the contact-free
// swing of scenarios/swing_free.toml: both take the classic Runge-Kutta method at 1 ms on the same
// robot (tests/mujoco_model.h), so over 1 s they must agree within the goal's 1e-6 rad, and in
// fact to rounding (seen: 8.9e-15 rad).
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "mujoco_model.h"
#include "rabbit/control/basic_controllers.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/sim/simulator.h"

namespace rabbit {
namespace {

TEST(FixedStepMujocoTest, Rk4At1msFollowsMujocoRk4OnTheContactFreeSwing) {
  Scenario scenario = LoadScenario(std::string(RABBIT_SOURCE_DIR) + "/scenarios/swing_free.toml");
  scenario.options.duration = 1.0;
  scenario.options.integrator.fixed_step = 1e-3;
  const Model model(scenario.model);
  const SimSetup setup = MakeSimSetup(scenario, &model);
  PassiveController passive;
  const SimResult ours = Simulate(setup, scenario.q0, scenario.qd0, &passive);
  ASSERT_EQ(ours.outcome, Outcome::kCompleted) << ours.reason;
  ASSERT_EQ(ours.samples.size(), 1001u);

  mujoco_ref::MujocoModelOptions options;
  options.integrator = "RK4";
  options.timestep = 1e-3;
  std::string error;
  mujoco_ref::ModelPtr m = mujoco_ref::LoadRabbitMujocoModel(scenario.model, options, &error);
  ASSERT_TRUE(m) << error;
  mujoco_ref::DataPtr d(mj_makeData(m.get()));
  mj_resetData(m.get(), d.get());
  mujoco_ref::SetMujocoState(m.get(), d.get(), scenario.q0, scenario.qd0);
  double worst = 0.0;
  for (size_t k = 1; k < ours.samples.size(); ++k) {
    mj_step(m.get(), d.get());
    const Vec7 diff = mujoco_ref::MujocoQ(m.get(), d.get()) - ours.samples[k].q;
    worst = std::max(worst, diff.cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-6);  // the goal's figure
  EXPECT_LT(worst, 1e-11);  // the same method: to rounding
  std::printf("fixed-step RK4 against MuJoCo RK4, 1 s swing: max |q difference| %.2e\n", worst);
}

}  // namespace
}  // namespace rabbit
