#include "suite_fixture.h"

#include <gtest/gtest.h>

#include "rabbit/io/error.h"
#include "rabbit/scenario/suite.h"

namespace rabbit::testing {

void SuiteFileTest::ExpectSuiteError(const std::string& text, int line, const std::string& key,
                                     const std::string& fragment) {
  const std::string path = Write(text);
  try {
    LoadSuite(path);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    if (line >= 0) {
      EXPECT_EQ(e.line(), line) << e.what();
    }
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

std::string WalkerKeysSuite(const std::string& table, const std::string& keys) {
  const std::string root = RABBIT_SOURCE_DIR;
  return "[suite]\nname = \"t\"\n[defaults.simulation]\nduration = 2.0\n"
         "[defaults.velocity]\nvalue = 0.6\n[defaults.controller]\n"
         "type = \"fuzzy_cmac\"\nfll = \"" +
         root + "/gaits/gait_pattern.fll\"\nnetworks = \"" + root +
         "/gaits/networks\"\ngaits = \"" + root + "/gaits/reference\"\n[defaults.controller." +
         table + "]\n" + keys + "[[scenario]]\nname = \"a\"\n";
}

}  // namespace rabbit::testing
