// Output folders of a tuning job (`rabbit tune`) for the tuning report's tests, written in the
// job's CSV formats (tune_report.h): a small hand-written one whose every number is known, and
// synthetic ones of any size.
#ifndef RABBIT_TESTS_TUNE_FIXTURE_H_
#define RABBIT_TESTS_TUNE_FIXTURE_H_

#include <string>

namespace rabbit::testing {

// Writes into dir (created) a bobyqa job "walk_gains" of 6 evaluations over 2 starts: evaluation
// 0 the initial candidate (objective 5.25), evaluation 3 invalid (objective 1e6, an error with a
// comma and markup), evaluation 4 the best (0.0312); parameters controller.k_p (100..1000, 600 ->
// 731.5) and controller.k_d (5..60, 30 -> 22.25); scenarios flat/walk_0.6 and push/"push & shove"
// (fell initially, completed with the best); a description with a <script> element.
void WriteTuneFixture(const std::string& dir);

// Writes into dir (created) a complete job of `evaluations` candidates (at least 1) alternating
// between 2 starts, `parameters` parameters and `scenarios` scenarios; every candidate valid, the
// objective decreasing with noise.
void WriteSyntheticTuneFixture(const std::string& dir, int evaluations, int parameters,
                               int scenarios);

}  // namespace rabbit::testing

#endif  // RABBIT_TESTS_TUNE_FIXTURE_H_
