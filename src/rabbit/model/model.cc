#include "rabbit/model/model.h"

#include <cmath>
#include <stdexcept>

namespace rabbit {
namespace {

// Absolute link indices: 0 trunk, 1 thigh 1, 2 shin 1, 3 thigh 2, 4 shin 2.
constexpr int kTrunk = 0;
inline int ThighIndex(int leg) { return 1 + 2 * leg; }
inline int ShinIndex(int leg) { return 2 + 2 * leg; }

// Absolute CCW link angles a = (B q)[2..6].
inline std::array<double, 5> LinkAngles(const Vec7& q) {
  return {-q[kQ0], q[kQ11] - q[kQ0], q[kQ11] + q[kQ12] - q[kQ0], q[kQ21] - q[kQ0],
          q[kQ21] + q[kQ22] - q[kQ0]};
}
// e(a) = (sin a, -cos a): unit vector of a link hanging at CCW angle a from the downward vertical.
inline Vec2 Down(double a) { return Vec2(std::sin(a), -std::cos(a)); }
// de/da = (cos a, sin a).
inline Vec2 Perp(double a) { return Vec2(std::cos(a), std::sin(a)); }

}  // namespace

Model::Model(const ModelParams& params) : params_(params) {
  std::string error;
  if (!params.IsValid(&error)) throw std::invalid_argument("invalid model parameter: " + error);
  const ModelParams& p = params_;
  total_mass_ = p.trunk_mass + 2.0 * (p.thigh_mass + p.shin_mass);
  joint_armature_ = p.gear_ratio * p.gear_ratio * p.rotor_inertia;
  gravity_ = p.gravity * Vec2(std::sin(p.slope), -std::cos(p.slope));

  // Signed arm of each body's CoM along each link: trunk CoM = hip - trunk_com * e(a0);
  // thigh CoM = hip + thigh_com * e(a_th); shin CoM = hip + thigh_length e(a_th) + shin_com
  // e(a_sh).
  moments_.setZero();
  first_moments_.setZero();
  moments_(kTrunk, kTrunk) = p.trunk_mass * p.trunk_com * p.trunk_com;
  first_moments_(kTrunk) = -p.trunk_mass * p.trunk_com;
  link_inertias_(kTrunk) = p.trunk_inertia;
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const int th = ThighIndex(leg), sh = ShinIndex(leg);
    moments_(th, th) =
        p.thigh_mass * p.thigh_com * p.thigh_com + p.shin_mass * p.thigh_length * p.thigh_length;
    moments_(th, sh) = moments_(sh, th) = p.shin_mass * p.thigh_length * p.shin_com;
    moments_(sh, sh) = p.shin_mass * p.shin_com * p.shin_com;
    first_moments_(th) = p.thigh_mass * p.thigh_com + p.shin_mass * p.thigh_length;
    first_moments_(sh) = p.shin_mass * p.shin_com;
    link_inertias_(th) = p.thigh_inertia;
    link_inertias_(sh) = p.shin_inertia;
  }
}

void ComputeLinkAngles(const Model& /*model*/, const Vec7& q, const Vec7& qd, Data* data) {
  data->ad = LinkAngles(qd);  // the same linear map as the angles
  if (q == data->angles_q) return;
  const std::array<double, 5> a = LinkAngles(q);
  for (int k = 0; k < 5; ++k) {
    data->sin_a[k] = std::sin(a[k]);
    data->cos_a[k] = std::cos(a[k]);
  }
  data->angles_q = q;
}

void ComputeAbsoluteDynamics(const Model& model, const Vec7& q, const Vec7& qd, Data* data) {
  ComputeLinkAngles(model, q, qd, data);
  const auto& s = data->sin_a;
  const auto& c = data->cos_a;
  const auto& P = model.moments();
  const auto& m1 = model.first_moments();
  const double gx = model.gravity().x(), gy = model.gravity().y();
  Mat7& Mp = data->Mp;
  Vec7& hp = data->hp;
  Mp.setZero();
  Mp(0, 0) = Mp(1, 1) = model.total_mass();
  // Gravity: V = -sum_b m_b g . p_b, so dV/dx = -m gx, dV/dy = -m gy and
  // dV/da_i = -c_i g . e'(a_i) = -c_i (gx cos a_i + gy sin a_i).
  hp[0] = -model.total_mass() * gx;
  hp[1] = -model.total_mass() * gy;
  for (int i = 0; i < 5; ++i) {
    const double ad2 = data->ad[i] * data->ad[i];
    // Translational rows: M_p[xy, a_i] = c_i e'(a_i); bias -c_i ad_i^2 e(a_i).
    Mp(0, 2 + i) = Mp(2 + i, 0) = m1[i] * c[i];
    Mp(1, 2 + i) = Mp(2 + i, 1) = m1[i] * s[i];
    hp[0] -= m1[i] * ad2 * s[i];
    hp[1] += m1[i] * ad2 * c[i];
    double hi = -m1[i] * (gx * c[i] + gy * s[i]);
    for (int j = 0; j < 5; ++j) {
      if (P(i, j) == 0.0) continue;
      // cos(a_i - a_j) and sin(a_j - a_i) from the cached sines and cosines.
      Mp(2 + i, 2 + j) = P(i, j) * (c[i] * c[j] + s[i] * s[j]);
      hi -= P(i, j) * data->ad[j] * data->ad[j] * (s[j] * c[i] - c[j] * s[i]);
    }
    Mp(2 + i, 2 + i) += model.link_inertias()[i];
    hp[2 + i] = hi;
  }
}

namespace {

// B^T v for v in absolute coordinates (p = B q; see the file comment of model.h).
template <typename In>
Vec7 ApplyBTranspose(const In& v) {
  Vec7 out;
  out << v[0], v[1], -(v[2] + v[3] + v[4] + v[5] + v[6]), v[3] + v[4], v[4], v[5] + v[6], v[6];
  return out;
}
// B^-T Q: the absolute-coordinate force equivalent to the joint-space force Q.
Vec7 ApplyBInverseTranspose(const Vec7& Q) {
  Vec7 out;
  out << Q[kX], Q[kY], -Q[kQ0] - Q[kQ11] - Q[kQ21], Q[kQ11] - Q[kQ12], Q[kQ12], Q[kQ21] - Q[kQ22],
      Q[kQ22];
  return out;
}
// B^-1 pdd: joint-space accelerations from absolute ones.
Vec7 ApplyBInverse(const Vec7& p) {
  Vec7 out;
  out << p[0], p[1], -p[2], p[3] - p[2], p[4] - p[3], p[5] - p[2], p[6] - p[5];
  return out;
}

// Solves Mp x = r using Mp = [m I2, C; C^T, D] with D = diag(trunk, 2x2 leg 1, 2x2 leg 2).
bool SolveAbsolute(const Mat7& Mp, const Vec7& r, Vec7* x) {
  // Y = D^-1 [C^T | r2]: three right-hand sides per block.
  Eigen::Matrix<double, 5, 3> rhs;
  rhs.leftCols<2>() = Mp.block<5, 2>(2, 0);
  rhs.col(2) = r.tail<5>();
  Eigen::Matrix<double, 5, 3> Y;
  if (!(Mp(2, 2) > 0.0)) return false;
  Y.row(0) = rhs.row(0) / Mp(2, 2);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const int k = 1 + 2 * leg;
    const Eigen::Matrix2d Dk = Mp.block<2, 2>(2 + k, 2 + k);
    const double det = Dk(0, 0) * Dk(1, 1) - Dk(0, 1) * Dk(1, 0);
    if (!(det > 0.0 && Dk(0, 0) > 0.0)) return false;
    Eigen::Matrix2d inv;
    inv << Dk(1, 1), -Dk(0, 1), -Dk(1, 0), Dk(0, 0);
    Y.middleRows<2>(k) = (inv / det) * rhs.middleRows<2>(k);
  }
  // Schur complement S = m I - C D^-1 C^T, S u = r1 - C D^-1 r2, then w = D^-1 (r2 - C^T u).
  const Eigen::Matrix<double, 2, 5> C = Mp.block<2, 5>(0, 2);
  Eigen::Matrix2d S = Mp.topLeftCorner<2, 2>() - C * Y.leftCols<2>();
  const Vec2 b = r.head<2>() - C * Y.col(2);
  const double det = S(0, 0) * S(1, 1) - S(0, 1) * S(1, 0);
  if (!(det > 0.0 && S(0, 0) > 0.0)) return false;
  const Vec2 u((S(1, 1) * b[0] - S(0, 1) * b[1]) / det, (S(0, 0) * b[1] - S(1, 0) * b[0]) / det);
  x->head<2>() = u;
  x->tail<5>() = Y.col(2) - Y.leftCols<2>() * u;
  return true;
}

// M = B^T Mp B (+ rotor inertia) and h = B^T hp: T = Mp B by columns, then B^T T by rows.
void FormJointSpace(const Model& model, Data* data) {
  const Mat7& Mp = data->Mp;
  Mat7 T;
  T.col(kX) = Mp.col(0);
  T.col(kY) = Mp.col(1);
  T.col(kQ0) = -(Mp.col(2) + Mp.col(3) + Mp.col(4) + Mp.col(5) + Mp.col(6));
  T.col(kQ11) = Mp.col(3) + Mp.col(4);
  T.col(kQ12) = Mp.col(4);
  T.col(kQ21) = Mp.col(5) + Mp.col(6);
  T.col(kQ22) = Mp.col(6);
  for (int j = 0; j < kNq; ++j) data->M.col(j) = ApplyBTranspose(T.col(j));
  for (int j = kQ11; j <= kQ22; ++j) data->M(j, j) += model.joint_armature();
  data->h = ApplyBTranspose(data->hp);
}

}  // namespace

void ComputeDynamics(const Model& model, const Vec7& q, const Vec7& qd, Data* data) {
  ComputeAbsoluteDynamics(model, q, qd, data);
  FormJointSpace(model, data);
}

bool SolveForAcceleration(const Model& model, const Vec7& Q, Data* data) {
  if (model.joint_armature() == 0.0) {
    Vec7 pdd;
    if (!SolveAbsolute(data->Mp, ApplyBInverseTranspose(Q) - data->hp, &pdd)) return false;
    data->qdd = ApplyBInverse(pdd);
    return true;
  }
  // Rotor inertia sits on the joint coordinates' diagonal: solve in joint space.
  FormJointSpace(model, data);
  data->llt.compute(data->M);
  if (data->llt.info() != Eigen::Success) return false;
  data->qdd = data->llt.solve(Q - data->h);
  return true;
}

bool ForwardDynamics(const Model& model, const Vec7& q, const Vec7& qd, const Vec7& Q, Data* data) {
  ComputeAbsoluteDynamics(model, q, qd, data);
  return SolveForAcceleration(model, Q, data);
}

void ComputeFootKinematics(const Model& model, const Vec7& q, const Vec7& qd, Data* data) {
  const ModelParams& p = model.params();
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const int th = ThighIndex(leg), sh = ShinIndex(leg);
    const double lt = p.thigh_length, ls = p.shin_length;
    data->foot_pos[leg] = Vec2(q[kX] + lt * data->sin_a[th] + ls * data->sin_a[sh],
                               q[kY] - lt * data->cos_a[th] - ls * data->cos_a[sh]);
    // d/dt of e(a) = (sin a, -cos a) is ad (cos a, sin a).
    const double wt = lt * data->ad[th], ws = ls * data->ad[sh];
    data->foot_vel[leg] = Vec2(qd[kX] + wt * data->cos_a[th] + ws * data->cos_a[sh],
                               qd[kY] + wt * data->sin_a[th] + ws * data->sin_a[sh]);
  }
}

void AddFootForce(const Model& model, const Data& data, int leg, const Vec2& F, Vec7* Q) {
  const ModelParams& p = model.params();
  const int th = ThighIndex(leg), sh = ShinIndex(leg);
  // Generalized force on the thigh and shin angles: L e'(a) . F, with e'(a) = (cos a, sin a);
  // then B^T maps absolute to joint coordinates (see model.h).
  const double f_th = p.thigh_length * (data.cos_a[th] * F.x() + data.sin_a[th] * F.y());
  const double f_sh = p.shin_length * (data.cos_a[sh] * F.x() + data.sin_a[sh] * F.y());
  const int hip = leg == 0 ? kQ11 : kQ21;
  (*Q)[kX] += F.x();
  (*Q)[kY] += F.y();
  (*Q)[kQ0] -= f_th + f_sh;
  (*Q)[hip] += f_th + f_sh;
  (*Q)[hip + 1] += f_sh;
}

Pose ComputePose(const Model& model, const Vec7& q, const Data& data) {
  const ModelParams& p = model.params();
  auto down = [&data](int k) { return Vec2(data.sin_a[k], -data.cos_a[k]); };
  Pose pose;
  pose.hip = Vec2(q[kX], q[kY]);
  pose.trunk_com = pose.hip - p.trunk_com * down(kTrunk);
  pose.trunk_top = pose.hip - p.trunk_length * down(kTrunk);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec2 e_th = down(ThighIndex(leg));
    const Vec2 e_sh = down(ShinIndex(leg));
    pose.thigh_com[leg] = pose.hip + p.thigh_com * e_th;
    pose.knee[leg] = pose.hip + p.thigh_length * e_th;
    pose.shin_com[leg] = pose.knee[leg] + p.shin_com * e_sh;
    pose.foot[leg] = pose.knee[leg] + p.shin_length * e_sh;
  }
  return pose;
}

double KineticEnergy(const Model& model, const Vec7& qd, const Data& data) {
  Vec7 pd;
  pd << qd[kX], qd[kY], data.ad[0], data.ad[1], data.ad[2], data.ad[3], data.ad[4];
  return 0.5 * pd.dot(data.Mp * pd) +
         0.5 * model.joint_armature() * qd.tail<kNumJoints>().squaredNorm();
}

double PotentialEnergy(const Model& model, const Vec7& q, const Data& data) {
  Vec2 moment = model.total_mass() * Vec2(q[kX], q[kY]);
  for (int k = 0; k < 5; ++k) {
    moment += model.first_moments()[k] * Vec2(data.sin_a[k], -data.cos_a[k]);
  }
  return -model.gravity().dot(moment);
}

Pose ComputePose(const Model& model, const Vec7& q) {
  const ModelParams& p = model.params();
  const std::array<double, 5> a = LinkAngles(q);
  Pose pose;
  pose.hip = Vec2(q[kX], q[kY]);
  pose.trunk_com = pose.hip - p.trunk_com * Down(a[kTrunk]);
  pose.trunk_top = pose.hip - p.trunk_length * Down(a[kTrunk]);
  for (int leg = 0; leg < kNumLegs; ++leg) {
    const Vec2 e_th = Down(a[ThighIndex(leg)]);
    const Vec2 e_sh = Down(a[ShinIndex(leg)]);
    pose.thigh_com[leg] = pose.hip + p.thigh_com * e_th;
    pose.knee[leg] = pose.hip + p.thigh_length * e_th;
    pose.shin_com[leg] = pose.knee[leg] + p.shin_com * e_sh;
    pose.foot[leg] = pose.knee[leg] + p.shin_length * e_sh;
  }
  return pose;
}

Vec2 FootPosition(const Model& model, const Vec7& q, int leg) {
  const std::array<double, 5> a = LinkAngles(q);
  const ModelParams& p = model.params();
  return Vec2(q[kX], q[kY]) + p.thigh_length * Down(a[ThighIndex(leg)]) +
         p.shin_length * Down(a[ShinIndex(leg)]);
}

Mat27 FootJacobian(const Model& model, const Vec7& q, int leg) {
  const std::array<double, 5> a = LinkAngles(q);
  const ModelParams& p = model.params();
  const Vec2 d_thigh = p.thigh_length * Perp(a[ThighIndex(leg)]);
  const Vec2 d_shin = p.shin_length * Perp(a[ShinIndex(leg)]);
  Mat27 J = Mat27::Zero();
  J(0, kX) = 1.0;
  J(1, kY) = 1.0;
  J.col(kQ0) = -(d_thigh + d_shin);
  const int hip = leg == 0 ? kQ11 : kQ21;
  J.col(hip) = d_thigh + d_shin;
  J.col(hip + 1) = d_shin;
  return J;
}

Vec7 JointTorqueToGeneralized(const Vec4& tau) {
  Vec7 Q = Vec7::Zero();
  Q.tail<4>() = tau;
  return Q;
}

double KineticEnergy(const Model& model, const Vec7& q, const Vec7& qd) {
  Data data;
  ComputeDynamics(model, q, qd, &data);
  return 0.5 * qd.dot(data.M * qd);
}

Vec2 CenterOfMass(const Model& model, const Vec7& q) {
  const std::array<double, 5> a = LinkAngles(q);
  Vec2 moment = model.total_mass() * Vec2(q[kX], q[kY]);
  for (int k = 0; k < 5; ++k) moment += model.first_moments()[k] * Down(a[k]);
  return moment / model.total_mass();
}

double PotentialEnergy(const Model& model, const Vec7& q) {
  return -model.total_mass() * model.gravity().dot(CenterOfMass(model, q));
}

}  // namespace rabbit
