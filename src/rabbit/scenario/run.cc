#include "rabbit/scenario/run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "rabbit/control/pragmatic_rules.h"
#include "rabbit/control/step_planner.h"
#include "rabbit/io/error.h"
#include "rabbit/learn/fll.h"
#include "rabbit/learn/gait_pattern.h"
#include "rabbit/scenario/stall_watch.h"

namespace rabbit {
namespace {

const char* MainVariant(const Scenario& s) {
  switch (s.controller) {
    case ControllerKind::kFuzzyCmac:
      return "fuzzy_cmac";
    case ControllerKind::kPragmatic:
      return "pragmatic";
    case ControllerKind::kPdHold:
      return "pd_hold";
    case ControllerKind::kPassive:
      break;
  }
  return "passive";
}

// "d_obs set/V_M set:activation;..." for the rules that fired.
std::string FiringRules(const TsFis& fis, const std::vector<double>& activation) {
  int v_m = 0, d_obs = 1;
  if (fis.inputs.size() == 2 && fis.inputs[0].name == "d_obs") std::swap(v_m, d_obs);
  std::string out;
  for (size_t r = 0; r < fis.rules.size() && r < activation.size(); ++r) {
    if (activation[r] <= 0.0) continue;
    const std::vector<int>& a = fis.rules[r].antecedent;
    char value[32];
    std::snprintf(value, sizeof value, ":%.3f", activation[r]);
    if (!out.empty()) out += ';';
    out += fis.inputs[d_obs].sets[a[d_obs]].name + "/" + fis.inputs[v_m].sets[a[v_m]].name + value;
  }
  return out;
}

bool Measured(const StepRow& s) { return s.step.t_step > 0.0; }

// A walking controller (the pragmatic rules or the walker, and every variant of such a scenario):
// the stall watch and the travel criterion apply to it. Standing (passive, pd_hold) is not walking.
bool Walking(const Scenario& s) {
  return s.controller == ControllerKind::kPragmatic || s.controller == ControllerKind::kFuzzyCmac;
}

// Simulates the scenario with `controller`, under the stall watch when the scenario walks.
SimResult SimulateRun(const Scenario& scenario, const SimSetup& setup, Controller* controller) {
  if (!Walking(scenario) || !scenario.criteria.stall.enabled()) {
    return Simulate(setup, scenario.q0, scenario.qd0, controller);
  }
  StallWatch watch(controller, scenario.criteria.stall);
  return Simulate(setup, scenario.q0, scenario.qd0, &watch);
}

// Exact text of the numbers that decide a multi-input CMAC pattern: the fuzzy system (sets,
// rules, output values), the domain and the options (hexadecimal floats: no two settings share a
// key).
std::string MultiCmacKey(const TsFis& fis, const MultiCmacPatternDomain& d,
                         const MultiCmacPatternOptions& o) {
  std::string key;
  auto add = [&key](double v) {
    char text[40];
    std::snprintf(text, sizeof text, "%a ", v);
    key += text;
  };
  for (const FuzzyInput& input : fis.inputs) {
    key += input.name + (input.lock_range ? " locked " : " ");
    add(input.min);
    add(input.max);
    for (const FuzzySet& set : input.sets) {
      const Membership& m = set.membership;
      key += std::to_string(static_cast<int>(m.shape)) + " ";
      for (double v : {m.a, m.b, m.c, m.d}) add(v);
    }
  }
  key += "| ";
  for (const FuzzyRule& r : fis.rules) {
    for (int a : r.antecedent) key += std::to_string(a) + " ";
    key += "-> " + std::to_string(r.consequent) + " ";
  }
  for (double v : fis.output_values) add(v);
  key += "| ";
  key += d.thigh_frame ? "thigh " : "joint ";
  for (double v : {d.e_min, d.e_max, d.v_m_min, d.v_m_max, d.d_obs_max}) add(v);
  key += "| ";
  for (int v :
       {o.layers, o.e_width, o.v_m_width, o.d_obs_width, o.hash_table_size, o.max_iterations}) {
    key += std::to_string(v) + " ";
  }
  key += std::to_string(o.hash_seed) + " ";
  for (double v : {o.e_quantum, o.v_m_quantum, o.d_obs_quantum, o.v_m_margin, o.grid_e_step,
                   o.grid_v_m_step, o.grid_d_obs_step, o.ridge, o.tolerance}) {
    add(v);
  }
  return key;
}

}  // namespace

std::shared_ptr<const MultiCmacPattern> MultiCmacPatternCache::Get(
    const FuzzyCmac& teacher, const MultiCmacPatternDomain& domain,
    const MultiCmacPatternOptions& options, MultiCmacTrainingSummary* summary) {
  const std::string key = MultiCmacKey(teacher.fis(), domain, options);
  std::shared_ptr<Entry> entry;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::shared_ptr<Entry>& slot = entries_[key];
    if (slot == nullptr) {
      slot = std::make_shared<Entry>();
      order_.push_back(key);
    }
    entry = slot;
    if (order_.size() > kMaxPatterns) {  // callers holding the oldest keep it alive
      entries_.erase(order_.front());
      order_.erase(order_.begin());
    }
  }
  std::lock_guard<std::mutex> lock(entry->mutex);
  if (entry->pattern == nullptr) {
    MultiCmacTrainingSummary trained;
    entry->pattern = std::make_shared<const MultiCmacPattern>(
        TrainMultiCmacPattern(teacher, domain, options, &trained));
    entry->summary = trained;
    std::lock_guard<std::mutex> count(mutex_);
    ++trainings_;
  }
  if (summary != nullptr) *summary = entry->summary;
  return entry->pattern;
}

int MultiCmacPatternCache::trainings() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return trainings_;
}

std::shared_ptr<const MultiCmacPattern> MultiCmacBaseline(const Scenario& scenario,
                                                          const GaitLibrary& library,
                                                          MultiCmacTrainingSummary* summary) {
  try {
    const FuzzyCmac teacher =
        scenario.fis ? library.pattern.WithFis(*scenario.fis) : library.pattern;
    std::vector<double> velocities;
    for (const GaitRecord& g : library.gaits) velocities.push_back(g.measured.v_m);
    const MultiCmacPatternDomain domain =
        TeacherDomain(teacher, velocities, scenario.walker.thigh_frame, scenario.walker.d_obs_max,
                      scenario.multi_cmac.v_m_margin);
    return library.multi_cmac->Get(teacher, domain, scenario.multi_cmac, summary);
  } catch (const std::invalid_argument& e) {
    throw InputError(scenario.file, 0, "controller.multi_cmac", e.what());
  }
}

std::shared_ptr<const GaitLibrary> LoadGaitLibrary(const GaitPatternFiles& files) {
  namespace fs = std::filesystem;
  std::vector<std::string> names;
  std::vector<GaitCmacs> networks = LoadGaitNetworks(files.networks, &names);
  TsFis fis = LoadFll(files.fll);
  const std::string index_path = (fs::path(files.gaits) / "index.csv").string();
  const std::vector<GaitIndexEntry> index = ReadGaitIndex(index_path);
  std::vector<GaitRecord> gaits;
  std::vector<double> pitches;
  // The walker blends the speed gaits only: the networks of library gaits (other step lengths,
  // for a step planner) are left out, so that the gait pattern's N_r gaits are the speed gaits.
  std::vector<GaitCmacs> speed_networks;
  std::vector<std::string> speed_names;
  for (size_t k = 0; k < names.size(); ++k) {
    const std::string& name = names[k];
    const auto entry = std::find_if(index.begin(), index.end(),
                                    [&name](const GaitIndexEntry& e) { return e.name == name; });
    if (entry == index.end()) {
      throw InputError(index_path, 0, name,
                       "the networks in " + files.networks + " learnt gait \"" + name +
                           "\", which the gait database does not list");
    }
    if (entry->role != GaitRole::kSpeed) continue;
    gaits.push_back(ReadGaitFile((fs::path(files.gaits) / entry->file).string()));
    pitches.push_back(gaits.back().spec.rules.q0_d);
    speed_networks.push_back(std::move(networks[k]));
    speed_names.push_back(name);
  }
  networks = std::move(speed_networks);
  names = std::move(speed_names);
  try {
    auto library = std::make_shared<GaitLibrary>(
        GaitLibrary{files, FuzzyCmac(std::move(fis), std::move(networks)), names, gaits});
    library->pattern.SetTrunkPitches(pitches);
    return library;
  } catch (const std::invalid_argument& e) {
    throw InputError(files.fll, 0, "",
                     std::string(e.what()) + " (networks: " + files.networks + ")");
  }
}

std::shared_ptr<const GaitLibrary> GaitLibraryCache::Get(const GaitPatternFiles& files) {
  namespace fs = std::filesystem;
  const std::string key = fs::weakly_canonical(files.fll).string() + "\n" +
                          fs::weakly_canonical(files.networks).string() + "\n" +
                          fs::weakly_canonical(files.gaits).string();
  std::lock_guard<std::mutex> lock(mutex_);
  auto found = loaded_.find(key);
  if (found != loaded_.end()) return found->second;
  std::shared_ptr<const GaitLibrary> library = LoadGaitLibrary(files);
  loaded_[key] = library;
  return library;
}

std::vector<std::string> ScenarioVariants(const Scenario& scenario) {
  std::vector<std::string> variants = {MainVariant(scenario)};
  for (const std::string& b : scenario.baselines) variants.push_back(b);
  return variants;
}

std::string RunName(const Scenario& scenario, const std::string& variant) {
  return variant == MainVariant(scenario) ? scenario.name : scenario.name + "+" + variant;
}

RunOutput RunScenario(const Scenario& scenario, const std::string& variant,
                      const GaitLibrary* library) {
  const auto start = std::chrono::steady_clock::now();
  RunOutput out;
  out.scenario = scenario.name;
  out.variant = variant;
  out.run = RunName(scenario, variant);
  out.controller = variant;
  out.family = scenario.family;
  out.required = scenario.required && variant == MainVariant(scenario);
  const Model model(scenario.model);
  const SimSetup setup = MakeSimSetup(scenario, &model);
  const bool walker = variant == "fuzzy_cmac" || variant == "nearest_gait" ||
                      variant == "multi_cmac" || variant == "chapter";
  if ((walker || scenario.controller == ControllerKind::kFuzzyCmac) && library == nullptr) {
    throw std::invalid_argument("RunScenario: walker scenarios need their gait library");
  }
  std::size_t pattern_memory = 0;
  if (walker) {
    // The baseline "chapter": the chapter preset's walker on the same gait pattern.
    WalkerParams params = variant == "chapter" ? scenario.chapter_walker : scenario.walker;
    params.log_every = scenario.options.record_every;
    params.gait_rules.clear();
    for (const GaitRecord& g : library->gaits) params.gait_rules.push_back(g.spec.rules);
    params.gait_l_steps.clear();
    for (const GaitRecord& g : library->gaits) params.gait_l_steps.push_back(g.measured.l_step);
    params.gait_pitches.clear();
    for (const GaitRecord& g : library->gaits) {
      params.gait_pitches.push_back({g.measured.v_m, g.spec.rules.q0_d});
    }
    if (params.planner.enabled && variant != "multi_cmac") {
      // The step planner blends the gaits by their step lengths: name the database they came from.
      try {
        (void)StepLengthFis(params.gait_l_steps);
      } catch (const std::invalid_argument& e) {
        throw InputError((std::filesystem::path(library->files.gaits) / "index.csv").string(), 0,
                         "measured_l_step_m",
                         std::string(e.what()) + " for the step planner of scenario \"" +
                             scenario.name + "\" (" + scenario.file + ", controller.planner)");
      }
    }
    // The database's per-gait settings, in the gait pattern's order (all 0: none, the chapter's
    // walker).
    params.rule_share.clear();
    bool any_share = false;
    for (const std::string& name : library->gait_names) {
      const auto found = scenario.gait_settings.find(name);
      const double share = found == scenario.gait_settings.end() ? 0.0 : found->second.rule_share;
      params.rule_share.push_back(share);
      any_share = any_share || share != 0.0;
    }
    if (!any_share) params.rule_share.clear();
    std::unique_ptr<SwingPattern> pattern;
    if (variant == "multi_cmac") {
      // The pure multi-input CMAC pattern: it has no per-gait weights to share the gaits' own
      // rules by (rule_share), so its swing is the pattern's alone.
      params.rule_share.clear();
      params.gait_rules.clear();
      params.planner.enabled = false;  // and no step planner (it sets per-gait weights too)
      pattern = std::make_unique<MultiCmacSwingPattern>(MultiCmacBaseline(scenario, *library));
    } else {
      pattern = std::make_unique<FuzzyCmacSwingPattern>(
          scenario.fis ? library->pattern.WithFis(*scenario.fis) : library->pattern,
          variant == "nearest_gait");
    }
    pattern_memory = pattern->MemoryBytes();
    FuzzyCmacWalker controller(params, std::move(pattern), scenario.velocity, 0);
    out.sim = SimulateRun(scenario, setup, &controller);
    // A pattern without per-gait weights (multi_cmac) reports NaN weights, so that steps.csv has
    // the columns of the other variants.
    const std::vector<double> no_weights(library->gait_names.size(),
                                         std::numeric_limits<double>::quiet_NaN());
    out.weight_gaits = library->gait_names;
    for (const WalkerStep& w : controller.steps()) {
      out.steps.push_back({w.step, w.v_d, w.v_m_used, w.d_obs, w.q0_d,
                           w.weights.empty() ? no_weights : w.weights,
                           FiringRules(library->pattern.fis(), w.activation), w.warmup});
    }
    out.tracking = controller.tracking();
  } else if (variant == "pragmatic") {
    // The pragmatic rules of the start gait (for a walker scenario) or of the scenario's gait.
    const PragmaticParams& rules = scenario.walking.rules;
    PragmaticController controller(rules, 0);
    out.sim = SimulateRun(scenario, setup, &controller);
    std::vector<double> weights;
    if (library != nullptr) {
      for (const std::string& name : library->gait_names) {
        weights.push_back(name == scenario.start_gait ? 1.0 : 0.0);
      }
      out.weight_gaits = library->gait_names;
    }
    const double d_max = scenario.walker.d_obs_max;
    for (const StepRecord& s : controller.meter().steps()) {
      const double v_d = scenario.has_velocity ? scenario.velocity.At(s.t_touchdown)
                                               : std::numeric_limits<double>::quiet_NaN();
      out.steps.push_back({s, v_d, s.v_m, ObstacleDistance(scenario.terrain, s.x, d_max),
                           rules.q0_d, weights, "", false});
    }
  } else {
    std::unique_ptr<Controller> controller = MakeController(scenario);
    out.sim = SimulateRun(scenario, setup, controller.get());
  }
  out.metrics = ComputeMetrics(scenario, model, out.sim, out.steps);
  out.metrics.pattern_memory_bytes = pattern_memory;
  EvaluateCriteria(scenario, &out);
  out.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

RunMetrics ComputeMetrics(const Scenario& scenario, const Model& model, const SimResult& sim,
                          const std::vector<StepRow>& steps) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  RunMetrics m;
  m.duration = sim.t_end;
  m.distance = sim.last.q[kX] - scenario.q0[kX];  // whatever was recorded
  m.steps = static_cast<int>(steps.size());
  for (int j = 0; j < kNumJoints; ++j) {
    m.saturation += sim.saturation_time(j, scenario.options.control_period);
  }
  m.energy = sim.positive_work;
  m.cost_of_transport = m.distance > 0.1
                            ? m.energy / (model.total_mass() * model.params().gravity * m.distance)
                            : nan;
  std::vector<const StepRow*> measured;
  for (const StepRow& s : steps) {
    if (Measured(s)) measured.push_back(&s);
  }
  if (measured.empty()) {
    m.mean_abs_speed_error = m.final_abs_speed_error = nan;
    m.l_step_mean = m.l_step_min = m.l_step_max = m.l_step_spread = nan;
    return m;
  }
  m.l_step_min = std::numeric_limits<double>::infinity();
  m.l_step_max = -m.l_step_min;
  for (const StepRow* s : measured) {
    m.mean_abs_speed_error += std::abs(s->step.v_m - s->v_d) / static_cast<double>(measured.size());
    m.l_step_mean += s->step.l_step / static_cast<double>(measured.size());
    m.l_step_min = std::min(m.l_step_min, s->step.l_step);
    m.l_step_max = std::max(m.l_step_max, s->step.l_step);
  }
  const size_t n = measured.size();
  const double stride = n >= 2 ? 0.5 * (measured[n - 1]->step.v_m + measured[n - 2]->step.v_m)
                               : measured[n - 1]->step.v_m;
  m.final_abs_speed_error = std::abs(stride - measured[n - 1]->v_d);
  const size_t window = std::min(n, static_cast<size_t>(scenario.criteria.spread_steps));
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (size_t i = n - window; i < n; ++i) {
    lo = std::min(lo, measured[i]->step.l_step);
    hi = std::max(hi, measured[i]->step.l_step);
  }
  m.l_step_spread = hi - lo;
  return m;
}

double VelocityIntegral(const VelocityProfile& velocity, double t_end) {
  if (!(t_end > 0.0)) return 0.0;
  // V_d is linear (ramp) or constant (steps, constant) between consecutive breakpoints, where the
  // midpoint rule is exact.
  std::vector<double> breaks = {0.0};
  for (const auto& point : velocity.points) {
    if (point.first > 0.0 && point.first < t_end) breaks.push_back(point.first);
  }
  breaks.push_back(t_end);
  double sum = 0.0;
  for (size_t i = 1; i < breaks.size(); ++i) {
    const double a = breaks[i - 1], b = breaks[i];
    if (b > a) sum += velocity.At(0.5 * (a + b)) * (b - a);
  }
  return sum;
}

void EvaluateCriteria(const Scenario& scenario, RunOutput* run) {
  const PassCriteria& c = scenario.criteria;
  std::vector<std::string>& fail = run->failures;
  char text[256];
  const std::string outcome = OutcomeName(run->sim.outcome);
  if (!scenario.expected_outcome.empty() && outcome != scenario.expected_outcome) {
    fail.push_back("outcome " + outcome + " (expected " + scenario.expected_outcome + ")" +
                   (run->sim.reason.empty() ? "" : ": " + run->sim.reason));
  }
  // Steps of the scenario's own controller: the warm-up's pragmatic steps do not count.
  int own_steps = 0, warmup_steps = 0;
  for (const StepRow& s : run->steps) (s.warmup ? warmup_steps : own_steps) += 1;
  if (own_steps < c.min_steps) {
    std::snprintf(text, sizeof text, "%d steps%s (at least %d required)", own_steps,
                  warmup_steps > 0 ? " after the warm-up" : "", c.min_steps);
    fail.push_back(text);
  }
  const double stop = scenario.options.stop_distance;
  if (std::isfinite(stop) && run->sim.outcome == Outcome::kCompleted &&
      !(run->metrics.distance >= stop)) {
    std::snprintf(text, sizeof text, "walked %.2f m of its %.2f m before the time limit (%.0f s)",
                  run->metrics.distance, stop, scenario.options.duration);
    fail.push_back(text);
  }
  if (c.min_distance > 0.0 && !(run->metrics.distance >= c.min_distance)) {
    std::snprintf(text, sizeof text, "walked %.2f m (at least %.2f m required)",
                  run->metrics.distance, c.min_distance);
    fail.push_back(text);
  }
  std::vector<const StepRow*> measured;
  for (const StepRow& s : run->steps) {
    if (Measured(s)) measured.push_back(&s);
  }
  if (std::isfinite(c.max_l_step_spread)) {
    if (static_cast<int>(measured.size()) < c.spread_steps) {
      std::snprintf(text, sizeof text, "only %zu measured steps for the L_step spread (need %d)",
                    measured.size(), c.spread_steps);
      fail.push_back(text);
    } else if (!(run->metrics.l_step_spread <= c.max_l_step_spread)) {
      std::snprintf(text, sizeof text,
                    "L_step spread %.4f m over the last %d steps (at most %.4f m)",
                    run->metrics.l_step_spread, c.spread_steps, c.max_l_step_spread);
      fail.push_back(text);
    }
  }
  if (c.min_l_step > 0.0) {
    if (static_cast<int>(measured.size()) < c.spread_steps) {
      std::snprintf(text, sizeof text, "only %zu measured steps for the final L_step (need %d)",
                    measured.size(), c.spread_steps);
      fail.push_back(text);
    } else {
      double sum = 0.0;
      for (size_t i = measured.size() - c.spread_steps; i < measured.size(); ++i) {
        sum += measured[i]->step.l_step;
      }
      const double mean = sum / c.spread_steps;
      if (!(mean >= c.min_l_step)) {
        std::snprintf(text, sizeof text,
                      "mean L_step %.3f m over the last %d steps (at least %.3f m required)", mean,
                      c.spread_steps, c.min_l_step);
        fail.push_back(text);
      }
    }
  }
  if (std::isfinite(c.speed_tolerance)) {
    int checked = 0, off = 0;
    double worst = 0.0, worst_t = 0.0;
    for (size_t i = 1; i < measured.size(); ++i) {
      const double v_d = measured[i]->v_d;
      if (v_d > c.track_up_to) continue;
      if (static_cast<int>(i) < c.settle_steps) continue;
      bool settled = true;
      for (size_t j = i - static_cast<size_t>(c.settle_steps); j < i; ++j) {
        settled = settled && measured[j]->v_d == v_d;
      }
      if (!settled) continue;
      ++checked;
      const double stride = 0.5 * (measured[i]->step.v_m + measured[i - 1]->step.v_m);
      const double error = std::abs(stride - v_d);
      if (error > c.speed_tolerance) ++off;
      if (error > worst) {
        worst = error;
        worst_t = measured[i]->step.t_touchdown;
      }
    }
    if (checked == 0) {
      fail.push_back("no step to check velocity tracking on (V_d never held for " +
                     std::to_string(c.settle_steps) + " steps)");
    } else if (off > 0) {
      std::snprintf(text, sizeof text,
                    "stride V_M off V_d by more than %.3f m/s at %d of %d settled steps (worst "
                    "%.3f m/s at t = %.2f s)",
                    c.speed_tolerance, off, checked, worst, worst_t);
      fail.push_back(text);
    }
  }
  if (Walking(scenario) && scenario.has_velocity && c.min_travel_ratio > 0.0) {
    const double wanted = VelocityIntegral(scenario.velocity, run->sim.t_end);
    if (!(run->metrics.distance >= c.min_travel_ratio * wanted)) {
      std::snprintf(
          text, sizeof text,
          "hip travelled %.2f m forward in %.2f s, %.1f %% of the %.2f m of V_d (at least "
          "%.0f %%: min_travel_ratio)",
          run->metrics.distance, run->sim.t_end,
          wanted > 0.0 ? 100.0 * run->metrics.distance / wanted : 0.0, wanted,
          100.0 * c.min_travel_ratio);
      fail.push_back(text);
    }
  }
  const std::vector<Obstacle>& obstacles = scenario.terrain.obstacles;
  if (!obstacles.empty()) {
    if (!c.allow_obstacle_contact) {
      for (const ContactEvent& e : run->sim.events) {
        if (e.from != ContactMode::kAir || e.to == ContactMode::kAir) continue;
        const int surface = scenario.terrain.SurfaceAt(e.x);
        if (surface != kGround && e.y > 0.5 * obstacles[surface].height) {
          std::snprintf(text, sizeof text, "foot %d landed on obstacle %d at t = %.3f s", e.leg + 1,
                        surface + 1, e.t);
          fail.push_back(text);
          break;
        }
      }
    }
    if (c.min_steps_after_obstacles > 0) {
      const double beyond = obstacles.back().x_end();
      int after = 0;
      for (const StepRow& s : run->steps) after += s.step.x > beyond ? 1 : 0;
      if (after < c.min_steps_after_obstacles) {
        std::snprintf(text, sizeof text, "%d steps beyond the last obstacle (at least %d required)",
                      after, c.min_steps_after_obstacles);
        fail.push_back(text);
      }
    }
  }
  run->passed = fail.empty();
}

}  // namespace rabbit
