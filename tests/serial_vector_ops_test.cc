// The compiled vector operations against SUNDIALS's own serial ones: every result bit for bit,
// over the special cases of the coefficients and the aliasing of arguments that select different
// formulas; then an ARKODE integration with root finding run with each, compared bit for bit.
#include "rabbit/sim/serial_vector_ops.h"

#include <arkode/arkode_erkstep.h>
#include <gtest/gtest.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

namespace rabbit {
namespace {

// Two vectors are the same when their bytes are: -0 differs from +0 and a NaN from a number.
bool SameBits(N_Vector a, N_Vector b) {
  return NV_LENGTH_S(a) == NV_LENGTH_S(b) &&
         std::memcmp(NV_DATA_S(a), NV_DATA_S(b), sizeof(realtype) * NV_LENGTH_S(a)) == 0;
}
bool SameBits(realtype a, realtype b) { return std::memcmp(&a, &b, sizeof a) == 0; }

class SerialVectorOpsTest : public ::testing::TestWithParam<int> {
 protected:
  void SetUp() override {
    ASSERT_EQ(SUNContext_Create(nullptr, &ctx_), 0);
    rng_.seed(static_cast<unsigned>(GetParam()) * 7919u + 1u);
  }
  void TearDown() override {
    for (N_Vector v : owned_) N_VDestroy(v);
    SUNContext_Free(&ctx_);
  }
  N_Vector Random() {
    N_Vector v = N_VNew_Serial(GetParam(), ctx_);
    std::uniform_real_distribution<double> u(-3.0, 3.0);
    for (int i = 0; i < GetParam(); ++i) NV_DATA_S(v)[i] = u(rng_);
    if (GetParam() > 2) NV_DATA_S(v)[1] = 0.0;  // signed zeros go through every formula
    if (GetParam() > 3) NV_DATA_S(v)[2] = -0.0;
    owned_.push_back(v);
    return v;
  }
  N_Vector Copy(N_Vector v) {
    N_Vector c = N_VNew_Serial(NV_LENGTH_S(v), ctx_);
    std::memcpy(NV_DATA_S(c), NV_DATA_S(v), sizeof(realtype) * NV_LENGTH_S(v));
    owned_.push_back(c);
    return c;
  }
  // The coefficients whose special cases select different formulas, and ordinary ones.
  std::vector<double> Coefficients() {
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    return {1.0, -1.0, 0.0, -0.0, 0.5, -0.5, u(rng_), u(rng_), 1e-300, 3.0};
  }

  SUNContext ctx_ = nullptr;
  std::mt19937 rng_;
  std::vector<N_Vector> owned_;
};

TEST_P(SerialVectorOpsTest, LinearSumMatchesEveryCoefficientPairAndAliasing) {
  for (double a : Coefficients()) {
    for (double b : Coefficients()) {
      // 0: z separate; 1: z is x; 2: z is y.
      for (int alias = 0; alias < 3; ++alias) {
        N_Vector x = Random(), y = Random(), z = Random();
        N_Vector x2 = Copy(x), y2 = Copy(y), z2 = Copy(z);
        N_Vector zo = alias == 1 ? x : (alias == 2 ? y : z);
        N_Vector zo2 = alias == 1 ? x2 : (alias == 2 ? y2 : z2);
        N_VLinearSum_Serial(a, x, b, y, zo);
        serial_ops::LinearSum(a, x2, b, y2, zo2);
        EXPECT_TRUE(SameBits(zo, zo2)) << "a = " << a << ", b = " << b << ", alias " << alias;
      }
    }
  }
}

TEST_P(SerialVectorOpsTest, ScaleConstAndNormsMatch) {
  for (double c : Coefficients()) {
    for (bool in_place : {false, true}) {
      N_Vector x = Random(), z = Random();
      N_Vector x2 = Copy(x), z2 = Copy(z);
      N_VScale_Serial(c, x, in_place ? x : z);
      serial_ops::Scale(c, x2, in_place ? x2 : z2);
      EXPECT_TRUE(SameBits(in_place ? x : z, in_place ? x2 : z2)) << "c = " << c;
    }
    N_Vector z = Random(), z2 = Copy(z);
    N_VConst_Serial(c, z);
    serial_ops::Const(c, z2);
    EXPECT_TRUE(SameBits(z, z2));
  }
  for (int trial = 0; trial < 20; ++trial) {
    N_Vector x = Random(), w = Random();
    EXPECT_TRUE(SameBits(N_VWSqrSumLocal_Serial(x, w), serial_ops::WSqrSumLocal(x, w)));
    EXPECT_TRUE(SameBits(N_VWrmsNorm_Serial(x, w), serial_ops::WrmsNorm(x, w)));
  }
}

TEST_P(SerialVectorOpsTest, LinearCombinationMatchesEveryCountAndAliasing) {
  for (int nvec = 1; nvec <= 7; ++nvec) {
    for (double c0 : {1.0, -1.0, 0.5, 2.0}) {
      // 0: z separate; 1: z is X[0]; 2: z is the last X (read after being written).
      for (int alias = 0; alias < (nvec > 1 ? 3 : 2); ++alias) {
        std::vector<double> c = Coefficients();
        c.resize(static_cast<size_t>(nvec));
        c[0] = c0;
        std::vector<N_Vector> X, X2;
        for (int k = 0; k < nvec; ++k) {
          X.push_back(Random());
          X2.push_back(Copy(X.back()));
        }
        const size_t at = alias == 2 ? X.size() - 1 : 0;
        N_Vector z = alias ? X[at] : Random();
        N_Vector z2 = alias ? X2[at] : Copy(z);
        std::vector<double> c2 = c;
        ASSERT_EQ(N_VLinearCombination_Serial(nvec, c.data(), X.data(), z), 0);
        ASSERT_EQ(serial_ops::LinearCombination(nvec, c2.data(), X2.data(), z2), 0);
        EXPECT_TRUE(SameBits(z, z2)) << nvec << " vectors, c0 = " << c0 << ", alias " << alias;
      }
    }
  }
}

TEST_P(SerialVectorOpsTest, ScaleAddMultiMatchesInPlaceAndNot) {
  for (int nvec = 1; nvec <= 5; ++nvec) {
    for (bool in_place : {false, true}) {
      std::vector<double> a = Coefficients();
      a.resize(static_cast<size_t>(nvec));
      N_Vector x = Random();
      std::vector<N_Vector> Y, Z, Y2, Z2;
      for (int k = 0; k < nvec; ++k) {
        Y.push_back(Random());
        Z.push_back(Random());
        Y2.push_back(Copy(Y.back()));
        Z2.push_back(Copy(Z.back()));
      }
      ASSERT_EQ(
          N_VScaleAddMulti_Serial(nvec, a.data(), x, Y.data(), in_place ? Y.data() : Z.data()), 0);
      ASSERT_EQ(
          serial_ops::ScaleAddMulti(nvec, a.data(), x, Y2.data(), in_place ? Y2.data() : Z2.data()),
          0);
      for (int k = 0; k < nvec; ++k) {
        EXPECT_TRUE(in_place ? SameBits(Y[k], Y2[k]) : SameBits(Z[k], Z2[k]))
            << nvec << " vectors, in place " << in_place;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Lengths, SerialVectorOpsTest, ::testing::Values(1, 5, 14));

// Seven damped pendula, each with its own length, swinging through zero: an integration whose
// step sizes, stops and root times depend on every operation above.
int PendulaRhs(realtype /*t*/, N_Vector y, N_Vector ydot, void* /*user*/) {
  const realtype* v = NV_DATA_S(y);
  realtype* d = NV_DATA_S(ydot);
  for (int k = 0; k < 7; ++k) {
    d[k] = v[7 + k];
    d[7 + k] = -9.81 / (0.3 + 0.1 * k) * std::sin(v[k]) - 0.05 * v[7 + k];
  }
  return 0;
}
int PendulaRoots(realtype /*t*/, N_Vector y, realtype* g, void* /*user*/) {
  g[0] = NV_DATA_S(y)[0];
  g[1] = NV_DATA_S(y)[3];
  return 0;
}

struct Trajectory {
  std::vector<double> values;  // state at every stop and root, then the step count
  long steps = 0;
  long roots = 0;
};

Trajectory Integrate(bool fast) {
  SUNContext ctx = nullptr;
  EXPECT_EQ(SUNContext_Create(nullptr, &ctx), 0);
  N_Vector y = N_VNew_Serial(14, ctx);
  N_VEnableFusedOps_Serial(y, SUNTRUE);
  if (fast) {
    InstallFastSerialOps(y);
    // The integrator's own vectors are clones: they must carry the replacements.
    N_Vector clone = N_VClone(y);
    EXPECT_EQ(clone->ops->nvlinearcombination, &serial_ops::LinearCombination);
    EXPECT_EQ(clone->ops->nvwrmsnorm, &serial_ops::WrmsNorm);
    N_VDestroy(clone);
  }
  for (int k = 0; k < 7; ++k) {
    NV_DATA_S(y)[k] = 0.2 + 0.15 * k;
    NV_DATA_S(y)[7 + k] = 0.0;
  }
  void* mem = ERKStepCreate(PendulaRhs, 0.0, y, ctx);
  ERKStepSStolerances(mem, 1e-6, 1e-8);
  ERKStepSetOrder(mem, 3);
  ERKStepRootInit(mem, 2, PendulaRoots);
  Trajectory out;
  double t = 0.0;
  for (int k = 1; k <= 2000; ++k) {
    const double t_stop = 1e-3 * k;
    ERKStepSetStopTime(mem, t_stop);
    while (t < t_stop) {
      const int flag = ERKStepEvolve(mem, t_stop, y, &t, ARK_NORMAL);
      EXPECT_GE(flag, 0);
      if (flag < 0) break;
      if (flag == ARK_ROOT_RETURN) ++out.roots;
      out.values.push_back(t);
      for (int i = 0; i < 14; ++i) out.values.push_back(NV_DATA_S(y)[i]);
    }
    // A held input changing at every sample, as the controller's torques do.
    ERKStepReset(mem, t, y);
  }
  ERKStepGetNumSteps(mem, &out.steps);
  ERKStepFree(&mem);
  N_VDestroy(y);
  SUNContext_Free(&ctx);
  return out;
}

TEST(SerialVectorOpsIntegrationTest, ArkodeWithRootsIsBitForBitTheSame) {
  const Trajectory plain = Integrate(false);
  const Trajectory fast = Integrate(true);
  ASSERT_GT(plain.steps, 2000);  // more than one step per sample
  ASSERT_GT(plain.roots, 4);     // the pendula cross zero several times in 2 s
  EXPECT_EQ(plain.steps, fast.steps);
  EXPECT_EQ(plain.roots, fast.roots);
  ASSERT_EQ(plain.values.size(), fast.values.size());
  EXPECT_EQ(
      std::memcmp(plain.values.data(), fast.values.data(), sizeof(double) * plain.values.size()),
      0);
}

}  // namespace
}  // namespace rabbit
