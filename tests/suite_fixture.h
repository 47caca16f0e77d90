// Tests that read suite files (suite_test, family_draws_test, the walker mechanisms' key tests):
// a suite written into the test's scratch folder and LoadSuite's error checked, and a walker
// suite whose one sub-table holds the keys under test.
#ifndef RABBIT_TESTS_SUITE_FIXTURE_H_
#define RABBIT_TESTS_SUITE_FIXTURE_H_

#include <string>
#include <utility>

#include "cli_fixture.h"

namespace rabbit::testing {

class SuiteFileTest : public ScratchDirTest {
 protected:
  using ScratchDirTest::ScratchDirTest;
  using ScratchDirTest::Write;
  // Writes text to dir_/suite.toml and returns its path.
  std::string Write(const std::string& text) { return Write("suite.toml", text); }
  // LoadSuite of text fails with an InputError naming the file, the line (line < 0: any), the
  // key and holding fragment.
  void ExpectSuiteError(const std::string& text, int line, const std::string& key,
                        const std::string& fragment);
};

// A suite of one 2 s walk at 0.6 m/s on the shipped gait pattern whose walker has `keys` in
// [defaults.controller.<table>] (the table's header is line 12: the first key is on line 13).
std::string WalkerKeysSuite(const std::string& table, const std::string& keys);

// A key test of one walker sub-table: `keys` written into WalkerKeysSuite(table, keys).
class WalkerKeysTest : public SuiteFileTest {
 protected:
  WalkerKeysTest(std::string prefix, std::string table)
      : SuiteFileTest(std::move(prefix)), table_(std::move(table)) {}
  std::string Write(const std::string& keys) {
    return SuiteFileTest::Write(WalkerKeysSuite(table_, keys));
  }
  // LoadSuite fails naming `key` on `line` (the first key's line by default) and holding
  // `fragment`.
  void ExpectError(const std::string& keys, int line, const std::string& key,
                   const std::string& fragment) {
    ExpectSuiteError(WalkerKeysSuite(table_, keys), line, key, fragment);
  }
  void ExpectError(const std::string& keys, const std::string& key) {
    ExpectError(keys, 13, key, "");
  }
  std::string table_;
};

}  // namespace rabbit::testing

#endif  // RABBIT_TESTS_SUITE_FIXTURE_H_
