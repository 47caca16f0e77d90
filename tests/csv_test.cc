// The CSV number and cell writers of io/csv.h: numbers read back as the same double, in the fewest
// significant digits and never longer than printf's %.Ng with the smallest N that round-trips,
// with NaN and the infinities spelled out.
#include "rabbit/io/csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace rabbit {
namespace {

// Significant digits of a decimal text: the mantissa's digits without leading or trailing zeros.
int SignificantDigits(const std::string& text) {
  std::string digits;
  for (char c : text) {
    if (c == 'e' || c == 'E') break;
    if (c >= '0' && c <= '9') digits += c;
  }
  const size_t a = digits.find_first_not_of('0');
  if (a == std::string::npos) return 1;  // zero
  const size_t b = digits.find_last_not_of('0');
  return static_cast<int>(b - a + 1);
}

// printf's %.Ng with the smallest N that reads back as v (the reference), and that N.
std::string ShortestPrintf(double v, int* digits) {
  char text[64];
  for (int n = 1; n <= 17; ++n) {
    std::snprintf(text, sizeof text, "%.*g", n, v);
    *digits = n;
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

TEST(FormatCsvNumber, SpellsOutSpecialValues) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(FormatCsvNumber(std::nan("")), "nan");
  EXPECT_EQ(FormatCsvNumber(-std::nan("")), "nan");
  EXPECT_EQ(FormatCsvNumber(inf), "inf");
  EXPECT_EQ(FormatCsvNumber(-inf), "-inf");
  EXPECT_EQ(FormatCsvNumber(0.0), "0");
  EXPECT_EQ(FormatCsvNumber(-0.0), "-0");
}

TEST(FormatCsvNumber, ShortestForm) {
  EXPECT_EQ(FormatCsvNumber(0.1), "0.1");
  EXPECT_EQ(FormatCsvNumber(0.6), "0.6");
  EXPECT_EQ(FormatCsvNumber(1e-3), "0.001");
  EXPECT_EQ(FormatCsvNumber(42.0), "42");
  EXPECT_EQ(FormatCsvNumber(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(FormatCsvNumber(1e22), "1e+22");
}

TEST(FormatCsvNumber, RoundTripsInTheFewestDigits) {
  std::mt19937_64 rng(20261201);
  std::uniform_real_distribution<double> uniform(-10.0, 10.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  int checked = 0;
  for (int i = 0; i < 20000; ++i) {
    double v = 0.0;
    switch (i % 3) {
      case 0:  // values of the size a run writes
        v = uniform(rng);
        break;
      case 1:  // any magnitude
        v = uniform(rng) * std::pow(10.0, exponent(rng));
        break;
      default: {  // any bit pattern that is a finite double
        const std::uint64_t bits = rng();
        std::memcpy(&v, &bits, sizeof v);
        if (!std::isfinite(v)) continue;
      }
    }
    const std::string text = FormatCsvNumber(v);
    ASSERT_LE(text.size(), static_cast<size_t>(kMaxCsvNumberChars)) << text;
    ASSERT_EQ(std::strtod(text.c_str(), nullptr), v) << text;
    int digits = 0;
    const std::string reference = ShortestPrintf(v, &digits);
    // Never longer than the reference; the same digits unless written as a whole number (a large
    // integer-valued double may be shorter in full, "845391365440196608", than with an exponent).
    ASSERT_LE(text.size(), reference.size()) << text << " against " << reference;
    if (text.find_first_of(".e") != std::string::npos) {
      ASSERT_EQ(SignificantDigits(text), digits) << text << " against " << reference;
    }
    std::string appended = "x,";
    AppendCsvNumber(v, &appended);
    ASSERT_EQ(appended, "x," + text);
    ++checked;
  }
  EXPECT_GT(checked, 19000);
}

TEST(FormatCsvNumber, LongestTextsFit) {
  for (double v : {-2.2250738585072014e-308, -1.7976931348623157e308, -4.9406564584124654e-324,
                   -0.00012345678901234567, -123456789012345.67}) {
    char text[kMaxCsvNumberChars];
    const char* end = WriteCsvNumber(text, v);
    EXPECT_LE(end - text, kMaxCsvNumberChars);
    EXPECT_EQ(std::strtod(std::string(text, static_cast<size_t>(end - text)).c_str(), nullptr), v);
  }
}

TEST(FormatCsvCell, QuotesOnlyWhenNeeded) {
  EXPECT_EQ(FormatCsvCell("plain text"), "plain text");
  EXPECT_EQ(FormatCsvCell("a,b"), "\"a,b\"");
  EXPECT_EQ(FormatCsvCell("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(FormatCsvCell("two\nlines"), "\"two lines\"");
}

}  // namespace
}  // namespace rabbit
