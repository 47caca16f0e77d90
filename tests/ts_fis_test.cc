// The TS-FIS evaluator: membership functions at hand-computed points and against fuzzylite's own
// terms (tolerance edges, degenerate and infinite vertices), validation, inference (one rule, no
// rule, weak rules, clamping), no allocation on reuse, the default gait pattern's Table 3, and
// agreement with fuzzylite's engine on the same system at 10,000 seeded random inputs.
#include "rabbit/learn/ts_fis.h"

#include <fl/Headers.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <memory>
#include <new>
#include <random>
#include <vector>

#include "rabbit/learn/fll.h"

// Counts heap allocations while g_count_allocations is set (for the allocation-free check).
namespace {
bool g_count_allocations = false;
long g_allocations = 0;
}  // namespace

// (GCC cannot see that these replace the global pair, hence the pragma.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  if (g_count_allocations) ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace rabbit {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The measured velocities of gaits/reference/index.csv (fll_test reads the file itself).
const std::vector<double> kVelocities = {0.389872, 0.491471, 0.584546, 0.694662, 0.806568};

Membership Make(Membership::Shape shape, double a, double b, double c = 0, double d = 0) {
  Membership m;
  m.shape = shape;
  m.a = a;
  m.b = b;
  m.c = c;
  m.d = d;
  return m;
}
using Shape = Membership::Shape;

// Same value, bit for bit (NaN equals NaN).
bool Same(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::memcmp(&a, &b, sizeof a) == 0;
}

std::unique_ptr<fl::Term> FuzzyliteTerm(const Membership& m) {
  switch (m.shape) {
    case Shape::kTriangle:
      return std::make_unique<fl::Triangle>("t", m.a, m.b, m.c);
    case Shape::kTrapezoid:
      return std::make_unique<fl::Trapezoid>("t", m.a, m.b, m.c, m.d);
    case Shape::kRampUp:
      return std::make_unique<fl::Ramp>("t", m.a, m.b);
    case Shape::kRampDown:
      return std::make_unique<fl::Ramp>("t", m.b, m.a);
    case Shape::kGaussian:
      return std::make_unique<fl::Gaussian>("t", m.a, m.b);
  }
  return nullptr;
}

TEST(MembershipTest, FuzzyliteToleranceIsOurs) {
  EXPECT_EQ(fl::fuzzylite::macheps(), kFuzzyEpsilon);
}

TEST(MembershipTest, TriangleAtHandComputedPoints) {
  const Membership m = Make(Shape::kTriangle, 0, 1, 2);
  EXPECT_EQ(m.Evaluate(0.5), 0.5);
  EXPECT_EQ(m.Evaluate(0.25), 0.25);
  EXPECT_EQ(m.Evaluate(1.0), 1.0);
  EXPECT_EQ(m.Evaluate(1.5), 0.5);
  EXPECT_EQ(m.Evaluate(0.0), 0.0);
  EXPECT_EQ(m.Evaluate(2.0), 0.0);
  EXPECT_EQ(m.Evaluate(-1.0), 0.0);
  EXPECT_EQ(m.Evaluate(3.0), 0.0);
  EXPECT_EQ(m.Evaluate(kInf), 0.0);
  EXPECT_EQ(m.Evaluate(-kInf), 0.0);
  EXPECT_TRUE(std::isnan(m.Evaluate(kNaN)));
  // fuzzylite's tolerance: within 1e-6 of the peak is the peak; just below the first vertex
  // (within 1e-6) is on the rising edge, hence slightly negative.
  EXPECT_EQ(m.Evaluate(1.0 + 5e-7), 1.0);
  EXPECT_EQ(m.Evaluate(1.0 - 5e-7), 1.0);
  EXPECT_EQ(m.Evaluate(1.0 - 2e-6), 1.0 - 2e-6);
  EXPECT_EQ(m.Evaluate(-5e-7), -5e-7);
  EXPECT_EQ(m.Evaluate(-2e-6), 0.0);
  EXPECT_EQ(m.Evaluate(2.0 + 5e-7), (2.0 - (2.0 + 5e-7)) / 1.0);
}

TEST(MembershipTest, DegenerateAndInfiniteTriangles) {
  const Membership left_right_angle = Make(Shape::kTriangle, 1, 1, 2);
  EXPECT_EQ(left_right_angle.Evaluate(1.0), 1.0);
  EXPECT_EQ(left_right_angle.Evaluate(1.5), 0.5);
  EXPECT_EQ(left_right_angle.Evaluate(0.9), 0.0);
  const Membership spike = Make(Shape::kTriangle, 1, 1, 1);
  EXPECT_EQ(spike.Evaluate(1.0), 1.0);
  EXPECT_EQ(spike.Evaluate(1.0 + 5e-7), 1.0);
  EXPECT_EQ(spike.Evaluate(1.1), 0.0);
  const Membership left_open = Make(Shape::kTriangle, -kInf, 0, 1);
  EXPECT_EQ(left_open.Evaluate(-1e300), 1.0);
  EXPECT_EQ(left_open.Evaluate(0.5), 0.5);
  const Membership right_open = Make(Shape::kTriangle, 0, 1, kInf);
  EXPECT_EQ(right_open.Evaluate(1e300), 1.0);
  EXPECT_EQ(right_open.Evaluate(0.5), 0.5);
}

TEST(MembershipTest, TrapezoidAtHandComputedPoints) {
  const Membership m = Make(Shape::kTrapezoid, 0, 1, 2, 4);
  EXPECT_EQ(m.Evaluate(0.5), 0.5);
  EXPECT_EQ(m.Evaluate(1.0), 1.0);
  EXPECT_EQ(m.Evaluate(1.5), 1.0);
  EXPECT_EQ(m.Evaluate(2.0), 1.0);
  EXPECT_EQ(m.Evaluate(3.0), 0.5);
  EXPECT_EQ(m.Evaluate(4.0), 0.0);
  EXPECT_EQ(m.Evaluate(4.0 - 5e-7), 0.0);  // within the tolerance of d
  EXPECT_EQ(m.Evaluate(5.0), 0.0);
  EXPECT_EQ(m.Evaluate(-1.0), 0.0);
  EXPECT_TRUE(std::isnan(m.Evaluate(kNaN)));
  const Membership shoulder = Make(Shape::kTrapezoid, -kInf, -kInf, 1, 2);
  EXPECT_EQ(shoulder.Evaluate(-1e9), 1.0);
  EXPECT_EQ(shoulder.Evaluate(1.5), 0.5);
  const Membership open_right = Make(Shape::kTrapezoid, 0, 1, 2, kInf);
  EXPECT_EQ(open_right.Evaluate(1e9), 1.0);
  EXPECT_EQ(open_right.Evaluate(kInf), 1.0);
  const Membership step = Make(Shape::kTrapezoid, 0, 0, 1, 2);
  EXPECT_EQ(step.Evaluate(0.0), 1.0);
}

TEST(MembershipTest, RampsAndGaussianAtHandComputedPoints) {
  const Membership up = Make(Shape::kRampUp, 0, 2);
  EXPECT_EQ(up.Evaluate(0.5), 0.25);
  EXPECT_EQ(up.Evaluate(0.0), 0.0);
  EXPECT_EQ(up.Evaluate(2.0), 1.0);
  EXPECT_EQ(up.Evaluate(3.0), 1.0);
  EXPECT_EQ(up.Evaluate(-1.0), 0.0);
  EXPECT_EQ(up.Evaluate(kInf), 1.0);
  const Membership down = Make(Shape::kRampDown, 0, 2);  // fuzzylite: Ramp 2 0
  EXPECT_EQ(down.Evaluate(0.5), 0.75);
  EXPECT_EQ(down.Evaluate(-1.0), 1.0);
  EXPECT_EQ(down.Evaluate(0.0), 1.0);
  EXPECT_EQ(down.Evaluate(2.0), 0.0);
  EXPECT_EQ(down.Evaluate(3.0), 0.0);
  EXPECT_EQ(Make(Shape::kRampUp, 1, 1).Evaluate(1.0), 0.0);  // equal ends: 0 everywhere
  EXPECT_EQ(Make(Shape::kRampUp, 1, 1).Evaluate(5.0), 0.0);
  const Membership g = Make(Shape::kGaussian, 1, 0.5);
  EXPECT_EQ(g.Evaluate(1.0), 1.0);
  EXPECT_DOUBLE_EQ(g.Evaluate(1.5), std::exp(-0.5));
  EXPECT_DOUBLE_EQ(g.Evaluate(0.0), std::exp(-2.0));
  EXPECT_EQ(g.Evaluate(kInf), 0.0);
  EXPECT_TRUE(std::isnan(g.Evaluate(kNaN)));
}

// Every shape, including degenerate and infinite vertices, against fuzzylite's terms bit for bit,
// at the vertices, around them at the tolerance's edges, far away and at random.
TEST(MembershipTest, MatchesFuzzyliteTermsBitForBit) {
  const std::vector<Membership> shapes = {
      Make(Shape::kTriangle, 0, 1, 2),
      Make(Shape::kTriangle, 0.389872, 0.491471, 0.584546),
      Make(Shape::kTriangle, 1, 1, 2),
      Make(Shape::kTriangle, 0, 2, 2),
      Make(Shape::kTriangle, 1, 1, 1),
      Make(Shape::kTriangle, 0, 5e-7, 1),
      Make(Shape::kTriangle, -kInf, 0, 1),
      Make(Shape::kTriangle, 0, 1, kInf),
      Make(Shape::kTriangle, -kInf, 0, kInf),
      Make(Shape::kTrapezoid, 0, 1, 2, 4),
      Make(Shape::kTrapezoid, 0, 0, 1, 2),
      Make(Shape::kTrapezoid, 0, 1, 2, 2),
      Make(Shape::kTrapezoid, 1, 1, 1, 1),
      Make(Shape::kTrapezoid, -kInf, -kInf, 1, 2),
      Make(Shape::kTrapezoid, 0, 1, kInf, kInf),
      Make(Shape::kTrapezoid, 0, 1, 2, kInf),
      Make(Shape::kRampUp, 0, 2),
      Make(Shape::kRampUp, 0.45, 0.5),
      Make(Shape::kRampUp, 1, 1),
      Make(Shape::kRampUp, 1, 1 + 5e-7),
      Make(Shape::kRampDown, 0, 0.15),
      Make(Shape::kRampDown, 0.389872, 0.491471),
      Make(Shape::kRampUp, -kInf, 0),
      Make(Shape::kRampDown, 0, kInf),
      Make(Shape::kGaussian, 1, 0.5),
      Make(Shape::kGaussian, -0.3, 1e-3),
      Make(Shape::kGaussian, 0, kInf),
  };
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> uniform(-3.0, 5.0);
  int compared = 0;
  for (const Membership& m : shapes) {
    const std::unique_ptr<fl::Term> reference = FuzzyliteTerm(m);
    std::vector<double> xs = {kNaN, kInf, -kInf, 0.0, -0.0, 1e300, -1e300};
    for (double v : {m.a, m.b, m.c, m.d}) {
      for (double dx : {0.0, 1e-12, 5e-7, 9.999e-7, 1e-6, 1.0001e-6, 2e-6, 1e-3, 0.1}) {
        xs.push_back(v + dx);
        xs.push_back(v - dx);
      }
    }
    for (int i = 0; i < 1000; ++i) xs.push_back(uniform(rng));
    for (double x : xs) {
      const double ours = m.Evaluate(x);
      const double theirs = reference->membership(x);
      EXPECT_TRUE(Same(ours, theirs)) << reference->toString() << " at x = " << x << ": ours "
                                      << ours << ", fuzzylite " << theirs;
      ++compared;
    }
  }
  EXPECT_GT(compared, 25000);
}

TEST(MembershipTest, Validity) {
  std::string error;
  EXPECT_TRUE(Make(Shape::kTriangle, 0, 1, 2).IsValid(&error));
  EXPECT_TRUE(Make(Shape::kTriangle, 1, 1, 1).IsValid(&error));
  EXPECT_TRUE(Make(Shape::kTrapezoid, 0, 0, 1, 1).IsValid(&error));
  EXPECT_TRUE(Make(Shape::kRampDown, 0, 0.15).IsValid(&error));
  EXPECT_TRUE(Make(Shape::kGaussian, 0, 0.1).IsValid(&error));
  EXPECT_FALSE(Make(Shape::kTriangle, 0, 3, 2).IsValid(&error));
  EXPECT_NE(error.find("a <= b <= c"), std::string::npos) << error;
  EXPECT_FALSE(Make(Shape::kTriangle, -kInf, 0, 1).IsValid(&error));
  EXPECT_NE(error.find("finite"), std::string::npos) << error;
  EXPECT_FALSE(Make(Shape::kTriangle, kNaN, 0, 1).IsValid(&error));
  EXPECT_FALSE(Make(Shape::kTrapezoid, 0, 2, 1, 3).IsValid(&error));
  EXPECT_FALSE(Make(Shape::kRampUp, 1, 1).IsValid(&error));
  EXPECT_FALSE(Make(Shape::kRampDown, 1, 0).IsValid(&error));
  EXPECT_FALSE(Make(Shape::kGaussian, 0, 0).IsValid(&error));
  EXPECT_FALSE(Make(Shape::kGaussian, 0, -1).IsValid(&error));
  EXPECT_FALSE(Make(Shape::kGaussian, 0, kInf).IsValid(&error));
}

// One input, two shoulders crossing at 0.5; O_lo = 10, O_hi = 20.
TsFis TwoRuleFis() {
  TsFis fis;
  FuzzyInput x;
  x.name = "x";
  x.min = 0;
  x.max = 1;
  x.sets = {{"lo", Make(Shape::kRampDown, 0, 1)}, {"hi", Make(Shape::kRampUp, 0, 1)}};
  fis.inputs = {x};
  fis.output_name = "y";
  fis.output_terms = {"lo", "hi"};
  fis.output_values = {10, 20};
  fis.default_value = 7;
  fis.output_min = 0;
  fis.output_max = 30;
  fis.rules = {{{0}, 0}, {{1}, 1}};
  return fis;
}

TEST(TsFisTest, Validity) {
  std::string error;
  ASSERT_TRUE(TwoRuleFis().IsValid(&error)) << error;
  const auto invalid = [](void (*edit)(TsFis*), const std::string& expected) {
    TsFis fis = TwoRuleFis();
    edit(&fis);
    std::string why;
    EXPECT_FALSE(fis.IsValid(&why)) << expected;
    EXPECT_NE(why.find(expected), std::string::npos)
        << "'" << why << "' lacks '" << expected << "'";
  };
  invalid([](TsFis* f) { f->rules[1].antecedent = {2}; }, "has no set 2");
  invalid([](TsFis* f) { f->rules[1].antecedent = {-1}; }, "has no set -1");
  invalid([](TsFis* f) { f->rules[1].antecedent = {0, 1}; }, "2 antecedents for 1 inputs");
  invalid([](TsFis* f) { f->rules[0].consequent = 2; }, "no output term 2");
  invalid([](TsFis* f) { f->rules.clear(); }, "no rules");
  invalid([](TsFis* f) { f->inputs.clear(); }, "no inputs");
  invalid([](TsFis* f) { f->inputs[0].sets[1].membership.b = kInf; }, "finite");
  invalid([](TsFis* f) { f->inputs[0].sets[1].membership.a = kNaN; }, "finite");
  invalid([](TsFis* f) { f->inputs[0].max = kInf; }, "range");
  invalid([](TsFis* f) { f->inputs[0].min = 2; }, "range");
  invalid([](TsFis* f) { f->inputs[0].sets[1].name = "lo"; }, "defined twice");
  invalid([](TsFis* f) { f->inputs[0].sets[1].name = "very"; }, "not an FLL identifier");
  invalid([](TsFis* f) { f->inputs[0].name = "x y"; }, "not an FLL identifier");
  invalid([](TsFis* f) { f->inputs[0].name = "y"; }, "output's name");
  invalid([](TsFis* f) { f->output_values.push_back(1); }, "2 output terms but 3 output values");
  invalid([](TsFis* f) { f->output_values[0] = kNaN; }, "non-finite value");
  invalid([](TsFis* f) { f->default_value = kInf; }, "default value is infinite");
  invalid([](TsFis* f) { f->output_max = -1; }, "output range");
  invalid([](TsFis* f) { f->name = "a # b"; }, "engine name");
  TsFis nan_default = TwoRuleFis();
  nan_default.default_value = kNaN;  // FLL's own default
  EXPECT_TRUE(nan_default.IsValid(&error)) << error;
}

TEST(TsFisTest, WeightedAverageOfTwoRules) {
  const TsFis fis = TwoRuleFis();
  TsFis::Result r;
  fis.Evaluate({0.25}, &r);
  EXPECT_TRUE(r.fired);
  EXPECT_EQ(r.output, (0.75 * 10 + 0.25 * 20) / (0.75 + 0.25));
  ASSERT_EQ(r.activation.size(), 2u);
  EXPECT_EQ(r.activation[0], 0.75);
  EXPECT_EQ(r.activation[1], 0.25);
  EXPECT_EQ(r.membership, (std::vector<double>{0.75, 0.25}));
}

TEST(TsFisTest, OnlyOneRuleFires) {
  const TsFis fis = TwoRuleFis();
  TsFis::Result r;
  fis.Evaluate({-3.0}, &r);
  EXPECT_TRUE(r.fired);
  EXPECT_EQ(r.output, 10.0);
  EXPECT_EQ(r.activation, (std::vector<double>{1.0, 0.0}));
  fis.Evaluate({1.0}, &r);
  EXPECT_EQ(r.output, 20.0);
  EXPECT_EQ(r.activation, (std::vector<double>{0.0, 1.0}));
}

TEST(TsFisTest, NoRuleFiresGivesTheDefault) {
  TsFis fis = TwoRuleFis();
  fis.inputs[0].sets[1].membership = Make(Shape::kTriangle, 0.4, 0.5, 0.6);
  fis.inputs[0].sets[0].membership = Make(Shape::kTriangle, 0.0, 0.1, 0.2);
  TsFis::Result r;
  fis.Evaluate({0.8}, &r);
  EXPECT_FALSE(r.fired);
  EXPECT_EQ(r.output, 7.0);
  EXPECT_EQ(r.activation, (std::vector<double>{0.0, 0.0}));
  fis.Evaluate({kNaN}, &r);  // NaN inputs fire nothing
  EXPECT_FALSE(r.fired);
  EXPECT_EQ(r.output, 7.0);
  fis.default_value = kNaN;
  fis.Evaluate({0.8}, &r);
  EXPECT_TRUE(std::isnan(r.output));
  fis.default_value = 99;  // outside the output range: clamped only with lock_output_range
  fis.Evaluate({0.8}, &r);
  EXPECT_EQ(r.output, 99.0);
  fis.lock_output_range = true;
  fis.Evaluate({0.8}, &r);
  EXPECT_EQ(r.output, 30.0);
}

TEST(TsFisTest, RulesBelowTheToleranceDoNotFire) {
  TsFis fis = TwoRuleFis();
  fis.inputs[0].sets[1].membership = Make(Shape::kRampUp, 0, 1);
  fis.inputs[0].sets[0].membership = Make(Shape::kTriangle, 0.5, 0.6, 0.7);
  TsFis::Result r;
  fis.Evaluate({5e-7}, &r);  // hi = 5e-7 > 0 ... but < 1e-6: fuzzylite does not trigger it
  EXPECT_FALSE(r.fired);
  EXPECT_EQ(r.output, 7.0);
  fis.Evaluate({3e-6}, &r);
  EXPECT_TRUE(r.fired);
  EXPECT_EQ(r.output, 20.0);
  EXPECT_EQ(r.activation[1], 1.0);  // normalised
}

TEST(TsFisTest, LockedInputIsClamped) {
  TsFis fis = TwoRuleFis();
  fis.inputs[0].sets[0].membership = Make(Shape::kTriangle, 0, 0.5, 1);
  fis.inputs[0].sets[1].membership = Make(Shape::kTriangle, 0.5, 1, 1.5);
  TsFis::Result r;
  fis.Evaluate({2.0}, &r);
  EXPECT_FALSE(r.fired);
  fis.inputs[0].lock_range = true;  // 2 -> 1: hi = 1
  fis.Evaluate({2.0}, &r);
  EXPECT_TRUE(r.fired);
  EXPECT_EQ(r.output, 20.0);
}

TEST(TsFisTest, WrongNumberOfInputsThrows) {
  TsFis::Result r;
  EXPECT_THROW(TwoRuleFis().Evaluate({0.1, 0.2}, &r), std::invalid_argument);
}

TEST(TsFisTest, EvaluateDoesNotAllocateWhenTheResultIsReused) {
  const TsFis fis = DefaultGaitPattern(kVelocities);
  TsFis::Result r;
  std::vector<double> x = {0.5, 0.3};
  fis.Evaluate(x, &r);  // sizes the result
  g_allocations = 0;
  g_count_allocations = true;
  double sum = 0;
  for (int i = 0; i < 1000; ++i) {
    x[0] = 0.3 + 0.0006 * i;
    x[1] = 0.6 - 0.0006 * i;
    fis.Evaluate(x, &r);
    sum += r.output;
  }
  g_count_allocations = false;
  EXPECT_EQ(g_allocations, 0);
  EXPECT_GT(sum, 0.0);
}

TEST(DefaultGaitPatternTest, Structure) {
  const TsFis fis = DefaultGaitPattern(kVelocities);
  std::string error;
  ASSERT_TRUE(fis.IsValid(&error)) << error;
  ASSERT_EQ(fis.inputs.size(), 2u);
  EXPECT_EQ(fis.inputs[0].name, "V_M");
  EXPECT_EQ(fis.inputs[1].name, "d_obs");
  const std::vector<std::string> names = {"VerySmall", "Small", "Medium", "Big", "VeryBig"};
  for (const FuzzyInput& input : fis.inputs) {
    ASSERT_EQ(input.sets.size(), 5u);
    for (int s = 0; s < 5; ++s) EXPECT_EQ(input.sets[s].name, names[s]);
    EXPECT_EQ(input.sets[0].membership.shape, Shape::kRampDown);
    EXPECT_EQ(input.sets[4].membership.shape, Shape::kRampUp);
  }
  EXPECT_EQ(fis.inputs[0].min, 0.0);
  EXPECT_EQ(fis.inputs[0].max, 1.5);
  EXPECT_EQ(fis.inputs[1].min, 0.0);
  EXPECT_EQ(fis.inputs[1].max, 1.0);
  EXPECT_EQ(fis.inputs[1].sets[4].membership.a, 0.45);  // VeryBig: rising from 0.45 m
  EXPECT_EQ(fis.inputs[1].sets[4].membership.b, 0.5);
  EXPECT_EQ(fis.output_values, (std::vector<double>{1, 2, 3, 4, 5}));
  EXPECT_EQ(fis.rules.size(), 25u);
  EXPECT_TRUE(std::isnan(fis.default_value));

  EXPECT_THROW(DefaultGaitPattern({0.4}), std::invalid_argument);
  EXPECT_THROW(DefaultGaitPattern(std::vector<double>(kMaxGaitPatternGaits + 1, 0.5)),
               std::invalid_argument);
  EXPECT_THROW(DefaultGaitPattern({0.4, 0.5, 0.5, 0.7, 0.8}), std::invalid_argument);
  EXPECT_THROW(DefaultGaitPattern({0.4, 0.5, kNaN, 0.7, 0.8}), std::invalid_argument);
  EXPECT_THROW(DefaultGaitPattern({-0.1, 0.5, 0.6, 0.7, 0.8}), std::invalid_argument);
}

// Any N_r: the generalised Table 3 is the chapter's for N_r = 5, and for other N_r each rule
// selects the documented gait; at a velocity centre and a d_obs peak that gait alone is used.
TEST(DefaultGaitPatternTest, AnyNumberOfGaitsGeneralisesTable3) {
  const int kTable3[5][5] = {
      {4, 4, 4, 4, 5}, {5, 5, 5, 5, 5}, {1, 1, 1, 1, 1}, {1, 2, 3, 4, 4}, {1, 2, 3, 4, 5}};
  for (int row = 0; row < 5; ++row) {
    for (int column = 0; column < 5; ++column) {
      EXPECT_EQ(GaitPatternRule(row, column, 5), kTable3[row][column]) << row << ", " << column;
    }
  }
  const std::vector<double> v = {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  const int n = static_cast<int>(v.size());
  const TsFis fis = DefaultGaitPattern(v);
  std::string error;
  ASSERT_TRUE(fis.IsValid(&error)) << error;
  ASSERT_EQ(fis.inputs[0].sets.size(), v.size());
  EXPECT_EQ(fis.inputs[0].sets[0].name, "V1");
  EXPECT_EQ(fis.inputs[0].sets[7].name, "V8");
  EXPECT_EQ(fis.rules.size(), 5u * v.size());
  EXPECT_EQ(fis.output_max, 8.0);
  const double peaks[5] = {0.0, 0.15, 0.30, 0.45, 0.8};  // d_obs VerySmall .. VeryBig
  const int expected_far[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  TsFis::Result result;
  for (int column = 0; column < n; ++column) {
    // Expected cells written out: VerySmall n-1 (n at the top), Small n, Medium 1, Big
    // min(k, n-1), VeryBig k.
    const int k = column + 1;
    const int expected[5] = {k < n ? n - 1 : n, n, 1, std::min(k, n - 1), expected_far[column]};
    for (int row = 0; row < 5; ++row) {
      fis.Evaluate({v[column], peaks[row]}, &result);
      ASSERT_TRUE(result.fired);
      EXPECT_NEAR(result.output, expected[row], 1e-12) << "V_M " << v[column] << ", row " << row;
    }
  }
}

// At a velocity centre and a d_obs peak exactly one rule fires: the output is Table 3's cell.
TEST(DefaultGaitPatternTest, Table3AtTheCentres) {
  const int table3[5][5] = {
      {4, 4, 4, 4, 5}, {5, 5, 5, 5, 5}, {1, 1, 1, 1, 1}, {1, 2, 3, 4, 4}, {1, 2, 3, 4, 5}};
  const double d_obs_peaks[5] = {0.0, 0.15, 0.30, 0.45, 0.5};
  const TsFis fis = DefaultGaitPattern(kVelocities);
  TsFis::Result r;
  for (int row = 0; row < 5; ++row) {
    for (int column = 0; column < 5; ++column) {
      fis.Evaluate({kVelocities[column], d_obs_peaks[row]}, &r);
      ASSERT_TRUE(r.fired);
      EXPECT_EQ(r.output, table3[row][column]) << "row " << row << " column " << column;
      int firing = 0;
      for (double a : r.activation) firing += a > 0;
      EXPECT_EQ(firing, 1);
      EXPECT_EQ(r.activation[static_cast<std::size_t>(5 * row + column)], 1.0);
    }
  }
}

TEST(DefaultGaitPatternTest, FarObstacleLeavesOnlyTheVelocity) {
  const TsFis fis = DefaultGaitPattern(kVelocities);
  TsFis::Result far, other;
  double previous = 0;
  for (double v_m = 0.2; v_m < 1.0; v_m += 0.001) {
    fis.Evaluate({v_m, 1.0}, &far);
    ASSERT_TRUE(far.fired);
    EXPECT_GE(far.output, previous - 1e-12) << "step length grows with V_M, at " << v_m;
    previous = far.output;
    for (double d_obs : {0.5, 0.7, 3.0, kInf}) {
      fis.Evaluate({v_m, d_obs}, &other);
      EXPECT_EQ(other.output, far.output) << v_m << " " << d_obs;
    }
  }
  EXPECT_EQ(previous, 5.0);
}

TEST(DefaultGaitPatternTest, ActivationsArePartitionsOfUnity) {
  const TsFis fis = DefaultGaitPattern(kVelocities);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> v(-0.5, 2.0), d(-0.5, 1.5);
  TsFis::Result r;
  for (int i = 0; i < 2000; ++i) {
    fis.Evaluate({v(rng), d(rng)}, &r);
    ASSERT_TRUE(r.fired);
    double sum = 0;
    for (double a : r.activation) sum += a;
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_GE(r.output, 1.0);
    EXPECT_LE(r.output, 5.0);
  }
  fis.Evaluate({kNaN, 0.3}, &r);
  EXPECT_FALSE(r.fired);
  EXPECT_TRUE(std::isnan(r.output));
}

// Inputs for the comparisons: uniform over the ranges and 10 % beyond, uniform over the sets'
// supports, and every vertex combination (with offsets at the tolerance's edges), where single
// rules fire.
std::vector<std::vector<double>> ComparisonInputs(const TsFis& fis, int random_count,
                                                  unsigned seed) {
  std::vector<std::vector<double>> inputs;
  std::mt19937_64 rng(seed);
  for (int i = 0; i < random_count; ++i) {
    std::vector<double> x;
    for (const FuzzyInput& input : fis.inputs) {
      double lo = input.min, hi = input.max;
      if (i % 2 == 1) {  // the supports of the sets: where the rules overlap
        lo = input.sets.front().membership.a - 0.02;
        hi = input.sets.back().membership.b + 0.02;
      }
      const double margin = 0.1 * (hi - lo);
      x.push_back(std::uniform_real_distribution<double>(lo - margin, hi + margin)(rng));
    }
    inputs.push_back(x);
  }
  std::vector<std::vector<double>> vertices;
  for (const FuzzyInput& input : fis.inputs) {
    std::vector<double> values;
    for (const FuzzySet& set : input.sets) {
      for (double v : {set.membership.a, set.membership.b}) {
        for (double dx : {0.0, 5e-7, -5e-7, 1.5e-6, -1.5e-6}) values.push_back(v + dx);
      }
    }
    vertices.push_back(values);
  }
  for (double a : vertices[0]) {
    for (double b : vertices[1]) inputs.push_back({a, b});
  }
  return inputs;
}

TEST(DefaultGaitPatternTest, MatchesFuzzyliteEngine) {
  const TsFis fis = DefaultGaitPattern(kVelocities);
  const std::unique_ptr<fl::Engine> engine = MakeFuzzyliteEngine(fis);
  std::string status;
  ASSERT_TRUE(engine->isReady(&status)) << status;
  fl::InputVariable* v_m = engine->getInputVariable(0);
  fl::InputVariable* d_obs = engine->getInputVariable(1);
  fl::OutputVariable* gait = engine->getOutputVariable(0);
  const fl::RuleBlock* rules = engine->getRuleBlock(0);
  TsFis::Result r;
  double max_difference = 0;
  int identical = 0, single_rule = 0, compared = 0;
  for (const std::vector<double>& x : ComparisonInputs(fis, 10000, 42)) {
    fis.Evaluate(x, &r);
    v_m->setValue(x[0]);
    d_obs->setValue(x[1]);
    engine->process();
    const double theirs = gait->getValue();
    ASSERT_FALSE(std::isnan(theirs));
    max_difference = std::max(max_difference, std::abs(r.output - theirs));
    identical += Same(r.output, theirs);
    int firing = 0;
    for (std::size_t k = 0; k < fis.rules.size(); ++k) {
      ASSERT_EQ(r.activation[k] > 0, rules->getRule(k)->isTriggered()) << x[0] << " " << x[1];
      firing += r.activation[k] > 0;
    }
    single_rule += firing == 1;
    ++compared;
  }
  EXPECT_LE(max_difference, 1e-12);
  EXPECT_GT(single_rule, 100);
  std::cout << "[ fuzzylite ] " << compared << " inputs, " << single_rule
            << " with a single rule firing: max |ours - fuzzylite| = " << max_difference << ", "
            << identical << " bit-identical\n";
}

}  // namespace
}  // namespace rabbit
