// SVG figures: well-formed output for ordinary data, and termination for degenerate or huge ranges.
#include "rabbit/report/svg.h"

#include <gtest/gtest.h>

namespace rabbit {
namespace {

TEST(SvgTest, LinePlotIsWellFormed) {
  const std::string svg = LinePlotSvg("t <1>", "x", "y", {{"a&b", {0, 1, 2}, {0, 1, 4}}});
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("t &lt;1&gt;"), std::string::npos);
  EXPECT_NE(svg.find("a&amp;b"), std::string::npos);
}

TEST(SvgTest, HugeAndDegenerateRangesTerminate) {
  // Once x + step == x a tick loop by increments would never end.
  const std::string huge = LinePlotSvg("huge", "x", "y", {{"s", {1e16, 1e16 + 2}, {0, 1}}});
  EXPECT_NE(huge.find("</svg>"), std::string::npos);
  const std::string flat = LinePlotSvg("flat", "x", "y", {{"s", {1, 1}, {2, 2}}});
  EXPECT_NE(flat.find("</svg>"), std::string::npos);
  const std::string empty = LinePlotSvg("empty", "x", "y", {});
  EXPECT_NE(empty.find("</svg>"), std::string::npos);
}

}  // namespace
}  // namespace rabbit
