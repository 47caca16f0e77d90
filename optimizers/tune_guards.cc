#include "tune_guards.h"

namespace rabbit::tune_internal {

std::vector<std::string> GuardRunner::Check(const std::vector<std::vector<double>>& xs) {
  std::vector<std::string> out;
  for (const Evaluation& e : evaluator_.Evaluate(xs)) {
    std::string broken;
    if (!e.error.empty()) {
      broken = "the guard suites do not load: " + e.error;
    } else {
      for (const RunScore& s : e.scores) {
        if (!s.passed) broken += (broken.empty() ? "" : "; ") + s.suite + "/" + s.scenario;
      }
    }
    out.push_back(broken);
  }
  return out;
}

}  // namespace rabbit::tune_internal
