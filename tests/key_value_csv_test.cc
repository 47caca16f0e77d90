// The key,value reader of meta.csv files: values by key, numbers and integers parsed strictly
// with the key and its line in the error, a missing key, a key given twice naming both lines.
#include "rabbit/io/key_value_csv.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "rabbit/io/error.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

class KeyValueCsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = (fs::temp_directory_path() /
             ("rabbit_key_value_csv_" + std::to_string(::getpid()) + ".csv"))
                .string();
  }
  void TearDown() override { fs::remove(path_); }
  KeyValueCsv Read(const std::string& text) {
    std::ofstream(path_) << text;
    return KeyValueCsv::Read(path_);
  }
  // The InputError reading `text` (and looking `key` up as a number), or a test failure.
  InputError ErrorOf(const std::string& text, const std::string& key) {
    try {
      Read(text).Number(key);
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "no error for:\n" << text;
    return InputError("", 0, "", "");
  }
  std::string path_;
};

TEST_F(KeyValueCsvTest, ValuesByKey) {
  const KeyValueCsv kv = Read("key,value\nname,\"a, b\"\nlength_m,0.47\nsteps,12\nv,nan\nnone,\n");
  EXPECT_EQ(kv.file(), path_);
  EXPECT_TRUE(kv.Has("name"));
  EXPECT_FALSE(kv.Has("other"));
  EXPECT_EQ(kv.Text("name"), "a, b");
  EXPECT_EQ(kv.Text("none"), "");
  EXPECT_EQ(kv.Number("length_m"), 0.47);
  EXPECT_EQ(kv.Integer("steps"), 12);
  EXPECT_TRUE(std::isnan(kv.Number("v", CsvNumber::kFiniteOrNan)));
  EXPECT_EQ(kv.line("name"), 2);
  EXPECT_EQ(kv.line("steps"), 4);
}

TEST_F(KeyValueCsvTest, ErrorsNameTheFileTheLineAndTheKey) {
  InputError e = ErrorOf("key,value\na,1\nb,x\n", "b");
  EXPECT_EQ(e.file(), path_);
  EXPECT_EQ(e.line(), 3);
  EXPECT_EQ(e.key(), "b");                 // not the column "value"
  e = ErrorOf("key,value\na,nan\n", "a");  // nan where a finite number is needed
  EXPECT_EQ(e.key(), "a");
  EXPECT_EQ(e.line(), 2);
  e = ErrorOf("key,value\na,1\n", "b");
  EXPECT_EQ(e.key(), "b");
  EXPECT_EQ(e.line(), 0);
  EXPECT_NE(std::string(e.what()).find("missing key"), std::string::npos) << e.what();
  e = ErrorOf("key,value\na,1\nb,2\na,3\n", "a");
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.key(), "key");
  EXPECT_NE(std::string(e.what()).find("\"a\" also on line 2"), std::string::npos) << e.what();
  e = ErrorOf("name,value\na,1\n", "a");
  EXPECT_EQ(e.key(), "key");  // the missing column
  try {
    Read("key,value\nn,2.5\n").Integer("n");
    ADD_FAILURE();
  } catch (const InputError& error) {
    EXPECT_EQ(error.key(), "n");
    EXPECT_EQ(error.line(), 2);
  }
}

}  // namespace
}  // namespace rabbit
