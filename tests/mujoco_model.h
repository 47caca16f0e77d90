// The RABBIT model rebuilt in MuJoCo (MJCF), as an independent reference for tests and benchmarks
// (docs/design/model.md: M, h and the energy checked against MuJoCo on the same model).
//
// Coordinate mapping: our q = [x, y, q0, q11, q12, q21, q22] is MuJoCo's qpos one-to-one, and qd
// is qvel (MuJoCo's z is our y; MuJoCo's y axis points out of our sagittal plane):
//   trunk  slide x (axis 1 0 0), slide z (axis 0 0 1), hinge q0 (axis 0 1 0) at the hip, CoM at
//          (0, 0, trunk_com); a positive rotation about +y takes +z toward +x, so the trunk axis
//          is (sin q0, cos q0) as in our convention;
//   thigh  child of the trunk, hinge qi1 (axis 0 -1 0) at the hip, CoM at (0, 0, -thigh_com): its
//          frame is rotated by q0 - qi1 about +y, so its axis is (sin th, -cos th), th = qi1 - q0;
//   shin   child of the thigh at (0, 0, -thigh_length), hinge qi2 (axis 0 -1 0), CoM at
//          (0, 0, -shin_com), foot site "foot1"/"foot2" at (0, 0, -shin_length).
// Each body's inertia is diaginertia (I, I, I) with I our planar inertia about the CoM (only the
// y component matters: every hinge axis is parallel to y). A non-zero rotor inertia becomes the
// joints' armature gear_ratio^2 * rotor_inertia, exactly as Model adds it to M's diagonal. No
// damping, springs or joint limits; gravity (0, 0, -g); energy computation enabled.
//
// Without ground no geom can collide and contact is disabled. With ground, a plane and a sphere of
// radius foot_radius centred on each foot are the only colliding geoms (spheres contype 1
// conaffinity 0, plane contype 0 conaffinity 1: feet touch the plane, never each other); the plane
// lies at z = -foot_radius so that a foot point at our y = 0 just touches it, as in our model.
// Contacts use MuJoCo's default soft-constraint parameters (solref, solimp, pyramidal cone,
// impratio 1). Note: with these defaults a foot under a steady tangential load creeps (about
// 2.5 mm/s per foot when standing with pd_hold); noslip_iterations > 0 removes the creep.
#ifndef RABBIT_TESTS_MUJOCO_MODEL_H_
#define RABBIT_TESTS_MUJOCO_MODEL_H_

#include <mujoco/mujoco.h>

#include <memory>
#include <string>

#include "rabbit/model/model.h"
#include "rabbit/model/params.h"

namespace rabbit {
namespace mujoco_ref {

struct MujocoModelOptions {
  bool ground = false;             // false: contact-free (contact flag disabled)
  double foot_radius = 0.01;       // m, foot spheres (ground variant)
  double friction = 0.8;           // sliding friction of feet and plane (ground variant)
  double timestep = 1e-3;          // s
  std::string integrator = "RK4";  // "RK4" or "Euler"
  int noslip_iterations = 0;       // MuJoCo's post-solver without soft-contact creep (0 = off)
  bool energy = true;              // <flag energy="enable"/>
};

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// The MJCF text of the model described in the file comment. Numbers are written with 17
// significant digits, so the compiled model holds exactly the doubles of `params`.
std::string MakeRabbitMjcf(const ModelParams& params, const MujocoModelOptions& options = {});

// Builds the MJCF and compiles it with mj_loadXML (through a MuJoCo virtual file system, no file
// is written). On failure returns null and, when error is not null, sets *error to a message
// naming the cause (invalid parameters, invalid options, or MuJoCo's compiler message).
ModelPtr LoadRabbitMujocoModel(const ModelParams& params, const MujocoModelOptions& options,
                               std::string* error);

// Sets qpos = q, qvel = qd (the mapping is the identity) and clears qfrc_applied and ctrl.
void SetMujocoState(const mjModel* m, mjData* d, const Vec7& q, const Vec7& qd);
// MuJoCo's state as our q and qd.
Vec7 MujocoQ(const mjModel* m, const mjData* d);
Vec7 MujocoQd(const mjModel* m, const mjData* d);
// The dense mass matrix from d->qM (valid after mj_forward, or mj_fwdPosition, or mj_crb).
Mat7 MujocoMassMatrix(const mjModel* m, const mjData* d);
// qfrc_bias (Coriolis, centrifugal and gravity: our h) after mj_forward or mj_fwdVelocity.
Vec7 MujocoBias(const mjModel* m, const mjData* d);

}  // namespace mujoco_ref
}  // namespace rabbit

#endif  // RABBIT_TESTS_MUJOCO_MODEL_H_
