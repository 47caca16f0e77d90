#include "mujoco_model.h"

#include <cstring>
#include <locale>
#include <sstream>
#include <type_traits>

namespace rabbit {
namespace mujoco_ref {
namespace {

static_assert(std::is_same<mjtNum, double>::value, "MuJoCo must be built with double mjtNum");

constexpr char kXmlName[] = "rabbit_mujoco_ref.xml";

// Writes doubles with enough digits for an exact round trip.
class Xml {
 public:
  Xml() {
    out_.imbue(std::locale::classic());
    out_.precision(17);
  }
  template <typename T>
  Xml& operator<<(const T& value) {
    out_ << value;
    return *this;
  }
  std::string str() const { return out_.str(); }

 private:
  std::ostringstream out_;
};

// One leg: thigh and shin bodies with their joints, inertias, drawing geoms and foot site.
void WriteLeg(const ModelParams& p, const MujocoModelOptions& options, double armature, int leg,
              Xml* xml) {
  const int n = leg + 1;
  Xml& x = *xml;
  x << "      <body name=\"thigh" << n << "\" pos=\"0 0 0\">\n"
    << "        <joint name=\"q" << n << "1\" type=\"hinge\" pos=\"0 0 0\" axis=\"0 -1 0\""
    << " armature=\"" << armature << "\"/>\n"
    << "        <inertial pos=\"0 0 " << -p.thigh_com << "\" mass=\"" << p.thigh_mass
    << "\" diaginertia=\"" << p.thigh_inertia << ' ' << p.thigh_inertia << ' ' << p.thigh_inertia
    << "\"/>\n"
    << "        <geom name=\"thigh" << n << "\" type=\"capsule\" size=\"0.02\" fromto=\"0 0 0 0 0 "
    << -p.thigh_length << "\"/>\n"
    << "        <body name=\"shin" << n << "\" pos=\"0 0 " << -p.thigh_length << "\">\n"
    << "          <joint name=\"q" << n << "2\" type=\"hinge\" pos=\"0 0 0\" axis=\"0 -1 0\""
    << " armature=\"" << armature << "\"/>\n"
    << "          <inertial pos=\"0 0 " << -p.shin_com << "\" mass=\"" << p.shin_mass
    << "\" diaginertia=\"" << p.shin_inertia << ' ' << p.shin_inertia << ' ' << p.shin_inertia
    << "\"/>\n"
    << "          <geom name=\"shin" << n
    << "\" type=\"capsule\" size=\"0.015\" fromto=\"0 0 0 0 0 " << -p.shin_length << "\"/>\n"
    << "          <site name=\"foot" << n << "\" pos=\"0 0 " << -p.shin_length << "\"/>\n";
  if (options.ground) {
    x << "          <geom name=\"foot_sphere" << n << "\" type=\"sphere\" size=\""
      << options.foot_radius << "\" pos=\"0 0 " << -p.shin_length
      << "\" contype=\"1\" conaffinity=\"0\" friction=\"" << options.friction
      << " 0.005 0.0001\"/>\n";
  }
  x << "        </body>\n"
    << "      </body>\n";
}

bool OptionsValid(const MujocoModelOptions& options, std::string* error) {
  if (options.integrator != "RK4" && options.integrator != "Euler") {
    *error = "integrator must be \"RK4\" or \"Euler\", got \"" + options.integrator + "\"";
    return false;
  }
  if (!(options.timestep > 0.0)) {
    *error = "timestep must be positive";
    return false;
  }
  if (options.noslip_iterations < 0) {
    *error = "noslip_iterations must be >= 0";
    return false;
  }
  if (options.ground && !(options.foot_radius > 0.0 && options.friction >= 0.0)) {
    *error = "foot_radius must be positive and friction non-negative";
    return false;
  }
  return true;
}

}  // namespace

std::string MakeRabbitMjcf(const ModelParams& p, const MujocoModelOptions& options) {
  const double armature = p.gear_ratio * p.gear_ratio * p.rotor_inertia;
  Xml x;
  x << "<mujoco model=\"rabbit\">\n"
    << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
    << "  <option timestep=\"" << options.timestep << "\" integrator=\"" << options.integrator
    << "\" gravity=\"0 0 " << -p.gravity << "\" noslip_iterations=\"" << options.noslip_iterations
    << "\">\n"
    << "    <flag energy=\"" << (options.energy ? "enable" : "disable") << "\" contact=\""
    << (options.ground ? "enable" : "disable") << "\"/>\n"
    << "  </option>\n"
    << "  <default>\n"
    << "    <joint damping=\"0\" stiffness=\"0\" armature=\"0\" limited=\"false\"/>\n"
    << "    <geom contype=\"0\" conaffinity=\"0\"/>\n"
    << "  </default>\n"
    << "  <worldbody>\n";
  if (options.ground) {
    x << "    <geom name=\"ground\" type=\"plane\" size=\"0 0 1\" pos=\"0 0 "
      << -options.foot_radius << "\" contype=\"0\" conaffinity=\"1\" friction=\""
      << options.friction << " 0.005 0.0001\"/>\n";
  }
  x << "    <body name=\"trunk\" pos=\"0 0 0\">\n"
    << "      <joint name=\"x\" type=\"slide\" pos=\"0 0 0\" axis=\"1 0 0\"/>\n"
    << "      <joint name=\"y\" type=\"slide\" pos=\"0 0 0\" axis=\"0 0 1\"/>\n"
    << "      <joint name=\"q0\" type=\"hinge\" pos=\"0 0 0\" axis=\"0 1 0\"/>\n"
    << "      <inertial pos=\"0 0 " << p.trunk_com << "\" mass=\"" << p.trunk_mass
    << "\" diaginertia=\"" << p.trunk_inertia << ' ' << p.trunk_inertia << ' ' << p.trunk_inertia
    << "\"/>\n"
    << "      <geom name=\"trunk\" type=\"capsule\" size=\"0.03\" fromto=\"0 0 0 0 0 "
    << p.trunk_length << "\"/>\n";
  for (int leg = 0; leg < kNumLegs; ++leg) WriteLeg(p, options, armature, leg, &x);
  x << "    </body>\n"
    << "  </worldbody>\n"
    << "</mujoco>\n";
  return x.str();
}

ModelPtr LoadRabbitMujocoModel(const ModelParams& params, const MujocoModelOptions& options,
                               std::string* error) {
  std::string message;
  if (!params.IsValid(&message)) {
    if (error) *error = "LoadRabbitMujocoModel: invalid model parameter: " + message;
    return nullptr;
  }
  if (!OptionsValid(options, &message)) {
    if (error) *error = "LoadRabbitMujocoModel: invalid option: " + message;
    return nullptr;
  }
  const std::string xml = MakeRabbitMjcf(params, options);

  // mjVFS holds fixed arrays of about 2 MB: keep it off the stack.
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), kXmlName, static_cast<int>(xml.size())) != 0) {
    if (error) *error = "LoadRabbitMujocoModel: could not create the MuJoCo VFS file";
    return nullptr;
  }
  std::memcpy(vfs->filedata[vfs->nfile - 1], xml.data(), xml.size());

  char buffer[1024] = "";
  ModelPtr model(mj_loadXML(kXmlName, vfs.get(), buffer, sizeof(buffer)));
  mj_deleteVFS(vfs.get());
  if (!model) {
    if (error) {
      *error = std::string("LoadRabbitMujocoModel: mj_loadXML failed: ") + buffer +
               "\n--- generated MJCF ---\n" + xml;
    }
    return nullptr;
  }
  if (model->nq != kNq || model->nv != kNq) {
    if (error) *error = "LoadRabbitMujocoModel: compiled model has nq != 7";
    return nullptr;
  }
  if (error) error->clear();
  return model;
}

void SetMujocoState(const mjModel* m, mjData* d, const Vec7& q, const Vec7& qd) {
  for (int i = 0; i < kNq; ++i) {
    d->qpos[i] = q[i];
    d->qvel[i] = qd[i];
  }
  mju_zero(d->qfrc_applied, m->nv);
  if (m->nu > 0) mju_zero(d->ctrl, m->nu);
}

Vec7 MujocoQ(const mjModel* /*m*/, const mjData* d) { return Eigen::Map<const Vec7>(d->qpos); }

Vec7 MujocoQd(const mjModel* /*m*/, const mjData* d) { return Eigen::Map<const Vec7>(d->qvel); }

Mat7 MujocoMassMatrix(const mjModel* m, const mjData* d) {
  Eigen::Matrix<double, kNq, kNq, Eigen::RowMajor> dense;
  mj_fullM(m, dense.data(), d->qM);
  return dense;
}

Vec7 MujocoBias(const mjModel* /*m*/, const mjData* d) {
  return Eigen::Map<const Vec7>(d->qfrc_bias);
}

}  // namespace mujoco_ref
}  // namespace rabbit
