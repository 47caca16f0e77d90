#include "tuner.h"

#include <ceres/ceres.h>
#include <glog/logging.h>
#include <nlopt.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/io/test_hooks.h"
#include "rabbit/learn/cmac.h"
#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/suite.h"
#include "tune_report.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

constexpr const char* kMarker = ".rabbit-tune";

// ---------------------------------------------------------------------------------------------
// Evaluating candidates: every matching scenario's main variant, runs dealt over ranks by index.

RunScore Score(const std::string& suite, const RunOutput& run) {
  RunScore s;
  s.suite = suite;
  s.scenario = run.scenario;
  s.passed = run.passed;
  s.outcome = OutcomeName(run.sim.outcome);
  const RunMetrics& m = run.metrics;
  s.value = {run.passed ? 0.0 : 1.0, m.mean_abs_speed_error, m.l_step_spread, m.energy,
             m.cost_of_transport,    m.saturation};
  return s;
}

// One line per score: "k passed outcome v0 ... v5" (numbers exact), for the gather.
std::string Serialise(size_t k, const RunScore& s) {
  std::string line = std::to_string(k) + " " + (s.passed ? "1" : "0") + " " + s.outcome;
  for (double v : s.value) line += " " + ExactNumber(v);
  return line + "\n";
}

struct Candidate {
  std::vector<double> x;
  std::vector<Suite> suites;
  std::vector<BatchJob> jobs;
  std::vector<std::string> job_suite;  // suite name of each job
  std::string error;
};

class Evaluator {
 public:
  Evaluator(const TuneJob& job, int threads) : job_(job), threads_(threads) {}

  // Evaluates the candidates (on every rank, collectively): scores, terms and objective.
  std::vector<Evaluation> Evaluate(const std::vector<std::vector<double>>& xs) {
    std::vector<std::unique_ptr<Candidate>> candidates;
    for (const std::vector<double>& x : xs) candidates.push_back(Load(x));
    // Flatten (candidate, run) and take this rank's share.
    std::vector<std::pair<size_t, size_t>> items;
    for (size_t c = 0; c < candidates.size(); ++c) {
      for (size_t j = 0; j < candidates[c]->jobs.size(); ++j) items.push_back({c, j});
    }
    std::vector<BatchJob> mine;
    std::vector<size_t> mine_items;
    for (size_t k = 0; k < items.size(); ++k) {
      if (static_cast<int>(k % static_cast<size_t>(Ranks::size())) != Ranks::rank()) continue;
      mine.push_back(candidates[items[k].first]->jobs[items[k].second]);
      mine_items.push_back(k);
    }
    std::string text;
    std::vector<std::string> lines(mine.size());
    RunAgreed([&] {  // a rank whose runs threw cannot leave the others in the gather
      if (mine.empty()) return;
      RunBatch(mine, threads_, &libraries_, [&](size_t i, RunOutput&& run) {
        const auto& [c, j] = items[mine_items[i]];
        lines[i] = Serialise(mine_items[i], Score(candidates[c]->job_suite[j], run));
      });
    });
    for (const std::string& l : lines) text += l;
    std::vector<RunScore> scores(items.size());
    for (const std::string& part : Ranks::AllGather(text)) Parse(part, items, candidates, &scores);
    std::vector<Evaluation> out(xs.size());
    for (size_t c = 0; c < candidates.size(); ++c) {
      out[c].x = xs[c];
      out[c].error = candidates[c]->error;
    }
    for (size_t k = 0; k < items.size(); ++k) out[items[k].first].scores.push_back(scores[k]);
    for (Evaluation& e : out) ScoreEvaluation(job_.objective, &e);
    return out;
  }

 private:
  std::unique_ptr<Candidate> Load(const std::vector<double>& x) {
    auto c = std::make_unique<Candidate>();
    c->x = x;
    const ParamOverlay overlay = job_.Overlay(x);
    try {
      for (const std::string& path : job_.suites) c->suites.push_back(LoadSuite(path, &overlay));
      const NameFilter filter(job_.filter, "job.filter", job_.filter);
      for (const Suite& suite : c->suites) {
        for (const Scenario& s : suite.scenarios) {
          if (!filter.Matches(s.name)) continue;
          if (s.controller == ControllerKind::kFuzzyCmac) libraries_.Get(s.pattern);
          c->jobs.push_back({&s, ScenarioVariants(s).front()});
          c->job_suite.push_back(suite.name);
        }
      }
    } catch (const InputError& e) {
      // Settings a candidate makes invalid (within the job's bounds) are a result, not a crash.
      c->error = e.what();
      c->jobs.clear();
      c->job_suite.clear();
    }
    return c;
  }

  static void Parse(const std::string& text, const std::vector<std::pair<size_t, size_t>>& items,
                    const std::vector<std::unique_ptr<Candidate>>& candidates,
                    std::vector<RunScore>* scores) {
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream cells(line);
      size_t k = 0;
      int passed = 0;
      RunScore s;
      cells >> k >> passed >> s.outcome;
      for (double& v : s.value) {
        std::string word;
        cells >> word;
        v = std::strtod(word.c_str(), nullptr);
      }
      if (!cells || k >= items.size()) throw std::runtime_error("tune: bad result from a rank");
      const Candidate& c = *candidates[items[k].first];
      s.passed = passed != 0;
      s.suite = c.job_suite[items[k].second];
      s.scenario = c.jobs[items[k].second].scenario->name;
      (*scores)[k] = std::move(s);
    }
  }

  const TuneJob& job_;
  int threads_;
  GaitLibraryCache libraries_;
};

// ---------------------------------------------------------------------------------------------
// The log: evaluations.csv and runs.csv, appended as rounds finish.

std::string CsvText(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += "\"\"";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out + "\"";
}

std::string EvaluationsHeader(const TuneJob& job) {
  std::string h = "eval,round,start,seq,objective";
  for (int t = 0; t < kNumTuneTerms; ++t) h += std::string(",") + TuneTermName(t);
  h += ",runs,failed";
  for (const TuneParameter& p : job.parameters) h += "," + p.name;
  return h + ",error,wall_s";
}

std::string RunsHeader() {
  std::string h = "eval,suite,scenario,passed,outcome";
  for (int t = 0; t < kNumTuneTerms; ++t) h += std::string(",") + TuneTermName(t);
  return h;
}

std::string EvaluationRow(const Evaluation& e) {
  std::string row = std::to_string(e.index) + "," + std::to_string(e.round) + "," +
                    std::to_string(e.start) + "," + std::to_string(e.seq) + "," +
                    ExactNumber(e.objective);
  for (double v : e.terms) row += "," + ExactNumber(v);
  row += "," + std::to_string(e.runs) + "," + std::to_string(e.failed);
  for (double v : e.x) row += "," + ExactNumber(v);
  char wall[32];
  std::snprintf(wall, sizeof wall, "%.3f", e.wall);
  return row + "," + CsvText(e.error) + "," + wall;
}

std::string RunRows(const Evaluation& e) {
  std::string rows;
  for (const RunScore& s : e.scores) {
    rows += std::to_string(e.index) + "," + s.suite + "," + s.scenario + "," +
            (s.passed ? "1" : "0") + "," + s.outcome;
    for (double v : s.value) rows += "," + ExactNumber(v);
    rows += "\n";
  }
  return rows;
}

// The complete lines of a text (a line cut short by a crash is dropped).
std::string CompleteLines(const std::string& text) {
  const size_t end = text.rfind('\n');
  return end == std::string::npos ? "" : text.substr(0, end + 1);
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Evaluations recorded in a log (evaluations.csv and runs.csv texts), keyed by (start, seq).
std::map<std::pair<int, int>, Evaluation> ParseLog(const TuneJob& job, const std::string& file,
                                                   const std::string& evaluations,
                                                   const std::string& runs) {
  std::map<std::pair<int, int>, Evaluation> out;
  if (evaluations.empty()) return out;
  const CsvTable table = CsvTable::Parse(evaluations, file);
  const std::string expected = EvaluationsHeader(job);
  std::string header;
  for (const std::string& h : table.header()) header += (header.empty() ? "" : ",") + h;
  if (header != expected) {
    throw InputError(file, 1, "", "the log's columns are not this job's (" + header + ")");
  }
  std::map<int, Evaluation*> by_index;
  for (size_t r = 0; r < table.num_rows(); ++r) {
    Evaluation e;
    size_t c = 0;
    e.index = table.Integer(r, c++);
    e.round = table.Integer(r, c++);
    e.start = table.Integer(r, c++);
    e.seq = table.Integer(r, c++);
    e.objective = table.Number(r, c++, CsvNumber::kAny);
    for (double& v : e.terms) v = table.Number(r, c++, CsvNumber::kAny);
    e.runs = table.Integer(r, c++);
    e.failed = table.Integer(r, c++);
    for (size_t p = 0; p < job.parameters.size(); ++p) e.x.push_back(table.Number(r, c++));
    e.error = table.Text(r, c++);
    e.wall = table.Number(r, c++, CsvNumber::kAny);
    auto [it, inserted] = out.emplace(std::make_pair(e.start, e.seq), std::move(e));
    if (!inserted) {
      throw InputError(file, table.line(r), "", "search " + std::to_string(it->first.first) +
                                                    " request " + std::to_string(it->first.second) +
                                                    " is logged twice");
    }
    by_index[it->second.index] = &it->second;
  }
  if (!runs.empty()) {
    const CsvTable rt = CsvTable::Parse(runs, file);
    for (size_t r = 0; r < rt.num_rows(); ++r) {
      const auto found = by_index.find(rt.Integer(r, 0));
      if (found == by_index.end()) continue;  // an evaluation the crash cut short
      RunScore s;
      s.suite = rt.Text(r, 1);
      s.scenario = rt.Text(r, 2);
      s.passed = rt.Integer(r, 3) != 0;
      s.outcome = rt.Text(r, 4);
      for (int t = 0; t < kNumTuneTerms; ++t) s.value[t] = rt.Number(r, 5 + t, CsvNumber::kAny);
      found->second->scores.push_back(std::move(s));
    }
  }
  for (auto& [key, e] : out) {
    if (static_cast<int>(e.scores.size()) != e.runs) {
      throw InputError(file, 0, "", "evaluation " + std::to_string(e.index) + " logs " +
                                        std::to_string(e.runs) + " runs but runs.csv holds " +
                                        std::to_string(e.scores.size()));
    }
  }
  return out;
}

class Log {
 public:
  // Opens the log files in `dir` for appending (rank 0 only; other ranks log nothing).
  void Open(const fs::path& dir, const TuneJob& job, const std::string& evaluations,
            const std::string& runs) {
    if (!Ranks::root()) return;
    // Rewrite what survived (complete lines only), then append.
    const fs::path e = dir / "evaluations.csv", r = dir / "runs.csv";
    WriteFileAtomically(e.string(), [&](std::ostream& out) {
      out << (evaluations.empty() ? EvaluationsHeader(job) + "\n" : evaluations);
    });
    WriteFileAtomically(r.string(), [&](std::ostream& out) {
      out << (runs.empty() ? RunsHeader() + "\n" : runs);
    });
    evaluations_ = std::fopen(e.string().c_str(), "ab");
    runs_ = std::fopen(r.string().c_str(), "ab");
    if (evaluations_ == nullptr || runs_ == nullptr) {
      throw std::runtime_error("cannot append to the log in " + dir.string());
    }
  }
  ~Log() {
    if (evaluations_ != nullptr) std::fclose(evaluations_);
    if (runs_ != nullptr) std::fclose(runs_);
  }
  // Runs first, then the evaluation's row: a row in evaluations.csv means its runs are logged.
  void Append(const Evaluation& e) {
    if (evaluations_ == nullptr) return;
    const std::string runs = RunRows(e), row = EvaluationRow(e) + "\n";
    if (std::fputs(runs.c_str(), runs_) < 0 || std::fflush(runs_) != 0 ||
        std::fputs(row.c_str(), evaluations_) < 0 || std::fflush(evaluations_) != 0) {
      throw std::runtime_error("cannot append to the log (disk full?)");
    }
    // For the resume tests: RABBIT_TUNE_KILL_AFTER=N kills the process (SIGKILL, no clean-up)
    // once N evaluations have been logged, half-way through writing the next row's text.
    if (kill_after_ > 0 && ++appended_ == kill_after_) {
      std::fputs("999,0,0", evaluations_);
      std::fflush(evaluations_);
      std::raise(SIGKILL);
    }
  }
  void KillAfter(int n) { kill_after_ = n; }

 private:
  std::FILE* evaluations_ = nullptr;
  std::FILE* runs_ = nullptr;
  int kill_after_ = 0, appended_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Rounds: the searches' requests, gathered in lockstep.

struct Aborted {};  // thrown into a search's thread when the job stops

class Rounds {
 public:
  using Serve = std::function<std::vector<std::vector<Evaluation>>(
      const std::vector<int>& starts, const std::vector<std::vector<std::vector<double>>>& xs)>;

  explicit Rounds(const std::vector<int>& starts) {
    for (int s : starts) state_[s];
  }

  // From search s's thread: blocks until its candidates are evaluated.
  std::vector<Evaluation> Submit(int s, std::vector<std::vector<double>> xs) {
    std::unique_lock<std::mutex> lock(mutex_);
    State& st = state_.at(s);
    st.request = std::move(xs);
    st.waiting = true;
    changed_.notify_all();
    changed_.wait(lock, [&] { return !st.waiting || aborted_; });
    if (aborted_) throw Aborted{};
    return std::move(st.result);
  }
  void Finish(int s) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_.at(s).finished = true;
    changed_.notify_all();
  }

  // From the main thread: serves rounds until every search has finished.
  void Run(const Serve& serve) {
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
  void Abort() {
    std::lock_guard<std::mutex> lock(mutex_);
    aborted_ = true;
    changed_.notify_all();
  }

 private:
  struct State {
    bool waiting = false, finished = false;
    std::vector<std::vector<double>> request;
    std::vector<Evaluation> result;
  };
  std::mutex mutex_;
  std::condition_variable changed_;
  std::map<int, State> state_;
  bool aborted_ = false;
};

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

// A search: one NLopt or Ceres optimisation in its own thread, asking the rounds for evaluations.
class Search {
 public:
  Search(const TuneJob& job, int start, std::vector<double> x0, int budget, Rounds* rounds)
      : job_(job), start_(start), x0_(std::move(x0)), budget_(budget), rounds_(rounds) {}

  void Run() {
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
  std::exception_ptr error() const { return error_; }

  // Remaining evaluations (memo hits are free).
  int remaining() const { return budget_ - used_; }
  std::vector<Evaluation> Ask(std::vector<std::vector<double>> xs) {
    std::vector<Evaluation> out = rounds_->Submit(start_, std::move(xs));
    return out;
  }
  // Charges the budget for evaluations the rounds ran (told by the rounds).
  void Charge(int n) { used_ += n; }

 private:
  static double NloptObjective(unsigned n, const double* x, double* grad, void* data) {
    (void)grad;  // derivative-free algorithms only
    auto* self = static_cast<Search*>(data);
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
        {TuneAlgorithm::kBobyqa, NLOPT_LN_BOBYQA}, {TuneAlgorithm::kSbplx, NLOPT_LN_SBPLX},
        {TuneAlgorithm::kCobyla, NLOPT_LN_COBYLA}, {TuneAlgorithm::kNelderMead, NLOPT_LN_NELDERMEAD},
        {TuneAlgorithm::kCrs2, NLOPT_GN_CRS2_LM},  {TuneAlgorithm::kIsres, NLOPT_GN_ISRES},
        {TuneAlgorithm::kEsch, NLOPT_GN_ESCH},     {TuneAlgorithm::kDirect, NLOPT_GN_DIRECT},
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
    nlopt_set_min_objective(opt_, &Search::NloptObjective, this);
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
    Cost(Search* search, int residuals) : search_(search) {
      set_num_residuals(residuals);
      mutable_parameter_block_sizes()->push_back(
          static_cast<int>(search->job_.parameters.size()));
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
    Search* search_;
  };

  class StopWhenSpent final : public ceres::IterationCallback {
   public:
    explicit StopWhenSpent(const Search* search) : search_(search) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary&) override {
      if (search_->callback_error_) return ceres::SOLVER_ABORT;
      const int per_iteration = static_cast<int>(search_->job_.parameters.size()) + 1;
      return search_->remaining() < per_iteration ? ceres::SOLVER_TERMINATE_SUCCESSFULLY
                                                  : ceres::SOLVER_CONTINUE;
    }

   private:
    const Search* search_;
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

// Start points: search 0 at the initial values, the others uniform in the bounds (seeded).
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

std::string Join(const std::vector<std::string>& parts, const char* separator) {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : separator) + p;
  return out;
}

void WriteOutputs(const TuneJob& job, const fs::path& dir, const TuneResult& result,
                  const TuneOptions& options, std::vector<std::string>* warnings) {
  const Evaluation& initial = result.evaluations[result.initial];
  const Evaluation& best = result.evaluations[result.best];
  const ParamOverlay overlay = job.Overlay(best.x);
  char summary[512];
  std::snprintf(summary, sizeof summary,
                "objective %s at evaluation %d (search %d) against %s at the initial values",
                ExactNumber(best.objective).c_str(), best.index, best.start,
                ExactNumber(initial.objective).c_str());
  WriteFileAtomically((dir / "best.toml").string(), [&](std::ostream& out) {
    out << ParamOverlayToml(
        overlay, "rabbit tune " + job.name + " (" + job.file + "): the best of " +
                     std::to_string(result.evaluations.size()) + " evaluations, " + summary +
                     ".\n" + TuneAlgorithmName(job.algorithm) + ", seed " +
                     std::to_string(job.seed) + ", suites " + Join(job.suites, ", ") +
                     ".\nUse: rabbit run --params best.toml SUITE");
  });
  WriteFileAtomically((dir / "parameters.csv").string(), [&](std::ostream& out) {
    out << "path,lower,upper,initial,best\n";
    for (size_t i = 0; i < job.parameters.size(); ++i) {
      const TuneParameter& p = job.parameters[i];
      out << p.name << "," << ExactNumber(p.lower) << "," << ExactNumber(p.upper) << ","
          << ExactNumber(initial.x[i]) << "," << ExactNumber(best.x[i]) << "\n";
    }
  });
  WriteFileAtomically((dir / "comparison.csv").string(), [&](std::ostream& out) {
    out << "suite,scenario,initial_passed,best_passed";
    for (int t = 0; t < kNumTuneTerms; ++t) {
      out << ",initial_" << TuneTermName(t) << ",best_" << TuneTermName(t);
    }
    out << "\n";
    std::map<std::pair<std::string, std::string>, const RunScore*> at_best;
    for (const RunScore& s : best.scores) at_best[{s.suite, s.scenario}] = &s;
    for (const RunScore& s : initial.scores) {
      const auto found = at_best.find({s.suite, s.scenario});
      const RunScore* b = found == at_best.end() ? nullptr : found->second;
      out << s.suite << "," << s.scenario << "," << (s.passed ? 1 : 0) << ","
          << (b == nullptr ? "nan" : (b->passed ? "1" : "0"));
      for (int t = 0; t < kNumTuneTerms; ++t) {
        out << "," << ExactNumber(s.value[t]) << ","
            << (b == nullptr ? "nan" : ExactNumber(b->value[t]));
      }
      out << "\n";
    }
  });
  std::vector<std::string> weights;
  for (int t = 0; t < kNumTuneTerms; ++t) {
    if (job.objective.weight[t] > 0.0) {
      weights.push_back(std::string(TuneTermName(t)) + "=" + ExactNumber(job.objective.weight[t]));
    }
  }
  WriteFileAtomically((dir / "meta.csv").string(), [&](std::ostream& out) {
    auto row = [&out](const std::string& key, const std::string& value) {
      out << key << "," << CsvText(value) << "\n";
    };
    out << "key,value\n";
    row("job", job.name);
    row("description", job.description);
    row("job_file", job.file);
    row("algorithm", TuneAlgorithmName(job.algorithm));
    row("seed", std::to_string(job.seed));
    row("starts", std::to_string(job.starts));
    row("max_evaluations", std::to_string(job.max_evaluations));
    row("form", job.objective.squares ? "mean_square" : "mean");
    row("weights", Join(weights, ";"));
    row("suites", Join(job.suites, ";"));
    row("evaluations", std::to_string(result.evaluations.size()));
    row("initial_eval", std::to_string(initial.index));
    row("best_eval", std::to_string(best.index));
    row("initial_objective", ExactNumber(initial.objective));
    row("best_objective", ExactNumber(best.objective));
    row("complete", "true");
    row("fingerprint", job.fingerprint);
  });
  if (options.html) {
    TuneReportOptions report;
    report.gnuplot = options.gnuplot;
    WriteTuneReport(dir.string(), report, warnings);
  }
}

}  // namespace

void ScoreEvaluation(const TuneObjective& objective, Evaluation* e) {
  e->runs = static_cast<int>(e->scores.size());
  e->failed = 0;
  for (const RunScore& s : e->scores) e->failed += s.passed ? 0 : 1;
  if (!e->error.empty() || e->scores.empty()) {
    e->terms.fill(std::numeric_limits<double>::quiet_NaN());
    e->objective = kInvalidObjective;
    if (e->error.empty()) e->error = "no runs";
    return;
  }
  e->objective = 0.0;
  for (int t = 0; t < kNumTuneTerms; ++t) {
    double sum = 0.0;
    for (const RunScore& s : e->scores) {
      const double v = std::isfinite(s.value[t]) ? s.value[t] : objective.missing[t];
      sum += objective.squares ? v * v : v;
    }
    e->terms[t] = sum / static_cast<double>(e->scores.size());
    if (objective.weight[t] > 0.0) e->objective += objective.weight[t] * e->terms[t];
  }
}

TuneResult RunTune(const TuneJob& job, const TuneOptions& options) {
  TuneResult result;
  const fs::path out = options.out.empty() ? fs::path("reports") / job.name : fs::path(options.out);
  result.out = out.string();
  const fs::path dir = options.shard.active()
                           ? out / "shards" /
                                 (std::to_string(options.shard.index) + "-of-" +
                                  std::to_string(options.shard.count))
                           : out;
  // The folder: a fresh one, or this job's log to resume (or, with --force, to start over).
  std::string evaluations_text, runs_text;
  std::map<std::pair<int, int>, Evaluation> recorded;  // replayable, from this folder's log
  std::map<std::pair<int, int>, Evaluation> foreign;   // from other shards' logs (to re-log)
  std::string problem;
  OutputLock lock;  // rank 0's, on the folder it writes, until the last file is written
  RunAgreed([&] {  // rank 0 alone looks at the folder: a throw there must stop every rank
    if (!Ranks::root()) return;
    lock = OutputLock(dir, "--out");
    const bool has_log = fs::exists(dir / "evaluations.csv");
    if (fs::exists(out) && !fs::is_directory(out)) {
      problem = out.string() + " exists and is not a folder";
    } else if (fs::exists(dir) && !fs::is_empty(dir) && !fs::exists(dir / kMarker) &&
               !(options.shard.active() == false && fs::exists(dir / "shards"))) {
      problem = dir.string() + " exists and is not a tuning job's folder (no " + kMarker +
                "): refusing to write into it";
    } else if (has_log && !options.resume && !options.force) {
      problem = dir.string() + " holds a log of this job: use --resume to continue it or " +
                "--force to start over";
    } else if (has_log && options.resume) {
      const std::string marker = ReadText(dir / kMarker);
      if (marker.find(job.fingerprint) == std::string::npos) {
        const std::string changed = ChangedInputs(marker, job.inputs);
        const bool named = !changed.empty() && marker.find("input = ") != std::string::npos;
        problem = (dir / "evaluations.csv").string() + " was written by another job or " +
                  "version of its files (fingerprint differs" + (named ? ": " + changed : "") +
                  "): use --force to start over";
      }
    }
    if (problem.empty() && options.force) {
      for (const char* f : {"evaluations.csv", "runs.csv", "best.toml", "comparison.csv",
                            "parameters.csv", "meta.csv", "index.html"}) {
        fs::remove(dir / f);
      }
      if (!options.shard.active()) fs::remove_all(dir / "shards");
    }
    if (problem.empty() && options.resume) {
      evaluations_text = CompleteLines(ReadText(dir / "evaluations.csv"));
      runs_text = CompleteLines(ReadText(dir / "runs.csv"));
    }
  });
  problem = Ranks::Broadcast(problem);
  if (!problem.empty()) throw InputError("--out", 0, out.string(), problem);
  evaluations_text = Ranks::Broadcast(evaluations_text);
  runs_text = Ranks::Broadcast(runs_text);
  recorded = ParseLog(job, (dir / "evaluations.csv").string(), evaluations_text, runs_text);
  {
    // What survived, rewritten whole: complete rows, and no runs of an evaluation cut short (also
    // when no row survived: the first evaluation's runs may be logged without its row).
    std::vector<const Evaluation*> order;
    for (const auto& [key, e] : recorded) order.push_back(&e);
    std::sort(order.begin(), order.end(),
              [](const Evaluation* a, const Evaluation* b) { return a->index < b->index; });
    evaluations_text = EvaluationsHeader(job) + "\n";
    runs_text = RunsHeader() + "\n";
    for (const Evaluation* e : order) {
      evaluations_text += EvaluationRow(*e) + "\n";
      runs_text += RunRows(*e);
    }
  }
  // Without --shard, --resume also replays every shard's log.
  std::string shard_logs;
  RunAgreed([&] {  // rank 0 reads; a bad shard must not leave the other ranks waiting
    if (!Ranks::root() || !options.resume || options.shard.active() ||
        !fs::exists(out / "shards")) {
      return;
    }
    std::vector<fs::path> logs;
    for (const fs::directory_entry& entry : fs::directory_iterator(out / "shards")) {
      const fs::path e = entry.path() / "evaluations.csv";
      if (!fs::exists(e)) continue;
      if (ReadText(entry.path() / kMarker).find(job.fingerprint) == std::string::npos) {
        throw InputError(e.string(), 0, "", "a shard of another job (fingerprint differs)");
      }
      logs.push_back(e);
    }
    std::sort(logs.begin(), logs.end());
    for (const fs::path& e : logs) shard_logs += e.string() + "\n";
  });
  std::istringstream shard_list(Ranks::Broadcast(shard_logs));
  for (std::string e; std::getline(shard_list, e);) {
    const fs::path p(e);
    const std::string ev = Ranks::Broadcast(
        Ranks::root() ? CompleteLines(ReadText(p)) : std::string());
    const std::string ru = Ranks::Broadcast(
        Ranks::root() ? CompleteLines(ReadText(p.parent_path() / "runs.csv")) : std::string());
    for (auto& [key, value] : ParseLog(job, e, ev, ru)) {
      if (recorded.count(key) == 0) foreign.emplace(key, std::move(value));
    }
  }
  Log log;
  RunAgreed([&] {  // only rank 0 writes
    if (Ranks::root()) {
      fs::create_directories(dir);
      WriteFileAtomically((dir / kMarker).string(), [&](std::ostream& o) {
        o << "rabbit-tune/1 " << job.name << " " << job.fingerprint << "\n"
          << InputLines(job.inputs);
      });
      TestKillPoint("tune-marked");
    }
    log.Open(dir, job, evaluations_text, runs_text);
  });
  if (const char* kill = std::getenv("RABBIT_TUNE_KILL_AFTER")) log.KillAfter(std::atoi(kill));
  int next_index = 0;
  for (const auto& [key, e] : recorded) next_index = std::max(next_index, e.index + 1);

  // The searches of this shard and their budgets (the job's budget dealt over all searches).
  std::vector<int> starts;
  for (int s = 0; s < job.starts; ++s) {
    if (options.shard.Owns(static_cast<size_t>(s))) starts.push_back(s);
  }
  Rounds rounds(starts);
  std::vector<std::unique_ptr<Search>> searches;
  std::map<int, Search*> by_start;
  for (int s : starts) {
    const int budget = job.max_evaluations / job.starts + (s < job.max_evaluations % job.starts);
    searches.push_back(std::make_unique<Search>(job, s, StartPoint(job, s), budget, &rounds));
    by_start[s] = searches.back().get();
  }
  Evaluator evaluator(job, options.threads);
  std::map<int, int> seq;                                  // per search: requests evaluated
  std::map<int, std::vector<const Evaluation*>> memo;      // per search: its evaluations
  std::vector<std::unique_ptr<Evaluation>> all;            // log order
  int round = 0;
  auto serve = [&](const std::vector<int>& ss,
                   const std::vector<std::vector<std::vector<double>>>& xs) {
    std::vector<std::vector<Evaluation>> answers(ss.size());
    std::vector<std::vector<double>> fresh;                  // to evaluate now
    std::vector<std::pair<size_t, size_t>> fresh_at;         // (request, candidate)
    std::vector<std::vector<const Evaluation*>> found(ss.size());
    // New in this folder's log this round, in request order: fresh ones and other shards' replays.
    std::vector<std::pair<Evaluation*, bool>> to_log;  // (evaluation, fresh)
    bool evaluated = false;
    for (size_t r = 0; r < ss.size(); ++r) {
      const int s = ss[r];
      int charged = 0;
      for (size_t c = 0; c < xs[r].size(); ++c) {
        const std::vector<double>& x = xs[r][c];
        const Evaluation* hit = nullptr;
        for (const Evaluation* e : memo[s]) {
          if (e->x == x) hit = e;
        }
        found[r].push_back(hit);
        if (hit != nullptr) continue;
        ++charged;
        const int k = seq[s]++;
        auto logged = recorded.find({s, k});
        auto other = foreign.find({s, k});
        const Evaluation* replay = logged != recorded.end() ? &logged->second
                                   : other != foreign.end() ? &other->second
                                                            : nullptr;
        evaluated = true;
        if (replay != nullptr) {
          if (replay->x != x) {
            throw InputError((dir / "evaluations.csv").string(), 0, "",
                             "the job no longer reproduces its log (search " + std::to_string(s) +
                                 ", request " + std::to_string(k) +
                                 " asks for other values): use --force to start over");
          }
          auto e = std::make_unique<Evaluation>(*replay);
          e->round = round;
          if (logged == recorded.end()) to_log.push_back({e.get(), false});  // from a shard
          ++result.replayed;
          memo[s].push_back(e.get());
          found[r].back() = e.get();
          all.push_back(std::move(e));
          continue;
        }
        fresh.push_back(x);
        fresh_at.push_back({r, c});
        // Reserve its place in the search's request order.
        auto e = std::make_unique<Evaluation>();
        e->start = s;
        e->seq = k;
        e->x = x;
        found[r].back() = e.get();
        memo[s].push_back(e.get());
        to_log.push_back({e.get(), true});
        all.push_back(std::move(e));
      }
      by_start.at(s)->Charge(charged);
    }
    if (!fresh.empty()) {
      const auto t0 = std::chrono::steady_clock::now();
      std::vector<Evaluation> done = evaluator.Evaluate(fresh);
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() /
          static_cast<double>(fresh.size());
      for (size_t f = 0; f < fresh.size(); ++f) {
        Evaluation* e = const_cast<Evaluation*>(found[fresh_at[f].first][fresh_at[f].second]);
        const int s = e->start, k = e->seq;
        *e = std::move(done[f]);
        e->start = s;
        e->seq = k;
        e->round = round;
        e->wall = wall;
      }
    }
    // Numbered and logged in request order (searches in order, then their candidates), as one
    // uninterrupted run does, whether or not some came from other shards' logs.
    for (const auto& [e, is_fresh] : to_log) e->index = next_index++;
    RunAgreed([&] {  // only rank 0 writes: a failed write must stop every rank
      for (const auto& [e, is_fresh] : to_log) {
        log.Append(*e);
        if (is_fresh && Ranks::root() && options.on_evaluation) options.on_evaluation(*e);
      }
    });
    for (size_t r = 0; r < ss.size(); ++r) {
      for (const Evaluation* e : found[r]) answers[r].push_back(*e);
    }
    if (evaluated) ++round;  // rounds of memo hits only are not rounds
    return answers;
  };
  std::vector<std::thread> threads;
  for (auto& search : searches) threads.emplace_back([&search] { search->Run(); });
  std::exception_ptr error;
  try {
    rounds.Run(serve);
  } catch (...) {
    error = std::current_exception();
  }
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
  for (auto& search : searches) {
    if (search->error()) std::rethrow_exception(search->error());
  }
  // The result, in log order.
  std::sort(all.begin(), all.end(),
            [](const auto& a, const auto& b) { return a->index < b->index; });
  for (auto& e : all) result.evaluations.push_back(std::move(*e));
  // Recorded evaluations no search asked for again stay in the log (and count).
  for (size_t i = 0; i < result.evaluations.size(); ++i) {
    const Evaluation& e = result.evaluations[i];
    if (e.start == 0 && e.seq == 0) result.initial = static_cast<int>(i);
    if (result.best < 0 || e.objective < result.evaluations[result.best].objective) {
      result.best = static_cast<int>(i);
    }
  }
  result.complete = !options.shard.active();
  if (Ranks::root() && result.complete && result.initial >= 0 && result.best >= 0) {
    TestKillPoint("tune-searched");
    std::vector<std::string> warnings;
    WriteOutputs(job, dir, result, options, &warnings);
    for (const std::string& w : warnings) std::fprintf(stderr, "rabbit tune: warning: %s\n", w.c_str());
  }
  return result;
}

}  // namespace rabbit
