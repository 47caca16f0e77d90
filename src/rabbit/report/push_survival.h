// Survival against push impulse: for every family whose members were pushed, each variant's
// success rate per push direction and impulse bin, built from summary.csv and each run's
// meta.csv (its `pushes`), so `rabbit report` rebuilds it like comparison.csv.
//
// DIR/push_survival.csv, one row per family, variant, direction and bin that holds runs (families
// in summary order, variants in their order of first appearance in the family, backward bins
// before forward ones, each from the smallest impulse up):
//   suite, group                  the suite; the family's name
//   variant                       as in summary.csv
//   direction                     "forward" (the run's impulse J > 0: along +x, the walking
//                                 direction) or "backward" (J < 0)
//   impulse_min_n_s, impulse_max_n_s   the bin of |J|: [min, max), bin_width wide from 0
//   runs, passed                  the variant's runs in the bin, and those that met every
//                                 criterion of their scenario
//   success_rate, ci_low, ci_high passed / runs and its 95% Wilson score interval (comparison.h)
// A run's J is the horizontal impulse of every push its scenario scheduled, sum of force_x *
// duration (N s), whether or not the push came (an event-timed push whose event never came has a
// `nan` start in meta.csv: the member was still drawn with that impulse). Runs with J = 0 (no
// horizontal push) are left out; a family none of whose runs has J != 0 gets no rows, and when no
// family has any, no file is written.
#ifndef RABBIT_REPORT_PUSH_SURVIVAL_H_
#define RABBIT_REPORT_PUSH_SURVIVAL_H_

#include <string>
#include <vector>

#include "rabbit/report/comparison.h"
#include "rabbit/report/report_data.h"

namespace rabbit {

constexpr const char* kPushSurvivalFile = "push_survival.csv";
// The default width of an impulse bin, N s.
constexpr double kDefaultSurvivalBin = 5.0;

// The horizontal impulse of meta.csv's `pushes` value, "start_s:duration_s:force_x_n:force_y_n:
// height_m;..." (empty: no push, 0): the sum of force_x_n * duration_s, N s. Throws InputError
// (file, line, key "pushes") for a malformed value.
double PushImpulse(const std::string& pushes, const std::string& file, int line);

// One row of push_survival.csv.
struct SurvivalBin {
  std::string suite, group, variant;
  bool forward = true;
  double impulse_min = 0.0, impulse_max = 0.0;  // N s, of |J|
  int runs = 0, passed = 0;
  double success_rate = 0.0;
  ProportionInterval ci;
};

// The bins of the family members among rows; impulses[i] is rows[i]'s J (nan: not known, the run
// is left out). bin_width > 0 and finite (else std::invalid_argument).
std::vector<SurvivalBin> PushSurvival(const std::vector<report_internal::SummaryRow>& rows,
                                      const std::vector<double>& impulses, double bin_width);

std::string PushSurvivalHeader();
std::string PushSurvivalCsv(const std::vector<SurvivalBin>& bins);

// The bins of DIR's summary rows (as ReadSummary read them), from every family member's
// DIR/<run>/meta.csv. A member whose meta.csv is missing (its folder deleted) is left out, with
// one warning in *warnings (may be null) for all of them; a malformed meta.csv throws InputError.
std::vector<SurvivalBin> ReadPushSurvival(const std::string& dir,
                                          const std::vector<report_internal::SummaryRow>& rows,
                                          double bin_width, std::vector<std::string>* warnings);
// Writes DIR/push_survival.csv atomically when there are bins (else nothing); returns whether it
// wrote.
bool WritePushSurvivalCsv(const std::string& dir, const std::vector<SurvivalBin>& bins);
// All three: DIR/summary.csv (InputError when missing or malformed), ReadPushSurvival, then
// WritePushSurvivalCsv.
std::vector<SurvivalBin> WritePushSurvival(const std::string& dir, double bin_width,
                                           std::vector<std::string>* warnings);

}  // namespace rabbit

#endif  // RABBIT_REPORT_PUSH_SURVIVAL_H_
