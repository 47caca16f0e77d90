#include "tuner.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <thread>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/error.h"
#include "rabbit/io/output_ownership.h"
#include "rabbit/io/test_hooks.h"
#include "rabbit/scenario/suite.h"
#include "tune_evaluator.h"
#include "tune_guards.h"
#include "tune_log.h"
#include "rabbit/report/tune_report.h"
#include "tune_search.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;
using namespace tune_internal;  // NOLINT: the tuner's own parts

constexpr const char* kMarker = ".rabbit-tune";

std::string Join(const std::vector<std::string>& parts, const char* separator) {
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : separator) + p;
  return out;
}

void WriteOutputs(const TuneJob& job, const fs::path& dir, const TuneResult& result,
                  const TuneOptions& options, std::vector<std::string>* warnings) {
  const Evaluation& initial = result.evaluations[result.initial];
  // No best (no candidate kept the guards): no best.toml, and the best columns left empty.
  const Evaluation* best = result.best >= 0 ? &result.evaluations[result.best] : nullptr;
  if (best != nullptr) {
    const ParamOverlay overlay = job.Overlay(best->x);
    char summary[512];
    std::snprintf(summary, sizeof summary,
                  "objective %s at evaluation %d (search %d) against %s at the initial values",
                  ExactNumber(best->objective).c_str(), best->index, best->start,
                  ExactNumber(initial.objective).c_str());
    const std::string guards =
        job.guards.empty() ? "" : ".\nIt keeps the required scenarios of " + Join(job.guards, ", ");
    WriteFileAtomically((dir / "best.toml").string(), [&](std::ostream& out) {
      out << ParamOverlayToml(
          overlay, "rabbit tune " + job.name + " (" + job.file + "): the best of " +
                       std::to_string(result.evaluations.size()) + " evaluations, " + summary +
                       ".\n" + TuneAlgorithmName(job.algorithm) + ", seed " +
                       std::to_string(job.seed) + ", suites " + Join(job.suites, ", ") + guards +
                       ".\nUse: rabbit run --params best.toml SUITE");
    });
  }
  WriteFileAtomically((dir / "parameters.csv").string(), [&](std::ostream& out) {
    out << "path,lower,upper,initial,best\n";
    for (size_t i = 0; i < job.parameters.size(); ++i) {
      const TuneParameter& p = job.parameters[i];
      out << p.name << "," << ExactNumber(p.lower) << "," << ExactNumber(p.upper) << ","
          << ExactNumber(initial.x[i]) << ","
          << (best != nullptr ? ExactNumber(best->x[i]) : std::string("nan")) << "\n";
    }
  });
  WriteFileAtomically((dir / "comparison.csv").string(), [&](std::ostream& out) {
    out << "suite,scenario,initial_passed,best_passed";
    for (int t = 0; t < kNumTuneTerms; ++t) {
      out << ",initial_" << TuneTermName(t) << ",best_" << TuneTermName(t);
    }
    out << "\n";
    std::map<std::pair<std::string, std::string>, const RunScore*> at_best;
    if (best != nullptr) {
      for (const RunScore& s : best->scores) at_best[{s.suite, s.scenario}] = &s;
    }
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
    row("guards", Join(job.guards, ";"));
    row("evaluations", std::to_string(result.evaluations.size()));
    row("initial_eval", std::to_string(initial.index));
    row("best_eval", best != nullptr ? std::to_string(best->index) : "");
    row("initial_objective", ExactNumber(initial.objective));
    row("best_objective", best != nullptr ? ExactNumber(best->objective) : "nan");
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

TuneResult RunTune(const TuneJob& job, const TuneOptions& options) {
  TuneResult result;
  const fs::path out = options.out.empty() ? fs::path("reports") / job.name : fs::path(options.out);
  result.out = out.string();
  const fs::path dir =
      options.shard.active()
          ? out / "shards" /
                (std::to_string(options.shard.index) + "-of-" + std::to_string(options.shard.count))
          : out;
  // The folder: a fresh one, or this job's log to resume (or, with --force, to start over).
  std::string evaluations_text, runs_text;
  std::map<std::pair<int, int>, Evaluation> recorded;  // replayable, from this folder's log
  std::map<std::pair<int, int>, Evaluation> foreign;   // from other shards' logs (to re-log)
  std::string problem;
  OutputLock lock;  // rank 0's, on the folder it writes, until the last file is written
  RunAgreed([&] {   // rank 0 alone looks at the folder: a throw there must stop every rank
    if (!Ranks::root()) return;
    // Before the lock, which makes the folders above a shard's: not through a user's link.
    problem = SymbolicLinkRefusal(out, "a tuning job's folder");
    if (!problem.empty()) return;
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
      const std::string marker = ReadText(dir / kMarker, kMarkerFileLimits);
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
      evaluations_text = CompleteLines(ReadText(dir / "evaluations.csv", kCsvTableLimits));
      runs_text = CompleteLines(ReadText(dir / "runs.csv", kCsvTableLimits));
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
      if (ReadText(entry.path() / kMarker, kMarkerFileLimits).find(job.fingerprint) ==
          std::string::npos) {
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
        Ranks::root() ? CompleteLines(ReadText(p, kCsvTableLimits)) : std::string());
    const std::string ru = Ranks::Broadcast(
        Ranks::root() ? CompleteLines(ReadText(p.parent_path() / "runs.csv", kCsvTableLimits))
                      : std::string());
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
    searches.push_back(MakeSearch(job, s, StartPoint(job, s), budget, &rounds));
    by_start[s] = searches.back().get();
  }
  Evaluator evaluator(job, options.threads);
  GuardRunner guards(job, options.threads);
  // Per search: the lowest objective of its candidates eligible as best so far.
  std::map<int, double> best_eligible;
  for (int s : starts) best_eligible[s] = std::numeric_limits<double>::infinity();
  std::map<int, int> seq;                              // per search: requests evaluated
  std::map<int, std::vector<const Evaluation*>> memo;  // per search: its evaluations
  std::vector<std::unique_ptr<Evaluation>> all;        // log order
  int round = 0;
  auto serve = [&](const std::vector<int>& ss,
                   const std::vector<std::vector<std::vector<double>>>& xs) {
    std::vector<std::vector<Evaluation>> answers(ss.size());
    std::vector<std::vector<double>> fresh;           // to evaluate now
    std::vector<std::pair<size_t, size_t>> fresh_at;  // (request, candidate)
    std::vector<std::vector<const Evaluation*>> found(ss.size());
    // New in this folder's log this round, in request order: fresh ones and other shards' replays.
    std::vector<std::pair<Evaluation*, bool>> to_log;  // (evaluation, fresh)
    // Every candidate new to the searches this round (not a memo hit), in request order.
    std::vector<std::pair<Evaluation*, bool>> this_round;  // (evaluation, fresh)
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
          this_round.push_back({e.get(), false});
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
        this_round.push_back({e.get(), true});
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
    // Guards: every candidate of the round that beats its search's best eligible objective as it
    // stood before the round (one batch, whatever the round's order of finishing); replayed
    // candidates carry their recorded verdict, which must be the one the job would reach now.
    if (!job.guards.empty()) {
      std::vector<Evaluation*> to_guard;
      for (const auto& [e, is_fresh] : this_round) {
        const bool wanted = e->error.empty() && e->objective < kInvalidObjective &&
                            e->objective < best_eligible.at(e->start);
        if (is_fresh) {
          if (wanted) to_guard.push_back(e);
        } else if (wanted != e->guards_run) {
          throw InputError((dir / "evaluations.csv").string(), 0, "",
                           "the job no longer reproduces its log (search " +
                               std::to_string(e->start) + ", request " + std::to_string(e->seq) +
                               (wanted ? " needs" : " does not need") +
                               " its guards run): use --force to start over");
        }
      }
      if (!to_guard.empty()) {
        std::vector<std::vector<double>> gx;
        for (const Evaluation* e : to_guard) gx.push_back(e->x);
        const std::vector<std::string> broken = guards.Check(gx);
        for (size_t g = 0; g < to_guard.size(); ++g) {
          to_guard[g]->guards_run = true;
          to_guard[g]->guard_broken = broken[g];
        }
      }
    }
    for (const auto& [e, is_fresh] : this_round) {
      if (EligibleAsBest(job, *e)) {
        best_eligible.at(e->start) = std::min(best_eligible.at(e->start), e->objective);
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
    if (!EligibleAsBest(job, e)) continue;
    if (result.best < 0 || e.objective < result.evaluations[result.best].objective) {
      result.best = static_cast<int>(i);
    }
  }
  result.complete = !options.shard.active();
  if (Ranks::root() && result.complete && result.initial >= 0) {
    TestKillPoint("tune-searched");
    std::vector<std::string> warnings;
    WriteOutputs(job, dir, result, options, &warnings);
    for (const std::string& w : warnings)
      std::fprintf(stderr, "rabbit tune: warning: %s\n", w.c_str());
  }
  return result;
}

}  // namespace rabbit