// A model-based step-to-step speed law for the walker's trunk pitch q0_d
// (docs/design/velocity-control.md, "The step-to-step map"): an alternative to the chapter's
// incremental law (eqs. 19-20) in velocity_control.h, chosen with [controller.velocity_control] law
// = "step_map".
//
// The map, identified from walks (IdentifyStepMap), predicts the next stride speed S[k+1] (the
// walker's V_M at touchdown k+1, the mean of the last two steps) from the current one S[k] and
// the pitch q0_d in force during the step that ended at touchdown k (a pitch set at a touchdown
// shows in the stride one touchdown later: the trunk leans during the step, the speed follows),
// linearised around the equilibrium of a speed band centred on V:
//   S[k+1] - V = a(V) (S[k] - V) + b(V) (q0_d[k-1] - q*(V)) + d,
// a, b and q* interpolated linearly between the bands' centres (constant beyond the ends), d an
// offset the law estimates as it walks (what the map leaves: another gait blend, a payload, a
// slope). At touchdown k, for the command V_c, the map first predicts S[k+1] from the pitch in
// force, e1 = S_pred[k+1] - V_c, and then chooses the pitch q0_d[k] so that the error two strides
// ahead is decay e1 (0: deadbeat, the error removed as soon as the pitch can act):
//   q0_d[k] = q*(V_c) + ((decay - a) e1 - d) / b,
// limited to max_change per step and clamped to the walker's q0_d range. The offset follows the
// error of the one-step prediction made at the previous touchdown: d += offset_gain (S[k] -
// S_pred[k]), |d| <= offset_max.
// Where the range clamps the pitch, the gait pattern is asked for the speed the pitch cannot
// give: the FIS's velocity input moves by fis_gain b / (1 - a) (q0_d[k] - wanted), at most
// fis_max either way (the map's steady gain times the pitch the clamp withheld).
#ifndef RABBIT_CONTROL_STEP_MAP_CONTROL_H_
#define RABBIT_CONTROL_STEP_MAP_CONTROL_H_

#include <string>
#include <vector>

namespace rabbit {

// One speed band of the map: its centre V (m/s), the equilibrium pitch q* (rad), the stride's
// own carry-over a and the pitch's effect b (m/s per rad).
struct StepMapBand {
  double v = 0.0;
  double q_star = 0.0;
  double a = 0.0;
  double b = 0.0;
};

struct StepMapParams {
  // Defaults: identified by bench/identify_step_map on the training walks of
  // scenarios/train/speed.toml (docs/design/velocity-control.md, "The step-to-step map").
  std::vector<StepMapBand> bands = DefaultStepMapBands();
  double decay = 0.6;          // wanted error ratio per step, in [0, 1) (0: deadbeat)
  double offset_gain = 0.3;    // the offset estimate's gain per step, in [0, 1]
  double offset_max = 0.2;     // m/s: the largest offset estimate
  double max_change = 0.0873;  // rad (5 deg): the largest change of q0_d per step
  double fis_gain = 0.0;       // share of the withheld speed asked of the gait pattern, [0, 2]
  double fis_max = 0.2;        // m/s: the largest shift of the FIS's velocity input
  bool IsValid(std::string* error) const;
  static std::vector<StepMapBand> DefaultStepMapBands();
};

// The map's coefficients at speed v (linear between the bands' centres, constant beyond).
StepMapBand StepMapAt(const std::vector<StepMapBand>& bands, double v);

class StepMapControl {
 public:
  explicit StepMapControl(const StepMapParams& params);  // throws std::invalid_argument
  // At a touchdown: the stride speed S (m/s), the command V_c (m/s) for the coming step, the
  // pitch in force during the step that ended (rad) and the walker's range (rad); returns the
  // pitch for the coming step.
  double Update(double s, double v_c, double q0_d, double q0_d_min, double q0_d_max);
  double offset() const { return offset_; }
  // The shift of the FIS's velocity input for the coming step (m/s; 0 unless clamped).
  double fis_offset() const { return fis_offset_; }
  // The stride speed the map predicted for this touchdown (NaN before the first choice).
  double predicted() const { return predicted_; }

 private:
  StepMapParams p_;
  double offset_ = 0.0;
  double fis_offset_ = 0.0;
  double predicted_;
};

// One transition of a walk for the identification: at a touchdown the stride S, the pitch q0_d
// in force during the step that ended there (set at the touchdown before, rad), the command V_c,
// and the stride S_next at the next touchdown.
struct StepMapSample {
  double s = 0.0;
  double q0_d = 0.0;
  double v_c = 0.0;
  double s_next = 0.0;
};

struct StepMapFit {
  std::vector<StepMapBand> bands;
  std::vector<int> samples;  // per band, the samples fitted
  std::vector<double> rms;   // per band, the residual's RMS (m/s)
};

// Least squares of S_next = c + a S + b q0_d, each sample in the band whose centre (ascending)
// is nearest its V_c: per band (c, a, b), or `pooled`, one a and b for all bands and a c per band
// (steadier where a band's pitch varies little). q* = (V (1 - a) - c) / b at the centre. A band
// with fewer than min_samples samples, or whose b is not positive, fails with a message naming
// it.
bool IdentifyStepMap(const std::vector<StepMapSample>& samples, const std::vector<double>& centres,
                     int min_samples, bool pooled, StepMapFit* fit, std::string* error);

}  // namespace rabbit

#endif  // RABBIT_CONTROL_STEP_MAP_CONTROL_H_
