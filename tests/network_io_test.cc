// CMAC network files (network_io.h): exact round trip, and every kind of malformed file refused
// with an InputError naming the file and line.
#include "rabbit/learn/network_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_fixture.h"
#include "rabbit/io/error.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

Cmac TrainedCmac(int hash_table_size) {
  CmacOptions o;  // the chapter's structure over [-0.7, 0.45] rad
  o.x_min = -0.7;
  o.x_max = 0.45;
  o.hash_table_size = hash_table_size;
  o.hash_seed = 0xDEADBEEFCAFEF00DULL;  // above 2^53: must not pass through a double
  Cmac cmac(o);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> weight(-2.0, 2.0);
  for (double& w : *cmac.mutable_weights()) w = weight(rng);
  (*cmac.mutable_weights())[0] = 0.1;     // short decimal
  (*cmac.mutable_weights())[1] = -0.0;    // signed zero
  (*cmac.mutable_weights())[2] = 1e-300;  // tiny
  (*cmac.mutable_weights())[3] = 1.0 / 3.0;
  return cmac;
}

const std::map<std::string, std::string> kMetadata = {
    {"gait", "vm_0.60"}, {"output", "q_i1_rad"}, {"note", "trained = yes, 3 epochs"}};

using testing::ReadText;

class NetworkIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rabbit_network_io_" + std::to_string(::getpid()) + "_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    good_ = (dir_ / "good.csv").string();
    WriteCmacFile(TrainedCmac(0), kMetadata, good_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The good file's lines (1-based line i is lines[i - 1]) changed by `edit`, saved as bad.csv.
  std::string Edited(const std::function<void(std::vector<std::string>*)>& edit) {
    std::vector<std::string> lines;
    std::istringstream in(ReadText(good_));
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    edit(&lines);
    const std::string bad = (dir_ / "bad.csv").string();
    std::ofstream out(bad);
    for (const std::string& line : lines) out << line << "\n";
    return bad;
  }
  // 1-based number of the good file's line starting with `prefix`.
  int LineOf(const std::string& prefix) {
    std::istringstream in(ReadText(good_));
    int number = 0;
    for (std::string line; std::getline(in, line);) {
      ++number;
      if (line.rfind(prefix, 0) == 0) return number;
    }
    ADD_FAILURE() << "no line starts with " << prefix;
    return 0;
  }
  std::string Replaced(const std::string& prefix, const std::string& replacement) {
    const int line = LineOf(prefix);
    return Edited([&](std::vector<std::string>* lines) { (*lines)[line - 1] = replacement; });
  }
  // Reading `path` must throw an InputError at `line` whose message starts with the file and
  // line (just the file for line 0) and contains every one of `parts`.
  void ExpectRefused(const std::string& path, int line, const std::vector<std::string>& parts) {
    try {
      ReadCmacFile(path, nullptr);
      ADD_FAILURE() << "accepted " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.line(), line) << e.what();
      const std::string what = e.what();
      const std::string where = line > 0 ? path + ":" + std::to_string(line) + ":" : path + ":";
      EXPECT_EQ(what.rfind(where, 0), 0u) << what;
      for (const std::string& part : parts) {
        EXPECT_NE(what.find(part), std::string::npos) << "\"" << part << "\" not in: " << what;
      }
    }
  }

  fs::path dir_;
  std::string good_;
};

TEST_F(NetworkIoTest, RoundTripIsExact) {
  for (int table : {0, 211}) {
    const Cmac original = TrainedCmac(table);
    const std::string path = (dir_ / ("net_" + std::to_string(table) + ".csv")).string();
    WriteCmacFile(original, kMetadata, path);
    std::map<std::string, std::string> metadata;
    const Cmac read = ReadCmacFile(path, &metadata);
    const CmacOptions& a = original.options();
    const CmacOptions& b = read.options();
    EXPECT_EQ(a.layers, b.layers);
    EXPECT_EQ(a.quantum, b.quantum);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.x_min, b.x_min);
    EXPECT_EQ(a.x_max, b.x_max);
    EXPECT_EQ(a.hash_table_size, b.hash_table_size);
    EXPECT_EQ(a.hash_seed, b.hash_seed);
    ASSERT_EQ(original.weights().size(), read.weights().size());
    for (size_t i = 0; i < original.weights().size(); ++i) {
      // Bit for bit, signed zero included.
      EXPECT_EQ(original.weights()[i], read.weights()[i]) << i;
      EXPECT_EQ(std::signbit(original.weights()[i]), std::signbit(read.weights()[i])) << i;
    }
    EXPECT_EQ(metadata, kMetadata);
    for (double x = -1.0; x <= 1.0; x += 0.01) EXPECT_EQ(original.Query(x), read.Query(x));
    // Writing what was read reproduces the file byte for byte.
    const std::string again = (dir_ / "again.csv").string();
    WriteCmacFile(read, metadata, again);
    EXPECT_EQ(ReadText(path), ReadText(again));
  }
}

TEST_F(NetworkIoTest, WritesAtomicallyAndLeavesNoTemporary) {
  const std::string path = (dir_ / "sub" / "dir" / "net.csv").string();
  WriteCmacFile(TrainedCmac(0), {}, path);
  WriteCmacFile(TrainedCmac(0), kMetadata, path);  // replaces
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir_ / "sub" / "dir")) {
    EXPECT_EQ(entry.path().filename(), "net.csv");
    ++files;
  }
  EXPECT_EQ(files, 1);
  std::map<std::string, std::string> metadata;
  ReadCmacFile(path, &metadata);
  EXPECT_EQ(metadata, kMetadata);
}

TEST_F(NetworkIoTest, FileLayout) {
  const std::string text = ReadText(good_);
  EXPECT_EQ(text.rfind("# format = rabbit-cmac/1\n", 0), 0u);
  for (const char* key : {"# layers = 6\n", "# width = 6\n", "# x_min = -0.7\n", "# x_max = 0.45\n",
                          "# hash_table_size = 0\n", "# hash_seed = 16045690984503111693\n",
                          "# gait = vm_0.60\n", "\nindex,weight\n0,0.1\n1,-0\n2,1e-300\n"}) {
    EXPECT_NE(text.find(key), std::string::npos) << key;
  }
}

TEST_F(NetworkIoTest, RefusesAMissingOrWrongFormat) {
  ExpectRefused(Edited([](std::vector<std::string>* l) { l->erase(l->begin()); }), 1,
                {"format", "missing"});
  ExpectRefused(Replaced("# format", "# format = rabbit-cmac/2"), 1,
                {"rabbit-cmac/2", "rabbit-cmac/1"});
  ExpectRefused(Replaced("# format", "# format = rabbit-gait/1"), 1, {"rabbit-gait/1"});
}

TEST_F(NetworkIoTest, RefusesMissingStructureKeys) {
  const int header = LineOf("index,weight");
  for (const std::string key :
       {"layers", "quantum_rad", "width", "x_min", "x_max", "hash_table_size", "hash_seed"}) {
    const int line = LineOf("# " + key + " =");
    const std::string bad =
        Edited([&](std::vector<std::string>* l) { l->erase(l->begin() + (line - 1)); });
    // Reported at the header row (one line up now), where the structure should be complete.
    ExpectRefused(bad, header - 1, {"'" + key + "'", "missing"});
  }
}

TEST_F(NetworkIoTest, RefusesNonNumbers) {
  struct Case {
    std::string prefix, replacement;
  };
  const std::vector<Case> cases = {
      {"# quantum_rad", "# quantum_rad = abc"},
      {"# quantum_rad", "# quantum_rad = nan"},
      {"# x_min", "# x_min = -inf"},
      {"# x_max", "# x_max = 0.45 rad"},
      {"# layers", "# layers = 6.5"},
      {"# width", "# width = six"},
      {"# hash_table_size", "# hash_table_size = 1e3"},
      {"# hash_seed", "# hash_seed = -1"},
      {"# x_max", "# x_max ="},
  };
  for (const Case& c : cases) {
    const std::string key = c.prefix.substr(2);
    ExpectRefused(Replaced(c.prefix, c.replacement), LineOf(c.prefix), {"'" + key + "'"});
  }
  // In the weights: NaN, infinity, text, an empty cell.
  const int row = LineOf("index,weight") + 5;  // weight 4
  for (const std::string cell : {"nan", "inf", "1.0x", ""}) {
    ExpectRefused(Edited([&](std::vector<std::string>* l) { (*l)[row - 1] = "4," + cell; }), row,
                  {"'weight'"});
  }
}

TEST_F(NetworkIoTest, RefusesHugeWeightsAndHugeTables) {
  Cmac cmac(CmacOptions{});
  const std::string path = (dir_ / "w.csv").string();
  WriteCmacFile(cmac, {}, path);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const size_t row = s.find("\n0,");
  ASSERT_NE(row, std::string::npos);
  s.replace(row, 3, "\n0,1e300\n0,");  // first weight 1e300 (the old row follows, then refused)
  std::ofstream(path) << s;
  try {
    ReadCmacFile(path, nullptr);
    ADD_FAILURE() << "accepted a 1e300 weight";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("1e6"), std::string::npos) << e.what();
  }
  CmacOptions huge;
  huge.hash_table_size = 2000000000;
  std::string error;
  EXPECT_FALSE(huge.IsValid(&error));
}

TEST_F(NetworkIoTest, RefusesAnInvalidStructure) {
  ExpectRefused(Replaced("# layers", "# layers = 0"), LineOf("# layers"), {"'layers'"});
  ExpectRefused(Replaced("# layers", "# layers = 7"), LineOf("# layers"),
                {"'layers'", "width"});  // layers <= width
  ExpectRefused(Replaced("# quantum_rad", "# quantum_rad = 1e-9"), LineOf("# quantum_rad"),
                {"'quantum_rad'", "too many quanta"});
  ExpectRefused(Replaced("# quantum_rad", "# quantum_rad = -0.1"), LineOf("# quantum_rad"),
                {"'quantum_rad'"});
  ExpectRefused(Replaced("# x_max", "# x_max = -0.7"), LineOf("# x_max"), {"'x_max'"});
  ExpectRefused(Replaced("# hash_table_size", "# hash_table_size = -3"),
                LineOf("# hash_table_size"), {"'hash_table_size'"});
}

TEST_F(NetworkIoTest, RefusesAWrongWeightCount) {
  const Cmac cmac = TrainedCmac(0);
  const int n = static_cast<int>(cmac.weights().size());
  const std::string expected = "expected " + std::to_string(n) + " weights";
  // One short: reported at the last line.
  const std::string short_one = Edited([](std::vector<std::string>* l) { l->pop_back(); });
  const int last = LineOf("index,weight") + n - 1;
  ExpectRefused(short_one, last, {expected, "got " + std::to_string(n - 1)});
  // Two extra: reported at the first extra row, with the total.
  const std::string long_one = Edited([n](std::vector<std::string>* l) {
    l->push_back(std::to_string(n) + ",0.5");
    l->push_back(std::to_string(n + 1) + ",0.25");
  });
  ExpectRefused(long_one, last + 2, {expected, "got " + std::to_string(n + 2)});
  // No rows at all.
  const int header = LineOf("index,weight");
  const std::string empty =
      Edited([header](std::vector<std::string>* l) { l->resize(static_cast<size_t>(header)); });
  ExpectRefused(empty, header, {expected, "got 0"});
  // Hashed: the count is the table size.
  const std::string hashed = Replaced("# hash_table_size", "# hash_table_size = 100");
  ExpectRefused(hashed, header + 101,
                {"expected 100 weights", "hash_table_size", "got " + std::to_string(n)});
}

TEST_F(NetworkIoTest, RefusesMalformedRowsAndHeaders) {
  const int header = LineOf("index,weight");
  ExpectRefused(Replaced("index,weight", "i,w"), header, {"index,weight"});
  ExpectRefused(Replaced("index,weight", "index,weight,extra"), header, {"index,weight"});
  ExpectRefused(Edited([header](std::vector<std::string>* l) { (*l)[header] = "0,1,2"; }),
                header + 1, {"expected 2 cells"});
  ExpectRefused(Edited([header](std::vector<std::string>* l) { (*l)[header + 1] = "7,0.5"; }),
                header + 2, {"expected index 1, got 7"});
  ExpectRefused(Edited([header](std::vector<std::string>* l) { (*l)[header] = "zero,0.5"; }),
                header + 1, {"'index'"});
  ExpectRefused(
      Edited([header](std::vector<std::string>* l) { l->insert(l->begin() + header + 3, "# x"); }),
      header + 4, {"comment after the header row"});
}

TEST_F(NetworkIoTest, RefusesRepeatedKeysAndOnlyAHeader) {
  const int layers = LineOf("# layers");
  ExpectRefused(Edited([layers](std::vector<std::string>* l) {
                  l->insert(l->begin() + layers, "# layers = 6");
                }),
                layers + 1, {"'layers'", "repeated", "line " + std::to_string(layers)});
  const int header = LineOf("index,weight");
  ExpectRefused(
      Edited([header](std::vector<std::string>* l) { l->resize(static_cast<size_t>(header - 1)); }),
      header - 1, {"no header row"});
  ExpectRefused((dir_ / "missing.csv").string(), 0, {"cannot open"});
}

TEST_F(NetworkIoTest, BlankLinesAndFreeCommentsAreAllowed) {
  const std::string path = Edited([](std::vector<std::string>* l) {
    l->insert(l->begin() + 1, "# a free comment without an equals sign");
    l->insert(l->begin() + 2, "");
    l->push_back("");
  });
  std::map<std::string, std::string> metadata;
  const Cmac read = ReadCmacFile(path, &metadata);
  EXPECT_EQ(read.weights(), TrainedCmac(0).weights());
  EXPECT_EQ(metadata, kMetadata);
}

TEST_F(NetworkIoTest, WriteRefusesMetadataThatWouldNotReadBack) {
  const Cmac cmac = TrainedCmac(0);
  const std::string path = (dir_ / "w.csv").string();
  for (const std::map<std::string, std::string>& bad :
       std::vector<std::map<std::string, std::string>>{{{"layers", "7"}},
                                                       {{"format", "x"}},
                                                       {{"", "x"}},
                                                       {{"a=b", "x"}},
                                                       {{" gait", "x"}},
                                                       {{"gait", "two\nlines"}},
                                                       {{"gait", "padded "}}}) {
    EXPECT_THROW(WriteCmacFile(cmac, bad, path), std::invalid_argument);
  }
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace rabbit
