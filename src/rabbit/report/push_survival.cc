// Survival against push impulse (push_survival.h).
#include "rabbit/report/push_survival.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"
#include "rabbit/io/key_value_csv.h"

namespace rabbit {

using report_internal::SummaryRow;

double PushImpulse(const std::string& pushes, const std::string& file, int line) {
  double impulse = 0.0;
  std::stringstream list(pushes);
  for (std::string push; std::getline(list, push, ';');) {
    std::vector<std::string> fields;
    std::stringstream parts(push);
    for (std::string field; std::getline(parts, field, ':');) fields.push_back(Trim(field));
    if (fields.size() != 5) {
      throw InputError(
          file, line, "pushes",
          "a push is start_s:duration_s:force_x_n:force_y_n:height_m, not \"" + push + "\"");
    }
    const double duration = ParseFiniteNumber(fields[1], file, line, "pushes");
    const double force_x = ParseFiniteNumber(fields[2], file, line, "pushes");
    if (duration < 0.0) throw InputError(file, line, "pushes", "a push's duration is negative");
    impulse += force_x * duration;
  }
  return impulse;
}

std::vector<SurvivalBin> PushSurvival(const std::vector<SummaryRow>& rows,
                                      const std::vector<double>& impulses, double bin_width) {
  if (!(bin_width > 0.0) || !std::isfinite(bin_width)) {
    throw std::invalid_argument("the impulse bin width must be a positive number of N s");
  }
  // Per family (in order), per variant (in order), the bins keyed by (forward, index).
  struct Variant {
    std::string name;
    std::map<std::pair<bool, long>, SurvivalBin> bins;
  };
  struct Family {
    std::string suite, name;
    std::vector<Variant> variants;
  };
  std::vector<Family> families;
  for (size_t i = 0; i < rows.size() && i < impulses.size(); ++i) {
    const SummaryRow& r = rows[i];
    const double j = impulses[i];
    if (!r.is_family_member || !std::isfinite(j) || j == 0.0) continue;
    auto f = std::find_if(families.begin(), families.end(), [&r](const Family& x) {
      return x.name == r.group && x.suite == r.suite;
    });
    if (f == families.end()) f = families.insert(families.end(), Family{r.suite, r.group, {}});
    auto v = std::find_if(f->variants.begin(), f->variants.end(),
                          [&r](const Variant& x) { return x.name == r.variant; });
    if (v == f->variants.end()) v = f->variants.insert(f->variants.end(), Variant{r.variant, {}});
    const long index = static_cast<long>(std::floor(std::abs(j) / bin_width));
    SurvivalBin& b = v->bins[{j > 0.0, index}];
    if (b.runs == 0) {
      b.suite = r.suite;
      b.group = r.group;
      b.variant = r.variant;
      b.forward = j > 0.0;
      b.impulse_min = static_cast<double>(index) * bin_width;
      b.impulse_max = static_cast<double>(index + 1) * bin_width;
    }
    ++b.runs;
    b.passed += r.passed ? 1 : 0;
  }
  std::vector<SurvivalBin> out;
  for (const Family& f : families) {
    for (const Variant& v : f.variants) {
      // Backward (false) before forward (true); each from the smallest impulse up.
      for (const auto& [key, bin] : v.bins) {
        SurvivalBin b = bin;
        b.success_rate = static_cast<double>(b.passed) / static_cast<double>(b.runs);
        b.ci = WilsonInterval(b.passed, b.runs);
        out.push_back(std::move(b));
      }
    }
  }
  return out;
}

std::string PushSurvivalHeader() {
  return "suite,group,variant,direction,impulse_min_n_s,impulse_max_n_s,runs,passed,success_rate,"
         "ci_low,ci_high";
}

std::string PushSurvivalCsv(const std::vector<SurvivalBin>& bins) {
  std::string out = PushSurvivalHeader() + "\n";
  for (const SurvivalBin& b : bins) {
    out += FormatCsvCell(b.suite) + ',' + FormatCsvCell(b.group) + ',' + FormatCsvCell(b.variant) +
           ',' + (b.forward ? "forward" : "backward") + ',' + FormatCsvNumber(b.impulse_min) + ',' +
           FormatCsvNumber(b.impulse_max) + ',' + std::to_string(b.runs) + ',' +
           std::to_string(b.passed) + ',' + FormatCsvNumber(b.success_rate) + ',' +
           FormatCsvNumber(b.ci.low) + ',' + FormatCsvNumber(b.ci.high) + '\n';
  }
  return out;
}

std::vector<SurvivalBin> ReadPushSurvival(const std::string& dir,
                                          const std::vector<SummaryRow>& rows, double bin_width,
                                          std::vector<std::string>* warnings) {
  namespace fs = std::filesystem;
  const fs::path root(dir);
  std::vector<double> impulses(rows.size(), std::numeric_limits<double>::quiet_NaN());
  int missing = 0;
  for (size_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].is_family_member) continue;
    const fs::path meta = root / rows[i].run / "meta.csv";
    if (!fs::is_regular_file(meta)) {
      ++missing;
      continue;
    }
    const KeyValueCsv kv = KeyValueCsv::Read(meta.string());
    impulses[i] =
        kv.Has("pushes") ? PushImpulse(kv.Text("pushes"), kv.file(), kv.line("pushes")) : 0.0;
  }
  if (missing > 0 && warnings != nullptr) {
    warnings->push_back(std::to_string(missing) + " family runs have no meta.csv: left out of " +
                        kPushSurvivalFile);
  }
  return PushSurvival(rows, impulses, bin_width);
}

bool WritePushSurvivalCsv(const std::string& dir, const std::vector<SurvivalBin>& bins) {
  if (bins.empty()) return false;
  const std::string csv = PushSurvivalCsv(bins);
  WriteFileAtomically((std::filesystem::path(dir) / kPushSurvivalFile).string(),
                      [&csv](std::ostream& out) { out << csv; });
  return true;
}

std::vector<SurvivalBin> WritePushSurvival(const std::string& dir, double bin_width,
                                           std::vector<std::string>* warnings) {
  const std::vector<SurvivalBin> bins = ReadPushSurvival(
      dir, report_internal::ReadSummary((std::filesystem::path(dir) / "summary.csv").string()),
      bin_width, warnings);
  WritePushSurvivalCsv(dir, bins);
  return bins;
}

}  // namespace rabbit
