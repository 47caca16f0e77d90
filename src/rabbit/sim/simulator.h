// The simulation loop: SUNDIALS integration of the RABBIT dynamics with compliant contact, a
// controller sampled at a fixed rate with zero-order-hold torques, actuator saturation, events
// (touchdown, lift-off, stick/slide, obstacle edges) located by root finding, and fall/trip checks.
#ifndef RABBIT_SIM_SIMULATOR_H_
#define RABBIT_SIM_SIMULATOR_H_

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "rabbit/contact/actuator.h"
#include "rabbit/contact/contact.h"
#include "rabbit/contact/terrain.h"
#include "rabbit/model/model.h"
#include "rabbit/sim/controller.h"
#include "rabbit/sim/integrator.h"

namespace rabbit {

// When a run counts as a fall (docs/design/model.md, "Gait measurement and falls"). Any knee at or
// below the ground also counts.
struct FallCriteria {
  double min_hip_height = 0.6;        // m, above the ground under the hip
  double max_trunk_pitch = 0.785398;  // rad (45 deg)
  bool enabled = true;
};

struct SimOptions {
  double duration = 5.0;         // s
  double control_period = 1e-3;  // s (1 kHz)
  bool contact = true;           // false: no ground at all (free flight / swing studies)
  // Restart the integrator at every control sample where the zero-order-hold torques change.
  // Without it, the integrator reuses derivatives of the previous period's torques (ARKODE's first
  // stage, CVODE's history): faster, but an O(h) error at every sample that tight tolerances
  // cannot meet (measured in bench/README.md).
  bool restart_at_samples = true;
  int max_events_per_period = 100;  // more means chattering: the run ends as diverged
  int record_every = 1;             // keep every n-th sample in the result (0 = none)
  // End the run (as completed) at the first sample where the hip has travelled this far in x (m).
  double stop_distance = std::numeric_limits<double>::infinity();
  // End the run (as timeout) once it has taken this much wall time (s), checked every
  // kWallCheckPeriods control periods. A safety net against a run that crawls (chattering
  // contacts, tiny integrator steps): where it ends depends on the machine's speed and load.
  double max_wall = std::numeric_limits<double>::infinity();
  IntegratorOptions integrator;
  FallCriteria fall;
  bool IsValid(std::string* error) const;
};

// The clock is read once per this many control periods (0.1 s at 1 kHz): cheap next to them.
constexpr long kWallCheckPeriods = 100;

// How a run ended (docs/outcomes.md): completed (the whole duration, or stop_distance reached),
// fell, tripped, stalled (the controller's stall watch ended it: Controller::CheckStall),
// diverged (integrator failure, non-finite state, chattering contacts) or timeout (max_wall).
enum class Outcome { kCompleted, kFell, kTripped, kStalled, kDiverged, kTimedOut };
inline constexpr std::array<Outcome, 6> kAllOutcomes = {Outcome::kCompleted, Outcome::kFell,
                                                        Outcome::kTripped,   Outcome::kStalled,
                                                        Outcome::kDiverged,  Outcome::kTimedOut};
const char* OutcomeName(Outcome outcome);
// The outcome named `name` (as OutcomeName writes it); false for an unknown name.
bool ParseOutcome(const std::string& name, Outcome* outcome);

struct SimSample {
  double t = 0.0;
  Vec7 q = Vec7::Zero(), qd = Vec7::Zero();
  Vec4 tau_cmd = Vec4::Zero();  // what the controller asked for
  Vec4 tau = Vec4::Zero();      // what the actuators applied (after saturation)
  std::array<Vec2, kNumLegs> foot_pos;
  std::array<FootForce, kNumLegs> foot_force{};
  std::array<ContactMode, kNumLegs> foot_mode{};
  double kinetic = 0.0, potential = 0.0, elastic = 0.0;
};

// A change of a foot's contact mode, located by root finding.
struct ContactEvent {
  double t = 0.0;
  int leg = 0;
  ContactMode from = ContactMode::kAir, to = ContactMode::kAir;
  double x = 0.0;  // foot position at the event
  double y = 0.0;
  double fn = 0.0;  // contact force just after the event
  double ft = 0.0;
  double anchor_x = 0.0;  // sticking spring's anchor after the event
};

struct SimResult {
  Outcome outcome = Outcome::kCompleted;
  std::string reason;  // why the run ended early (empty when completed)
  double t_end = 0.0;
  std::vector<SimSample> samples;  // every record_every-th sample, and the last
  // The last sample (the state at t_end, or at the start of the period that failed), kept
  // whatever record_every is: metrics do not depend on what is recorded. Its energies are set
  // only when it was recorded.
  SimSample last;
  IntegratorStats integrator;
  long num_events = 0;
  std::vector<ContactEvent> events;  // every contact mode change, in time order
  long num_periods = 0;
  std::array<long, kNumJoints> saturated_periods{};  // control periods with saturation per joint
  // Mechanical work of the actuators, sum over joints and periods of max(0, tau_j qd_j) dt with
  // the torque and rate at each sample (J): the energy term of the cost of transport.
  double positive_work = 0.0;
  // When each push of the set-up started (s; nan: its event never came).
  std::vector<double> push_starts;
  double saturation_time(int joint, double period) const {
    return static_cast<double>(saturated_periods[joint]) * period;
  }
};

// An external force on the trunk (a push), in the simulation frame, at the point `height` above the
// hip on the trunk's axis, acting on the control samples t_k with start <= t_k < start + duration
// (held over each period like the torques, so its timing is quantised to the control period).
// Instead of a start time, a push may wait for an event (rabbit/sim/push_schedule.h): the
// after_touchdown-th touchdown (1-based, counted as the gait meter counts them: a foot landing
// after at least 0.05 s in the air), then `phase` times the step's expected duration (the time
// between that touchdown and the one before it); or the hip passing at_hip_x; or both (the
// touchdowns counted from the hip passing at_hip_x).
struct TrunkPush {
  double start = 0.0;         // s (event-timed pushes: 0)
  double duration = 0.1;      // s
  Vec2 force = Vec2::Zero();  // N
  double height = 0.2;        // m above the hip, along the trunk
  int after_touchdown = 0;    // >= 1: timed from that touchdown (0: not)
  double phase = 0.0;         // [0, 1]: the fraction of the step's expected duration
  double at_hip_x = std::numeric_limits<double>::quiet_NaN();  // m (nan: not)
  bool event_timed() const { return after_touchdown > 0 || !std::isnan(at_hip_x); }
  bool IsValid(std::string* error) const;
};

// The generalized force of a force F at `height` on the trunk axis (virtual work):
// Q_x = F_x, Q_y = F_y, Q_q0 = height (F_x cos q0 - F_y sin q0).
Vec7 TrunkForceToGeneralized(const Vec7& q, const Vec2& force, double height);

// Everything a run needs besides its initial state and controller. The model and terrain are
// shared read-only (several threads may simulate with one Setup).
struct SimSetup {
  const Model* model = nullptr;
  ContactParams contact;
  ActuatorParams actuator;
  Terrain terrain;
  std::vector<TrunkPush> pushes;
  SimOptions options;
};

// Runs one simulation from (q0, qd0). Never throws for physical failures (falls, trips, integrator
// failures, NaN): they end the run with an Outcome and a reason. Throws std::invalid_argument for
// invalid options.
SimResult Simulate(const SimSetup& setup, const Vec7& q0, const Vec7& qd0, Controller* controller);

// Total mechanical energy of a sample: kinetic + potential + contact elastic.
inline double TotalEnergy(const SimSample& s) { return s.kinetic + s.potential + s.elastic; }

}  // namespace rabbit

#endif  // RABBIT_SIM_SIMULATOR_H_
