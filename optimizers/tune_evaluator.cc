#include "tune_evaluator.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "rabbit/io/error.h"
#include "rabbit/scenario/ranks.h"

namespace rabbit {
namespace tune_internal {
namespace {

RunScore Score(const std::string& suite, const RunOutput& run) {
  RunScore s;
  s.suite = suite;
  s.scenario = run.scenario;
  s.passed = run.passed;
  s.outcome = OutcomeName(run.sim.outcome);
  const RunMetrics& m = run.metrics;
  s.value = {run.passed ? 0.0 : 1.0,
             m.mean_abs_speed_error,
             m.l_step_spread,
             m.energy,
             m.cost_of_transport,
             m.saturation,
             run.sim.outcome == Outcome::kCompleted ? 0.0 : 1.0};
  return s;
}

// One line per score: "k passed outcome v0 ... v6" (numbers exact), for the gather.
std::string Serialise(size_t k, const RunScore& s) {
  std::string line = std::to_string(k) + " " + (s.passed ? "1" : "0") + " " + s.outcome;
  for (double v : s.value) line += " " + ExactNumber(v);
  return line + "\n";
}

}  // namespace

std::vector<Evaluation> Evaluator::Evaluate(const std::vector<std::vector<double>>& xs) {
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

std::unique_ptr<Evaluator::Candidate> Evaluator::Load(const std::vector<double>& x) {
  auto c = std::make_unique<Candidate>();
  c->x = x;
  const ParamOverlay overlay = job_.Overlay(x);
  try {
    for (const std::string& path : suites_) c->suites.push_back(LoadSuite(path, &overlay));
    const NameFilter filter(filter_, "job.filter", filter_);
    for (const Suite& suite : c->suites) {
      for (const Scenario& s : suite.scenarios) {
        if (!filter.Matches(s.name) || (required_only_ && !s.required)) continue;
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

void Evaluator::Parse(const std::string& text, const std::vector<std::pair<size_t, size_t>>& items,
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

}  // namespace tune_internal

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

bool EligibleAsBest(const TuneJob& job, const Evaluation& e) {
  if (job.guards.empty()) return true;  // the lowest objective, whatever it is
  return e.error.empty() && e.objective < kInvalidObjective && e.guards_run &&
         e.guard_broken.empty();
}

}  // namespace rabbit
