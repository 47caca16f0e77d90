// A thin wrapper over the two SUNDIALS integrators the simulator can use, with root finding:
//   kCvodeBdf    CVODE, variable-order BDF with Newton iterations and a dense direct linear solver
//                (difference-quotient Jacobian): for stiff settings (very stiff contact);
//   kCvodeAdams  CVODE, variable-order Adams-Moulton with fixed-point iterations (no Jacobian, no
//                linear solver);
//   kArkodeErk   ARKODE ERKStep, adaptive explicit Runge-Kutta of the given order (ARKODE's
//                default table for it: 2 Heun-Euler, 3 Bogacki-Shampine, 4 Zonneveld,
//                5 Cash-Karp, ...); or, with a fixed step and no error control, the classic
//                four-stage Runge-Kutta method at order 4 (and 0, the default order), ARKODE's
//                default table at any other order.
// Guards are oriented so that every event is a guard turning from positive to negative.
#ifndef RABBIT_SIM_INTEGRATOR_H_
#define RABBIT_SIM_INTEGRATOR_H_

#include <memory>
#include <string>
#include <vector>

namespace rabbit {

enum class IntegratorKind { kCvodeBdf, kCvodeAdams, kArkodeErk };
const char* IntegratorName(IntegratorKind kind);
// Parses "cvode", "cvode-adams" or "arkode"; returns false for anything else.
bool ParseIntegratorName(const std::string& name, IntegratorKind* kind);

struct IntegratorOptions {
  IntegratorKind kind = IntegratorKind::kArkodeErk;
  double rtol = 1e-5;
  double atol = 1e-7;
  double max_step = 0.0;            // s; 0 = no limit
  long max_steps_per_call = 20000;  // internal steps allowed between two stops
  // ARKODE: the method's order (2..8). CVODE: the maximum order (BDF 1..5, Adams 1..12). 0 = the
  // default (ARKODE 4, CVODE its own maximum).
  int order = 0;
  // ARKODE only: > 0 steps at this size (s) without error control, rtol and atol unused (the last
  // step before a stop or an event is shortened to land on it); 0 = adaptive steps.
  double fixed_step = 0.0;
  bool IsValid(std::string* error) const;
};

struct IntegratorStats {
  long steps = 0;
  long rhs_evals = 0;
  long root_evals = 0;
  long reinits = 0;
};

// Right-hand side ydot = f(t, y) and guards g(t, y). Return 0 on success, > 0 for a recoverable
// failure (the integrator retries with a smaller step), < 0 for an unrecoverable one.
using OdeRhsFn = int (*)(double t, const double* y, double* ydot, void* user);
using OdeRootFn = int (*)(double t, const double* y, double* g, void* user);

class OdeIntegrator {
 public:
  enum class Status { kReachedStop, kRoot, kFailure };

  virtual ~OdeIntegrator() = default;
  // Integrates from the current time towards t_stop without passing it. On kRoot, *t is the
  // located event time and y the state there; on kFailure, error() says why.
  virtual Status Advance(double t_stop, double* t, double* y) = 0;
  // Which guards fired at the last kRoot (non-zero entries).
  virtual void RootsFound(std::vector<int>* fired) = 0;
  // Restart from (t, y), e.g. after a discrete state changed at an event.
  virtual void Reinit(double t, const double* y) = 0;
  // Continue from (t, y) with a right-hand side that changed there (the zero-order-hold torques
  // at a control sample): no information from before t is reused, but the step size is kept.
  virtual void Restart(double t, const double* y) = 0;
  virtual IntegratorStats Stats() const = 0;
  const std::string& error() const { return error_; }

  static std::unique_ptr<OdeIntegrator> Create(const IntegratorOptions& options, int n,
                                               int num_roots, OdeRhsFn rhs, OdeRootFn roots,
                                               void* user, double t0, const double* y0);

 protected:
  std::string error_;
};

}  // namespace rabbit

#endif  // RABBIT_SIM_INTEGRATOR_H_
