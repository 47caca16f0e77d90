// Cross-check of the RABBIT dynamics against MuJoCo on the same robot (docs/design/model.md):
// M(q), h(q, qd), kinetic and potential energy, forward dynamics, foot kinematics and Jacobians at
// random states, for the documented parameters and for non-default ones.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "mujoco_model.h"
#include "rabbit/model/model.h"
#include "rabbit/model/params.h"

namespace rabbit {
namespace {

using mujoco_ref::DataPtr;
using mujoco_ref::LoadRabbitMujocoModel;
using mujoco_ref::ModelPtr;
using mujoco_ref::MujocoModelOptions;

// Relative to the largest |entry| of the MuJoCo quantity being compared.
const double kTolerance = 1e-9;
constexpr int kNumStates = 100;

// Largest relative errors seen over the whole run, reported at the end.
struct MaxErrors {
  double mass = 0.0, bias = 0.0, kinetic = 0.0, potential = 0.0, qacc = 0.0, kinematics = 0.0;
};
MaxErrors& Seen() {
  static MaxErrors errors;
  return errors;
}

// A random state: angles and x in +-1, hip height in [0.9, 1.1] m, rates in +-3.
struct State {
  Vec7 q, qd;
};
std::vector<State> RandomStates(unsigned seed, int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<State> states(count);
  for (State& s : states) {
    for (int i = 0; i < kNq; ++i) {
      s.q[i] = unit(rng);
      s.qd[i] = 3.0 * unit(rng);
    }
    s.q[kY] = 1.0 + 0.1 * unit(rng);
  }
  return states;
}

// max |a - b| / max |b| (b is the MuJoCo reference); |a - b| when b is exactly zero.
template <typename A, typename B>
double RelativeError(const A& ours, const B& reference) {
  const double scale = reference.cwiseAbs().maxCoeff();
  const double diff = (ours - reference).cwiseAbs().maxCoeff();
  return scale > 0.0 ? diff / scale : diff;
}
double RelativeError(double ours, double reference) {
  const double diff = std::abs(ours - reference);
  return reference != 0.0 ? diff / std::abs(reference) : diff;
}

void Track(double error, double* worst) { *worst = std::max(*worst, error); }

class MujocoComparison {
 public:
  explicit MujocoComparison(const ModelParams& params) : model_(params) {
    std::string error;
    mj_model_ = LoadRabbitMujocoModel(params, MujocoModelOptions{}, &error);
    if (mj_model_) mj_data_.reset(mj_makeData(mj_model_.get()));
    load_error_ = error;
  }
  bool ok() const { return mj_model_ != nullptr && mj_data_ != nullptr; }
  const std::string& load_error() const { return load_error_; }

  // Compares M, h, kinetic and potential energy at every state.
  void CompareDynamics(const std::vector<State>& states, const std::string& label) {
    mjModel* m = mj_model_.get();
    mjData* d = mj_data_.get();
    Data data;
    MaxErrors local;
    for (size_t k = 0; k < states.size(); ++k) {
      const State& s = states[k];
      mujoco_ref::SetMujocoState(m, d, s.q, s.qd);
      mj_forward(m, d);
      mj_energyPos(m, d);
      mj_energyVel(m, d);
      ComputeDynamics(model_, s.q, s.qd, &data);

      const Mat7 mj_mass = mujoco_ref::MujocoMassMatrix(m, d);
      const Vec7 mj_bias = mujoco_ref::MujocoBias(m, d);
      const double e_mass = RelativeError(data.M, mj_mass);
      const double e_bias = RelativeError(data.h, mj_bias);
      const double kinetic = 0.5 * s.qd.dot(data.M * s.qd);
      const double e_kin = RelativeError(kinetic, d->energy[1]);
      const double e_pot = RelativeError(PotentialEnergy(model_, s.q), d->energy[0]);
      const double e_kin_fn = RelativeError(KineticEnergy(model_, s.q, s.qd), d->energy[1]);
      EXPECT_LE(e_mass, kTolerance) << label << " state " << k << "\nours M:\n"
                                    << data.M << "\nMuJoCo M:\n"
                                    << mj_mass;
      EXPECT_LE(e_bias, kTolerance) << label << " state " << k << "\nours h: " << data.h.transpose()
                                    << "\nMuJoCo qfrc_bias: " << mj_bias.transpose();
      EXPECT_LE(e_kin, kTolerance)
          << label << " state " << k << " kinetic " << kinetic << " vs MuJoCo " << d->energy[1];
      EXPECT_LE(e_kin_fn, kTolerance) << label << " state " << k;
      EXPECT_LE(e_pot, kTolerance) << label << " state " << k << " potential "
                                   << PotentialEnergy(model_, s.q) << " vs MuJoCo " << d->energy[0];
      Track(e_mass, &local.mass);
      Track(e_bias, &local.bias);
      Track(std::max(e_kin, e_kin_fn), &local.kinetic);
      Track(e_pot, &local.potential);
    }
    Track(local.mass, &Seen().mass);
    Track(local.bias, &Seen().bias);
    Track(local.kinetic, &Seen().kinetic);
    Track(local.potential, &Seen().potential);
    std::printf("[%s] max rel. error over %zu states: M %.3g, h %.3g, KE %.3g, PE %.3g\n",
                label.c_str(), states.size(), local.mass, local.bias, local.kinetic,
                local.potential);
  }

  // qdd = M^-1 (S^T tau - h) against MuJoCo's qacc with tau in qfrc_applied.
  void CompareForwardDynamics(const std::vector<State>& states, unsigned seed) {
    mjModel* m = mj_model_.get();
    mjData* d = mj_data_.get();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> torque(-75.0, 75.0);
    Data data;
    for (size_t k = 0; k < states.size(); ++k) {
      const State& s = states[k];
      const Vec4 tau(torque(rng), torque(rng), torque(rng), torque(rng));
      const Vec7 Q = JointTorqueToGeneralized(tau);
      mujoco_ref::SetMujocoState(m, d, s.q, s.qd);
      for (int i = 0; i < kNq; ++i) d->qfrc_applied[i] = Q[i];
      mj_forward(m, d);
      ASSERT_TRUE(ForwardDynamics(model_, s.q, s.qd, Q, &data));
      const Vec7 qacc = Eigen::Map<const Vec7>(d->qacc);
      const double e = RelativeError(data.qdd, qacc);
      EXPECT_LE(e, kTolerance) << "state " << k << "\nours qdd: " << data.qdd.transpose()
                               << "\nMuJoCo qacc: " << qacc.transpose();
      Track(e, &Seen().qacc);
    }
  }

  // Foot sites, body CoMs and foot Jacobians against ComputePose / FootJacobian.
  void CompareKinematics(const std::vector<State>& states) {
    mjModel* m = mj_model_.get();
    mjData* d = mj_data_.get();
    const ModelParams& p = model_.params();
    const double length = p.thigh_length + p.shin_length;
    std::vector<mjtNum> jacp(3 * m->nv);
    for (size_t k = 0; k < states.size(); ++k) {
      const State& s = states[k];
      mujoco_ref::SetMujocoState(m, d, s.q, s.qd);
      mj_forward(m, d);
      const Pose pose = ComputePose(model_, s.q);
      auto planar = [](const mjtNum* v) { return Vec2(v[0], v[2]); };
      auto body_com = [&](const char* name) {
        const int id = mj_name2id(m, mjOBJ_BODY, name);
        EXPECT_GE(id, 0) << name;
        return planar(d->xipos + 3 * id);
      };
      double worst = (body_com("trunk") - pose.trunk_com).norm();
      for (int leg = 0; leg < kNumLegs; ++leg) {
        const std::string n = std::to_string(leg + 1);
        const int site = mj_name2id(m, mjOBJ_SITE, ("foot" + n).c_str());
        ASSERT_GE(site, 0);
        const int shin = mj_name2id(m, mjOBJ_BODY, ("shin" + n).c_str());
        worst = std::max(worst, (planar(d->site_xpos + 3 * site) - pose.foot[leg]).norm());
        worst = std::max(worst, (planar(d->xpos + 3 * shin) - pose.knee[leg]).norm());
        worst = std::max(worst, (body_com(("thigh" + n).c_str()) - pose.thigh_com[leg]).norm());
        worst = std::max(worst, (body_com(("shin" + n).c_str()) - pose.shin_com[leg]).norm());
        // Foot Jacobian: rows x and z of MuJoCo's (3 x nv, row-major).
        mj_jacSite(m, d, jacp.data(), nullptr, site);
        Mat27 mj_jac;
        for (int j = 0; j < kNq; ++j) {
          mj_jac(0, j) = jacp[j];
          mj_jac(1, j) = jacp[2 * m->nv + j];
          EXPECT_EQ(jacp[m->nv + j], 0.0) << "out-of-plane Jacobian entry";
        }
        const double e_jac = RelativeError(FootJacobian(model_, s.q, leg), mj_jac);
        EXPECT_LE(e_jac, kTolerance) << "state " << k << " leg " << leg;
        worst = std::max(worst, e_jac * length);
      }
      EXPECT_LE(worst / length, kTolerance) << "state " << k;
      Track(worst / length, &Seen().kinematics);
    }
  }

 private:
  Model model_;
  ModelPtr mj_model_;
  DataPtr mj_data_;
  std::string load_error_;
};

// Prints the largest errors seen by all the tests that ran, after the last one.
class ReportMaxErrors : public ::testing::Environment {
 public:
  void TearDown() override {
    const MaxErrors& e = Seen();
    std::printf(
        "max relative error vs MuJoCo: M %.3g, h %.3g, kinetic %.3g, potential %.3g, "
        "kinematics %.3g, qacc %.3g (tolerance %.0e)\n",
        e.mass, e.bias, e.kinetic, e.potential, e.kinematics, e.qacc, kTolerance);
  }
};
const ::testing::Environment* const kReportMaxErrors =
    ::testing::AddGlobalTestEnvironment(new ReportMaxErrors);

TEST(ModelMujocoTest, GeneratedModelHasTheExpectedStructure) {
  std::string error;
  ModelPtr m = LoadRabbitMujocoModel(ModelParams{}, MujocoModelOptions{}, &error);
  ASSERT_TRUE(m) << error;
  EXPECT_EQ(m->nq, kNq);
  EXPECT_EQ(m->nv, kNq);
  EXPECT_EQ(m->nbody, 6);  // world, trunk, 2 thighs, 2 shins
  const char* names[kNq] = {"x", "y", "q0", "q11", "q12", "q21", "q22"};
  for (int i = 0; i < kNq; ++i) {
    const int id = mj_name2id(m.get(), mjOBJ_JOINT, names[i]);
    ASSERT_GE(id, 0) << names[i];
    EXPECT_EQ(m->jnt_qposadr[id], i) << names[i];
    EXPECT_EQ(m->jnt_dofadr[id], i) << names[i];
    EXPECT_EQ(m->dof_armature[i], 0.0);
    EXPECT_EQ(m->dof_damping[i], 0.0);
    EXPECT_EQ(m->jnt_limited[id], 0);
  }
  double total = 0.0;
  for (int b = 1; b < m->nbody; ++b) total += m->body_mass[b];
  EXPECT_DOUBLE_EQ(total, Model(ModelParams{}).total_mass());
  EXPECT_TRUE(m->opt.disableflags & mjDSBL_CONTACT);
  EXPECT_TRUE(m->opt.enableflags & mjENBL_ENERGY);
  EXPECT_EQ(m->opt.gravity[2], -ModelParams{}.gravity);
}

TEST(ModelMujocoTest, DefaultParametersMatchAtRandomStates) {
  MujocoComparison comparison{ModelParams{}};
  ASSERT_TRUE(comparison.ok()) << comparison.load_error();
  const std::vector<State> states = RandomStates(20240601u, kNumStates);
  comparison.CompareDynamics(states, "default");
}

TEST(ModelMujocoTest, StandingAndZeroVelocityStates) {
  // Special configurations: all zero (straight legs, upright), and zero velocity (gravity only).
  MujocoComparison comparison{ModelParams{}};
  ASSERT_TRUE(comparison.ok()) << comparison.load_error();
  std::vector<State> states = RandomStates(7u, 20);
  for (State& s : states) s.qd.setZero();
  State upright;
  upright.q = Vec7::Zero();
  upright.q[kY] = 0.87;
  upright.qd = Vec7::Zero();
  states.push_back(upright);
  comparison.CompareDynamics(states, "zero velocity");
}

TEST(ModelMujocoTest, NonDefaultParametersMatch) {
  struct Case {
    const char* label;
    ModelParams params;
  };
  std::vector<Case> cases;
  {
    ModelParams p;  // different masses, lengths, CoMs and inertias
    p.trunk_mass = 20.5;
    p.trunk_com = 0.35;
    p.trunk_inertia = 2.1;
    p.thigh_mass = 4.3;
    p.thigh_length = 0.55;
    p.thigh_com = 0.21;
    p.thigh_inertia = 0.09;
    p.shin_mass = 1.7;
    p.shin_length = 0.38;
    p.shin_com = 0.13;
    p.shin_inertia = 0.035;
    cases.push_back({"masses+lengths", p});
  }
  {
    ModelParams p;
    p.gravity = 0.0;
    cases.push_back({"gravity 0", p});
  }
  {
    ModelParams p;
    p.gravity = 3.71;
    p.trunk_com = 0.0;  // trunk CoM at the hip
    p.shin_com = 0.47;  // shin CoM at the foot
    cases.push_back({"mars, CoMs at joints", p});
  }
  {
    ModelParams p;  // RABBIT's rotor inertia: armature 50^2 * 3.32e-4 on every joint
    p.rotor_inertia = 3.32e-4;
    cases.push_back({"rotor inertia", p});
  }
  unsigned seed = 1000u;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.label);
    MujocoComparison comparison{c.params};
    ASSERT_TRUE(comparison.ok()) << comparison.load_error();
    comparison.CompareDynamics(RandomStates(seed++, kNumStates), c.label);
    comparison.CompareKinematics(RandomStates(seed++, 20));
  }
}

TEST(ModelMujocoTest, ForwardDynamicsMatchesMujocoAcceleration) {
  MujocoComparison comparison{ModelParams{}};
  ASSERT_TRUE(comparison.ok()) << comparison.load_error();
  comparison.CompareForwardDynamics(RandomStates(99u, kNumStates), 5u);
}

TEST(ModelMujocoTest, FootKinematicsAndJacobiansMatch) {
  MujocoComparison comparison{ModelParams{}};
  ASSERT_TRUE(comparison.ok()) << comparison.load_error();
  comparison.CompareKinematics(RandomStates(31u, kNumStates));
}

TEST(ModelMujocoTest, InvalidInputGivesAClearError) {
  ModelParams p;
  p.thigh_mass = -1.0;
  std::string error;
  EXPECT_FALSE(LoadRabbitMujocoModel(p, MujocoModelOptions{}, &error));
  EXPECT_NE(error.find("invalid model parameter"), std::string::npos) << error;
  EXPECT_NE(error.find("thigh_mass"), std::string::npos) << error;

  MujocoModelOptions options;
  options.integrator = "implicitfast";
  EXPECT_FALSE(LoadRabbitMujocoModel(ModelParams{}, options, &error));
  EXPECT_NE(error.find("integrator"), std::string::npos) << error;
}

TEST(ModelMujocoTest, GroundVariantFeetTouchOnlyThePlane) {
  MujocoModelOptions options;
  options.ground = true;
  options.integrator = "Euler";
  std::string error;
  ModelPtr m = LoadRabbitMujocoModel(ModelParams{}, options, &error);
  ASSERT_TRUE(m) << error;
  EXPECT_FALSE(m->opt.disableflags & mjDSBL_CONTACT);
  DataPtr d(mj_makeData(m.get()));
  const Model model{ModelParams{}};
  const int ground = mj_name2id(m.get(), mjOBJ_GEOM, "ground");
  const int foot1 = mj_name2id(m.get(), mjOBJ_GEOM, "foot_sphere1");
  const int foot2 = mj_name2id(m.get(), mjOBJ_GEOM, "foot_sphere2");
  ASSERT_GE(ground, 0);
  ASSERT_GE(foot1, 0);
  ASSERT_GE(foot2, 0);

  // Legs together and straight, feet 1 mm into the ground: the two spheres and the two shins
  // overlap, yet the only contacts are foot-ground.
  Vec7 q = Vec7::Zero();
  q[kY] = model.leg_length() - 1e-3;
  mujoco_ref::SetMujocoState(m.get(), d.get(), q, Vec7::Zero());
  mj_forward(m.get(), d.get());
  ASSERT_EQ(d->ncon, 2);
  for (int i = 0; i < d->ncon; ++i) {
    const mjContact& c = d->contact[i];
    const int other = c.geom1 == ground ? c.geom2 : c.geom1;
    EXPECT_TRUE(c.geom1 == ground || c.geom2 == ground);
    EXPECT_TRUE(other == foot1 || other == foot2);
    EXPECT_NEAR(c.dist, -1e-3, 1e-12);  // the plane at -radius makes the foot point the contact
    EXPECT_DOUBLE_EQ(c.friction[0], 0.8);
  }
  // Feet 1 mm above the ground: no contact.
  q[kY] = model.leg_length() + 1e-3;
  mujoco_ref::SetMujocoState(m.get(), d.get(), q, Vec7::Zero());
  mj_forward(m.get(), d.get());
  EXPECT_EQ(d->ncon, 0);
  // The ground geoms add no mass: M matches the contact-free model.
  Data data;
  ComputeDynamics(model, q, Vec7::Zero(), &data);
  EXPECT_LE(RelativeError(data.M, mujoco_ref::MujocoMassMatrix(m.get(), d.get())), kTolerance);
}

}  // namespace
}  // namespace rabbit
