#include "rabbit/sim/integrator.h"

#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "rabbit/sim/serial_vector_ops.h"

namespace rabbit {

const char* IntegratorName(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::kCvodeBdf:
      return "cvode";
    case IntegratorKind::kCvodeAdams:
      return "cvode-adams";
    case IntegratorKind::kArkodeErk:
      return "arkode";
  }
  return "?";
}

bool ParseIntegratorName(const std::string& name, IntegratorKind* kind) {
  if (name == "cvode") {
    *kind = IntegratorKind::kCvodeBdf;
  } else if (name == "cvode-adams") {
    *kind = IntegratorKind::kCvodeAdams;
  } else if (name == "arkode") {
    *kind = IntegratorKind::kArkodeErk;
  } else {
    return false;
  }
  return true;
}

bool IntegratorOptions::IsValid(std::string* error) const {
  if (!(std::isfinite(rtol) && rtol > 0.0 && rtol < 1.0)) {
    *error = "rtol must be in (0, 1)";
    return false;
  }
  if (!(std::isfinite(atol) && atol > 0.0)) {
    *error = "atol must be > 0";
    return false;
  }
  if (!(std::isfinite(max_step) && max_step >= 0.0)) {
    *error = "max_step must be >= 0";
    return false;
  }
  // 0 = the default; otherwise what each method supports.
  const int max_order =
      kind == IntegratorKind::kCvodeBdf ? 5 : (kind == IntegratorKind::kCvodeAdams ? 12 : 8);
  const int min_order = kind == IntegratorKind::kArkodeErk ? 2 : 1;
  if (order != 0 && (order < min_order || order > max_order)) {
    *error = std::string("order must be 0 (default) or in ") + std::to_string(min_order) + ".." +
             std::to_string(max_order) + " for " + IntegratorName(kind);
    return false;
  }
  if (!(std::isfinite(fixed_step) && fixed_step >= 0.0 && fixed_step <= 1.0)) {
    *error = "fixed_step must be in [0, 1] s";
    return false;
  }
  if (fixed_step > 0.0 && kind != IntegratorKind::kArkodeErk) {
    *error = std::string("fixed_step needs the arkode integrator, not ") + IntegratorName(kind);
    return false;
  }
  if (max_steps_per_call <= 0) {
    *error = "max_steps_per_call must be > 0";
    return false;
  }
  return true;
}

namespace {

constexpr int kDefaultErkOrder = 4;

// The classic four-stage, fourth-order Runge-Kutta method (no embedding: fixed steps only), as
// MuJoCo's RK4 integrator steps.
ARKodeButcherTable ClassicRk4() {
  const double c[4] = {0.0, 0.5, 0.5, 1.0};
  const double A[16] = {0.0, 0.0, 0.0, 0.0,  //
                        0.5, 0.0, 0.0, 0.0,  //
                        0.0, 0.5, 0.0, 0.0,  //
                        0.0, 0.0, 1.0, 0.0};
  const double b[4] = {1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0};
  return ARKodeButcherTable_Create(4, 4, 0, const_cast<double*>(c), const_cast<double*>(A),
                                   const_cast<double*>(b), nullptr);
}

// ARKODE's default table of an order (as ERKStepSetOrder picks it).
ARKodeButcherTable DefaultErkTable(int order) {
  switch (order) {
    case 2:
      return ARKodeButcherTable_LoadERK(ARKODE_HEUN_EULER_2_1_2);
    case 3:
      return ARKodeButcherTable_LoadERK(ARKODE_BOGACKI_SHAMPINE_4_2_3);
    case 4:
      return ARKodeButcherTable_LoadERK(ARKODE_ZONNEVELD_5_3_4);
    case 5:
      return ARKodeButcherTable_LoadERK(ARKODE_CASH_KARP_6_4_5);
    case 6:
      return ARKodeButcherTable_LoadERK(ARKODE_VERNER_8_5_6);
    default:
      return ARKodeButcherTable_LoadERK(ARKODE_FEHLBERG_13_7_8);
  }
}

// SUNDIALS 6.4's ERKStep takes every table whose last node c_s is 1 (within 1e-10) as
// first-same-as-last: at the end of a step it reuses the last stage's f as f(y_{n+1}), for the next
// step's first stage and the interpolant. That holds only when the last row of A is b: for the
// classic method (and Heun-Euler, Verner's 6(5)) it silently lowers the order (measured on the
// swing: 2.2e-10 rad after 1 s at 1 ms instead of the classic method's 1.4e-12). The right-hand
// side here does not depend on t (torques and pushes are held over a period), so such a table's
// last node is moved to 1 - 2^-20, which changes nothing but that test: ARKODE then evaluates
// f(y_{n+1}) as the method needs.
void AvoidFalseFsal(ARKodeButcherTable table) {
  const int s = table->stages;
  if (std::abs(table->c[s - 1] - 1.0) > 1e-10) return;
  bool fsal = true;
  for (int j = 0; j < s; ++j) fsal = fsal && table->A[s - 1][j] == table->b[j];
  if (!fsal) table->c[s - 1] = 1.0 - std::ldexp(1.0, -20);
}

// Owns the SUNDIALS context and vector shared by both integrators, and adapts the callbacks.
class SundialsBase : public OdeIntegrator {
 public:
  SundialsBase(int n, int num_roots, OdeRhsFn rhs, OdeRootFn roots, void* user)
      : n_(n), num_roots_(num_roots), rhs_(rhs), roots_(roots), user_(user) {
    if (SUNContext_Create(nullptr, &ctx_) != 0) throw std::runtime_error("SUNContext_Create");
    y_ = N_VNew_Serial(n, ctx_);
    // Fused vector operations: one call per linear combination instead of one per term (the
    // per-step overhead, not the right-hand side, dominates on a 14-state system).
    N_VEnableFusedOps_Serial(y_, SUNTRUE);
    // Compiled versions of the operations an integrator step spends its time in, with the same
    // rounding (serial_vector_ops.h); every vector the integrator clones from y_ gets them too.
    InstallFastSerialOps(y_);
  }
  ~SundialsBase() override {
    if (y_ != nullptr) N_VDestroy(y_);
    if (ctx_ != nullptr) SUNContext_Free(&ctx_);
  }
  SundialsBase(const SundialsBase&) = delete;
  SundialsBase& operator=(const SundialsBase&) = delete;

 protected:
  static int Rhs(realtype t, N_Vector y, N_Vector ydot, void* self) {
    auto* s = static_cast<SundialsBase*>(self);
    ++s->rhs_evals_;
    return s->rhs_(t, NV_DATA_S(y), NV_DATA_S(ydot), s->user_);
  }
  static int Roots(realtype t, N_Vector y, realtype* g, void* self) {
    auto* s = static_cast<SundialsBase*>(self);
    ++s->root_evals_;
    return s->roots_(t, NV_DATA_S(y), g, s->user_);
  }
  // Error weights 1 / (rtol |y_i| + atol), as SStolerances gives them, in one pass instead of four
  // vector operations.
  static int ErrorWeights(N_Vector y, N_Vector ewt, void* self) {
    auto* s = static_cast<SundialsBase*>(self);
    const double* yv = NV_DATA_S(y);
    double* w = NV_DATA_S(ewt);
    for (int i = 0; i < s->n_; ++i) w[i] = 1.0 / (s->rtol_ * std::abs(yv[i]) + s->atol_);
    return 0;
  }
  static void ErrorHandler(int code, const char* module, const char* function, char* msg,
                           void* self) {
    auto* s = static_cast<SundialsBase*>(self);
    if (code < 0) {
      s->error_ =
          std::string(module) + "::" + function + " (code " + std::to_string(code) + "): " + msg;
    }
  }
  void LoadY(const double* y) { std::memcpy(N_VGetArrayPointer(y_), y, sizeof(double) * n_); }
  void StoreY(double* y) const { std::memcpy(y, N_VGetArrayPointer(y_), sizeof(double) * n_); }
  void Check(int flag, const char* what) {
    if (flag < 0) throw std::runtime_error(std::string("SUNDIALS setup failed: ") + what);
  }

  int n_, num_roots_;
  double rtol_ = 0.0, atol_ = 0.0;
  OdeRhsFn rhs_;
  OdeRootFn roots_;
  void* user_;
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr;
  long reinits_ = 0;
  long steps_before_reinit_ = 0;  // CVODE's step counter restarts at every re-initialisation
  // Counted here rather than asked of SUNDIALS, whose counters do not all survive a restart.
  long rhs_evals_ = 0;
  long root_evals_ = 0;
};

class CvodeIntegrator final : public SundialsBase {
 public:
  CvodeIntegrator(const IntegratorOptions& o, int n, int num_roots, OdeRhsFn rhs, OdeRootFn roots,
                  void* user, double t0, const double* y0)
      : SundialsBase(n, num_roots, rhs, roots, user) {
    LoadY(y0);
    const bool bdf = o.kind == IntegratorKind::kCvodeBdf;
    mem_ = CVodeCreate(bdf ? CV_BDF : CV_ADAMS, ctx_);
    if (mem_ == nullptr) throw std::runtime_error("CVodeCreate failed");
    Check(CVodeSetErrHandlerFn(mem_, ErrorHandler, this), "CVodeSetErrHandlerFn");
    Check(CVodeInit(mem_, Rhs, t0, y_), "CVodeInit");
    Check(CVodeSetUserData(mem_, this), "CVodeSetUserData");
    rtol_ = o.rtol;
    atol_ = o.atol;
    Check(CVodeWFtolerances(mem_, ErrorWeights), "CVodeWFtolerances");
    if (o.order > 0) Check(CVodeSetMaxOrd(mem_, o.order), "CVodeSetMaxOrd");
    if (bdf) {
      A_ = SUNDenseMatrix(n, n, ctx_);
      ls_ = SUNLinSol_Dense(y_, A_, ctx_);
      Check(CVodeSetLinearSolver(mem_, ls_, A_), "CVodeSetLinearSolver");
    } else {
      nls_ = SUNNonlinSol_FixedPoint(y_, 0, ctx_);
      Check(CVodeSetNonlinearSolver(mem_, nls_), "CVodeSetNonlinearSolver");
    }
    Check(CVodeSetMaxNumSteps(mem_, o.max_steps_per_call), "CVodeSetMaxNumSteps");
    if (o.max_step > 0.0) Check(CVodeSetMaxStep(mem_, o.max_step), "CVodeSetMaxStep");
    if (num_roots > 0) {
      Check(CVodeRootInit(mem_, num_roots, Roots), "CVodeRootInit");
      std::vector<int> dir(num_roots, -1);
      Check(CVodeSetRootDirection(mem_, dir.data()), "CVodeSetRootDirection");
      Check(CVodeSetNoInactiveRootWarn(mem_), "CVodeSetNoInactiveRootWarn");
    }
  }
  ~CvodeIntegrator() override {
    CVodeFree(&mem_);
    if (ls_ != nullptr) SUNLinSolFree(ls_);
    if (A_ != nullptr) SUNMatDestroy(A_);
    if (nls_ != nullptr) SUNNonlinSolFree(nls_);
  }

  Status Advance(double t_stop, double* t, double* y) override {
    CVodeSetStopTime(mem_, t_stop);
    const int flag = CVode(mem_, t_stop, y_, t, CV_NORMAL);
    StoreY(y);
    if (flag == CV_ROOT_RETURN) return Status::kRoot;
    if (flag >= 0) return Status::kReachedStop;
    if (error_.empty()) error_ = "CVODE failed with flag " + std::to_string(flag);
    return Status::kFailure;
  }
  void RootsFound(std::vector<int>* fired) override {
    fired->assign(num_roots_, 0);
    CVodeGetRootInfo(mem_, fired->data());
  }
  void Reinit(double t, const double* y) override {
    steps_before_reinit_ = Stats().steps;
    LoadY(y);
    CVodeReInit(mem_, t, y_);
    ++reinits_;
  }
  void Restart(double t, const double* y) override {
    // CVODE's multistep history holds derivatives of the old right-hand side: re-initialise.
    Reinit(t, y);
  }
  IntegratorStats Stats() const override {
    IntegratorStats s;
    long steps = 0;
    CVodeGetNumSteps(mem_, &steps);
    s.steps = steps_before_reinit_ + steps;
    s.rhs_evals = rhs_evals_;
    s.root_evals = root_evals_;
    s.reinits = reinits_;
    return s;
  }

 private:
  void* mem_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver ls_ = nullptr;
  SUNNonlinearSolver nls_ = nullptr;
};

class ArkodeErkIntegrator final : public SundialsBase {
 public:
  ArkodeErkIntegrator(const IntegratorOptions& o, int n, int num_roots, OdeRhsFn rhs,
                      OdeRootFn roots, void* user, double t0, const double* y0)
      : SundialsBase(n, num_roots, rhs, roots, user) {
    LoadY(y0);
    mem_ = ERKStepCreate(Rhs, t0, y_, ctx_);
    if (mem_ == nullptr) throw std::runtime_error("ERKStepCreate failed");
    Check(ERKStepSetErrHandlerFn(mem_, ErrorHandler, this), "ERKStepSetErrHandlerFn");
    Check(ERKStepSetUserData(mem_, this), "ERKStepSetUserData");
    rtol_ = o.rtol;
    atol_ = o.atol;
    Check(ERKStepWFtolerances(mem_, ErrorWeights), "ERKStepWFtolerances");
    const int order = o.order > 0 ? o.order : kDefaultErkOrder;
    if (o.fixed_step > 0.0) {
      Check(ERKStepSetFixedStep(mem_, o.fixed_step), "ERKStepSetFixedStep");
      ARKodeButcherTable table = order == 4 ? ClassicRk4() : DefaultErkTable(order);
      if (table == nullptr) throw std::runtime_error("cannot build the Butcher table");
      AvoidFalseFsal(table);
      const int flag = ERKStepSetTable(mem_, table);  // copies the table
      ARKodeButcherTable_Free(table);
      Check(flag, "ERKStepSetTable");
    } else {
      Check(ERKStepSetOrder(mem_, order), "ERKStepSetOrder");
    }
    Check(ERKStepSetMaxNumSteps(mem_, o.max_steps_per_call), "ERKStepSetMaxNumSteps");
    if (o.max_step > 0.0) Check(ERKStepSetMaxStep(mem_, o.max_step), "ERKStepSetMaxStep");
    if (num_roots > 0) {
      Check(ERKStepRootInit(mem_, num_roots, Roots), "ERKStepRootInit");
      std::vector<int> dir(num_roots, -1);
      Check(ERKStepSetRootDirection(mem_, dir.data()), "ERKStepSetRootDirection");
      Check(ERKStepSetNoInactiveRootWarn(mem_), "ERKStepSetNoInactiveRootWarn");
    }
  }
  ~ArkodeErkIntegrator() override { ERKStepFree(&mem_); }

  Status Advance(double t_stop, double* t, double* y) override {
    ERKStepSetStopTime(mem_, t_stop);
    const int flag = ERKStepEvolve(mem_, t_stop, y_, t, ARK_NORMAL);
    StoreY(y);
    if (flag == ARK_ROOT_RETURN) return Status::kRoot;
    if (flag >= 0) return Status::kReachedStop;
    if (error_.empty()) error_ = "ARKODE failed with flag " + std::to_string(flag);
    return Status::kFailure;
  }
  void RootsFound(std::vector<int>* fired) override {
    fired->assign(num_roots_, 0);
    ERKStepGetRootInfo(mem_, fired->data());
  }
  // A one-step method carries nothing across a jump of the right-hand side but its stored first
  // stage f(t, y): ERKStepReset drops that and keeps the step-size history (and the counters),
  // which serves both an event and a change of torques.
  void Reinit(double t, const double* y) override {
    LoadY(y);
    ERKStepReset(mem_, t, y_);
    ++reinits_;
  }
  void Restart(double t, const double* y) override {
    LoadY(y);
    ERKStepReset(mem_, t, y_);
    ++restarts_;
  }
  IntegratorStats Stats() const override {
    IntegratorStats s;
    ERKStepGetNumSteps(mem_, &s.steps);  // kept across ERKStepReset
    s.rhs_evals = rhs_evals_;
    s.root_evals = root_evals_;
    s.reinits = reinits_ + restarts_;
    return s;
  }

 private:
  void* mem_ = nullptr;
  long restarts_ = 0;
};

}  // namespace

std::unique_ptr<OdeIntegrator> OdeIntegrator::Create(const IntegratorOptions& options, int n,
                                                     int num_roots, OdeRhsFn rhs, OdeRootFn roots,
                                                     void* user, double t0, const double* y0) {
  if (options.kind != IntegratorKind::kArkodeErk) {
    return std::make_unique<CvodeIntegrator>(options, n, num_roots, rhs, roots, user, t0, y0);
  }
  return std::make_unique<ArkodeErkIntegrator>(options, n, num_roots, rhs, roots, user, t0, y0);
}

}  // namespace rabbit
