// Compliant point-foot contact with stick/slide friction (chapter eqs. 2-5, DESIGN.md section 1).
//
// Each foot is a hybrid system: its mode (air, stick, slide), anchor x_c and surface are discrete
// state that changes only at events located by the integrator's root finding; between events the
// force is a smooth function of the foot's position and velocity:
//   Fn  = max(0, k_n |y| - lambda_n |y| yd)                  (y <= 0: foot below its surface)
//   Ft1 = -k_t (x - x_c) - lambda_t xd                        (stick; the chapter prints +k_t)
//   Ft2 = -s lambda_g Fn - mu_g xd                            (slide in direction s)
// Events (each guard is positive in the current mode and an event fires when it turns negative):
//   air   -> contact  when y crosses 0 downward (touchdown; anchor x_c = x);
//   contact -> air    when y crosses 0 upward (lift-off);
//   stick -> slide    when |Ft1| reaches mu_s Fn;
//   slide -> stick    when the slip reverses, or when the sticking force the foot would need at its
//                     slip speed, |Ft2 - lambda_t xd| = lambda_g Fn + (mu_g + lambda_t)|xd|, falls
//                     below lambda_g Fn + resume_fraction (mu_s - lambda_g) Fn. The anchor moves to
//                     x + Ft2 / k_t (DESIGN.md): the spring carries the sliding force, so sticking
//                     resumes without a jump in the spring force, inside the cone by a margin
//                     (1 - resume_fraction)(mu_s - lambda_g) Fn, which keeps the switch from
//                     chattering. A foot landing with some tangential speed starts in slide and
//                     sticks as soon as its normal force can hold it (as the chapter's eq. 3).
#ifndef RABBIT_CONTACT_CONTACT_H_
#define RABBIT_CONTACT_CONTACT_H_

#include <Eigen/Core>
#include <string>

#include "rabbit/contact/terrain.h"

namespace rabbit {

struct ContactParams {
  double k_n = 1e5;       // normal stiffness, N/m
  double lambda_n = 1e6;  // normal damping, N s/m^2 (multiplies |y| yd)
  double k_t = 1e5;       // tangential stiffness, N/m
  double lambda_t = 2e3;  // tangential damping, N s/m
  double mu_s = 0.8;      // static friction coefficient
  double lambda_g = 0.6;  // dynamic (Coulomb) friction coefficient
  double mu_g = 20.0;     // viscous friction while sliding, N s/m
  // Where in the hysteresis band [lambda_g Fn, mu_s Fn] a slipping foot sticks again (0..1).
  double resume_fraction = 0.5;
  bool IsValid(std::string* error) const;
};

enum class ContactMode { kAir = 0, kStick = 1, kSlide = 2 };
const char* ContactModeName(ContactMode mode);

struct FootContactState {
  ContactMode mode = ContactMode::kAir;
  double anchor_x = 0.0;   // x_c, the sticking spring's anchor (stick mode)
  double slide_dir = 0.0;  // +1 or -1, direction of slip (slide mode)
  int surface = kGround;   // what the foot stands above (terrain surface index)
};

struct FootForce {
  double fn = 0.0;  // normal (vertical) force on the foot, N, >= 0
  double ft = 0.0;  // tangential (horizontal) force on the foot, N
};

// Height of the foot above its current surface (negative: penetration).
double FootHeight(const Terrain& terrain, const FootContactState& state,
                  const Eigen::Vector2d& pos);

// Contact force on a foot at position pos, velocity vel, in the given discrete state.
FootForce ComputeFootForce(const ContactParams& params, const Terrain& terrain,
                           const FootContactState& state, const Eigen::Vector2d& pos,
                           const Eigen::Vector2d& vel);

// Guards for root finding, positive while the current mode holds (see file comment):
// TouchGuard for air <-> contact; SlipGuard for stick -> slide and for a slip that reverses;
// ResumeGuard for a slip slow enough to stick again (1 outside slide).
double TouchGuard(const Terrain& terrain, const FootContactState& state,
                  const Eigen::Vector2d& pos);
double SlipGuard(const ContactParams& params, const Terrain& terrain, const FootContactState& state,
                 const Eigen::Vector2d& pos, const Eigen::Vector2d& vel);
double ResumeGuard(const ContactParams& params, const Terrain& terrain,
                   const FootContactState& state, const Eigen::Vector2d& pos,
                   const Eigen::Vector2d& vel);
// Guard of obstacle j's span [x_start, x_end]: positive while the foot stays on its side of it.
double SpanGuard(const Terrain& terrain, const FootContactState& state, const Eigen::Vector2d& pos,
                 int obstacle);

// Transitions, applied when the integrator reports that a guard turned negative:
// OnTouchEvent toggles air <-> contact (touchdown anchors the spring at the impact point; a foot
// that lands moving starts in slide); OnFrictionEvent (SlipGuard or ResumeGuard) toggles
// stick <-> slide.
void OnTouchEvent(const Eigen::Vector2d& pos, const Eigen::Vector2d& vel, FootContactState* state);
void OnFrictionEvent(const ContactParams& params, const Terrain& terrain,
                     const Eigen::Vector2d& pos, const Eigen::Vector2d& vel,
                     FootContactState* state);

// Re-evaluates which surface the foot is above after a span guard fired. Returns false when the
// foot entered an obstacle through its side (a trip); otherwise updates the surface (a foot in
// contact that leaves an obstacle's top goes to the air).
bool UpdateFootSurface(const Terrain& terrain, const Eigen::Vector2d& pos, FootContactState* state);

// Mode of a foot at the start of a run, from rest: contact (stick, anchored where it is) when at or
// below its surface, else air.
FootContactState InitialFootState(const Terrain& terrain, const Eigen::Vector2d& pos);

// Energy stored in the contact springs: 0.5 k_n y^2 (y < 0) + 0.5 k_t (x - x_c)^2 (stick).
// The contact law is passive (it never adds energy) but for one step: when slip stops, the anchor
// rule of DESIGN.md (no force jump) loads the tangential spring with 0.5 Ft2^2 / k_t at once.
double ContactElasticEnergy(const ContactParams& params, const Terrain& terrain,
                            const FootContactState& state, const Eigen::Vector2d& pos);

}  // namespace rabbit

#endif  // RABBIT_CONTACT_CONTACT_H_
