#include "gait_build.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>
#include <tuple>

#include "gait_build_staging.h"
#include "gait_manifest.h"
#include "rabbit/gait/database_layout.h"
#include "rabbit/gait/walker_settings.h"
#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/error.h"
#include "rabbit/io/sha256.h"
#include "rabbit/io/test_hooks.h"
#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/params.h"
#include "rabbit/scenario/ranks.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace fs = std::filesystem;
namespace {

// Seconds of walking over which a synthesized gait is measured and recorded: at least 30 steps
// for the slowest gaits (t_step up to 0.65 s).
constexpr double kRecordWalk = 20.0;
constexpr int kRecordSteps = 30;                   // steps the recorded walk must take
constexpr double kAcceptedVelocityError = 0.03;    // m/s
constexpr double kAcceptedStepSpread = 0.01;       // m
constexpr double kAcceptedStepLengthError = 0.03;  // m
std::string ReadBytes(const std::string& path) { return ReadBoundedFile(path, kGaitFileLimits); }

void WriteBytes(const std::string& path, const std::string& bytes) {
  WriteFileAtomically(path, [&bytes](std::ostream& out) { out << bytes; });
}

// Every regular file below root, relative, '/'-separated, sorted.
std::vector<std::string> FilesBelow(const fs::path& root) {
  std::vector<std::string> files;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), root).generic_string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string ModelSha(const GaitTargets& targets) {
  if (targets.model_file.empty()) return "builtin:" + ModelHash(targets.model);
  return Sha256OfFile(targets.model_file);
}

// One synthesis's outcome, as it travels between ranks: "<index> <met> <walks>\n<gait file>".
struct SynthesisOutcome {
  size_t index = 0;
  bool met = false;
  int walks = 0;
  std::string text;  // the gait file (empty when no swing was recorded)
};
std::string Encode(const std::vector<SynthesisOutcome>& outcomes) {
  std::string s;
  for (const SynthesisOutcome& o : outcomes) {
    s += std::to_string(o.index) + " " + (o.met ? "1" : "0") + " " + std::to_string(o.walks) + " " +
         std::to_string(o.text.size()) + "\n" + o.text;
  }
  return s;
}
std::vector<SynthesisOutcome> Decode(const std::string& s) {
  std::vector<SynthesisOutcome> out;
  size_t pos = 0;
  while (pos < s.size()) {
    const size_t eol = s.find('\n', pos);
    std::istringstream head(s.substr(pos, eol - pos));
    SynthesisOutcome o;
    int met = 0;
    size_t size = 0;
    head >> o.index >> met >> o.walks >> size;
    o.met = met != 0;
    o.text = s.substr(eol + 1, size);
    pos = eol + 1 + size;
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace

bool SynthesizeReferenceGait(const SynthesisOptions& options, const ModelParams& params,
                             const std::string& name, bool quiet, GaitRecord* record, int* walks,
                             std::vector<std::string>* limits) {
  const Model model{params};
  SimSetup setup;
  setup.model = &model;
  setup.options.record_every = 0;
  const SynthesisResult r = SynthesizeGait(setup, options, [&](const SynthesisProgress& p) {
    if (quiet || (p.evaluation % 25 != 0)) return;
    std::fprintf(stderr, "  [%s %4d] best cost %.3g: %d steps, V_M %.3f m/s, L_step %.3f m\n",
                 p.stage, p.evaluation, p.best_cost, p.best.steps, p.best.v_m, p.best.l_step);
  });
  // Measure the result over a longer walk (the acceptance figures: at least 30 steps, last 10).
  SimSetup record_setup = setup;
  record_setup.options.record_every = 1;
  GaitRun run = WalkGait(record_setup, r.spec, kRecordWalk, 10);
  int recorded_walks = 1;
  double record_walk = kRecordWalk;
  if (!run.metrics.fell && run.metrics.steps > 12 && run.metrics.steps < kRecordSteps) {
    // A slow-stepping gait (t_step over 20 s / 30): walked for the time of 31 steps at its pace.
    record_walk = kRecordWalk * (kRecordSteps + 1) / run.metrics.steps;
    run = WalkGait(record_setup, r.spec, record_walk, 10);
    recorded_walks = 2;
  }
  if (walks != nullptr) *walks = r.walks + recorded_walks;
  record->name = name;
  record->target_v_m = options.target_v_m;
  record->target_l_step = options.target_l_step;
  record->measured = run.metrics;
  record->spec = r.spec;
  record->model_hash = ModelHash(model.params());
  record->source = "synthesized";
  record->seed = options.seed;
  record->swing = AverageSwingTrajectory(run, 10, 101);
  if (!quiet) {
    std::printf(
        "%s: %s after %d simulations (%d walked, %d of them ahead on %d threads; %.1f s, "
        "%.1f walks/s)\n",
        name.c_str(), r.success ? "criteria met" : "criteria NOT met", r.evaluations, r.walks,
        r.walks_ahead, options.threads, r.wall_seconds, r.walks / std::max(r.wall_seconds, 1e-9));
    std::printf(
        "  %d steps in %.0f s%s; last 10: V_M %.3f m/s (spread %.3f), L_step %.3f m "
        "(spread %.4f), t_step %.3f s\n",
        run.metrics.steps, record_walk,
        run.metrics.fell ? (" (" + run.metrics.reason + ")").c_str() : "", run.metrics.v_m,
        run.metrics.v_m_spread, run.metrics.l_step, run.metrics.l_step_spread, run.metrics.t_step);
  }
  // The acceptance on the recorded walk: 30 steps, the last 10 within 0.03 m/s of the
  // target, L_step varying by less than 1 cm (and within 0.03 m of a requested step length).
  const GaitMetrics& m = run.metrics;
  std::vector<std::string> missed = r.limits;
  if (r.success) {  // the search's criteria met: the acceptance of the recorded walk
    char text[200];
    if (m.fell || record->swing.empty()) {
      std::snprintf(text, sizeof text,
                    "the %.0f s walk of the found gait falls after %d steps (%s)", record_walk,
                    m.steps, m.reason.c_str());
      missed.push_back(text);
    } else if (m.steps < kRecordSteps) {
      std::snprintf(text, sizeof text,
                    "the found gait takes %d steps in %.0f s, fewer than the %d its record needs",
                    m.steps, record_walk, kRecordSteps);
      missed.push_back(text);
    } else {
      if (std::abs(m.v_m - options.target_v_m) > kAcceptedVelocityError) {
        std::snprintf(text, sizeof text, "over %.0f s, V_M %.3f m/s drifts %.3f from the target",
                      record_walk, m.v_m, m.v_m - options.target_v_m);
        missed.push_back(text);
      }
      if (!(m.l_step_spread < kAcceptedStepSpread)) {
        std::snprintf(text, sizeof text, "over %.0f s, L_step varies by %.4f m", record_walk,
                      m.l_step_spread);
        missed.push_back(text);
      }
      if (options.target_l_step > 0.0 &&
          std::abs(m.l_step - options.target_l_step) > kAcceptedStepLengthError) {
        std::snprintf(text, sizeof text, "over %.0f s, L_step %.3f m drifts %.3f from the target",
                      record_walk, m.l_step, m.l_step - options.target_l_step);
        missed.push_back(text);
      }
    }
  }
  if (!quiet && !missed.empty()) {
    std::printf("  what stops it:\n");
    for (const std::string& why : missed) std::printf("    - %s\n", why.c_str());
  }
  if (limits != nullptr) *limits = missed;
  return r.success && missed.empty();
}

std::string SimulatorSettingsText() {
  const SimSetup s;
  const ContactParams& c = s.contact;
  const ActuatorParams& a = s.actuator;
  const SimOptions& o = s.options;
  std::ostringstream t;
  t << "contact " << ExactNumber(c.k_n) << ' ' << ExactNumber(c.lambda_n) << ' '
    << ExactNumber(c.k_t) << ' ' << ExactNumber(c.lambda_t) << ' ' << ExactNumber(c.mu_s) << ' '
    << ExactNumber(c.lambda_g) << ' ' << ExactNumber(c.mu_g) << ' '
    << ExactNumber(c.resume_fraction) << "\nactuator " << ExactNumber(a.max_torque) << ' '
    << ExactNumber(a.max_power) << ' ' << ExactNumber(a.full_torque_speed) << ' '
    << ExactNumber(a.max_speed) << ' ' << a.enabled << "\noptions " << ExactNumber(o.control_period)
    << ' ' << o.contact << ' ' << o.restart_at_samples << ' ' << o.max_events_per_period
    << "\nintegrator " << static_cast<int>(o.integrator.kind) << ' '
    << ExactNumber(o.integrator.rtol) << ' ' << ExactNumber(o.integrator.atol) << ' '
    << ExactNumber(o.integrator.max_step) << ' ' << o.integrator.max_steps_per_call << ' '
    << o.integrator.order << "\nfall " << ExactNumber(o.fall.min_hip_height) << ' '
    << ExactNumber(o.fall.max_trunk_pitch) << ' ' << o.fall.enabled << "\nrecord "
    << ExactNumber(kRecordWalk) << ' ' << kRecordSteps << ' ' << ExactNumber(kAcceptedVelocityError)
    << ' ' << ExactNumber(kAcceptedStepSpread) << ' ' << ExactNumber(kAcceptedStepLengthError)
    << "\n";
  return t.str();
}

GaitBuildResult BuildGaitDatabase(const GaitTargets& targets, const GaitBuildOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  // The check suite runs on the built database, which its scenarios need; the file itself is read
  // now, so a missing or wrong one is named before the work, not after it.
  if (!targets.check_suite.empty()) {
    CheckNamedSuiteFile(targets.check_suite, targets.file, targets.check_line, "check.suite");
  }
  const fs::path out(options.out);
  const bool out_existed = fs::exists(fs::symlink_status(out));
  auto log = [&](const std::string& line) {
    if (options.log && Ranks::root()) options.log(line);
  };
  Manifest old;
  bool existing = false;
  std::map<std::string, SynthesizedGait> synthesized;  // the files on rank 0 only
  // Rank 0 first (it finishes a commit a killed build left), then the others read what it left.
  RunAgreed([&] {
    if (Ranks::root()) existing = InspectOut(out, &old, &synthesized);
  });
  RunAgreed([&] {
    if (!Ranks::root()) existing = InspectOut(out, &old, &synthesized);
  });
  {  // every rank deals the same targets: the names and inputs of rank 0's synthesized gaits
    std::string names;
    for (const auto& [name, gait] : synthesized) names += name + " " + gait.inputs_sha256 + "\n";
    std::istringstream in(Ranks::Broadcast(names));
    for (std::string name, inputs; in >> name >> inputs;) {
      if (synthesized.count(name) == 0) synthesized[name] = {inputs, ""};
    }
  }
  const std::string model_sha = ModelSha(targets);
  const std::string simulator_sha = Sha256Hex(SimulatorSettingsText());
  const std::string version = std::string("rabbit ") + RABBIT_VERSION;
  std::vector<std::string> inputs;
  for (const GaitTarget& g : targets.gaits) {
    inputs.push_back(Sha256Hex(TargetInputsText(g) + "model " + model_sha + "\nsimulator " +
                               simulator_sha + "\nversion " + version + "\n"));
  }
  // Which gaits are kept: the same name, inputs and (verified) file.
  std::map<std::string, const ManifestRow*> old_gaits;
  for (const ManifestRow& r : old.rows) {
    if (r.kind == "gait") old_gaits[r.name] = &r;
  }
  GaitBuildResult result;
  std::vector<size_t> todo;
  std::vector<char> kept(targets.gaits.size(), 0);
  std::vector<char> reused(targets.gaits.size(), 0);  // synthesized by an unfinished build
  for (size_t i = 0; i < targets.gaits.size(); ++i) {
    const std::string& name = targets.gaits[i].name;
    const auto found = old_gaits.find(name);
    kept[i] = existing && found != old_gaits.end() && found->second->inputs_sha256 == inputs[i] &&
              found->second->file == std::string(kReferenceDir) + "/" + name + ".csv";
    const auto left = synthesized.find(name);
    reused[i] = !kept[i] && left != synthesized.end() && left->second.inputs_sha256 == inputs[i];
    if (kept[i]) {
      result.kept.push_back(name);
    } else if (reused[i]) {
      result.reused.push_back(name);
    } else {
      todo.push_back(i);
    }
  }
  log("gaits build: " + std::to_string(targets.gaits.size()) + " targets, " +
      std::to_string(result.kept.size()) + " kept, " +
      (result.reused.empty()
           ? std::string()
           : std::to_string(result.reused.size()) + " synthesized by an unfinished build, ") +
      std::to_string(todo.size()) + " to synthesize (" + std::to_string(Ranks::size()) +
      " rank(s))");
  // Synthesis: item k of todo on rank k mod size, on this rank's threads.
  std::vector<size_t> mine;
  for (size_t k = 0; k < todo.size(); ++k) {
    if (static_cast<int>(k % Ranks::size()) == Ranks::rank()) mine.push_back(todo[k]);
  }
  std::vector<SynthesisOutcome> outcomes(mine.size());
  std::vector<std::string> errors(mine.size());
  const auto synthesis_start = std::chrono::steady_clock::now();
  {
    std::atomic<size_t> next{0};
    std::mutex print;
    auto worker = [&] {
      for (size_t k = next++; k < mine.size(); k = next++) {
        const GaitTarget& g = targets.gaits[mine[k]];
        GaitRecord record;
        SynthesisOutcome& o = outcomes[k];
        o.index = mine[k];
        std::vector<std::string> limits;
        try {
          o.met = SynthesizeReferenceGait(g.synthesis, targets.model, g.name, true, &record,
                                          &o.walks, &limits);
          record.role = g.role;
          if (!record.swing.empty()) o.text = GaitFileText(record);
        } catch (const std::exception& e) {
          errors[k] = e.what();
        }
        std::lock_guard<std::mutex> lock(print);
        if (options.log) {
          char line[256];
          std::snprintf(line, sizeof line,
                        "%s: %s; %d steps, V_M %.3f m/s, L_step %.3f m (spread %.4f), %d walks",
                        g.name.c_str(), o.met ? "criteria met" : "criteria NOT met",
                        record.measured.steps, record.measured.v_m, record.measured.l_step,
                        record.measured.l_step_spread, o.walks);
          options.log(line);
          if (!o.met) {
            for (const std::string& why : limits) options.log("  what stops it: " + why);
          }
        }
      }
    };
    const int threads =
        std::max(1, std::min<int>(static_cast<int>(std::max<size_t>(mine.size(), 1)),
                                  ThreadsPerRank(options.threads)));
    std::vector<std::thread> pool;
    for (int j = 0; j < threads; ++j) pool.emplace_back(worker);
    for (std::thread& t : pool) t.join();
  }
  // A failed synthesis on one rank fails every rank (none is left waiting in the gather below).
  RunAgreed([&] {
    for (size_t k = 0; k < mine.size(); ++k) {
      if (!errors[k].empty()) {
        throw std::runtime_error(targets.gaits[mine[k]].name + ": " + errors[k]);
      }
    }
  });
  // Gather every rank's outcomes on rank 0.
  std::vector<SynthesisOutcome> all;
  const std::vector<std::string> gathered = Ranks::Gather(Encode(outcomes));
  if (Ranks::size() == 1) {
    all = outcomes;
  } else {
    for (const std::string& s : gathered) {
      for (SynthesisOutcome& o : Decode(s)) all.push_back(std::move(o));
    }
  }
  result.synthesis_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - synthesis_start).count();
  if (Ranks::root()) TestKillPoint("gaits-build-synthesized");
  std::map<size_t, const SynthesisOutcome*> by_index;
  for (const SynthesisOutcome& o : all) {
    by_index[o.index] = &o;
    result.walks += o.walks;
  }
  int code = 0;
  RunAgreed([&] {
    if (!Ranks::root()) return;
    const fs::path staging = out / kStagingDir;
    fs::remove_all(staging);
    fs::create_directories(staging / kReferenceDir);
    std::vector<GaitRecord> records;
    std::map<std::string, GaitWalkerSettings> walker;
    std::map<std::string, std::string> inputs_of;
    std::map<std::string, SynthesizedGait> built;  // by this build or an unfinished one
    for (size_t i = 0; i < targets.gaits.size(); ++i) {
      const GaitTarget& g = targets.gaits[i];
      const std::string file = std::string(kReferenceDir) + "/" + g.name + ".csv";
      if (kept[i]) {
        WriteBytes((staging / file).string(), ReadBytes((out / file).string()));
      } else if (reused[i]) {
        built[g.name] = synthesized.at(g.name);
        WriteBytes((staging / file).string(), built[g.name].text);
        result.built.push_back(g.name);
      } else {
        const SynthesisOutcome* o = by_index.at(i);
        if (!o->met) {
          result.missed.push_back(g.name);  // nothing written for it
          continue;
        }
        built[g.name] = {inputs[i], o->text};
        WriteBytes((staging / file).string(), o->text);
        result.built.push_back(g.name);
      }
      records.push_back(ReadGaitFile((staging / file).string()));
      walker[g.name] = g.walker;
      inputs_of[g.name] = inputs[i];
    }
    // What the steps below may still stop on (a check suite's settings, the speed gaits' measured
    // order) leaves the synthesis to the next build.
    WriteSynthesizedList(staging, built);
    if (options.staged != nullptr) *options.staged = true;
    const auto speed_gaits = std::count_if(records.begin(), records.end(), [](const GaitRecord& g) {
      return g.role == GaitRole::kSpeed;
    });
    if (speed_gaits < 2) {  // the fuzzy system blends at least 2 speed gaits
      fs::remove_all(staging);
      // Nothing is written: a folder the build made for its staging goes too.
      std::error_code ec;
      if (!out_existed) fs::remove(out, ec);
      result.too_few_speed_gaits = true;
      return;
    }
    // The index as AddGaitToDatabase keeps it: the speed gaits first, by target velocity, then
    // the library gaits by target velocity and step length (so the speed gaits' networks and the
    // fuzzy system's outputs come first).
    std::vector<GaitIndexEntry> index;
    for (const GaitRecord& g : records) {
      index.push_back({g.name, g.name + ".csv", g.source, g.target_v_m, g.measured.v_m,
                       g.measured.l_step, g.measured.t_step, g.measured.steps, g.role,
                       g.target_l_step});
    }
    std::sort(index.begin(), index.end(), [](const GaitIndexEntry& a, const GaitIndexEntry& b) {
      return std::make_tuple(a.role, a.target_v_m, a.target_l_step, a.name) <
             std::make_tuple(b.role, b.target_v_m, b.target_l_step, b.name);
    });
    WriteGaitIndex(index, (staging / kReferenceDir / kIndexFile).string());
    std::vector<GaitRecord> ordered;
    for (const GaitIndexEntry& e : index) {
      for (const GaitRecord& g : records) {
        if (g.name == e.name) ordered.push_back(g);
      }
    }
    WriteGaitNetworks(TrainGaitNetworks(ordered, options.training),
                      (staging / kNetworksDir).string());
    TestKillPoint("gaits-build-networks");
    WriteDefaultGaitPattern((staging / kReferenceDir).string(),
                            (staging / kGaitPatternFile).string());
    TestKillPoint("gaits-build-fll");
    WriteWalkerSettings(walker, (staging / kWalkerSettingsFile).string());
    // The check: the targets' suite on the new database; each required scenario must pass.
    if (!targets.check_suite.empty()) {
      ParamOverlay overlay;
      overlay.gait_database = staging.string();
      const Suite suite = LoadSuite(targets.check_suite, &overlay);
      std::vector<BatchJob> jobs;
      for (const Scenario& s : suite.scenarios) jobs.push_back({&s, ScenarioVariants(s)[0]});
      RunBatch(jobs, ThreadsPerRank(options.threads), nullptr, [&](size_t k, RunOutput&& run) {
        if (!run.passed && jobs[k].scenario->required) {
          result.check_failures.push_back(run.run + " (" + OutcomeName(run.sim.outcome) + ")");
        }
      });
      std::sort(result.check_failures.begin(), result.check_failures.end());
    }
    RemoveSynthesizedList(staging);  // not part of the database
    if (options.staged != nullptr) *options.staged = false;
    Manifest manifest;
    manifest.generator = version;
    manifest.model_sha256 = model_sha;
    manifest.simulator_sha256 = simulator_sha;
    for (const std::string& file : FilesBelow(staging)) {
      ManifestRow row{"file", "", file, Sha256OfFile((staging / file).string()), "", ""};
      const std::string prefix = std::string(kReferenceDir) + "/";
      if (file.rfind(prefix, 0) == 0 && file != prefix + kIndexFile) {
        row.kind = "gait";
        row.name = file.substr(prefix.size(), file.size() - prefix.size() - 4);
        for (const GaitTarget& g : targets.gaits) {
          if (g.name == row.name) row.seed = std::to_string(g.synthesis.seed);
        }
        row.inputs_sha256 = inputs_of.at(row.name);
      }
      manifest.rows.push_back(row);
    }
    WriteBytes((staging / kManifestFile).string(), ManifestText(manifest));
    TestKillPoint("gaits-build-manifest");
    std::set<std::string> old_files;
    for (const ManifestRow& r : old.rows) old_files.insert(r.file);
    CommitStaging(out, old_files);
    TestKillPoint("gaits-build-committed");
  });
  code =
      result.missed.empty() && result.check_failures.empty() && !result.too_few_speed_gaits ? 0 : 1;
  result.code = std::stoi(Ranks::Broadcast(std::to_string(code)));
  result.wall_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace rabbit
