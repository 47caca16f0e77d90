// Compliant point-foot contact with stick/slide friction (chapter eqs. 2-5).
//
// Each foot is a hybrid system: its mode (air, stick, slide), anchor x_c, surface (the ground or an
// obstacle's top) and ground segment are discrete state that changes only at events located by the
// integrator's root finding; between events the force is a smooth function of the foot's position
// and velocity. Everything is measured in the frame of the straight surface under the foot (the
// ground segment under it, or a flat obstacle top): y is the foot's distance from the surface
// along its unit normal n = (sin a, cos a) (a: the slope, positive descending toward +x), x the
// coordinate along its unit tangent t = (cos a, -sin a), and the force on the foot is
// Ft t + Fn n. On flat ground (a = 0) these are the world's x and y:
//   Fn  = max(0, k_n |y| - lambda_n |y| yd)                  (y <= 0: foot below its surface)
//   Ft1 = -k_t (x - x_c) - lambda_t xd                        (stick; the chapter prints +k_t)
//   Ft2 = -s lambda_g Fn - mu_g xd                            (slide in direction s)
// where x - x_c is the spring's stretch along t from its anchor, the surface point above world
// abscissa anchor_x: (p - A).t = (x_p - anchor_x) / cos a - (y_p - H(x_p)) sin a for a foot at p
// over the surface line y = H(x).
// Events (each guard is positive in the current mode and an event fires when it turns negative):
//   air   -> contact  when y crosses 0 downward (touchdown; anchor x_c = x);
//   contact -> air    when y crosses 0 upward (lift-off);
//   stick -> slide    when |Ft1| reaches mu_s Fn;
//   slide -> stick    when the slip reverses, or when the sticking force the foot would need at its
//                     slip speed, |Ft2 - lambda_t xd| = lambda_g Fn + (mu_g + lambda_t)|xd|, falls
//                     below lambda_g Fn + resume_fraction (mu_s - lambda_g) Fn. The anchor moves to
//                     x + Ft2 / k_t: the spring carries the sliding force, so sticking
//                     resumes without a jump in the spring force, inside the cone by a margin
//                     (1 - resume_fraction)(mu_s - lambda_g) Fn, which keeps the switch from
//                     chattering. A foot landing with some tangential speed starts in slide and
//                     sticks as soon as its normal force can hold it (as the chapter's eq. 3);
//   the foot crosses an obstacle's edge or a breakpoint of the ground profile (its surface or
//                     segment changes; a foot in contact that finds itself above its new surface
//                     goes to the air; a foot that crosses a step below the level beyond it has
//                     hit the step's face: a trip, as at an obstacle's side).
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
  // The sticking spring's anchor (stick mode): the world abscissa of the surface point it is
  // fixed to (on flat ground, x_c itself).
  double anchor_x = 0.0;
  double slide_dir = 0.0;  // +1 or -1, direction of slip along the tangent (slide mode)
  int surface = kGround;   // what the foot stands above (terrain surface index)
  int segment = 0;         // the ground segment under the foot (GroundProfile::SegmentAt)
};

struct FootForce {
  double fn = 0.0;  // normal force on the foot along the surface normal n, N, >= 0
  double ft = 0.0;  // tangential force on the foot along the surface tangent t (toward +x), N
  // The same force in the world frame, ft t + fn n (on flat ground: fx = ft, fy = fn), N.
  double fx = 0.0, fy = 0.0;
};

// Distance of the foot from its current surface along the surface's normal (negative:
// penetration); on flat ground its height above it.
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
// Guard of the foot's ground segment: positive while the foot's x stays inside it (needed only
// when the ground profile has breakpoints: with one segment it would be infinite).
double SegmentGuard(const Terrain& terrain, const FootContactState& state,
                    const Eigen::Vector2d& pos);

// Transitions, applied when the integrator reports that a guard turned negative:
// OnTouchEvent toggles air <-> contact (touchdown anchors the spring at the impact point; a foot
// that lands moving along the surface starts in slide); OnFrictionEvent (SlipGuard or ResumeGuard)
// toggles stick <-> slide.
void OnTouchEvent(const Terrain& terrain, const Eigen::Vector2d& pos, const Eigen::Vector2d& vel,
                  FootContactState* state);
// The same on flat ground (the slip direction from the horizontal velocity).
void OnTouchEvent(const Eigen::Vector2d& pos, const Eigen::Vector2d& vel, FootContactState* state);
void OnFrictionEvent(const ContactParams& params, const Terrain& terrain,
                     const Eigen::Vector2d& pos, const Eigen::Vector2d& vel,
                     FootContactState* state);

// Re-evaluates which surface and ground segment the foot is above after a span or segment guard
// fired. Returns false when the foot entered an obstacle through its side or crossed a step's
// face below the level beyond it (a trip); otherwise
// updates them (a foot in contact that leaves an obstacle's top, or crosses onto a ground segment
// that it is above, goes to the air; a sticking foot crossing a breakpoint keeps its spring's
// stretch, its anchor moved onto the new segment).
bool UpdateFootSurface(const Terrain& terrain, const Eigen::Vector2d& pos, FootContactState* state);

// Mode of a foot at the start of a run, from rest: contact (stick, anchored where it is) when at or
// below its surface, else air.
FootContactState InitialFootState(const Terrain& terrain, const Eigen::Vector2d& pos);

// Energy stored in the contact springs: 0.5 k_n y^2 (y < 0) + 0.5 k_t (x - x_c)^2 (stick), in the
// surface's frame.
// The contact law is passive (it never adds energy) but for one step: when slip stops, the anchor
// rule (no force jump) loads the tangential spring with 0.5 Ft2^2 / k_t at once.
double ContactElasticEnergy(const ContactParams& params, const Terrain& terrain,
                            const FootContactState& state, const Eigen::Vector2d& pos);

}  // namespace rabbit

#endif  // RABBIT_CONTACT_CONTACT_H_
