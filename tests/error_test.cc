// InputError and FormatLimit (rabbit/io/error.h): the message every bad input gets names the
// file, the line when known and the key when there is one, in that order; the place is kept
// apart for callers; a limit is written as %g writes it.
#include "rabbit/io/error.h"

#include <gtest/gtest.h>

namespace rabbit {
namespace {

TEST(InputErrorTest, NamesTheFileLineAndKey) {
  const InputError e("suite.toml", 12, "scenario[2].simulation.duration", "must be positive");
  EXPECT_STREQ(e.what(), "suite.toml:12: 'scenario[2].simulation.duration': must be positive");
  EXPECT_EQ(e.file(), "suite.toml");
  EXPECT_EQ(e.line(), 12);
  EXPECT_EQ(e.key(), "scenario[2].simulation.duration");
  // Without a line (0) or a key, the message leaves them out.
  EXPECT_STREQ(InputError("--out", 0, "", "exists").what(), "--out: exists");
  EXPECT_STREQ(InputError("f.csv", 0, "col", "bad").what(), "f.csv: 'col': bad");
  EXPECT_STREQ(InputError("f.csv", 3, "", "bad").what(), "f.csv:3: bad");
}

TEST(InputErrorTest, FormatLimitWritesAsPercentG) {
  EXPECT_EQ(FormatLimit(3600), "3600");
  EXPECT_EQ(FormatLimit(1e6), "1e+06");
  EXPECT_EQ(FormatLimit(0.5), "0.5");
  EXPECT_EQ(FormatLimit(2e6), "2e+06");
}

}  // namespace
}  // namespace rabbit
