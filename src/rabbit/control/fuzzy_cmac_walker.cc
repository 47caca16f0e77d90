#include "rabbit/control/fuzzy_cmac_walker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "rabbit/control/terrain_command.h"
#include "rabbit/learn/cmac.h"

namespace rabbit {

double ObstacleDistance(const Terrain& terrain, double x, double d_max) {
  return std::min(terrain.DistanceToNextObstacle(x), d_max);
}

FuzzyCmacWalker::FuzzyCmacWalker(const WalkerParams& params, FuzzyCmac gait_pattern,
                                 VelocityProfile velocity, int stance_leg)
    : FuzzyCmacWalker(params,
                      std::make_unique<FuzzyCmacSwingPattern>(std::move(gait_pattern), false),
                      std::move(velocity), stance_leg) {}

FuzzyCmacWalker::FuzzyCmacWalker(const WalkerParams& params,
                                 std::unique_ptr<SwingPattern> gait_pattern,
                                 VelocityProfile velocity, int stance_leg)
    : p_(params),
      pattern_(std::move(gait_pattern)),
      velocity_(std::move(velocity)),
      warmup_(params.warmup, stance_leg),
      recovery_(params.recovery),
      response_(params.recovery),
      watch_(params.planner.enabled ? params.planner.push_dead : 0.0),
      slope_(params.slope),
      stall_(params.stall_recovery),
      terrain_steps_(params.steps),
      warming_up_(params.warmup_steps > 0),
      stance_(stance_leg),
      q0_d_(params.q0_d_initial),
      v_m_(params.v_m_initial),
      speed_(
          params.velocity_control, params.k_p, params.k_v, params.q0_d_min, params.q0_d_max,
          params.q0_d_initial,
          PitchMap(params.velocity_control.pitch_map.empty() ? params.gait_pitches
                                                             : params.velocity_control.pitch_map)),
      choice_(params.rule_gait_choice, params.gait_pitches, params.rule_share,
              params.rule_gait_choice_mixed_below, params.rule_gait_choice_mixed_point,
              params.rule_gait_choice_hold_rate),
      rng_(CmacMix64(params.seed)) {
  std::string error;
  if (!p_.IsValid(&error)) throw std::invalid_argument("walker: " + error);
  if (pattern_ == nullptr) throw std::invalid_argument("walker: no gait pattern");
  if (p_.thigh_frame && !pattern_->Supports(true)) {
    throw std::invalid_argument("walker: the thigh frame needs the reference gaits' trunk pitches");
  }
  if (!p_.thigh_frame && !pattern_->Supports(false)) {
    throw std::invalid_argument("walker: the gait pattern was learnt in the thigh frame");
  }
  if (!p_.rule_share.empty() && (p_.rule_share.size() != pattern_->GaitWeights().size() ||
                                 p_.gait_rules.size() != p_.rule_share.size())) {
    throw std::invalid_argument(
        "walker: rule_share needs one factor and the rules of each of the " +
        std::to_string(pattern_->GaitWeights().size()) + " reference gaits");
  }
  rule_states_.resize(p_.gait_rules.size());
  if (p_.planner.enabled) {
    if (p_.gait_l_steps.size() != pattern_->GaitWeights().size()) {
      throw std::invalid_argument("walker: the step planner needs one L_step per reference gait");
    }
    // The gaits it blends: all, or (planner.tracked_gaits_only) those the walker tracks, whose
    // rule share is below 1/2: the foot lift acts through the tracked references.
    std::vector<double> l_steps;
    for (size_t k = 0; k < p_.gait_l_steps.size(); ++k) {
      const bool ruled = k < p_.rule_share.size() && p_.rule_share[k] >= 0.5;
      if (p_.planner.tracked_gaits_only && ruled) continue;
      planner_gaits_.push_back(k);
      l_steps.push_back(p_.gait_l_steps[k]);
    }
    if (planner_gaits_.size() < 2) {
      throw std::invalid_argument("walker: the step planner needs at least two gaits to blend");
    }
    step_fis_ = StepLengthFis(l_steps);
    planner_bias_ = p_.planner.bias_initial;
  }
}

StepPlan FuzzyCmacWalker::PlanNextStep(const Observation& obs, const StepRecord& step, double front,
                                       double d_obs) {
  const StepPlannerParams& pp = p_.planner;
  // A step that landed behind (a backward step after a push) was no attempt at the plan: it
  // does not feed the bias; nor does a step a push disturbed before an obstacle (push_dead).
  if (planner_target_ >= 0.0 && step.t_step > 0.0 && step.l_step > 0.0 &&
      (pp.over_feedback || !planner_after_over_) && (planner_face_ || !watch_.last_disturbed())) {
    planner_bias_ = std::clamp(planner_bias_ + pp.feedback_gain * (step.l_step - planner_target_),
                               -pp.bias_max, pp.bias_max);
  }
  planner_target_ = -1.0;
  double length = 0.0;
  for (const Obstacle& o : obs.terrain->obstacles) {
    if (o.x_start >= front) {
      length = o.x_end() - o.x_start;
      break;
    }
  }
  // A step's face nearer than any obstacle is planned for as one (terrain_steps.h).
  double face_length = 0.0;
  const double face = terrain_steps_.FaceAhead(*obs.terrain, front, pp.horizon, pp.margin_before,
                                               pp.margin_after, &face_length);
  planner_face_ = face < obs.terrain->DistanceToNextObstacle(front);
  if (planner_face_) length = face_length;
  if (pp.follow_gait && d_obs <= pp.horizon && planner_l_gait_ < 0.0) FreezeGait();
  StepPlannerParams ep = FollowGait(pp, planner_l_gait_ < 0.0 ? NAN : planner_l_gait_);
  if (planner_face_) ep.l_over_min = 0.0;  // a face's step across is the step planner's own
  StepPlan plan = PlanStep(ep, d_obs, length);
  double target = plan.step_length;
  planner_after_over_ = recovery_left_ > 0 || (plan.active && plan.approach_steps == 0);
  if (plan.active && plan.approach_steps == 0) pitch_hold_left_ = pp.hold_pitch_steps;
  if (plan.active) {
    recovery_left_ = plan.approach_steps == 0 ? pp.recovery_steps : 0;
  } else if (recovery_left_ > 0) {
    // The steps after the step over: back to the nominal step through the planner.
    --recovery_left_;
    target = ep.l_nominal;
  } else {
    planner_l_gait_ = -1.0;  // the next obstacle measures the gait afresh
    return plan;
  }
  planner_target_ = target;
  const double base = planner_l_gait_ < 0.0 ? pp.l_nominal : planner_l_db_;
  const double input = base + pp.stretch * (target - ep.l_nominal) - planner_bias_;
  // (Nearest-gait switching rounds them to the strongest gait in its SwingPattern.)
  const std::vector<double> some = StepLengthWeights(step_fis_, input);
  std::vector<double> w(p_.gait_l_steps.size(), 0.0);
  for (size_t i = 0; i < planner_gaits_.size(); ++i) w[planner_gaits_[i]] = some[i];
  pattern_->SetGaitWeights(w);
  return plan;
}

void FuzzyCmacWalker::FreezeGait() {
  // The mean of the last two measured (forward) steps, and the database step of the weights the
  // walker walks with now (Table 3's, before the planner sets any).
  double sum = 0.0;
  int n = 0;
  const std::vector<StepRecord>& steps = meter_.steps();
  for (auto it = steps.rbegin(); it != steps.rend() && n < 2; ++it) {
    if (it->t_step > 0.0 && it->l_step > 0.0) {
      sum += it->l_step;
      ++n;
    }
  }
  if (n == 0) return;  // nothing measured yet: the fixed settings
  const std::vector<double>& w = pattern_->GaitWeights();
  double l_db = 0.0, w_sum = 0.0;
  for (size_t k = 0; k < w.size() && k < p_.gait_l_steps.size(); ++k) {
    l_db += w[k] * p_.gait_l_steps[k];
    w_sum += w[k];
  }
  if (!(w_sum > 0.0)) return;
  planner_l_gait_ = sum / n;
  planner_l_db_ = l_db / w_sum;
  planner_bias_ = 0.0;
}

// Standard normal deviate from splitmix64 and Box-Muller: the same numbers on every platform
// (std::normal_distribution is not specified bit for bit).
double FuzzyCmacWalker::Gaussian() {
  auto uniform = [this] {
    rng_ += 0x9E3779B97F4A7C15ULL;
    return (static_cast<double>(CmacMix64(rng_) >> 11) + 0.5) * 0x1.0p-53;  // in (0, 1)
  };
  const double u1 = uniform(), u2 = uniform();
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

double FuzzyCmacWalker::ObstacleAhead(const Observation& obs, double x) const {
  return obs.terrain != nullptr ? ObstacleDistance(*obs.terrain, x, p_.d_obs_max) : p_.d_obs_max;
}

bool FuzzyCmacWalker::WarmupEnds(const Observation& obs, int taken, double front_x) const {
  // An obstacle close enough that the step planner should plan the approach (step_planner.h,
  // end_warmup_within): the rules do not plan. Asked only where the step count does not decide.
  const auto obstacle_near = [&] {
    const double within = p_.planner.enabled ? p_.planner.end_warmup_within : 0.0;
    return within > 0.0 && obs.terrain != nullptr &&
           obs.terrain->DistanceToNextObstacle(front_x) < within;
  };
  // The push response's rule steps: their number, or the obstacle.
  if (rules_until_ >= 0) return taken >= rules_until_ || obstacle_near();
  // The start's warm-up: its length; early, a step short of the start gait's (a robot the rules
  // slow down) or the obstacle.
  if (taken >= p_.warmup_steps) return true;
  if (taken <= p_.warmup_handover_after) return false;
  return meter_.last_step().l_step < p_.warmup_handover_ratio * p_.warmup_l_step || obstacle_near();
}

void FuzzyCmacWalker::SetContext(double v_m, double d_obs) {
  pattern_->SetContext(choice_.Input(v_m), d_obs);  // no rule firing keeps the previous weights
}

void FuzzyCmacWalker::OnTouchdown(const Observation& obs) {
  const StepRecord& step = meter_.last_step();
  const double v_d = velocity_.At(obs.t);
  // V_M is measured only when the leg's take-off was seen (not the first landing). The gait
  // meter's L_step and V_M are signed: a step that lands behind the stance foot (the push
  // recovery's backward step) has a negative V_M. Such a step is a recovery step, not a step of
  // the gait: it is recorded, but the velocity control and the FIS keep the V_M and q0_d they had
  // (clamping its V_M at 0 instead reads it as a standstill, and the velocity control then leans
  // the trunk forward by several degrees per backward step, into a fall).
  const bool measured = step.t_step > 0.0 && step.l_step > 0.0;
  const Vec2& other_foot = obs.foot_pos[1 - step.leg];
  const Vec2& landing = obs.foot_pos[step.leg];
  // The known change of grade ahead, and whether the ground around the feet is level.
  const GradeView grade = GradeAround(obs.terrain, landing, other_foot, step.l_step);
  const bool level = std::abs(slope_.slope()) < 0.02 && grade.level;  // for the push response
  // With slope.touchdown_heights the other foot's height as it was at its own touchdown.
  Vec2 other_seen = other_foot;
  const StepRecord* other_landing = meter_.LastLanding(1 - step.leg);
  if (p_.slope.touchdown_heights && other_landing != nullptr) other_seen.y() = other_landing->y;
  slope_.OnTouchdown(obs.terrain != nullptr
                         ? terrain_steps_.LevelledLanding(*obs.terrain, landing, other_seen)
                         : landing,
                     other_seen, grade.change);
  if (obs.terrain != nullptr) {
    terrain_steps_.OnTouchdown(*obs.terrain, obs.t, obs.foot_pos[step.leg], other_foot);
  }
  if (measured) {
    measured_.push_back(
        std::max(0.0, step.v_m + (p_.v_m_noise > 0.0 ? p_.v_m_noise * Gaussian() : 0.0)));
    const size_t n = std::min(measured_.size(), static_cast<size_t>(p_.v_m_average_steps));
    double sum = 0.0;
    for (size_t i = measured_.size() - n; i < measured_.size(); ++i) sum += measured_[i];
    v_m_ = sum / static_cast<double>(n);
  }
  // The command the walker acts on (V_d itself unless velocity_control is enabled): the terrain's
  // speed command (slope, obstacle and step approach speeds), rate-limited; a step down of the
  // profile's own V_d is a drop (velocity_control.h).
  const double v_c = speed_.Command(TerrainSpeedCommand(obs.terrain, slope_, p_.planner,
                                                        terrain_steps_, v_d, landing, other_foot),
                                    v_m_, v_d);
  response_.Command(v_c, level);
  watch_.Command(v_c, level);
  choice_.OnCommand(v_c);
  const bool hold_pitch = pitch_hold_left_ > 0;  // planner.hold_pitch_steps after a step over
  if (hold_pitch) --pitch_hold_left_;
  // Below rule_gait_choice_mixed_below the choice takes the gait shift's place while V_c holds
  // (the law then keeps no effort below the floor unless velocity_control.idle_shift_windup).
  const bool choice_shift = choice_.holding() && v_c < p_.rule_gait_choice_mixed_below;
  speed_.SetShiftIdle(choice_shift);
  // Nor at the steps.hold_steps touchdowns from a step's crossing (its V_M is the climb's or the
  // drop's, not the gait's).
  if (measured && !warming_up_ && !hold_pitch && !terrain_steps_.HoldsPitch() &&
      !response_.HoldsPitch()) {
    if (!speed_.started()) {
      // The settled map at the start only on open level ground
      // (velocity_control.settled_start_clear).
      const double clear = p_.velocity_control.settled_start_clear;
      speed_.UseStartMap(clear <= 0.0 ||
                         OpenLevelGround(obs.terrain, std::min(landing.x(), other_foot.x()),
                                         std::max(landing.x(), other_foot.x()) + clear));
    }
    q0_d_ = speed_.Update(v_m_, step.t_step, slope_.OvershootCorrection(v_m_, v_c));
  }
  const double front = obs.foot_pos[step.leg].x();
  double d_obs = ObstacleAhead(obs, front);
  double d_noise = 0.0;
  if (p_.d_obs_noise > 0.0) {
    d_noise = p_.d_obs_noise * Gaussian();
    d_obs = std::clamp(d_obs + d_noise, 0.0, p_.d_obs_max);
  }
  fis_v_ = v_m_ + p_.fis_v_lead * (v_c - v_m_) + slope_.FisVelocityOffset() +
           (choice_shift ? 0.0 : speed_.FisOffset());
  fis_d_obs_ = d_obs;
  SetContext(fis_v_ + response_.FisOffset(), d_obs);
  StepPlan plan;
  if (p_.planner.enabled && obs.terrain != nullptr) {
    // The planner sees beyond d_obs_max (its horizon), with the same perception noise.
    double face_length = 0.0;
    const double ahead = std::min(
        obs.terrain->DistanceToNextObstacle(front),
        terrain_steps_.FaceAhead(*obs.terrain, front, p_.planner.horizon, p_.planner.margin_before,
                                 p_.planner.margin_after, &face_length));
    plan = PlanNextStep(obs, step, front, std::max(0.0, ahead + d_noise));
  }
  planned_ = plan.active || recovery_left_ > 0;
  // The foot lift is armed for the step over (the planner's, when it plans) and the trailing leg.
  lift_armed_ = plan.active ? plan.approach_steps == 0 : d_obs < p_.lift.d_obs;
  lift_trailing_ = false;
  if (obs.terrain != nullptr) {
    const double back = obs.foot_pos[1 - step.leg].x();
    for (const Obstacle& o : obs.terrain->obstacles) {
      if (back < o.x_end() && front > o.x_start) lift_armed_ = lift_trailing_ = true;
    }
    if (terrain_steps_.LiftArmed()) lift_armed_ = true;
  }
  WalkerStep record;
  record.step = step;
  record.v_d = v_d;
  record.v_m_used = v_m_;
  record.d_obs = d_obs;
  record.planned_steps = plan.active ? plan.approach_steps : -1;
  record.planned_l_step = plan.step_length;
  record.q0_d = q0_d_;
  record.weights = pattern_->GaitWeights();
  record.activation = pattern_->RuleActivations();
  record.warmup = warming_up_ && rules_until_ < 0;  // the response's rules: steps of the walk
  steps_.push_back(std::move(record));
}

double FuzzyCmacWalker::LiftHeight(const Terrain& terrain, double foot_x) const {
  double h = -std::numeric_limits<double>::infinity();
  const double trail = p_.planner.enabled ? p_.planner.over_lift_trail : p_.lift.trail;
  const double release = p_.planner.enabled ? p_.planner.over_lift_release : p_.lift.release;
  for (size_t i = 0; i < terrain.obstacles.size(); ++i) {
    const Obstacle& o = terrain.obstacles[i];
    const double a = LiftRamp(p_.lift, o, trail, release, foot_x);
    // Above the ground the obstacle stands on (absolute heights: the hip's y is absolute).
    if (a > 0.0) {
      h = std::max(h, terrain.ObstacleBase(static_cast<int>(i)) +
                          a * (o.height + LiftClearance(p_.lift, o.height, lift_trailing_)));
    }
  }
  return h;
}

void FuzzyCmacWalker::ApplyLift(const Observation& obs, int sw_hip, Eigen::Vector4d* ref) {
  const Vec7& q = obs.q;
  const double l1 = p_.thigh_length, l2 = p_.shin_length;
  Eigen::Vector4d& r = *ref;
  const Eigen::Vector2d& foot = obs.foot_pos[1 - stance_];
  const double h_obstacle = LiftHeight(*obs.terrain, foot.x());
  const double h = std::max(h_obstacle, terrain_steps_.LiftHeight(*obs.terrain, foot.x()));
  lift_raised_ =
      (lift_t_ >= 0.0 && lift_raised_) || h_obstacle > -std::numeric_limits<double>::infinity();
  Eigen::Vector2d delta = Eigen::Vector2d::Zero();
  if (h > -std::numeric_limits<double>::infinity()) {
    // The pattern's foot point relative to the hip (absolute thigh and shin angles).
    const double a_th = r[0] - q[kQ0], a_sh = r[0] + r[1] - q[kQ0];
    double px = l1 * std::sin(a_th) + l2 * std::sin(a_sh);
    const double py = -l1 * std::cos(a_th) - l2 * std::cos(a_sh);
    const double px_pattern = px;
    if (p_.planner.enabled && p_.planner.hold_margin > 0.0) {
      // Hold a foot that is below the next obstacle's top, behind its near edge, back from it.
      for (const Obstacle& o : obs.terrain->obstacles) {
        if (foot.x() < o.x_start) {
          if (foot.y() < o.height) {
            px = std::min(px, o.x_start - p_.planner.hold_margin - q[kX]);
          }
          break;
        }
      }
    }
    if (q[kY] + py < h || px != px_pattern) {
      // Inverse kinematics of the raised point (px, h - y_hip), knee flexed (negative).
      const double y = std::max(h, q[kY] + py) - q[kY];
      const double reach = std::min(std::hypot(px, y), 0.999 * (l1 + l2));
      const double c = std::clamp((reach * reach - l1 * l1 - l2 * l2) / (2 * l1 * l2), -1.0, 1.0);
      const double flex = std::acos(c);
      const double th =
          std::atan2(px, -y) + std::atan2(l2 * std::sin(flex), l1 + l2 * std::cos(flex));
      delta << th + q[kQ0] - r[0], -flex - r[1];
    }
    if (p_.lift.feedback) {
      // The least further knee flexion that puts the foot at h with the measured thigh.
      const double a_m = q[sw_hip] - q[kQ0];
      const double knee = r[1] + delta[1];
      if (q[kY] - l1 * std::cos(a_m) - l2 * std::cos(a_m + knee) < h) {
        const double s0 = std::acos(std::clamp((q[kY] - l1 * std::cos(a_m) - h) / l2, -1.0, 1.0));
        // The shin angle that reaches h: backward (-s0) unless forward is nearer and allowed.
        const double shin =
            (s0 <= a_m && std::abs(s0 - (a_m + knee)) < std::abs(-s0 - (a_m + knee))) ? s0 : -s0;
        delta[1] = std::min(delta[1], std::min(shin - a_m, 0.0) - r[1]);
      }
    }
  }
  // The lift's rate joins the rate references (finite difference over the control period); with
  // lift_release_rate, the lift's pace and the lifted references' own rates (foot_lift.h).
  const double dt = lift_t_ >= 0.0 && obs.t > lift_t_ ? obs.t - lift_t_ : 0.0;
  const bool paced = p_.lift.release_rate > 0.0 && lift_raised_ && dt > 0.0;
  if (paced) delta = LimitLiftRelease(p_.lift, delta, lift_delta_, dt);
  const Eigen::Vector2d lifted = r.head<2>() + delta;
  Eigen::Vector2d rate = Eigen::Vector2d::Zero();
  if (dt > 0.0) rate = (delta - lift_delta_) / dt;
  if (paced && delta.squaredNorm() > 0.0) rate = (lifted - lift_ref_) / dt - r.tail<2>();
  r.head<2>() = lifted;
  r.tail<2>() += rate;
  lift_ref_ = lifted;
  lift_delta_ = delta;
  lift_t_ = obs.t;
}

Eigen::Vector2d FuzzyCmacWalker::RuleTorques(const Observation& obs, double* share) {
  const int st_hip = 3 + 2 * stance_, sw_hip = 3 + 2 * (1 - stance_);
  const Vec7& q = obs.q;
  const Vec7& qd = obs.qd;
  const double qr1 = q[sw_hip] - q[st_hip], qr1_rate = qd[sw_hip] - qd[st_hip];
  const double knee = q[sw_hip + 1], knee_rate = qd[sw_hip + 1];
  const double phase = obs.t - swing_start_;
  const std::vector<double>& w = pattern_->GaitWeights();
  Eigen::Vector2d tau = Eigen::Vector2d::Zero();
  *share = 0.0;
  for (size_t k = 0; k < p_.rule_share.size() && k < w.size(); ++k) {
    // The rule state follows the measured swing for every gait, weighted or not, so that a gait
    // that gains weight mid-swing is in its right phase.
    const PragmaticParams& r = p_.gait_rules[k];
    RuleState& s = rule_states_[k];
    if (!s.hip_locked && qr1 > r.qr1_dsw) s.hip_locked = true;
    if (knee < r.qi2_dsw) s.knee_flexed = true;
    if (!s.knee_locked && ((s.knee_flexed && knee >= r.qi2_dsw) || s.hip_locked)) {
      s.knee_locked = true;
    }
    const double wr = w[k] * p_.rule_share[k];
    if (wr == 0.0) continue;
    *share += wr;
    double hip = 0.0, knee_tau = 0.0;
    if (s.hip_locked) {
      hip = r.hip_kp * (r.qr1_dsw - qr1) - r.hip_kd * qr1_rate;
    } else if (phase > r.pulse_start && phase < r.pulse_start + r.pulse_duration) {
      hip = r.pulse_torque;
    }
    if (s.knee_locked) knee_tau = r.knee_kp * (r.qi2_dsw - knee) - r.knee_kd * knee_rate;
    tau += wr * Eigen::Vector2d(hip, knee_tau);
  }
  return tau;
}

Vec4 FuzzyCmacWalker::Compute(const Observation& obs) {
  if (periods_ == 0) {
    // The first step's context: the assumed V_M and the obstacle ahead of the stance foot.
    SetContext(v_m_, ObstacleAhead(obs, obs.foot_pos[stance_].x()));
  }
  const int swing = 1 - stance_;
  if (meter_.Update(obs) && meter_.last_step().leg == swing &&
      (obs.foot_pos[swing].x() > obs.foot_pos[stance_].x() || recovery_.AcceptsLandingBehind(obs) ||
       response_.Catching())) {
    stance_ = swing;
    swing_start_ = obs.t;
    // The landing knee's angle, when the swing that ends here was lifted (a step over or the
    // trailing leg's step); else none (0).
    stance_knee_landing_ = lift_armed_ ? obs.q[3 + 2 * swing + 1] : 0.0;
    std::fill(rule_states_.begin(), rule_states_.end(), RuleState{});
    const int taken = static_cast<int>(meter_.steps().size());
    if (warming_up_ && WarmupEnds(obs, taken, obs.foot_pos[swing].x())) {
      warming_up_ = false;
      rules_until_ = -1;
    }
    response_.OnTouchdown(obs.t, meter_.last_step().t_step);
    watch_.OnTouchdown(obs.t, meter_.last_step().t_step);
    OnTouchdown(obs);
    recovery_.OnTouchdown(obs.t, meter_.last_step().t_step);
  }
  recovery_.Observe(obs, stance_);
  // The push response (push_response.h), armed in plain walking: the FIS's input, the rules.
  if (response_.Observe(obs.t, recovery_.v_orb(), !warming_up_ && !planned_ && !lift_armed_,
                        obs.qd[kX])) {
    SetContext(fis_v_ + response_.FisOffset(), fis_d_obs_);
  }
  // The approach watch: the walker's own steps, neither the step over nor the steps after it.
  watch_.Observe(obs.t, recovery_.v_orb(),
                 !warming_up_ && !lift_armed_ && recovery_left_ == 0 && pitch_hold_left_ == 0);
  if (!warming_up_ && response_.TakesRules()) {
    warmup_.Restart(swing_start_, stance_);
    warming_up_ = true;
    rules_until_ = static_cast<int>(meter_.steps().size()) + p_.recovery.response_rules_steps;
  }
  stall_.Observe(obs, !warming_up_);
  if (warming_up_) {
    const Vec4 tau = warmup_.Compute(obs);
    // The rules are in charge: their stance leg is the walker's (they exchange support on any
    // landing, so after a scuff the two could differ at the handover).
    stance_ = warmup_.stance_leg();
    if (p_.log_every > 0 && periods_ % p_.log_every == 0) {
      const int sw_hip = 3 + 2 * (1 - stance_);
      tracking_.push_back({obs.t, stance_, obs.q[3 + 2 * stance_], std::nan(""), obs.q[sw_hip],
                           std::nan(""), obs.q[sw_hip + 1], p_.warmup.q0_d, obs.q[kQ0]});
    }
    ++periods_;
    return tau;
  }
  const int st = stance_, sw = 1 - stance_;
  const int st_hip = 3 + 2 * st, sw_hip = 3 + 2 * sw;
  const Vec7& q = obs.q;
  const Vec7& qd = obs.qd;
  const double e = q[st_hip];
  Eigen::Vector4d ref;
  if (p_.thigh_frame) {
    const double frame = slope_.FrameAngle();  // 0 unless the slope adaptation tilts it
    ref = pattern_->QueryThigh(e - q[kQ0] - frame);
    ref[0] += q[kQ0] + frame;  // swing thigh's absolute angle -> the hip joint's angle
    ref[2] += qd[kQ0];
  } else {
    ref = pattern_->Query(e);
  }
  if (lift_armed_ && p_.lift.clearance > 0.0 && obs.terrain != nullptr && !obs.foot_contact[sw]) {
    ApplyLift(obs, sw_hip, &ref);
  } else {
    lift_delta_.setZero();
    lift_t_ = -1.0;
  }
  ref[0] += recovery_.SwingOffset(obs.t) + response_.SwingOffset(obs.t);
  response_.ApplyReach(obs, sw, p_.thigh_length + p_.shin_length, &ref);
  response_.ApplyCatch(obs, sw, p_.thigh_length + p_.shin_length, &ref);
  stall_.Apply(obs, stance_, &ref);
  Vec4 tau;
  double share = 0.0;
  Eigen::Vector2d rules = Eigen::Vector2d::Zero();
  // The foot lift acts through the PD references: while it is armed (the step over and the
  // trailing leg's step) the swing is tracked, whatever the rule share, unless lift_keeps_rules.
  if (!p_.rule_share.empty() && !(lift_armed_ && !p_.lift.keeps_rules) && !stall_.Active(obs.t) &&
      !stall_.Catching(obs, stance_) && !response_.Catching()) {
    rules = RuleTorques(obs, &share);
  }
  tau[2 * sw] = rules[0] + (1.0 - share) * (p_.hip_kp * (ref[0] - q[sw_hip]) +
                                            p_.hip_kd * (ref[2] - qd[sw_hip]));
  tau[2 * sw + 1] = rules[1] + (1.0 - share) * (p_.knee_kp * (ref[1] - q[sw_hip + 1]) +
                                                p_.knee_kd * (ref[3] - qd[sw_hip + 1]));
  double knee_kp = p_.stance_knee_kp, knee_kd = p_.stance_knee_kd;
  if (share > 0.0) {
    const std::vector<double>& w = pattern_->GaitWeights();
    knee_kp *= 1.0 - share;
    knee_kd *= 1.0 - share;
    for (size_t k = 0; k < p_.rule_share.size() && k < w.size(); ++k) {
      knee_kp += w[k] * p_.rule_share[k] * p_.gait_rules[k].knee_kp;
      knee_kd += w[k] * p_.rule_share[k] * p_.gait_rules[k].knee_kd;
    }
  }
  terrain_steps_.Observe(obs.t, q[kX]);
  double knee_ref = stall_.StanceKnee(obs.t) + terrain_steps_.StanceKnee(obs.t);
  if (p_.stance_knee_rate > 0.0 && stance_knee_landing_ < p_.stance_knee_flexed) {
    // A leg that landed flexed: its knee straightens at stance_knee_rate from its landing angle.
    knee_ref =
        std::min(knee_ref, stance_knee_landing_ + p_.stance_knee_rate * (obs.t - swing_start_));
  }
  tau[2 * st + 1] = knee_kp * (knee_ref - q[st_hip + 1]) - knee_kd * qd[st_hip + 1];
  const double q0_d = q0_d_ + recovery_.TrunkOffset(obs.t) + response_.TrunkOffset() +
                      slope_.TrunkOffset() + stall_.TrunkOffset(obs.t) +
                      terrain_steps_.TrunkOffset();
  tau[2 * st] = p_.trunk_kp * (q0_d - q[kQ0]) - p_.trunk_kd * qd[kQ0];
  if (!tau.allFinite()) tau.setZero();  // NaN measurements: no torque (the run reports the fall)
  if (p_.log_every > 0 && periods_ % p_.log_every == 0) {
    tracking_.push_back({obs.t, st, e, ref[0], q[sw_hip], ref[1], q[sw_hip + 1], q0_d_, q[kQ0]});
  }
  ++periods_;
  return tau;
}

}  // namespace rabbit
