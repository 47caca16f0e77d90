// Evaluating tuning candidates (rabbit tune): the runs of every matching scenario's main variant
// of some suites (the job's, or its guard suites' required ones) under a candidate's overlay, dealt
// over MPI ranks by index and over threads within a rank (RunBatch), gathered back in order and
// scored (ScoreEvaluation, tuner.h).
#ifndef RABBIT_OPTIMIZERS_TUNE_EVALUATOR_H_
#define RABBIT_OPTIMIZERS_TUNE_EVALUATOR_H_

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/suite.h"
#include "tune_job.h"
#include "tuner.h"

namespace rabbit::tune_internal {

class Evaluator {
 public:
  // The job's suites, scenarios matching its filter.
  Evaluator(const TuneJob& job, int threads)
      : Evaluator(job, job.suites, job.filter, false, threads) {}
  // Other suites (e.g. the job's guards): scenarios matching `filter`, the required ones only
  // when `required_only`; the candidates' overlay is still the job's.
  Evaluator(const TuneJob& job, std::vector<std::string> suites, std::string filter,
            bool required_only, int threads)
      : job_(job),
        suites_(std::move(suites)),
        filter_(std::move(filter)),
        required_only_(required_only),
        threads_(threads) {}

  // Evaluates the candidates (on every rank, collectively): scores, terms and objective.
  std::vector<Evaluation> Evaluate(const std::vector<std::vector<double>>& xs);

 private:
  struct Candidate {
    std::vector<double> x;
    std::vector<Suite> suites;
    std::vector<BatchJob> jobs;
    std::vector<std::string> job_suite;  // suite name of each job
    std::string error;
  };

  std::unique_ptr<Candidate> Load(const std::vector<double>& x);
  static void Parse(const std::string& text, const std::vector<std::pair<size_t, size_t>>& items,
                    const std::vector<std::unique_ptr<Candidate>>& candidates,
                    std::vector<RunScore>* scores);

  const TuneJob& job_;
  std::vector<std::string> suites_;
  std::string filter_;
  bool required_only_;
  int threads_;
  GaitLibraryCache libraries_;
};

}  // namespace rabbit::tune_internal

#endif  // RABBIT_OPTIMIZERS_TUNE_EVALUATOR_H_
