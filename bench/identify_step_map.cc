// Regenerates the step-to-step map's bands (rabbit/control/step_map_control.h) from walks:
//   identify_step_map [--rate M_S] [--per-band] [--families a,b] RUN_DIR...
// RUN_DIR: the output of `rabbit run --out` (summary.csv and one folder per run with steps.csv).
// Only runs that completed are used, and only transitions between two measured steps outside
// the warm-up. The command V_c of each step is rebuilt from V_d with the rate limit --rate (the
// suite's velocity_control.v_d_rate, 0: V_c = V_d). One a and b for all bands unless --per-band
// (IdentifyStepMap). Prints the bands as the TOML key `bands` of
// [controller.velocity_control.step_map], with each band's sample count and residual RMS.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "rabbit/control/step_map_control.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"

namespace {

std::set<std::string> SplitNames(const std::string& list) {
  std::set<std::string> names;
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (!name.empty()) names.insert(name);
  }
  return names;
}

void AddRun(const std::string& steps_csv, double rate, std::vector<rabbit::StepMapSample>* out) {
  const rabbit::CsvTable t = rabbit::CsvTable::Read(steps_csv);
  const size_t v_d = t.Column("v_d_m_s"), v_m = t.Column("v_m_m_s"), s = t.Column("v_m_used_m_s"),
               q = t.Column("q0_d_deg"), warm = t.Column("warmup");
  double v_c = std::nan("");
  double prev_s = std::nan(""), prev_q = std::nan(""), prev_vc = 0.0, in_force = std::nan("");
  for (size_t row = 0; row < t.num_rows(); ++row) {
    const double vd = t.Number(row, v_d);
    v_c = std::isnan(v_c) || rate <= 0.0 ? vd : std::clamp(vd, v_c - rate, v_c + rate);
    const bool measured =
        !std::isnan(t.Number(row, v_m, rabbit::CsvNumber::kFiniteOrNan)) && t.Flag(row, warm) == 0;
    const double stride = t.Number(row, s, rabbit::CsvNumber::kFiniteOrNan);
    // The pitch in force during the step that ended at the previous row: set one row earlier.
    if (measured && !std::isnan(prev_s) && !std::isnan(in_force))
      out->push_back({prev_s, in_force, prev_vc, stride});
    prev_s = measured ? stride : std::nan("");
    in_force = prev_q;
    prev_q = t.Number(row, q) * M_PI / 180.0;
    prev_vc = v_c;
  }
}

}  // namespace

int main(int argc, char** argv) {
  double rate = 0.1;
  bool pooled = true;
  std::set<std::string> families;
  std::vector<std::string> dirs;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--rate" && i + 1 < argc) {
      rate = std::stod(argv[++i]);
    } else if (arg == "--per-band") {
      pooled = false;
    } else if (arg == "--families" && i + 1 < argc) {
      families = SplitNames(argv[++i]);
    } else if (!arg.empty() && arg[0] == '-') {
      std::fprintf(
          stderr,
          "usage: identify_step_map [--rate M_S] [--per-band] [--families a,b] RUN_DIR...\n");
      return 2;
    } else {
      dirs.push_back(arg);
    }
  }
  if (dirs.empty()) {
    std::fprintf(
        stderr, "usage: identify_step_map [--rate M_S] [--per-band] [--families a,b] RUN_DIR...\n");
    return 2;
  }
  std::vector<rabbit::StepMapSample> samples;
  int runs = 0;
  try {
    for (const std::string& dir : dirs) {
      const rabbit::CsvTable summary =
          rabbit::CsvTable::Read((std::filesystem::path(dir) / "summary.csv").string());
      const size_t name = summary.Column("scenario"), outcome = summary.Column("outcome"),
                   family = summary.Column("family");
      for (size_t row = 0; row < summary.num_rows(); ++row) {
        if (summary.Text(row, outcome) != "completed") continue;
        if (!families.empty() && families.count(summary.Text(row, family)) == 0) continue;
        AddRun((std::filesystem::path(dir) / summary.Text(row, name) / "steps.csv").string(), rate,
               &samples);
        ++runs;
      }
    }
  } catch (const rabbit::InputError& e) {
    std::fprintf(stderr, "identify_step_map: %s\n", e.what());
    return 2;
  }
  const std::vector<double> centres = {0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
  rabbit::StepMapFit fit;
  std::string error;
  if (!rabbit::IdentifyStepMap(samples, centres, 20, pooled, &fit, &error)) {
    std::fprintf(stderr, "identify_step_map: %s\n", error.c_str());
    return 1;
  }
  std::printf("# %zu transitions of %d completed runs\n", samples.size(), runs);
  std::printf("# [V_m_s, q_star_deg, a, b_m_s_per_deg]   samples  rms_m_s\n");
  std::printf("bands = [\n");
  for (size_t i = 0; i < fit.bands.size(); ++i) {
    const rabbit::StepMapBand& b = fit.bands[i];
    std::printf("  [%.2f, %.2f, %.3f, %.5f],   # %5d  %.4f\n", b.v, b.q_star * 180.0 / M_PI, b.a,
                b.b * M_PI / 180.0, fit.samples[i], fit.rms[i]);
  }
  std::printf("]\n");
  return 0;
}
