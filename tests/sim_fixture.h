// The simulator tests' shared set-up (simulator_test, simulator_profile_test, ground_steps_test):
// the robot's A-frame stance, a PD hold of it, and a test run with each integrator.
#ifndef RABBIT_TESTS_SIM_FIXTURE_H_
#define RABBIT_TESTS_SIM_FIXTURE_H_

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "rabbit/control/basic_controllers.h"
#include "rabbit/model/model.h"
#include "rabbit/sim/simulator.h"

namespace rabbit::testing {

inline constexpr double kDeg = M_PI / 180.0;

// The A-frame stance of scenarios/standing_pd_hold.toml: legs +-12 deg, knees straight, with the
// lowest foot `clearance` above the ground.
Vec7 Stance(const Model& model, double clearance, double half_angle_deg = 12.0);

// A PD hold of the joints at q's.
PdHoldParams HoldAt(const Vec7& q);

// What the drop test's acceptance numbers are read from: the deepest foot below the ground
// (<= 0), the highest foot above it once that foot has touched down, and which feet have.
struct DropMeasures {
  double deepest = 0.0, rebound = 0.0;
  std::array<bool, kNumLegs> landed{};
};
DropMeasures MeasureDrop(const SimResult& r);

// A test run with each integrator (the parameter).
class SimulatorTest : public ::testing::TestWithParam<IntegratorKind> {
 protected:
  // Not "Setup": that would hide gtest's Setup() misspelling trap (clang: -Woverloaded-virtual).
  SimSetup BaseSetup(const Model& model, double duration) const {
    SimSetup setup;
    setup.model = &model;
    setup.options.duration = duration;
    setup.options.integrator.kind = GetParam();
    return setup;
  }
};

}  // namespace rabbit::testing

#endif  // RABBIT_TESTS_SIM_FIXTURE_H_
