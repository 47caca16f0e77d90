#include "rabbit/sim/serial_vector_ops.h"

#include <cmath>

namespace rabbit {
namespace serial_ops {
namespace {

inline sunindextype Length(N_Vector v) { return NV_LENGTH_S(v); }
inline realtype* Data(N_Vector v) { return NV_DATA_S(v); }

// z += c_k X_k for k = 1 .. nvec - 1, one vector after the other (the serial module's order).
void AddRest(int nvec, const realtype* c, N_Vector* X, sunindextype n, realtype* zd) {
  for (int k = 1; k < nvec; ++k) {
    const realtype* xd = Data(X[k]);
    const realtype ck = c[k];
    for (sunindextype i = 0; i < n; ++i) zd[i] += ck * xd[i];
  }
}

// The same sums for the simulator's state length, kept in registers: z is read (when it is X[0])
// and written once instead of once per term. Only when no X_k (k >= 1) is z, whose elements the
// loop above would read after writing them.
constexpr sunindextype kStateLength = 14;
void LinearCombinationInRegisters(int nvec, const realtype* c, N_Vector* X, realtype* zd,
                                  bool z_is_x0) {
  realtype acc[kStateLength];
  const realtype* x0 = Data(X[0]);
  const realtype c0 = c[0];
  if (!z_is_x0) {
    for (sunindextype i = 0; i < kStateLength; ++i) acc[i] = c0 * x0[i];
  } else if (c0 != 1.0) {
    for (sunindextype i = 0; i < kStateLength; ++i) acc[i] = x0[i] * c0;
  } else {
    for (sunindextype i = 0; i < kStateLength; ++i) acc[i] = x0[i];
  }
  for (int k = 1; k < nvec; ++k) {
    const realtype* xd = Data(X[k]);
    const realtype ck = c[k];
    for (sunindextype i = 0; i < kStateLength; ++i) acc[i] += ck * xd[i];
  }
  for (sunindextype i = 0; i < kStateLength; ++i) zd[i] = acc[i];
}

}  // namespace

// Each case below is one of the serial module's, taken in its order: the cases round differently
// (c (x + y) is not c x + c y), so the order decides which formula a pair of coefficients gets.
void LinearSum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z) {
  const sunindextype n = Length(x);
  const realtype* xd = Data(x);
  const realtype* yd = Data(y);
  realtype* zd = Data(z);
  if (b == 1.0 && z == y) {  // y += a x
    for (sunindextype i = 0; i < n; ++i) zd[i] += a * xd[i];
    return;
  }
  if (a == 1.0 && z == x) {  // x += b y
    for (sunindextype i = 0; i < n; ++i) zd[i] += b * yd[i];
    return;
  }
  if (a == 1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] + yd[i];
    return;
  }
  if (a == 1.0 && b == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i] - yd[i];
    return;
  }
  if (a == -1.0 && b == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = yd[i] - xd[i];
    return;
  }
  if (a == 1.0) {  // b y + x
    for (sunindextype i = 0; i < n; ++i) zd[i] = b * yd[i] + xd[i];
    return;
  }
  if (b == 1.0) {  // a x + y
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * xd[i] + yd[i];
    return;
  }
  if (a == -1.0) {  // b y - x
    for (sunindextype i = 0; i < n; ++i) zd[i] = b * yd[i] - xd[i];
    return;
  }
  if (b == -1.0) {  // a x - y
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * xd[i] - yd[i];
    return;
  }
  if (a == b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] + yd[i]);
    return;
  }
  if (a == -b) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = a * (xd[i] - yd[i]);
    return;
  }
  for (sunindextype i = 0; i < n; ++i) zd[i] = (a * xd[i]) + (b * yd[i]);
}

void Scale(realtype c, N_Vector x, N_Vector z) {
  const sunindextype n = Length(x);
  const realtype* xd = Data(x);
  realtype* zd = Data(z);
  if (z == x) {
    for (sunindextype i = 0; i < n; ++i) zd[i] *= c;
  } else if (c == 1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = xd[i];
  } else if (c == -1.0) {
    for (sunindextype i = 0; i < n; ++i) zd[i] = -xd[i];
  } else {
    for (sunindextype i = 0; i < n; ++i) zd[i] = c * xd[i];
  }
}

void Const(realtype c, N_Vector z) {
  const sunindextype n = Length(z);
  realtype* zd = Data(z);
  for (sunindextype i = 0; i < n; ++i) zd[i] = c;
}

// The sum in index order, as the serial module forms it (no reassociation: the norm decides step
// sizes, and a different last bit would change the step sequence).
realtype WSqrSumLocal(N_Vector x, N_Vector w) {
  const sunindextype n = Length(x);
  const realtype* xd = Data(x);
  const realtype* wd = Data(w);
  realtype sum = 0.0;
  for (sunindextype i = 0; i < n; ++i) {
    const realtype p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

realtype WrmsNorm(N_Vector x, N_Vector w) {
  return std::sqrt(WSqrSumLocal(x, w) / static_cast<realtype>(Length(x)));
}

int LinearCombination(int nvec, realtype* c, N_Vector* X, N_Vector z) {
  if (nvec < 1) return -1;
  if (nvec == 1) {
    Scale(c[0], X[0], z);
    return 0;
  }
  if (nvec == 2) {
    LinearSum(c[0], X[0], c[1], X[1], z);
    return 0;
  }
  const sunindextype n = Length(z);
  realtype* zd = Data(z);
  if (n == kStateLength) {
    bool z_in_rest = false;
    for (int k = 1; k < nvec; ++k) z_in_rest |= X[k] == z;
    if (!z_in_rest) {
      LinearCombinationInRegisters(nvec, c, X, zd, X[0] == z);
      return 0;
    }
  }
  if (X[0] == z) {  // z = c_0 z + sum c_k X_k, k >= 1 (no scaling when c_0 is 1)
    const realtype c0 = c[0];
    if (c0 != 1.0) {
      for (sunindextype i = 0; i < n; ++i) zd[i] *= c0;
    }
  } else {  // z = sum c_k X_k
    const realtype* xd = Data(X[0]);
    const realtype c0 = c[0];
    for (sunindextype i = 0; i < n; ++i) zd[i] = c0 * xd[i];
  }
  AddRest(nvec, c, X, n, zd);
  return 0;
}

int ScaleAddMulti(int nvec, realtype* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  if (nvec < 1) return -1;
  if (nvec == 1) {
    LinearSum(a[0], x, 1.0, Y[0], Z[0]);
    return 0;
  }
  const sunindextype n = Length(x);
  const realtype* xd = Data(x);
  if (Y == Z) {
    for (int k = 0; k < nvec; ++k) {
      realtype* yd = Data(Y[k]);
      const realtype ak = a[k];
      for (sunindextype i = 0; i < n; ++i) yd[i] += ak * xd[i];
    }
    return 0;
  }
  for (int k = 0; k < nvec; ++k) {
    const realtype* yd = Data(Y[k]);
    realtype* zd = Data(Z[k]);
    const realtype ak = a[k];
    for (sunindextype i = 0; i < n; ++i) zd[i] = ak * xd[i] + yd[i];
  }
  return 0;
}

}  // namespace serial_ops

void InstallFastSerialOps(N_Vector v) {
  N_Vector_Ops ops = v->ops;
  ops->nvlinearsum = serial_ops::LinearSum;
  ops->nvscale = serial_ops::Scale;
  ops->nvconst = serial_ops::Const;
  ops->nvwrmsnorm = serial_ops::WrmsNorm;
  ops->nvwsqrsumlocal = serial_ops::WSqrSumLocal;
  ops->nvlinearcombination = serial_ops::LinearCombination;
  ops->nvscaleaddmulti = serial_ops::ScaleAddMulti;
}

}  // namespace rabbit
