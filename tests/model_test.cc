// Model: M(q) symmetric positive definite; M and h against finite differences of an independent
// Lagrangian written straight from the axis conventions of docs/design/model.md; Jacobians against
// finite differences; torque sign conventions.
#include "rabbit/model/model.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <random>

namespace rabbit {
namespace {

// Reference kinematics written independently of model.cc, from docs/design/model.md, "Coordinates
// and signs": trunk axis (sin q0, cos q0); thigh axis (sin th, -cos th), th = qi1 - q0; shin axis
// (sin sh, -cos sh), sh = th + qi2. Returns the CoM of body b (0 trunk, 1 thigh1, 2 shin1, 3
// thigh2, 4 shin2). Templated on the scalar so that complex-step differentiation gives exact
// velocities.
template <typename T>
Eigen::Matrix<T, 2, 1> RefCom(const ModelParams& p, const Eigen::Matrix<T, 7, 1>& q, int body) {
  using std::cos;
  using std::sin;
  using V = Eigen::Matrix<T, 2, 1>;
  const V hip(q[kX], q[kY]);
  if (body == 0) return hip + p.trunk_com * V(sin(q[kQ0]), cos(q[kQ0]));
  const int leg = (body - 1) / 2;
  const T th = q[kQ11 + 2 * leg] - q[kQ0];
  const T sh = th + q[kQ12 + 2 * leg];
  const V u_th(sin(th), -cos(th)), u_sh(sin(sh), -cos(sh));
  if (body % 2 == 1) return hip + p.thigh_com * u_th;
  return hip + p.thigh_length * u_th + p.shin_com * u_sh;
}
Vec2 RefCom(const ModelParams& p, const Vec7& q, int body) { return RefCom<double>(p, q, body); }
// Angular velocity (counter-clockwise) of body b.
double RefOmega(const Vec7& qd, int body) {
  if (body == 0) return -qd[kQ0];
  const int leg = (body - 1) / 2;
  const double thd = qd[kQ11 + 2 * leg] - qd[kQ0];
  return body % 2 == 1 ? thd : thd + qd[kQ12 + 2 * leg];
}
double RefMass(const ModelParams& p, int b) {
  return b == 0 ? p.trunk_mass : (b % 2 == 1 ? p.thigh_mass : p.shin_mass);
}
double RefInertia(const ModelParams& p, int b) {
  return b == 0 ? p.trunk_inertia : (b % 2 == 1 ? p.thigh_inertia : p.shin_inertia);
}

// Kinetic energy with CoM velocities v = d com/dq . qd by complex-step differentiation
// (Im(com(q + i eps qd)) / eps, exact to machine precision).
double RefKinetic(const ModelParams& p, const Vec7& q, const Vec7& qd) {
  using C = std::complex<double>;
  const double eps = 1e-30;
  const Eigen::Matrix<C, 7, 1> qc = q.cast<C>() + C(0.0, eps) * qd.cast<C>();
  double t = 0.0;
  for (int b = 0; b < 5; ++b) {
    const Vec2 v = RefCom<C>(p, qc, b).imag() / eps;
    const double w = RefOmega(qd, b);
    t += 0.5 * RefMass(p, b) * v.squaredNorm() + 0.5 * RefInertia(p, b) * w * w;
  }
  const double armature = p.gear_ratio * p.gear_ratio * p.rotor_inertia;
  for (int j = kQ11; j <= kQ22; ++j) t += 0.5 * armature * qd[j] * qd[j];
  return t;
}
double RefPotential(const ModelParams& p, const Vec7& q) {
  const Vec2 g = p.gravity * Vec2(std::sin(p.slope), -std::cos(p.slope));
  double v = 0.0;
  for (int b = 0; b < 5; ++b) v -= RefMass(p, b) * g.dot(RefCom(p, q, b));
  return v;
}
// M from the quadratic form T(u) = 0.5 u^T M u: M_ii = 2 T(e_i), M_ij = T(e_i + e_j) - T(e_i) -
// T(e_j).
Mat7 RefMassMatrix(const ModelParams& p, const Vec7& q) {
  Mat7 M;
  for (int i = 0; i < kNq; ++i) {
    for (int j = 0; j < kNq; ++j) {
      const Vec7 ei = Vec7::Unit(i), ej = Vec7::Unit(j);
      M(i, j) = i == j ? 2 * RefKinetic(p, q, ei)
                       : RefKinetic(p, q, ei + ej) - RefKinetic(p, q, ei) - RefKinetic(p, q, ej);
    }
  }
  return M;
}
// h = d/dt(dL/dqd)|_{qdd=0} - dL/dq = (dM/dq . qd) qd - dT/dq + dV/dq, by central differences.
Vec7 RefBias(const ModelParams& p, const Vec7& q, const Vec7& qd) {
  const double eps = 1e-5;
  const Vec7 ddt =
      (RefMassMatrix(p, q + eps * qd) * qd - RefMassMatrix(p, q - eps * qd) * qd) / (2 * eps);
  Vec7 dl;
  for (int k = 0; k < kNq; ++k) {
    const Vec7 e = eps * Vec7::Unit(k);
    const double lp = RefKinetic(p, q + e, qd) - RefPotential(p, q + e);
    const double lm = RefKinetic(p, q - e, qd) - RefPotential(p, q - e);
    dl[k] = (lp - lm) / (2 * eps);
  }
  return ddt - dl;
}

Vec7 RandomState(std::mt19937* rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Vec7 v;
  for (int i = 0; i < kNq; ++i) v[i] = u(*rng);
  return v;
}

TEST(ModelTest, MassMatrixSymmetricPositiveDefinite) {
  const Model model{ModelParams{}};
  std::mt19937 rng(1);
  Data data;
  for (int n = 0; n < 1000; ++n) {
    const Vec7 q = RandomState(&rng, M_PI);
    ComputeDynamics(model, q, Vec7::Zero(), &data);
    const double kSymmetryTolerance = 1e-12;
    EXPECT_LE((data.M - data.M.transpose()).cwiseAbs().maxCoeff(),
              kSymmetryTolerance * data.M.cwiseAbs().maxCoeff());
    Eigen::SelfAdjointEigenSolver<Mat7> eig(data.M);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0) << "q = " << q.transpose();
  }
}

void ExpectMatchesLagrangian(const ModelParams& params, int seed) {
  const Model model(params);
  std::mt19937 rng(seed);
  Data data;
  // M is exact (complex step); h uses central differences of step 1e-5: truncation O(1e-10),
  // rounding O(1e-11) relative. The tolerance leaves a margin over that and catches any term.
  const double kTolerance = 1e-8;
  for (int n = 0; n < 50; ++n) {
    Vec7 q = RandomState(&rng, 1.0);
    q[kY] += 1.0;
    const Vec7 qd = RandomState(&rng, 3.0);
    ComputeDynamics(model, q, qd, &data);
    const Mat7 M_ref = RefMassMatrix(params, q);
    const Vec7 h_ref = RefBias(params, q, qd);
    EXPECT_LE((data.M - M_ref).cwiseAbs().maxCoeff(), kTolerance * M_ref.cwiseAbs().maxCoeff());
    EXPECT_LE((data.h - h_ref).cwiseAbs().maxCoeff(), kTolerance * h_ref.cwiseAbs().maxCoeff())
        << "h = " << data.h.transpose() << "\nref = " << h_ref.transpose();
    EXPECT_NEAR(KineticEnergy(model, q, qd), RefKinetic(params, q, qd),
                1e-9 * RefKinetic(params, q, qd));
    EXPECT_NEAR(PotentialEnergy(model, q), RefPotential(params, q), 1e-9);
  }
}

TEST(ModelTest, MatchesFiniteDifferencesOfLagrangian) { ExpectMatchesLagrangian(ModelParams{}, 2); }

TEST(ModelTest, MatchesLagrangianWithOtherParameters) {
  ModelParams p;
  p.trunk_mass = 20.0;
  p.trunk_com = 0.3;
  p.thigh_length = 0.5;
  p.thigh_com = 0.2;
  p.shin_mass = 2.0;
  p.shin_com = 0.1;
  p.rotor_inertia = 3.32e-4;
  p.slope = 0.2;
  ExpectMatchesLagrangian(p, 3);
}

TEST(ModelTest, FootJacobianMatchesFiniteDifferences) {
  const Model model{ModelParams{}};
  std::mt19937 rng(4);
  Data data;
  const double eps = 1e-6;
  const double kTolerance = 1e-8;  // central differences: O(eps^2) truncation, O(1e-16/eps) noise
  for (int n = 0; n < 100; ++n) {
    const Vec7 q = RandomState(&rng, 1.5), qd = RandomState(&rng, 2.0);
    ComputeDynamics(model, q, qd, &data);
    ComputeFootKinematics(model, q, qd, &data);
    for (int leg = 0; leg < kNumLegs; ++leg) {
      Mat27 J_fd;
      for (int k = 0; k < kNq; ++k) {
        const Vec7 e = eps * Vec7::Unit(k);
        J_fd.col(k) =
            (FootPosition(model, q + e, leg) - FootPosition(model, q - e, leg)) / (2 * eps);
      }
      EXPECT_LE((FootJacobian(model, q, leg) - J_fd).cwiseAbs().maxCoeff(), kTolerance);
      const Vec2 F(37.0, -250.0);
      Vec7 Q = Vec7::Zero();
      AddFootForce(model, data, leg, F, &Q);
      EXPECT_LE((Q - J_fd.transpose() * F).cwiseAbs().maxCoeff(), 1e-5);  // |F| ~ 250 N
      EXPECT_LE((data.foot_pos[leg] - FootPosition(model, q, leg)).norm(), 1e-14);
      EXPECT_LE((data.foot_vel[leg] - J_fd * qd).norm(), 1e-7);
      EXPECT_LE((ComputePose(model, q).foot[leg] - FootPosition(model, q, leg)).norm(), 1e-14);
    }
  }
}

TEST(ModelTest, BlockSolveEqualsCholeskyAndCachedQuantitiesAgree) {
  // Forward dynamics through the absolute-coordinate block solve (no rotor inertia) must satisfy
  // M qdd + h = Q with the joint-space M and h; the cached pose and energies equal the direct ones.
  const Model model{ModelParams{}};
  std::mt19937 rng(5);
  Data data;
  const double kTolerance = 1e-10;
  for (int n = 0; n < 200; ++n) {
    const Vec7 q = RandomState(&rng, M_PI), qd = RandomState(&rng, 3.0);
    const Vec7 Q = RandomState(&rng, 100.0);
    ASSERT_TRUE(ForwardDynamics(model, q, qd, Q, &data));
    const Vec7 qdd = data.qdd;
    ComputeDynamics(model, q, qd, &data);
    const Vec7 residual = data.M * qdd + data.h - Q;
    EXPECT_LE(residual.cwiseAbs().maxCoeff(), kTolerance * (Q - data.h).cwiseAbs().maxCoeff());
    EXPECT_NEAR(KineticEnergy(model, qd, data), 0.5 * qd.dot(data.M * qd),
                kTolerance * (1.0 + 0.5 * qd.dot(data.M * qd)));
    EXPECT_NEAR(PotentialEnergy(model, q, data), PotentialEnergy(model, q), kTolerance * 100);
    const Pose a = ComputePose(model, q), b = ComputePose(model, q, data);
    EXPECT_LE((a.foot[1] - b.foot[1]).norm() + (a.trunk_top - b.trunk_top).norm(), 1e-14);
  }
  // With rotor inertia the joint-space Cholesky path runs: same residual check.
  ModelParams with_rotor;
  with_rotor.rotor_inertia = 3.32e-4;
  const Model rotor_model(with_rotor);
  for (int n = 0; n < 50; ++n) {
    const Vec7 q = RandomState(&rng, M_PI), qd = RandomState(&rng, 3.0);
    const Vec7 Q = RandomState(&rng, 100.0);
    ASSERT_TRUE(ForwardDynamics(rotor_model, q, qd, Q, &data));
    const Vec7 qdd = data.qdd;
    ComputeDynamics(rotor_model, q, qd, &data);
    EXPECT_LE((data.M * qdd + data.h - Q).cwiseAbs().maxCoeff(),
              kTolerance * (Q - data.h).cwiseAbs().maxCoeff());
  }
}

TEST(ModelTest, StandingStraightGeometry) {
  const Model model{ModelParams{}};
  Vec7 q = Vec7::Zero();
  q[kY] = 0.87;
  const Pose pose = ComputePose(model, q);
  EXPECT_NEAR(pose.foot[0].y(), 0.0, 1e-15);
  EXPECT_NEAR(pose.knee[1].y(), 0.47, 1e-15);
  EXPECT_NEAR(pose.trunk_com.y(), 0.87 + 0.20, 1e-15);
  // Leaning the trunk forward moves its top toward +x; a positive hip angle with the trunk
  // upright puts the knee ahead of the hip; a negative knee angle puts the foot behind the knee.
  q[kQ0] = 0.3;
  EXPECT_GT(ComputePose(model, q).trunk_top.x(), 0.0);
  q[kQ0] = 0.0;
  q[kQ11] = 0.3;
  q[kQ12] = -0.6;
  const Pose bent = ComputePose(model, q);
  EXPECT_GT(bent.knee[0].x(), 0.0);
  EXPECT_LT(bent.foot[0].x(), bent.knee[0].x());
}

TEST(ModelTest, PositiveHipTorqueTiltsTrunkForwardAndSwingsThighForward) {
  // docs/design/model.md: with the stance thigh held, a positive stance-hip torque increases q0. In
  // free flight at rest without gravity, the torque turns the thigh counter-clockwise (knee
  // forward) and, by reaction, the trunk clockwise (q0 increases).
  ModelParams p;
  p.gravity = 0.0;
  const Model model(p);
  Vec7 q = Vec7::Zero();
  q[kY] = 1.0;
  q[kQ11] = 0.2;
  q[kQ21] = -0.2;
  Data data;
  ASSERT_TRUE(ForwardDynamics(model, q, Vec7::Zero(),
                              JointTorqueToGeneralized(Vec4(10.0, 0.0, 0.0, 0.0)), &data));
  EXPECT_GT(data.qdd[kQ0], 0.0);
  EXPECT_GT(data.qdd[kQ11] - data.qdd[kQ0], 0.0);  // thigh 1 absolute angle accelerates forward
  // With the thigh held (x, y, thigh 1 fixed; q0 and q11 move together), the reduced dynamics
  // along v = e_q0 + e_q11 give q0dd = v^T Q / v^T M v > 0.
  Vec7 v = Vec7::Zero();
  v[kQ0] = v[kQ11] = 1.0;
  const double reduced =
      v.dot(JointTorqueToGeneralized(Vec4(10.0, 0.0, 0.0, 0.0))) / v.dot(data.M * v);
  EXPECT_GT(reduced, 0.0);
}

TEST(ModelTest, InvalidParametersAreRejected) {
  ModelParams p;
  p.shin_mass = -1.0;
  std::string error;
  EXPECT_FALSE(p.IsValid(&error));
  EXPECT_NE(error.find("shin_mass"), std::string::npos);
  EXPECT_THROW(Model{p}, std::invalid_argument);
  p = ModelParams{};
  p.thigh_com = std::nan("");
  EXPECT_FALSE(p.IsValid(&error));
}

}  // namespace
}  // namespace rabbit
