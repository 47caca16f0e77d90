// RABBIT rigid-body model: kinematics, mass matrix, nonlinear effects, energy
// (docs/design/model.md, "The model").
//
// Generalized coordinates q = [x, y, q0, q11, q12, q21, q22]:
//   x, y  hip position (world, y up);
//   q0    trunk pitch from the upward vertical, positive leaning forward;
//   qi1   hip of leg i, relative trunk->thigh; thigh absolute angle th_i = qi1 - q0 from the
//         downward vertical, positive with the knee ahead of the hip;
//   qi2   knee of leg i, relative thigh->shin, 0 straight, negative flexed.
// Equations of motion:  M(q) qdd + h(q, qd) = S^T tau + sum_feet J_f(q)^T F_f,
// with tau = [T_hip1, T_knee1, T_hip2, T_knee2] acting on q11, q12, q21, q22.
//
// Internally the model works in "absolute" coordinates p = B q = [x, y, a0..a4], where a_k are
// the counter-clockwise angles of the five links (a0 = -q0 trunk, a1 = q11 - q0 thigh 1,
// a2 = q11 + q12 - q0 shin 1, a3, a4 leg 2). Every link point is hip + sum_k s_k e(a_k) with
// e(a) = (sin a, -cos a), so M_p and h_p have a closed form in the constant moments
//   P(i, j) = sum_b m_b s_{b,i} s_{b,j},   c_i = sum_b m_b s_{b,i},
// and M = B^T M_p B (+ rotor inertia), h = B^T h_p.
//
// Model/data split (as in Pinocchio): a Model is built once from validated parameters and never
// modified; each simulation owns a Data with all scratch space, so threads share one Model.
#ifndef RABBIT_MODEL_MODEL_H_
#define RABBIT_MODEL_MODEL_H_

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <array>
#include <limits>

#include "rabbit/model/params.h"

namespace rabbit {

using Vec2 = Eigen::Vector2d;
using Vec4 = Eigen::Vector4d;
using Vec7 = Eigen::Matrix<double, 7, 1>;
using Mat7 = Eigen::Matrix<double, 7, 7>;
using Mat27 = Eigen::Matrix<double, 2, 7>;

// Indices into q.
enum Coord : int { kX = 0, kY = 1, kQ0 = 2, kQ11 = 3, kQ12 = 4, kQ21 = 5, kQ22 = 6 };
constexpr int kNq = 7;
constexpr int kNumJoints = 4;  // hip1, knee1, hip2, knee2 (q index = 3 + joint)
constexpr int kNumLegs = 2;

class Model {
 public:
  // Throws std::invalid_argument when !params.IsValid().
  explicit Model(const ModelParams& params);

  const ModelParams& params() const { return params_; }
  double total_mass() const { return total_mass_; }
  double leg_length() const { return params_.thigh_length + params_.shin_length; }
  // Constant moments of the absolute-coordinate formulation (see file comment).
  const Eigen::Matrix<double, 5, 5>& moments() const { return moments_; }
  const Eigen::Matrix<double, 5, 1>& first_moments() const { return first_moments_; }
  const Eigen::Matrix<double, 5, 1>& link_inertias() const { return link_inertias_; }
  double joint_armature() const { return joint_armature_; }
  // Gravity vector in the simulation frame, gravity * (sin slope, -cos slope).
  const Vec2& gravity() const { return gravity_; }

 private:
  ModelParams params_;
  double total_mass_ = 0.0;
  double joint_armature_ = 0.0;
  Vec2 gravity_ = Vec2::Zero();
  Eigen::Matrix<double, 5, 5> moments_;
  Eigen::Matrix<double, 5, 1> first_moments_;
  Eigen::Matrix<double, 5, 1> link_inertias_;
};

// Per-simulation scratch space and results of the algorithms below.
struct Data {
  std::array<double, 5> sin_a{}, cos_a{}, ad{};  // link angles' sines, cosines, rates
  // The q at which sin_a and cos_a were last computed: the integrator evaluates the right-hand
  // side, the guards and the sample at the same q several times per step, and the sines are the
  // largest part of a right-hand side. A Data serves one Model.
  Vec7 angles_q = Vec7::Constant(std::numeric_limits<double>::quiet_NaN());
  Mat7 Mp = Mat7::Zero();                         // mass matrix in absolute coordinates p
  Vec7 hp = Vec7::Zero();                         // nonlinear effects in absolute coordinates
  Mat7 M = Mat7::Zero();                          // mass matrix M(q)
  Vec7 h = Vec7::Zero();                          // nonlinear effects h(q, qd)
  Eigen::LLT<Mat7> llt;                           // factorisation of M (with rotor inertia)
  Vec7 qdd = Vec7::Zero();                        // result of ForwardDynamics
  std::array<Vec2, kNumLegs> foot_pos, foot_vel;  // results of ComputeFootKinematics
};

// Planar positions of the robot's points, for contact, checks and drawing.
struct Pose {
  Vec2 hip, trunk_com, trunk_top;
  std::array<Vec2, kNumLegs> knee, foot, thigh_com, shin_com;
};

// Fills data->sin_a, cos_a and ad (the links' absolute angles' sines, cosines and rates).
void ComputeLinkAngles(const Model& model, const Vec7& q, const Vec7& qd, Data* data);

// Fills data->sin_a, cos_a, ad, Mp and hp at (q, qd): everything forward dynamics needs.
void ComputeAbsoluteDynamics(const Model& model, const Vec7& q, const Vec7& qd, Data* data);

// Fills data->sin_a, cos_a, ad, Mp, hp, and the joint-space M = B^T Mp B (+ rotor inertia) and
// h = B^T hp at (q, qd).
void ComputeDynamics(const Model& model, const Vec7& q, const Vec7& qd, Data* data);

// Fills data->foot_pos and foot_vel from the sines, cosines and rates that ComputeLinkAngles (or
// ComputeDynamics) cached for the same (q, qd).
void ComputeFootKinematics(const Model& model, const Vec7& q, const Vec7& qd, Data* data);

// Q += J_f^T F for a force F (world frame) on foot `leg`, from the cached link angles, without
// forming the Jacobian.
void AddFootForce(const Model& model, const Data& data, int leg, const Vec2& F, Vec7* Q);

// Solves M qdd = Q - h into data->qdd, from the Mp and hp in data (after ComputeAbsoluteDynamics
// or ComputeDynamics). Without rotor inertia it solves Mp pdd = B^-T Q - hp in absolute
// coordinates, where Mp = [m I2, C; C^T, D] has D block-diagonal (trunk, leg 1, leg 2), through
// the 2x2 Schur complement m I2 - C D^-1 C^T; with rotor inertia, a Cholesky factorisation of M.
// Returns false when the matrix is not positive definite (never for a valid model, finite q).
bool SolveForAcceleration(const Model& model, const Vec7& Q, Data* data);

// qdd = M^-1 (Q - h) with Q the total generalized force, into data->qdd.
bool ForwardDynamics(const Model& model, const Vec7& q, const Vec7& qd, const Vec7& Q, Data* data);

// Position of every point of interest at q.
Pose ComputePose(const Model& model, const Vec7& q);
// The same from the sines and cosines that ComputeLinkAngles cached for this q.
Pose ComputePose(const Model& model, const Vec7& q, const Data& data);

// Foot i position and velocity (world frame) and its Jacobian d(foot)/dq.
Vec2 FootPosition(const Model& model, const Vec7& q, int leg);
Mat27 FootJacobian(const Model& model, const Vec7& q, int leg);

// Generalized force of the motor torques tau = [T_hip1, T_knee1, T_hip2, T_knee2].
Vec7 JointTorqueToGeneralized(const Vec4& tau);

// Kinetic energy 0.5 qd^T M qd and gravitational potential energy -sum m_b g . p_b (= sum m_b g
// y_b on flat ground).
double KineticEnergy(const Model& model, const Vec7& q, const Vec7& qd);
double PotentialEnergy(const Model& model, const Vec7& q);
// Both from the Mp and link angles cached by ComputeAbsoluteDynamics for this (q, qd).
double KineticEnergy(const Model& model, const Vec7& qd, const Data& data);
double PotentialEnergy(const Model& model, const Vec7& q, const Data& data);
// Position of the whole robot's centre of mass.
Vec2 CenterOfMass(const Model& model, const Vec7& q);

}  // namespace rabbit

#endif  // RABBIT_MODEL_MODEL_H_
