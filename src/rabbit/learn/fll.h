// TS-FIS definitions in fuzzylite's FLL language (docs/formats/fll.md): parsed by fuzzylite's own
// importer (libfuzzylite-dev), then checked and compiled into the project's evaluator (ts_fis.h).
//
// Supported: a zero-order Takagi-Sugeno system as TsFis represents it, i.e.
//   - input variables (enabled) with Triangle, Trapezoid, Ramp or Gaussian terms of height 1,
//     names that are FLL identifiers, optional lock-range (the input is clamped);
//   - exactly one output variable (enabled) with Constant terms, defuzzifier WeightedAverage
//     (TakagiSugeno or Automatic), lock-previous false, optional lock-range, any default;
//   - exactly one rule block (enabled), conjunction AlgebraicProduct, activation General (or
//     none), rules `if A is X and B is Y ... then out is T` naming every input once, in any order,
//     without hedges or weights. Aggregation, implication and disjunction do not affect this
//     inference and are accepted as written (saved as none).
// Anything else, malformed FLL included, is an InputError naming the file, the line (0 when it
// cannot be placed) and the FLL key, with fuzzylite's message where it has one.
//
// fuzzylite's import logs to stdout by default; ParseFll silences it while importing (fuzzylite's
// logging switch is global: imports take a process-wide lock, so they may come from any thread).
#ifndef RABBIT_LEARN_FLL_H_
#define RABBIT_LEARN_FLL_H_

#include <memory>
#include <string>

#include "rabbit/learn/ts_fis.h"

namespace fl {
class Engine;
}  // namespace fl

namespace rabbit {

// Reads and compiles an FLL file. Throws InputError.
TsFis LoadFll(const std::string& path);
// The same from text; `file` names it in errors.
TsFis ParseFll(const std::string& text, const std::string& file);

// FLL text for `fis` (numbers in the shortest form that reads back exactly), with `comment` (lines
// without '#') at the top. RampDown {a, b} is written `Ramp b a`. Throws std::invalid_argument if
// !fis.IsValid().
std::string ToFll(const TsFis& fis, const std::string& comment = "");
// Writes ToFll(fis, comment) to path atomically (WriteFileAtomically).
void SaveFll(const TsFis& fis, const std::string& path, const std::string& comment = "");

// The equivalent fuzzylite engine, built through fuzzylite's API (not through FLL): for cross-
// checks and benchmarks. Throws std::invalid_argument if !fis.IsValid().
std::unique_ptr<fl::Engine> MakeFuzzyliteEngine(const TsFis& fis);

}  // namespace rabbit

#endif  // RABBIT_LEARN_FLL_H_
