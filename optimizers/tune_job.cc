#include "tune_job.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rabbit/io/bounded_read.h"
#include "rabbit/io/error.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/scenario/batch.h"
#include "rabbit/scenario/suite.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

struct AlgorithmName {
  const char* name;
  TuneAlgorithm algorithm;
};
constexpr AlgorithmName kAlgorithms[] = {
    {"bobyqa", TuneAlgorithm::kBobyqa},    {"sbplx", TuneAlgorithm::kSbplx},
    {"cobyla", TuneAlgorithm::kCobyla},    {"neldermead", TuneAlgorithm::kNelderMead},
    {"crs2", TuneAlgorithm::kCrs2},        {"isres", TuneAlgorithm::kIsres},
    {"esch", TuneAlgorithm::kEsch},        {"direct", TuneAlgorithm::kDirect},
    {"direct_l", TuneAlgorithm::kDirectL}, {"ceres", TuneAlgorithm::kCeres}};

// A run without a value for a term counts this (docs/formats/tune-job.md).
constexpr double kDefaultMissing[kNumTuneTerms] = {1.0, 1.0, 0.5, 0.0, 5.0, 0.0, 1.0};

std::string FileText(const std::string& path) {
  return ReadBoundedFileIfExists(path, kTomlFileLimits);
}

std::uint64_t Fnv1a(const std::string& text, std::uint64_t h) {
  for (const char c : text) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001B3ULL;
  return h;
}

// Settings of `settings` whose path shares the parameter's first part, to suggest in errors.
std::string Near(const std::map<std::string, double>& settings, const std::string& path) {
  const std::string head = path.substr(0, path.find('.') + 1);
  std::string out;
  int shown = 0;
  for (const auto& [key, value] : settings) {
    if (key.rfind(head, 0) != 0 || key.find(".sets.") != std::string::npos || key[0] == '#') {
      continue;
    }
    if (shown++ == 12) {
      out += ", ...";
      break;
    }
    out += (out.empty() ? "" : ", ") + key;
  }
  return out;
}

}  // namespace

const char* TuneTermName(int term) {
  static const char* const kNames[kNumTuneTerms] = {
      "failure_rate",      "speed_error",     "step_length_spread", "energy",
      "cost_of_transport", "saturation_time", "incomplete_rate"};
  return kNames[term];
}

const char* TuneAlgorithmName(TuneAlgorithm a) {
  for (const AlgorithmName& n : kAlgorithms) {
    if (n.algorithm == a) return n.name;
  }
  return "?";
}

bool IsGlobal(TuneAlgorithm a) {
  return a == TuneAlgorithm::kCrs2 || a == TuneAlgorithm::kIsres || a == TuneAlgorithm::kEsch ||
         a == TuneAlgorithm::kDirect || a == TuneAlgorithm::kDirectL;
}

ParamOverlay TuneJob::Overlay(const std::vector<double>& x) const {
  ParamOverlay overlay = base;
  overlay.file = file;
  for (size_t i = 0; i < parameters.size(); ++i) {
    for (const std::string& path : parameters[i].paths) {
      bool replaced = false;
      for (ParamValue& v : overlay.values) {
        if (v.path == path) {
          v.value = x[i];
          v.line = parameters[i].line;
          v.file = file;
          replaced = true;
        }
      }
      if (!replaced) overlay.values.push_back({path, x[i], parameters[i].line, file});
    }
  }
  return overlay;
}

TuneJob LoadTuneJob(const std::string& path, const ParamOverlay* extra) {
  TomlReader root = TomlReader::ParseFile(path);
  TuneJob job;
  job.file = path;
  const fs::path dir = fs::path(path).parent_path();
  auto resolve = [&dir](const std::string& p) {
    return fs::path(p).is_absolute() ? p : (dir / p).lexically_normal().string();
  };

  TomlReader head = root.Table("job");
  if (!root.Has("job")) root.Fail("job", "a tuning job needs a [job] table");
  job.name = head.String("name", fs::path(path).stem().string());
  if (!IsSafeName(job.name)) {
    head.Fail("name", SafeNameRule(job.name) + " (it names the output folder)");
  }
  job.description = head.String("description", "");
  // A suite file that is missing, unreadable or another kind of file is named at the key that
  // lists it (its path is resolved from the job's folder); its contents' errors name the suite.
  auto listed = [&head, &resolve, &path](const char* key, std::vector<std::string>* paths) {
    for (const std::string& s : head.Strings(key, {})) {
      if (s.empty()) head.Fail(key, "an empty path: name a suite file");
      paths->push_back(resolve(s));
      CheckNamedSuiteFile(paths->back(), path, head.KeyLine(key), std::string("job.") + key);
    }
  };
  listed("suites", &job.suites);
  if (job.suites.empty()) head.Fail("suites", "name at least one suite file");
  listed("guards", &job.guards);
  job.filter = head.String("filter", "");
  const std::string filter_problem = RegexFilterProblem(job.filter);
  if (!filter_problem.empty()) head.Fail("filter", "bad regex: " + filter_problem);
  const std::string base = head.String("params", "");
  if (!base.empty()) job.base = LoadParamOverlay(resolve(base));
  if (extra != nullptr) {
    job.base.gait_database = extra->gait_database;  // --gaits
    for (const ParamValue& v : extra->values) {
      bool replaced = false;
      for (ParamValue& mine : job.base.values) {
        if (mine.path == v.path) {
          mine = v;
          replaced = true;
        }
      }
      if (!replaced) job.base.values.push_back(v);
    }
  }
  const std::string algorithm = head.String("algorithm", "bobyqa");
  bool known = false;
  for (const AlgorithmName& n : kAlgorithms) {
    if (algorithm == n.name) {
      job.algorithm = n.algorithm;
      known = true;
    }
  }
  if (!known) {
    std::string names;
    for (const AlgorithmName& n : kAlgorithms)
      names += (names.empty() ? "" : ", ") + std::string(n.name);
    head.Fail("algorithm",
              "unknown algorithm \"" + algorithm + "\" (expected one of: " + names + ")");
  }
  job.max_evaluations =
      static_cast<int>(head.Integer("max_evaluations", job.max_evaluations, 1, 1000000));
  job.seed =
      static_cast<std::uint64_t>(head.Integer("seed", 1, 0, std::numeric_limits<long>::max()));
  job.starts = static_cast<int>(head.Integer("starts", job.starts, 1, 1000));
  job.initial_step = head.Double("initial_step", job.initial_step);
  if (!(job.initial_step > 0.0 && job.initial_step <= 1.0)) {
    head.Fail("initial_step", "must lie in (0, 1] (a fraction of each parameter's range)");
  }
  job.population = static_cast<int>(head.Integer("population", job.population, 0, 100000));
  job.xtol_rel = head.Double("xtol_rel", job.xtol_rel);
  job.ftol_rel = head.Double("ftol_rel", job.ftol_rel);
  if (job.xtol_rel < 0.0) head.Fail("xtol_rel", "must be >= 0");
  if (job.ftol_rel < 0.0) head.Fail("ftol_rel", "must be >= 0");
  head.Finish();
  if (job.max_evaluations < job.starts) {
    head.Fail("max_evaluations", "must be at least `starts` (" + std::to_string(job.starts) + ")");
  }

  TomlReader objective = root.Table("objective");
  if (!root.Has("objective")) root.Fail("objective", "a tuning job needs an [objective] table");
  const std::string form =
      objective.String("form", job.algorithm == TuneAlgorithm::kCeres ? "mean_square" : "mean");
  if (form != "mean" && form != "mean_square") {
    objective.Fail("form", "expected \"mean\" or \"mean_square\"");
  }
  job.objective.squares = form == "mean_square";
  if (job.algorithm == TuneAlgorithm::kCeres && !job.objective.squares) {
    objective.Fail("form", "Ceres minimises sums of squares: use form = \"mean_square\"");
  }
  TomlReader missing = objective.Table("missing");
  double total = 0.0;
  for (int t = 0; t < kNumTuneTerms; ++t) {
    job.objective.weight[t] = objective.Double(TuneTermName(t), 0.0);
    if (job.objective.weight[t] < 0.0) objective.Fail(TuneTermName(t), "weights must be >= 0");
    total += job.objective.weight[t];
    job.objective.missing[t] = missing.Double(TuneTermName(t), kDefaultMissing[t]);
    if (job.objective.missing[t] < 0.0) missing.Fail(TuneTermName(t), "must be >= 0");
  }
  missing.Finish();
  objective.Finish();
  if (!(total > 0.0)) objective.Fail("", "give at least one term a weight > 0");

  TomlReader ceres = root.Table("ceres");
  job.fd_step = ceres.Double("fd_step", job.fd_step);
  if (!(job.fd_step > 0.0 && job.fd_step <= 0.5)) {
    ceres.Fail("fd_step", "must lie in (0, 0.5] (a fraction of each parameter's range)");
  }
  job.ceres_iterations =
      static_cast<int>(ceres.Integer("max_iterations", job.ceres_iterations, 1, 100000));
  job.function_tolerance = ceres.Double("function_tolerance", job.function_tolerance);
  if (job.function_tolerance < 0.0) ceres.Fail("function_tolerance", "must be >= 0");
  ceres.Finish();

  std::vector<TomlReader> params = root.TableArray("parameter");
  std::vector<bool> given_initial;
  if (params.empty()) root.Fail("parameter", "a tuning job needs at least one [[parameter]]");
  for (TomlReader& p : params) {
    TuneParameter q;
    q.line = p.line();
    q.paths =
        p.IsArray("path") ? p.Strings("path", {}) : std::vector<std::string>{p.String("path", "")};
    if (q.paths.empty()) p.Fail("path", "name at least one key path");
    for (const std::string& one : q.paths) {
      std::string error;
      if (!IsParamPath(one, &error)) p.Fail("path", error);
    }
    q.path = q.paths.front();
    q.name = p.String("name", q.path);
    if (q.name.empty() || q.name.find_first_of(",\"\n\r") != std::string::npos) {
      p.Fail("name", "a column name: no commas, quotes or line breaks");
    }
    // evaluations.csv's own columns: a parameter of the same name would make it unreadable.
    bool taken = false;
    for (const char* column : {"eval", "round", "start", "seq", "objective", "runs", "failed",
                               "guards_run", "guard_broken", "error", "wall_s"}) {
      taken = taken || q.name == column;
    }
    for (int t = 0; t < kNumTuneTerms; ++t) taken = taken || q.name == TuneTermName(t);
    if (taken) {
      p.Fail(p.Has("name") ? "name" : "path",
             "\"" + q.name + "\" is a column of evaluations.csv already: give another `name`");
    }
    q.lower = p.RequiredDouble("lower");
    q.upper = p.RequiredDouble("upper");
    if (!(q.lower < q.upper)) p.Fail("lower", "bounds need lower < upper");
    if (!std::isfinite(q.upper - q.lower)) p.Fail("upper", "the range upper - lower overflows");
    q.initial = p.Double("initial", std::numeric_limits<double>::quiet_NaN());
    given_initial.push_back(p.Has("initial"));
    if (p.Has("initial") && !(q.initial >= q.lower && q.initial <= q.upper)) {
      p.Fail("initial", "must lie within [lower, upper]");
    }
    p.Finish();
    for (const TuneParameter& other : job.parameters) {
      for (const std::string& a : other.paths) {
        for (const std::string& b : q.paths) {
          if (a == b) p.Fail("path", "\"" + a + "\" is tuned twice");
        }
      }
      if (other.name == q.name) p.Fail("name", "two parameters named \"" + q.name + "\"");
    }
    job.parameters.push_back(q);
  }
  if (job.algorithm == TuneAlgorithm::kBobyqa && job.parameters.size() < 2) {
    root.Fail("job.algorithm", "BOBYQA needs at least 2 parameters (use sbplx or cobyla for one)");
  }
  root.Finish();

  // Every parameter must name a numeric setting of every scenario; its current value is the
  // default initial value.
  std::uint64_t h = Fnv1a(std::string("rabbit-tune/1 ") + RABBIT_VERSION, 0xCBF29CE484222325ULL);
  h = Fnv1a(FileText(path), h);
  for (const ParamValue& v : job.base.values)
    h = Fnv1a(v.path + "=" + ExactNumber(v.value) + ";", h);
  std::map<std::string, std::string> suite_names;  // name -> file
  // A candidate's values apply to every scenario of each suite and guard file (the filter selects
  // what runs, not what is read): a tuned path that one of them lacks would make every candidate
  // invalid, so it stops the job here.
  auto check_paths = [&](const std::map<std::string, double>& settings, const std::string& scenario,
                         const std::string& file, const char* where) {
    for (const TuneParameter& q : job.parameters) {
      for (const std::string& one : q.paths) {
        if (settings.count(one) == 0) {
          const std::string near = Near(settings, one);
          throw InputError(path, q.line, one,
                           "names no numeric setting of scenario \"" + scenario + "\" in " + file +
                               (near.empty() ? "" : " (its settings there: " + near + ")") + where);
        }
        if (settings.count("#integer:" + one) != 0) {
          throw InputError(path, q.line, one,
                           "is an integer setting of scenario \"" + scenario + "\" in " + file +
                               ": only real-valued settings can be tuned" + where);
        }
      }
    }
  };
  for (const std::string& suite_path : job.suites) {
    h = Fnv1a(FileText(suite_path), h);
    std::vector<std::map<std::string, double>> settings;
    const Suite suite = LoadSuite(suite_path, &job.base, &settings);
    for (const InputFile& f : HashInputFiles(SuiteInputFiles(suite))) {
      h = Fnv1a(f.sha256, h);
      job.inputs.push_back(f);
    }
    // The logs and comparison.csv name a run by suite and scenario: a suite twice would mix them.
    const auto [named, fresh] = suite_names.emplace(suite.name, suite_path);
    if (!fresh) {
      throw InputError(path, 0, "job.suites",
                       "two suites named \"" + suite.name + "\" (" + named->second + " and " +
                           suite_path + "): list each suite once");
    }
    const NameFilter filter(job.filter, path, "job.filter");
    bool any = false;
    for (size_t i = 0; i < suite.scenarios.size(); ++i) {
      const Scenario& s = suite.scenarios[i];
      const bool selected = filter.Matches(s.name);
      check_paths(settings[i], s.name, suite_path,
                  selected ? ""
                           : "; the filter leaves this scenario out, but a candidate's values "
                             "apply to every scenario of the file: tune a path they all have, or "
                             "move the others to a suite of their own");
      if (!selected) continue;
      any = true;
      for (size_t k = 0; k < job.parameters.size(); ++k) {
        TuneParameter& q = job.parameters[k];
        for (const std::string& one : q.paths) {
          const auto found = settings[i].find(one);
          if (std::isnan(q.initial)) {
            q.initial = found->second;
          } else if (!given_initial[k] && q.initial != found->second) {
            throw InputError(path, q.line, one,
                             "its current value differs between its paths or scenarios (" +
                                 ExactNumber(q.initial) + " and " + ExactNumber(found->second) +
                                 " in \"" + s.name + "\"): give `initial`");
          }
        }
      }
    }
    if (!any) {
      throw InputError(path, 0, "job.filter",
                       "no scenario of " + suite_path + " matches \"" + job.filter + "\"");
    }
  }
  // Guard suites: read (under the base overlay, as a candidate's are) and fingerprinted; each
  // needs a required scenario, the only ones a guard runs.
  std::map<std::string, std::string> guard_names;  // name -> file
  for (const std::string& guard_path : job.guards) {
    h = Fnv1a("guard:" + FileText(guard_path), h);
    std::vector<std::map<std::string, double>> settings;
    const Suite suite = LoadSuite(guard_path, &job.base, &settings);
    for (size_t i = 0; i < suite.scenarios.size(); ++i) {
      check_paths(settings[i], suite.scenarios[i].name, guard_path,
                  "; a guard suite's scenarios run with a candidate's values too: guard with a "
                  "suite whose scenarios all have this setting");
    }
    for (const InputFile& f : HashInputFiles(SuiteInputFiles(suite))) {
      h = Fnv1a(f.sha256, h);
      job.inputs.push_back(f);
    }
    const auto [named, fresh] = guard_names.emplace(suite.name, guard_path);
    if (!fresh) {
      throw InputError(path, 0, "job.guards",
                       "two guard suites named \"" + suite.name + "\" (" + named->second + " and " +
                           guard_path + "): list each suite once");
    }
    bool required = false;
    for (const Scenario& s : suite.scenarios) required = required || s.required;
    if (!required) {
      throw InputError(path, 0, "job.guards",
                       guard_path + " has no required scenario: it cannot guard anything");
    }
  }
  for (const TuneParameter& q : job.parameters) {
    if (!(q.initial >= q.lower && q.initial <= q.upper)) {
      throw InputError(path, q.line, q.path,
                       "its current value " + ExactNumber(q.initial) +
                           " lies outside [lower, upper]: widen the bounds or give `initial`");
    }
  }
  char fingerprint[32];
  std::snprintf(fingerprint, sizeof fingerprint, "%016llx", static_cast<unsigned long long>(h));
  job.fingerprint = fingerprint;
  return job;
}

}  // namespace rabbit
