#include "rabbit/learn/ts_fis.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace rabbit {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// fuzzylite 6's Op::isEq, isLt, isLE, isGt, isGE with its default macheps (fl/Operation.h).
bool IsEq(double a, double b) {
  return a == b || std::abs(a - b) < kFuzzyEpsilon || (a != a && b != b);
}
bool IsLt(double a, double b) { return !IsEq(a, b) && a < b; }
bool IsGt(double a, double b) { return !IsEq(a, b) && a > b; }
bool IsLE(double a, double b) { return IsEq(a, b) || a < b; }
bool IsGE(double a, double b) { return IsEq(a, b) || a > b; }

// fuzzylite's Op::bound.
double Bound(double x, double min, double max) {
  if (x > max) return max;
  if (x < min) return min;
  return x;
}

// The membership functions of fuzzylite 6 (src/term/*.cpp), with height 1.
double Triangle(double x, double a, double b, double c) {
  if (x != x) return kNaN;
  if (IsLt(x, a) || IsGt(x, c)) return 0.0;
  if (IsEq(x, b)) return 1.0;
  if (IsLt(x, b)) {
    if (a == -kInf) return 1.0;
    return (x - a) / (b - a);
  }
  if (c == kInf) return 1.0;
  return (c - x) / (c - b);
}

double Trapezoid(double x, double a, double b, double c, double d) {
  if (x != x) return kNaN;
  if (IsLt(x, a) || IsGt(x, d)) return 0.0;
  if (IsLt(x, b)) {
    if (a == -kInf) return 1.0;
    const double rising = (x - a) / (b - a);
    if (rising != rising) return 1.0;  // Op::min(1.0, rising)
    return 1.0 < rising ? 1.0 : rising;
  }
  if (IsLE(x, c)) return 1.0;
  if (IsLt(x, d)) {
    if (d == kInf) return 1.0;
    return (d - x) / (d - c);
  }
  if (d == kInf) return 1.0;
  return 0.0;
}

double Ramp(double x, double start, double end) {
  if (x != x) return kNaN;
  if (IsEq(start, end)) return 0.0;
  if (IsLt(start, end)) {
    if (IsLE(x, start)) return 0.0;
    if (IsGE(x, end)) return 1.0;
    return (x - start) / (end - start);
  }
  if (IsGE(x, start)) return 0.0;
  if (IsLE(x, end)) return 1.0;
  return (start - x) / (start - end);
}

double Gaussian(double x, double mean, double standard_deviation) {
  if (x != x) return kNaN;
  return std::exp((-(x - mean) * (x - mean)) / (2.0 * standard_deviation * standard_deviation));
}

bool Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

// The shortest text that reads back as x.
std::string Num(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[64];
  const std::to_chars_result result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

// Words the FLL rule parser reads as keywords or hedges, so they cannot name anything.
bool IsReservedWord(const std::string& name) {
  static const char* const kWords[] = {"if",  "is",  "and",  "or",     "then",     "with",
                                       "not", "any", "very", "seldom", "somewhat", "extremely"};
  for (const char* word : kWords) {
    if (name == word) return true;
  }
  return false;
}

bool IsFllName(const std::string& name) {
  if (name.empty() || IsReservedWord(name)) return false;
  for (char ch : name) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '_' || ch == '.';
    if (!ok) return false;
  }
  return true;
}

bool CheckName(const std::string& what, const std::string& name, std::string* error) {
  if (IsFllName(name)) return true;
  return Fail(error, what + " name '" + name +
                         "' is not an FLL identifier (letters, digits, '_', '.'; not a rule "
                         "keyword or hedge)");
}

}  // namespace

double Membership::Evaluate(double x) const {
  switch (shape) {
    case Shape::kTriangle:
      return Triangle(x, a, b, c);
    case Shape::kTrapezoid:
      return Trapezoid(x, a, b, c, d);
    case Shape::kRampUp:
      return Ramp(x, a, b);
    case Shape::kRampDown:
      return Ramp(x, b, a);
    case Shape::kGaussian:
      return Gaussian(x, a, b);
  }
  return kNaN;
}

bool Membership::IsValid(std::string* error) const {
  const auto finite = [](std::initializer_list<double> values) {
    for (double v : values) {
      if (!std::isfinite(v)) return false;
    }
    return true;
  };
  switch (shape) {
    case Shape::kTriangle:
      if (!finite({a, b, c})) return Fail(error, "triangle vertices must be finite");
      if (!(a <= b && b <= c)) {
        return Fail(error,
                    "triangle needs a <= b <= c, got " + Num(a) + " " + Num(b) + " " + Num(c));
      }
      return true;
    case Shape::kTrapezoid:
      if (!finite({a, b, c, d})) return Fail(error, "trapezoid vertices must be finite");
      if (!(a <= b && b <= c && c <= d)) {
        return Fail(error, "trapezoid needs a <= b <= c <= d, got " + Num(a) + " " + Num(b) + " " +
                               Num(c) + " " + Num(d));
      }
      return true;
    case Shape::kRampUp:
    case Shape::kRampDown:
      if (!finite({a, b})) return Fail(error, "ramp ends must be finite");
      if (!(a < b)) {
        return Fail(error, "ramp needs a < b (a ramp with equal ends is 0 everywhere), got " +
                               Num(a) + " " + Num(b));
      }
      return true;
    case Shape::kGaussian:
      if (!finite({a, b})) return Fail(error, "gaussian mean and deviation must be finite");
      if (!(b > 0)) return Fail(error, "gaussian needs a standard deviation > 0, got " + Num(b));
      return true;
  }
  return Fail(error, "unknown membership shape");
}

bool TsFis::IsValid(std::string* error) const {
  const auto blank = [](char ch) { return std::isspace(static_cast<unsigned char>(ch)) != 0; };
  if (name.find_first_of("#\r\n") != std::string::npos ||
      (!name.empty() && (blank(name.front()) || blank(name.back())))) {
    return Fail(error, "engine name '" + name +
                           "' must not contain '#' or line breaks, nor start "
                           "or end with blanks");
  }
  if (inputs.empty()) return Fail(error, "no inputs");
  if (!CheckName("output", output_name, error)) return false;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const FuzzyInput& input = inputs[i];
    if (!CheckName("input", input.name, error)) return false;
    if (input.name == output_name) {
      return Fail(error, "input '" + input.name + "' has the output's name");
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (inputs[j].name == input.name) return Fail(error, "two inputs named '" + input.name + "'");
    }
    if (!std::isfinite(input.min) || !std::isfinite(input.max) || !(input.min <= input.max)) {
      return Fail(error, "input '" + input.name + "': range needs finite min <= max, got " +
                             Num(input.min) + " " + Num(input.max));
    }
    if (input.sets.empty()) return Fail(error, "input '" + input.name + "' has no sets");
    for (std::size_t s = 0; s < input.sets.size(); ++s) {
      const FuzzySet& set = input.sets[s];
      const std::string where = "input '" + input.name + "' set '" + set.name + "'";
      if (!CheckName(where + ":", set.name, error)) return false;
      for (std::size_t t = 0; t < s; ++t) {
        if (input.sets[t].name == set.name) return Fail(error, where + " defined twice");
      }
      std::string why;
      if (!set.membership.IsValid(&why)) return Fail(error, where + ": " + why);
    }
  }
  if (output_terms.empty()) return Fail(error, "no output terms");
  if (output_terms.size() != output_values.size()) {
    return Fail(error, std::to_string(output_terms.size()) + " output terms but " +
                           std::to_string(output_values.size()) + " output values");
  }
  for (std::size_t k = 0; k < output_terms.size(); ++k) {
    if (!CheckName("output term", output_terms[k], error)) return false;
    for (std::size_t t = 0; t < k; ++t) {
      if (output_terms[t] == output_terms[k]) {
        return Fail(error, "output term '" + output_terms[k] + "' defined twice");
      }
    }
    if (!std::isfinite(output_values[k])) {
      return Fail(error, "output term '" + output_terms[k] + "' has a non-finite value");
    }
  }
  if (std::isinf(default_value)) return Fail(error, "default value is infinite");
  if (!std::isfinite(output_min) || !std::isfinite(output_max) || !(output_min <= output_max)) {
    return Fail(error, "output range needs finite min <= max, got " + Num(output_min) + " " +
                           Num(output_max));
  }
  if (rules.empty()) return Fail(error, "no rules");
  for (std::size_t r = 0; r < rules.size(); ++r) {
    const FuzzyRule& rule = rules[r];
    const std::string where = "rule " + std::to_string(r + 1);
    if (rule.antecedent.size() != inputs.size()) {
      return Fail(error, where + ": " + std::to_string(rule.antecedent.size()) +
                             " antecedents for " + std::to_string(inputs.size()) + " inputs");
    }
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      const int set = rule.antecedent[i];
      if (set < 0 || static_cast<std::size_t>(set) >= inputs[i].sets.size()) {
        return Fail(error,
                    where + ": input '" + inputs[i].name + "' has no set " + std::to_string(set));
      }
    }
    if (rule.consequent < 0 || static_cast<std::size_t>(rule.consequent) >= output_terms.size()) {
      return Fail(error, where + ": no output term " + std::to_string(rule.consequent));
    }
  }
  return true;
}

void TsFis::Evaluate(const std::vector<double>& x, Result* result) const {
  if (x.size() != inputs.size()) {
    throw std::invalid_argument("TsFis::Evaluate: " + std::to_string(x.size()) + " values for " +
                                std::to_string(inputs.size()) + " inputs");
  }
  // Fuzzification: every set of every input, once.
  std::size_t count = 0;
  for (const FuzzyInput& input : inputs) count += input.sets.size();
  result->membership.resize(count);
  std::size_t k = 0;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const FuzzyInput& input = inputs[i];
    const double value = input.lock_range ? Bound(x[i], input.min, input.max) : x[i];
    for (const FuzzySet& set : input.sets) result->membership[k++] = set.membership.Evaluate(value);
  }

  // Activation (eq. 9) and the weighted average (eqs. 10-11), as fuzzylite sums them.
  result->activation.resize(rules.size());
  double sum = 0.0;
  double weights = 0.0;
  for (std::size_t r = 0; r < rules.size(); ++r) {
    const FuzzyRule& rule = rules[r];
    double u = 0.0;
    std::size_t offset = 0;
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      const double mu = result->membership[offset + static_cast<std::size_t>(rule.antecedent[i])];
      u = i == 0 ? mu : u * mu;
      offset += inputs[i].sets.size();
    }
    if (u >= kFuzzyEpsilon) {  // Op::isGt(u, 0.0); false for NaN
      result->activation[r] = u;
      sum += u * output_values[static_cast<std::size_t>(rule.consequent)];
      weights += u;
    } else {
      result->activation[r] = 0.0;
    }
  }

  result->fired = weights > 0.0;
  if (result->fired) {
    result->output = sum / weights;
    for (double& a : result->activation) a /= weights;
  } else {
    result->output = default_value;
  }
  if (lock_output_range) result->output = Bound(result->output, output_min, output_max);
}

namespace {

// The d_obs partition: five sets (the chapter's), whatever N_r.
constexpr int kObstacleSets = 5;
const char* const kSetNames[kObstacleSets] = {"VerySmall", "Small", "Medium", "Big", "VeryBig"};
// d_obs peaks (m): VerySmall is 1 up to the first, VeryBig from the last.
const std::vector<double> kObstaclePeaks = {0.0, 0.15, 0.30, 0.45, 0.50};
enum ObstacleRow { kVerySmall = 0, kSmall, kMedium, kBig, kVeryBig };

// Sets peaking at p[0..n-1] (n >= 2): a falling shoulder, n - 2 triangles, a rising shoulder.
std::vector<FuzzySet> RuspiniSets(const std::vector<double>& p,
                                  const std::vector<std::string>& names) {
  const int n = static_cast<int>(p.size());
  std::vector<FuzzySet> sets(n);
  for (int s = 0; s < n; ++s) {
    sets[s].name = names[s];
    Membership& m = sets[s].membership;
    if (s == 0) {
      m.shape = Membership::Shape::kRampDown;
      m.a = p[0];
      m.b = p[1];
    } else if (s == n - 1) {
      m.shape = Membership::Shape::kRampUp;
      m.a = p[s - 1];
      m.b = p[s];
    } else {
      m.shape = Membership::Shape::kTriangle;
      m.a = p[s - 1];
      m.b = p[s];
      m.c = p[s + 1];
    }
  }
  return sets;
}

void CheckReferenceVelocities(const std::vector<double>& v) {
  bool ok = v.size() >= 2 && v.size() <= kMaxGaitPatternGaits;
  for (std::size_t i = 0; ok && i < v.size(); ++i) {
    ok = std::isfinite(v[i]) && v[i] > 0 && (i == 0 || v[i] > v[i - 1]);
  }
  if (!ok) {
    throw std::invalid_argument("DefaultGaitPattern: needs 2 to " +
                                std::to_string(kMaxGaitPatternGaits) +
                                " finite, positive, strictly increasing reference velocities");
  }
}

double VelocityRangeMax(const std::vector<double>& v) { return std::max(1.5, 1.5 * v.back()); }

// The V_M sets' names: the chapter's five for N_r = 5, else V1..VN.
std::vector<std::string> VelocitySetNames(int n) {
  std::vector<std::string> names;
  for (int k = 0; k < n; ++k)
    names.push_back(n == kObstacleSets ? kSetNames[k] : "V" + std::to_string(k + 1));
  return names;
}

}  // namespace

int GaitPatternRule(int d_obs_row, int v_m_set, int n) {
  const int k = v_m_set + 1;  // the gait of this velocity: O^k
  switch (d_obs_row) {
    case kVerySmall:
      return k < n ? n - 1 : n;
    case kSmall:
      return n;
    case kMedium:
      return 1;
    case kBig:
      return std::min(k, n - 1);
    default:
      return k;
  }
}

TsFis DefaultGaitPattern(const std::vector<double>& reference_velocities) {
  CheckReferenceVelocities(reference_velocities);
  const int n = static_cast<int>(reference_velocities.size());
  TsFis fis;
  fis.name = "gait_pattern";

  FuzzyInput v_m;
  v_m.name = "V_M";
  v_m.min = 0.0;
  v_m.max = VelocityRangeMax(reference_velocities);
  v_m.sets = RuspiniSets(reference_velocities, VelocitySetNames(n));
  FuzzyInput d_obs;
  d_obs.name = "d_obs";
  d_obs.min = 0.0;
  d_obs.max = 1.0;
  d_obs.sets =
      RuspiniSets(kObstaclePeaks, std::vector<std::string>(kSetNames, kSetNames + kObstacleSets));
  fis.inputs = {v_m, d_obs};

  fis.output_name = "gait";
  for (int k = 1; k <= n; ++k) {
    fis.output_terms.push_back("O" + std::to_string(k));
    fis.output_values.push_back(static_cast<double>(k));
  }
  fis.default_value = kNaN;
  fis.output_min = 1.0;
  fis.output_max = n;

  for (int row = 0; row < kObstacleSets; ++row) {
    for (int column = 0; column < n; ++column) {
      FuzzyRule rule;
      rule.antecedent = {column, row};  // {V_M set, d_obs set}
      rule.consequent = GaitPatternRule(row, column, n) - 1;
      fis.rules.push_back(rule);
    }
  }
  return fis;
}

std::string DefaultGaitPatternComment(const std::vector<double>& reference_velocities) {
  CheckReferenceVelocities(reference_velocities);
  const std::vector<double>& c = reference_velocities;
  const int n = static_cast<int>(c.size());
  const std::vector<std::string> v_names = VelocitySetNames(n);
  std::ostringstream out;
  out << "The gait pattern (chapter section 5.1): a zero-order Takagi-Sugeno\n"
         "fuzzy system choosing among the N_r = "
      << n
      << " reference gaits from the measured average velocity\n"
         "V_M (m/s) and the distance d_obs (m) between the swing foot and the next obstacle.\n"
         "Rule activation = product of memberships (eq. 9); the output is the weighted average of\n"
         "the gait indices (eqs. 10-11), and the Fuzzy-CMAC blends the reference gaits' CMACs\n"
         "with the same normalised activations (eq. 13).\n"
         "\n"
         "Written by `rabbit fis generate` (rabbit::DefaultGaitPattern, "
         "src/rabbit/learn/ts_fis.h)\n"
         "from the measured_v_m column of the gait database's index.csv, in m/s:\n";
  for (size_t i = 0; i < c.size(); ++i) out << (i == 0 ? "" : " ") << Num(c[i]);
  out << ".\n"
         "It may be edited: rabbit reads any zero-order Takagi-Sugeno system of this form.\n"
         "\n"
         "V_M: "
      << v_names.front()
      << " is 1 below the slowest gait's velocity and falls to 0 at the next one;\n"
         "each middle set is a triangle peaking at its gait's velocity with feet at the\n"
         "neighbouring gaits' velocities; "
      << v_names.back()
      << " rises from the next-to-last velocity and stays 1\n"
         "above the fastest gait's.\n"
         "d_obs: VerySmall 1 at 0 m (and below) falling to 0 at 0.15 m; Small, Medium, Big\n"
         "triangles peaking at 0.15, 0.30, 0.45 m; VeryBig rising from 0.45 m to 1 at 0.5 m: from\n"
         "0.5 m on (and for d_obs = inf) there is no obstacle and only V_M matters. Neighbouring\n"
         "sets cross at 0.5 and sum to 1, so finite inputs always fire some rule; the default\n"
         "(nan) is returned only for NaN inputs. Inputs are not clamped to their ranges.\n"
         "FLL's Ramp is 'Ramp start end': 0 at start, 1 at end (falling when start > end).\n"
         "\n"
         "Rules: the chapter's Table 3 generalised to N_r gaits (identical for N_r = 5); rows\n"
         "d_obs, columns V_M, cell k = use gait O^k:\n"
         "  d_obs \\ V_M ";
  for (const std::string& name : v_names) out << ' ' << name;
  out << '\n';
  for (int row = 0; row < kObstacleSets; ++row) {
    std::string label = kSetNames[row];
    label.resize(13, ' ');
    out << "  " << label;
    for (int column = 0; column < n; ++column) out << " O" << GaitPatternRule(row, column, n);
    out << '\n';
  }
  out << "Obstacle far (VeryBig): the gait of the velocity. Big: the same, but never the fastest.\n"
         "Medium: the slowest (shortest) gait, to land just before the obstacle. Small: the\n"
         "fastest (longest), to step over it; VerySmall: the next-to-fastest (the fastest at the\n"
         "top velocity).";
  return out.str();
}

}  // namespace rabbit
