// Range checks of the numeric command-line flags, in one place (docs/bad-input.md lists the
// ranges). A CLI11 validator sees the flag's text before CLI11 converts it, so an empty text
// (`--vm ""`), trailing junk (`--vm 1x`), NaN and values outside the range are usage errors (exit
// 2) naming the flag, instead of a silent 0 or a nonsense value.
#ifndef RABBIT_CLI_FLAG_CHECKS_H_
#define RABBIT_CLI_FLAG_CHECKS_H_

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <system_error>

#include "rabbit/report/gnuplot.h"

namespace rabbit::cli {

// --family-details: -1 (every member) or at most this many members per family.
constexpr long kMaxFamilyDetails = 100000;

inline std::string FormatFlagBound(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

// The whole text as a number in [lo, hi] (an integer when `integer`); "inf" only if hi is
// infinite. `unit` is appended to the range in the message.
inline CLI::Validator NumberIn(double lo, double hi, const std::string& unit = "",
                               bool integer = false) {
  const std::string range = "[" + FormatFlagBound(lo) + ", " + FormatFlagBound(hi) + "]" +
                            (unit.empty() ? "" : " " + unit);
  const std::string kind = integer ? "an integer" : "a number";
  return CLI::Validator(
      [lo, hi, range, kind, integer](std::string& text) -> std::string {
        double value = 0.0;
        const char* end = text.data() + text.size();
        const std::from_chars_result r = std::from_chars(text.data(), end, value);
        const bool parsed = !text.empty() && r.ec == std::errc() && r.ptr == end;
        if (!parsed || std::isnan(value) || !(value >= lo && value <= hi) ||
            (integer && value != std::floor(value))) {
          return "expected " + kind + " in " + range + ", got \"" + text + "\"";
        }
        return std::string();
      },
      kind + " in " + range);
}

// Any option's text: an empty one (`--out ''`, `--gaits ""`) is a usage error naming the option,
// not a silent fall back to the option's default or to the working folder.
inline CLI::Validator NonEmptyText() {
  return CLI::Validator(
      [](std::string& text) {
        return text.empty() ? std::string("expected a value, got an empty text") : std::string();
      },
      "");
}

// --gnuplot: a gnuplot the user names must be one this process can run, so that a typo is a usage
// error before the work, not a warning after it that the figures were left out (without the
// flag, a machine without gnuplot gets the warning: figures are optional).
inline CLI::Validator RunnableExecutable() {
  return CLI::Validator(
      [](std::string& text) {
        if (rabbit::IsRunnableExecutable(text)) return std::string();
        return "cannot run '" + text + "': " +
               (text.find('/') != std::string::npos
                    ? std::string("not an executable file")
                    : std::string("no executable of that name on PATH"));
      },
      "EXECUTABLE");
}

inline CLI::Validator IntegerIn(long lo, long hi, const std::string& unit = "") {
  return NumberIn(static_cast<double>(lo), static_cast<double>(hi), unit, true);
}

}  // namespace rabbit::cli

#endif  // RABBIT_CLI_FLAG_CHECKS_H_
