// Zero-order Takagi-Sugeno fuzzy inference (chapter section 3.2), compiled
// into a flat evaluator: for inputs x, each rule's activation is the product of its antecedents'
// memberships (eq. 9), and the output is the normalised weighted average of the rules' constant
// consequents (eqs. 10-11). Rules are a table over the input sets (every combination, "and").
//
// No rule fires (all activations 0): the output is the output variable's default value (as
// fuzzylite does), and Evaluate reports it.
//
// The evaluator reproduces fuzzylite 6's own inference of the same system (fl::Engine::process
// with an AlgebraicProduct conjunction and a WeightedAverage TakagiSugeno defuzzifier) bit for
// bit, tolerance included: fuzzylite compares with a tolerance kFuzzyEpsilon (its macheps), so
//  - a membership function treats x within 1e-6 of a vertex as at the vertex (a triangle is
//    exactly 1 within 1e-6 of its peak; just below its first vertex it returns (x - a) / (b - a),
//    which is slightly negative, exactly as fuzzylite does);
//  - a rule fires only when its activation u_k >= 1e-6 (fuzzylite triggers a rule only if
//    Op::isGt(u_k, 0)); weaker rules contribute nothing and report activation 0;
//  - the output is sum(u_k c_k) / sum(u_k) over the firing rules, summed in rule order.
// Activations are multiplied in input order; fuzzylite multiplies in the order the rule text names
// the inputs, which is the same number for two inputs and within a few ulps for more.
//
// Loading and saving in fuzzylite's FLL language: rabbit/learn/fll.h.
#ifndef RABBIT_LEARN_TS_FIS_H_
#define RABBIT_LEARN_TS_FIS_H_

#include <string>
#include <vector>

namespace rabbit {

// fuzzylite's comparison tolerance (fl::fuzzylite::macheps(), 1e-6 unless a program changes it).
constexpr double kFuzzyEpsilon = 1e-6;

struct Membership {
  enum class Shape { kTriangle, kTrapezoid, kRampUp, kRampDown, kGaussian };
  Shape shape = Shape::kTriangle;
  // Triangle: a <= b <= c (peak at b). Trapezoid: a <= b <= c <= d. RampUp (a shoulder rising from
  // a to b, 1 beyond): a, b. RampDown (1 before a, falling to 0 at b): a, b. Gaussian: mean a,
  // standard deviation b > 0.
  double a = 0, b = 0, c = 0, d = 0;
  // In [0, 1] (see above for the 1e-6 margins), fuzzylite's definitions, NaN for NaN; RampDown
  // {a, b} is fuzzylite's Ramp with start b and end a. Infinite vertices behave as in fuzzylite
  // (a triangle or trapezoid with a = -inf is 1 left of its peak, with c or d = +inf right of it).
  double Evaluate(double x) const;
  // Parameters finite and ordered: Triangle a <= b <= c, Trapezoid a <= b <= c <= d, ramps a < b,
  // Gaussian b > 0. (Evaluate follows fuzzylite for any parameters.)
  bool IsValid(std::string* error) const;
};

struct FuzzySet {
  std::string name;  // VerySmall, Small, Medium, Big, VeryBig
  Membership membership;
};

struct FuzzyInput {
  std::string name;  // e.g. V_M, d_obs
  double min = 0.0, max = 1.0;
  std::vector<FuzzySet> sets;
  bool lock_range = false;  // clamp the input to [min, max] before fuzzifying (FLL lock-range)
};

struct FuzzyRule {
  std::vector<int> antecedent;  // one set index per input
  int consequent = 0;           // index into TsFis::outputs (the constant terms)
};

struct TsFis {
  std::string name = "ts_fis";  // the FLL engine's name
  std::vector<FuzzyInput> inputs;
  std::string output_name = "gait";
  std::vector<std::string> output_terms;  // e.g. O1..O5: which reference gait a rule selects
  std::vector<double> output_values;      // their constants (the gait index k for the gait pattern)
  double default_value = 0.0;             // output when no rule fires (NaN allowed, as in FLL)
  double output_min = 0.0, output_max = 1.0;  // the output variable's range (FLL)
  bool lock_output_range = false;  // clamp the output (default value too) to it (FLL lock-range)
  std::vector<FuzzyRule> rules;

  // Names are FLL identifiers (letters, digits, '_', '.'; not a rule keyword or hedge), unique per
  // scope; at least one input, set, output term and rule; every rule names an existing set for
  // each input and an existing output term; ranges min <= max; parameters finite.
  bool IsValid(std::string* error) const;

  struct Result {
    double output = 0.0;
    bool fired = false;              // some rule fired (activation >= kFuzzyEpsilon, see above)
    std::vector<double> activation;  // per rule, normalised to sum 1 when fired (eq. 10)
    std::vector<double> membership;  // the inputs' memberships, input by input, set by set
  };
  // x: one value per input (throws std::invalid_argument otherwise). Requires IsValid().
  // Allocation-free when `result` is reused.
  void Evaluate(const std::vector<double>& x, Result* result) const;
};

// The chapter's gait pattern generalised to N_r reference gaits (2 <= N_r <=
// kMaxGaitPatternGaits): inputs V_M (m/s; N_r sets centred on the reference gaits' measured
// velocities, shoulders at both ends) and d_obs (m; five sets over [0, 0.5], VeryBig a shoulder
// from 0.45 m up), and Table 3 generalised (GaitPatternRule) as the rule base.
//
// Shapes, with c1 < ... < cN the reference velocities (throws std::invalid_argument unless
// finite, positive and strictly increasing):
//   V_M   (range [0, max(1.5, 1.5 cN)] m/s): the first set RampDown c1..c2 (1 below c1), set k
//         Triangle c(k-1) ck c(k+1), the last RampUp c(N-1)..cN (1 above cN). Names: the
//         chapter's VerySmall, Small, Medium, Big, VeryBig for N_r = 5, else V1..VN.
//   d_obs (range [0, 1] m): VerySmall RampDown 0..0.15 (1 at contact and below), Small Triangle
//         0 0.15 0.30, Medium Triangle 0.15 0.30 0.45, Big Triangle 0.30 0.45 0.50, VeryBig RampUp
//         0.45..0.50 (1 from 0.5 m on: no obstacle within reach; d_obs = +inf also means none).
// Both inputs are Ruspini partitions (neighbouring sets cross at 0.5 and sum to 1), so for any
// finite inputs some rule fires; neither input is clamped. Output gait: O1..ON = 1..N, range
// [1, N], default NaN (only NaN inputs fire nothing). Rules row by row (d_obs), N_r per row.
constexpr std::size_t kMaxGaitPatternGaits = 64;
// Table 3 generalised: the gait O^k (1-based) of the rule (d_obs set `d_obs_row` 0..4 =
// VerySmall..VeryBig, V_M set `v_m_set` 0..n-1) for n gaits. VeryBig: k = v_m_set + 1 (the gait
// of the velocity); Big: min(k, n - 1); Medium: 1 (the slowest, shortest step); Small: n (the
// longest); VerySmall: n - 1, or n at the top velocity. For n = 5 it is the chapter's Table 3.
int GaitPatternRule(int d_obs_row, int v_m_set, int n);
TsFis DefaultGaitPattern(const std::vector<double>& reference_velocities);

// A comment for the FLL file of DefaultGaitPattern(reference_velocities) (see SaveFll): what the
// system is, its sets and Table 3. Lines without the leading '#'.
std::string DefaultGaitPatternComment(const std::vector<double>& reference_velocities);

}  // namespace rabbit

#endif  // RABBIT_LEARN_TS_FIS_H_
