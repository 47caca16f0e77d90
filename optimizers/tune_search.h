// The searches of a tuning job (rabbit tune) and the rounds that serve them:
//
//   - `starts` searches run side by side, each in its own thread (NLopt or Ceres drive it through
//     a callback) and each with its share of the budget;
//   - a round holds the next request of every search still running (Ceres asks for a point and
//     its forward differences at once), so the rounds, and therefore the results, are the same
//     whatever the number of threads or ranks.
#ifndef RABBIT_OPTIMIZERS_TUNE_SEARCH_H_
#define RABBIT_OPTIMIZERS_TUNE_SEARCH_H_

#include <condition_variable>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "tune_job.h"
#include "tuner.h"

namespace rabbit::tune_internal {

struct Aborted {};  // thrown into a search's thread when the job stops

// Rounds: the searches' requests, gathered in lockstep.
class Rounds {
 public:
  using Serve = std::function<std::vector<std::vector<Evaluation>>(
      const std::vector<int>& starts, const std::vector<std::vector<std::vector<double>>>& xs)>;

  explicit Rounds(const std::vector<int>& starts);

  // From search s's thread: blocks until its candidates are evaluated.
  std::vector<Evaluation> Submit(int s, std::vector<std::vector<double>> xs);
  void Finish(int s);

  // From the main thread: serves rounds until every search has finished.
  void Run(const Serve& serve);
  void Abort();

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

// A search: one NLopt or Ceres optimisation in its own thread, asking the rounds for evaluations.
class Search {
 public:
  virtual ~Search() = default;
  // The search's thread: runs the optimisation to its end (or until the rounds abort).
  virtual void Run() = 0;
  // What stopped the search, if it failed.
  virtual std::exception_ptr error() const = 0;
  // Charges the budget for evaluations the rounds ran (told by the rounds; memo hits are free).
  virtual void Charge(int n) = 0;
};

// Search number `start` of the job from x0, with `budget` evaluations.
std::unique_ptr<Search> MakeSearch(const TuneJob& job, int start, std::vector<double> x0,
                                   int budget, Rounds* rounds);

// Start points: search 0 at the initial values, the others uniform in the bounds (seeded).
std::vector<double> StartPoint(const TuneJob& job, int start);

}  // namespace rabbit::tune_internal

#endif  // RABBIT_OPTIMIZERS_TUNE_SEARCH_H_
