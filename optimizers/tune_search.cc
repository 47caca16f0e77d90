#include "tune_search.h"

#include <ceres/ceres.h>
#include <glog/logging.h>
#include <nlopt.h>

#include <cmath>
#include <cstdint>

#include "rabbit/learn/cmac.h"

namespace rabbit::tune_internal {
namespace {

// The residuals of an evaluation for Ceres: sqrt(w_t / runs) * value for each weighted term of
// each run, so that their sum of squares is the mean_square objective.
std::vector<double> Residuals(const TuneObjective& objective, const Evaluation& e) {
  std::vector<double> r;
  const double n = static_cast<double>(std::max<size_t>(1, e.scores.size()));
  for (const RunScore& s : e.scores) {
    for (int t = 0; t < kNumTuneTerms; ++t) {
      if (objective.weight[t] <= 0.0) continue;
      const double v = std::isfinite(s.value[t]) ? s.value[t] : objective.missing[t];
      r.push_back(std::sqrt(objective.weight[t] / n) * v);
    }
  }
  return r;
}

class NloptOrCeres final : public Search {
 public:
  NloptOrCeres(const TuneJob& job, int start, std::vector<double> x0, int budget, Rounds* rounds)
      : job_(job), start_(start), x0_(std::move(x0)), budget_(budget), rounds_(rounds) {}

  void Run() override {
    try {
      // The initial point is every search's first evaluation (search 0's is the job's initial).
      Ask({x0_});
      if (budget_ > 1) {
        if (job_.algorithm == TuneAlgorithm::kCeres) {
          RunCeres();
        } else {
          RunNlopt();
        }
      }
    } catch (const Aborted&) {
    } catch (...) {
      error_ = std::current_exception();
      rounds_->Abort();
    }
    rounds_->Finish(start_);
  }
  std::exception_ptr error() const override { return error_; }

  // Remaining evaluations (memo hits are free).
  int remaining() const { return budget_ - used_; }
  std::vector<Evaluation> Ask(std::vector<std::vector<double>> xs) {
    std::vector<Evaluation> out = rounds_->Submit(start_, std::move(xs));
    return out;
  }
  void Charge(int n) override { used_ += n; }

 private:
  static double NloptObjective(unsigned n, const double* x, double* grad, void* data) {
    (void)grad;  // derivative-free algorithms only
    auto* self = static_cast<NloptOrCeres*>(data);
    if (self->remaining() <= 0) {
      nlopt_force_stop(self->opt_);
      return self->last_;
    }
    try {
      const std::vector<Evaluation> e = self->Ask({std::vector<double>(x, x + n)});
      self->last_ = e[0].objective;
      return self->last_;
    } catch (...) {
      self->callback_error_ = std::current_exception();
      nlopt_force_stop(self->opt_);
      return self->last_;
    }
  }

  void RunNlopt() {
    static const std::map<TuneAlgorithm, nlopt_algorithm> kNlopt = {
        {TuneAlgorithm::kBobyqa, NLOPT_LN_BOBYQA},
        {TuneAlgorithm::kSbplx, NLOPT_LN_SBPLX},
        {TuneAlgorithm::kCobyla, NLOPT_LN_COBYLA},
        {TuneAlgorithm::kNelderMead, NLOPT_LN_NELDERMEAD},
        {TuneAlgorithm::kCrs2, NLOPT_GN_CRS2_LM},
        {TuneAlgorithm::kIsres, NLOPT_GN_ISRES},
        {TuneAlgorithm::kEsch, NLOPT_GN_ESCH},
        {TuneAlgorithm::kDirect, NLOPT_GN_DIRECT},
        {TuneAlgorithm::kDirectL, NLOPT_GN_DIRECT_L}};
    const unsigned n = static_cast<unsigned>(job_.parameters.size());
    // NLopt's random numbers are thread-local: seeding here makes this search reproducible.
    nlopt_srand(CmacHashStep(CmacMix64(job_.seed), static_cast<std::uint64_t>(start_)));
    opt_ = nlopt_create(kNlopt.at(job_.algorithm), n);
    std::vector<double> lo, hi, step, x = x0_;
    for (const TuneParameter& p : job_.parameters) {
      lo.push_back(p.lower);
      hi.push_back(p.upper);
      step.push_back(job_.initial_step * (p.upper - p.lower));
    }
    nlopt_set_lower_bounds(opt_, lo.data());
    nlopt_set_upper_bounds(opt_, hi.data());
    nlopt_set_min_objective(opt_, &NloptOrCeres::NloptObjective, this);
    nlopt_set_maxeval(opt_, budget_);  // a backstop: the budget is counted in NloptObjective
    nlopt_set_xtol_rel(opt_, job_.xtol_rel);
    nlopt_set_ftol_rel(opt_, job_.ftol_rel);
    if (!IsGlobal(job_.algorithm)) nlopt_set_initial_step(opt_, step.data());
    if (job_.population > 0) nlopt_set_population(opt_, static_cast<unsigned>(job_.population));
    double f = 0.0;
    nlopt_optimize(opt_, x.data(), &f);  // the result code is not needed: the log has the best
    nlopt_destroy(opt_);
    opt_ = nullptr;
    if (callback_error_) std::rethrow_exception(callback_error_);
  }

  class Cost final : public ceres::CostFunction {
   public:
    Cost(NloptOrCeres* search, int residuals) : search_(search) {
      set_num_residuals(residuals);
      mutable_parameter_block_sizes()->push_back(static_cast<int>(search->job_.parameters.size()));
    }
    bool Evaluate(double const* const* parameters, double* residuals,
                  double** jacobians) const override {
      const TuneJob& job = search_->job_;
      const size_t n = job.parameters.size();
      const std::vector<double> x(parameters[0], parameters[0] + n);
      std::vector<std::vector<double>> batch = {x};
      std::vector<double> h(n);
      const bool jacobian = jacobians != nullptr && jacobians[0] != nullptr;
      if (jacobian) {
        for (size_t i = 0; i < n; ++i) {
          const TuneParameter& p = job.parameters[i];
          h[i] = job.fd_step * (p.upper - p.lower);
          if (x[i] + h[i] > p.upper) h[i] = -h[i];  // backward at the upper bound
          std::vector<double> xi = x;
          xi[i] += h[i];
          batch.push_back(xi);
        }
      }
      if (search_->remaining() < static_cast<int>(batch.size())) return false;
      std::vector<Evaluation> e;
      try {
        e = search_->Ask(batch);
      } catch (...) {  // not through Ceres: stop it (StopWhenSpent) and rethrow after Solve
        search_->callback_error_ = std::current_exception();
        return false;
      }
      for (const Evaluation& ev : e) {
        if (!ev.error.empty()) return false;
      }
      const std::vector<double> r0 = Residuals(job.objective, e[0]);
      if (static_cast<int>(r0.size()) != num_residuals()) return false;
      std::copy(r0.begin(), r0.end(), residuals);
      if (jacobian) {
        for (size_t i = 0; i < n; ++i) {
          const std::vector<double> ri = Residuals(job.objective, e[i + 1]);
          if (ri.size() != r0.size()) return false;
          for (size_t k = 0; k < r0.size(); ++k) {
            jacobians[0][k * n + i] = (ri[k] - r0[k]) / h[i];  // row-major, n columns
          }
        }
      }
      return true;
    }

   private:
    NloptOrCeres* search_;
  };

  class StopWhenSpent final : public ceres::IterationCallback {
   public:
    explicit StopWhenSpent(const NloptOrCeres* search) : search_(search) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
      if (search_->callback_error_) return ceres::SOLVER_ABORT;
      const int per_iteration = static_cast<int>(search_->job_.parameters.size()) + 1;
      return search_->remaining() < per_iteration ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
                                                  : ceres::SOLVER_CONTINUE;
    }

   private:
    const NloptOrCeres* search_;
  };

  // Ceres logs through glog, which prints "Logging before InitGoogleLogging()" and an ERROR line
  // when a step's evaluation fails (an invalid candidate: a result here, not an error). Once per
  // process: glog initialised and kept to FATAL messages only.
  static void QuietGlog() {
    static std::once_flag once;
    std::call_once(once, [] {
      if (!google::IsGoogleLoggingInitialized()) google::InitGoogleLogging("rabbit");
      FLAGS_minloglevel = google::GLOG_FATAL;
    });
  }

  void RunCeres() {
    QuietGlog();
    const std::vector<Evaluation> first = Ask({x0_});  // a memo hit: the residual count
    const int residuals = static_cast<int>(Residuals(job_.objective, first[0]).size());
    if (!first[0].error.empty() || residuals == 0) return;
    std::vector<double> x = x0_;
    ceres::Problem problem;
    problem.AddResidualBlock(new Cost(this, residuals), nullptr, x.data());
    for (size_t i = 0; i < job_.parameters.size(); ++i) {
      problem.SetParameterLowerBound(x.data(), static_cast<int>(i), job_.parameters[i].lower);
      problem.SetParameterUpperBound(x.data(), static_cast<int>(i), job_.parameters[i].upper);
    }
    ceres::Solver::Options options;
    options.minimizer_type = ceres::TRUST_REGION;
    options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
    options.linear_solver_type = ceres::DENSE_QR;
    options.max_num_iterations = job_.ceres_iterations;
    options.function_tolerance = job_.function_tolerance;
    options.num_threads = 1;  // the runs are parallel, not Ceres
    options.logging_type = ceres::SILENT;
    StopWhenSpent stop(this);
    options.callbacks.push_back(&stop);
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    if (callback_error_) std::rethrow_exception(callback_error_);
  }

  const TuneJob& job_;
  int start_;
  std::vector<double> x0_;
  int budget_;
  Rounds* rounds_;
  int used_ = 0;
  nlopt_opt opt_ = nullptr;
  double last_ = kInvalidObjective;
  std::exception_ptr callback_error_, error_;
};

}  // namespace

Rounds::Rounds(const std::vector<int>& starts) {
  for (int s : starts) state_[s];
}

std::vector<Evaluation> Rounds::Submit(int s, std::vector<std::vector<double>> xs) {
  std::unique_lock<std::mutex> lock(mutex_);
  State& st = state_.at(s);
  st.request = std::move(xs);
  st.waiting = true;
  changed_.notify_all();
  changed_.wait(lock, [&] { return !st.waiting || aborted_; });
  if (aborted_) throw Aborted{};
  return std::move(st.result);
}

void Rounds::Finish(int s) {
  std::lock_guard<std::mutex> lock(mutex_);
  state_.at(s).finished = true;
  changed_.notify_all();
}

void Rounds::Run(const Serve& serve) {
  while (true) {
    std::vector<int> starts;
    std::vector<std::vector<std::vector<double>>> xs;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] {
        if (aborted_) return true;
        for (const auto& [s, st] : state_) {
          if (!st.finished && !st.waiting) return false;
        }
        return true;
      });
      if (aborted_) return;  // a search failed: its error is rethrown by the caller
      for (auto& [s, st] : state_) {
        if (st.waiting) {
          starts.push_back(s);
          xs.push_back(st.request);
        }
      }
    }
    if (starts.empty()) return;
    std::vector<std::vector<Evaluation>> results;
    try {
      results = serve(starts, xs);
    } catch (...) {
      Abort();
      throw;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    for (size_t i = 0; i < starts.size(); ++i) {
      State& st = state_.at(starts[i]);
      st.result = std::move(results[i]);
      st.waiting = false;
    }
    changed_.notify_all();
  }
}

void Rounds::Abort() {
  std::lock_guard<std::mutex> lock(mutex_);
  aborted_ = true;
  changed_.notify_all();
}

std::unique_ptr<Search> MakeSearch(const TuneJob& job, int start, std::vector<double> x0,
                                   int budget, Rounds* rounds) {
  return std::make_unique<NloptOrCeres>(job, start, std::move(x0), budget, rounds);
}

std::vector<double> StartPoint(const TuneJob& job, int start) {
  std::vector<double> x;
  for (size_t i = 0; i < job.parameters.size(); ++i) {
    const TuneParameter& p = job.parameters[i];
    if (start == 0) {
      x.push_back(p.initial);
      continue;
    }
    const std::uint64_t h = CmacHashStep(
        CmacHashStep(CmacMix64(job.seed ^ 0x5EEDULL), static_cast<std::uint64_t>(start)), i);
    x.push_back(p.lower + static_cast<double>(h >> 11) * 0x1.0p-53 * (p.upper - p.lower));
  }
  return x;
}

}  // namespace rabbit::tune_internal
