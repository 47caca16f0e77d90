// Compiled replacements for the serial N_Vector operations that ARKODE and CVODE call at every
// internal step (linear combinations, linear sums, scaling, weighted RMS norms).
//
// Why: the integrators' own arithmetic on a 14-element state is most of an integrator step's
// cost, and the serial vector module that SUNDIALS ships is built without optimisation on some
// distributions (Debian 12's 6.4.1 among them): its loops keep every index and pointer in memory.
// These replacements do the same floating-point operations on every element, in the same order
// and with the same special cases, so an integration with them is bit for bit the one without them
// (`tests/serial_vector_ops_test.cc` checks every operation against the library's own, and a walk
// against a walk). The file is compiled without contraction into fused multiply-adds, which would
// round differently.
#ifndef RABBIT_SIM_SERIAL_VECTOR_OPS_H_
#define RABBIT_SIM_SERIAL_VECTOR_OPS_H_

#include <nvector/nvector_serial.h>

namespace rabbit {

// Replaces the operations above in a serial vector's operation table (and so in every vector
// cloned from it afterwards). Call after N_VEnableFusedOps_Serial, which it needs: the linear
// combination is a fused operation.
void InstallFastSerialOps(N_Vector v);

// The replacements themselves (exposed for the test that compares them with SUNDIALS's).
namespace serial_ops {
void LinearSum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z);
void Scale(realtype c, N_Vector x, N_Vector z);
void Const(realtype c, N_Vector z);
realtype WSqrSumLocal(N_Vector x, N_Vector w);
realtype WrmsNorm(N_Vector x, N_Vector w);
int LinearCombination(int nvec, realtype* c, N_Vector* X, N_Vector z);
int ScaleAddMulti(int nvec, realtype* a, N_Vector x, N_Vector* Y, N_Vector* Z);
}  // namespace serial_ops

}  // namespace rabbit

#endif  // RABBIT_SIM_SERIAL_VECTOR_OPS_H_
