// The HTML report of a tuning job (`rabbit tune JOB.toml`), built afterwards from the CSV files
// the job wrote, never from live objects, so that it can be rebuilt at any time (also for a job
// that stopped early: its files hold the evaluations so far).
//
// Input, the job's output folder DIR:
//   DIR/meta.csv         key,value: job, description, job_file, algorithm, seed, starts,
//                        max_evaluations, form, weights, suites, evaluations, initial_eval,
//                        best_eval, initial_objective, best_objective, complete, fingerprint
//   DIR/evaluations.csv  one row per candidate, in evaluation order: eval, round, start, seq,
//                        objective, the seven terms, runs, failed, one column per tuned parameter
//                        (named by its key path, as in parameters.csv), error, wall_s
//   DIR/runs.csv         one row per run of a candidate: eval, suite, scenario, passed, outcome,
//                        the seven terms
//   DIR/parameters.csv   path, lower, upper, initial, best
//   DIR/comparison.csv   suite, scenario, initial_passed, best_passed, initial_<term>,
//                        best_<term> for each of the seven terms
//   DIR/best.toml        the best parameters (shown verbatim; optional)
// The seven terms: failure_rate, speed_error, step_length_spread, energy, cost_of_transport,
// saturation_time, incomplete_rate (a log written before the last had none: read as NaN). An
// evaluation with an error, or an objective of at least 1e6 (the penalty of an invalid candidate),
// is invalid.
//
// Output, DIR/index.html: one self-contained page (inline CSS, figures as data: SVG images from
// one gnuplot process, nothing fetched): the job's header (algorithm, seed, budget, form,
// weights, suites, best against initial objective), the convergence plot, the parameter traces,
// best against initial per scenario, and the tables of parameters, of the comparison per
// scenario and of every evaluation.
#ifndef RABBIT_REPORT_TUNE_REPORT_H_
#define RABBIT_REPORT_TUNE_REPORT_H_

#include <string>
#include <vector>

namespace rabbit {

struct TuneReportOptions {
  std::string gnuplot = "gnuplot";  // the plotter's executable (searched on PATH without a '/')
  double timeout = 60.0;            // s; gnuplot is killed after this and the figures left out
  // A non-empty gnuplot without line breaks and a positive finite timeout.
  bool IsValid(std::string* error) const;
};

// Reads the job's files in dir and writes dir/index.html atomically. When gnuplot cannot be run
// (or fails) appends one warning to *warnings (may be null) and writes the page without figures:
// never a failure for that. Throws InputError (file, line, column or key) for a missing or
// malformed CSV file, or one that contradicts the others (an unknown evaluation, a parameter
// without its column), and std::invalid_argument for invalid options.
void WriteTuneReport(const std::string& dir, const TuneReportOptions& options,
                     std::vector<std::string>* warnings);

}  // namespace rabbit

#endif  // RABBIT_REPORT_TUNE_REPORT_H_
