// The CSV table reader: columns by name, strict numbers with the line and column in the error,
// RFC 4180 quoted cells, `nan` where a column allows missing values.
#include "rabbit/io/csv_table.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "rabbit/io/error.h"

namespace rabbit {
namespace {

TEST(CsvTableTest, ColumnsByName) {
  const CsvTable t = CsvTable::Parse("a, b ,c\n1,2.5,x y\n-3e2, 0 ,\n", "t.csv");
  ASSERT_EQ(t.num_columns(), 3u);
  ASSERT_EQ(t.num_rows(), 2u);
  EXPECT_EQ(t.header()[1], "b");
  EXPECT_EQ(t.Column("c"), 2u);
  EXPECT_TRUE(t.HasColumn("a"));
  EXPECT_FALSE(t.HasColumn("d"));
  EXPECT_EQ(t.Number(0, t.Column("b")), 2.5);
  EXPECT_EQ(t.Number(1, t.Column("a")), -300.0);
  EXPECT_EQ(t.Text(0, t.Column("c")), "x y");
  EXPECT_EQ(t.Text(1, t.Column("c")), "");  // a trailing comma gives an empty last cell
  EXPECT_EQ(t.Integer(1, t.Column("b")), 0);
  EXPECT_EQ(t.line(0), 2);
  EXPECT_EQ(t.line(1), 3);
  EXPECT_EQ(t.Numbers("a"), (std::vector<double>{1.0, -300.0}));
}

TEST(CsvTableTest, MissingColumnNamesFileAndColumn) {
  const CsvTable t = CsvTable::Parse("a,b\n1,2\n", "dir/summary.csv");
  try {
    t.Column("outcome");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "dir/summary.csv");
    EXPECT_EQ(e.key(), "outcome");
    EXPECT_NE(std::string(e.what()).find("dir/summary.csv"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("'outcome'"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("missing column"), std::string::npos);
  }
}

TEST(CsvTableTest, BadNumberNamesLineAndColumn) {
  const CsvTable t = CsvTable::Parse("t_s,x_m\n0,1\n0.1,1.2x\n", "traj.csv");
  EXPECT_EQ(t.Number(0, 1), 1.0);
  try {
    t.Number(1, 1);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "traj.csv");
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.key(), "x_m");
    EXPECT_NE(std::string(e.what()).find("1.2x"), std::string::npos);
  }
  EXPECT_THROW(CsvTable::Parse("a\n1.5\n", "f").Integer(0, 0), InputError);
  EXPECT_THROW(CsvTable::Parse("a\n\"\"\n", "f").Number(0, 0), InputError);  // empty
}

TEST(CsvTableTest, QuotedCells) {
  const CsvTable t = CsvTable::Parse(
      "name,note,n\n"
      "\"a, b\", \"say \"\"hi\"\"\" ,1\n"
      "plain,\"two\nlines\",2\r\n"
      "\"\",\"  kept  \",3\n",
      "q.csv");
  ASSERT_EQ(t.num_rows(), 3u);
  EXPECT_EQ(t.Text(0, 0), "a, b");
  EXPECT_EQ(t.Text(0, 1), "say \"hi\"");
  EXPECT_EQ(t.Text(1, 1), "two\nlines");
  EXPECT_EQ(t.Number(1, 2), 2.0);
  EXPECT_EQ(t.Text(2, 0), "");
  EXPECT_EQ(t.Text(2, 1), "  kept  ");  // blanks inside quotes are the cell's
  EXPECT_EQ(t.line(2), 5);              // the quoted line break counts
  try {
    CsvTable::Parse("a,b\n1,\"open\n2,3\n", "bad.csv");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("unterminated"), std::string::npos);
  }
  EXPECT_THROW(CsvTable::Parse("a,b\n\"x\"y,1\n", "bad.csv"), InputError);
}

TEST(CsvTableTest, NanWhereAllowed) {
  const CsvTable t = CsvTable::Parse("v,d\nnan,inf\nNaN,-inf\n-nan,0.5\n", "n.csv");
  EXPECT_TRUE(std::isnan(t.Number(0, 0, CsvNumber::kFiniteOrNan)));
  EXPECT_TRUE(std::isnan(t.Number(1, 0, CsvNumber::kFiniteOrNan)));
  EXPECT_TRUE(std::isnan(t.Number(2, 0, CsvNumber::kAny)));
  EXPECT_THROW(t.Number(0, 0), InputError);  // finite only by default
  EXPECT_THROW(t.Number(0, 1, CsvNumber::kFiniteOrNan), InputError);
  EXPECT_EQ(t.Number(0, 1, CsvNumber::kAny), INFINITY);
  EXPECT_EQ(t.Number(1, 1, CsvNumber::kAny), -INFINITY);
  EXPECT_EQ(t.Number(2, 1, CsvNumber::kFiniteOrNan), 0.5);
  try {
    t.Numbers("v");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.key(), "v");
  }
}

TEST(CsvTableTest, ShapeErrors) {
  try {
    CsvTable::Parse("a,b,c\n1,2,3\n4,5\n", "shape.csv");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(std::string(e.what()).find("expected 3 cells"), std::string::npos);
  }
  EXPECT_THROW(CsvTable::Parse("", "empty.csv"), InputError);
  EXPECT_THROW(CsvTable::Parse("\n \n", "blank.csv"), InputError);
  EXPECT_THROW(CsvTable::Parse("a,a\n", "dup.csv"), InputError);
  EXPECT_THROW(CsvTable::Parse("a,,b\n", "noname.csv"), InputError);
  // A byte-order mark, CRLF and blank lines are fine.
  const CsvTable t = CsvTable::Parse("\xEF\xBB\xBFx,y\r\n\r\n1,2\r\n\n", "ok.csv");
  EXPECT_EQ(t.header()[0], "x");
  ASSERT_EQ(t.num_rows(), 1u);
  EXPECT_EQ(t.Number(0, 1), 2.0);
  EXPECT_TRUE(t.ColumnsWithPrefix("w_").empty());
}

TEST(CsvTableTest, ColumnsWithPrefixInFileOrder) {
  const CsvTable t = CsvTable::Parse("step,w_O1,rules,w_O2,w_O3\n", "s.csv");
  EXPECT_EQ(t.ColumnsWithPrefix("w_O"), (std::vector<size_t>{1, 3, 4}));
  EXPECT_EQ(t.num_rows(), 0u);
}

TEST(CsvTableTest, FlagsAreOneZeroTrueFalseOrMissingWhereAllowed) {
  const CsvTable t = CsvTable::Parse("f\n1\ntrue\n0\nfalse\n\"\"\nnan\nyes\n", "f.csv");
  EXPECT_EQ(t.Flag(0, 0), 1);
  EXPECT_EQ(t.Flag(1, 0), 1);
  EXPECT_EQ(t.Flag(2, 0), 0);
  EXPECT_EQ(t.Flag(3, 0), 0);
  EXPECT_EQ(t.Flag(4, 0, true), -1);
  EXPECT_EQ(t.Flag(5, 0, true), -1);
  EXPECT_THROW(t.Flag(4, 0), InputError);
  try {
    t.Flag(6, 0, true);
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "f.csv");
    EXPECT_EQ(e.line(), 8);
    EXPECT_EQ(e.key(), "f");
    EXPECT_NE(std::string(e.what()).find("expected 1 or 0, got \"yes\""), std::string::npos);
  }
}

TEST(CsvTableTest, ReadNamesAMissingFile) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "rabbit_csv_table_test_missing.csv").string();
  std::filesystem::remove(path);
  try {
    CsvTable::Read(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
  }
  std::ofstream(path) << "k,v\nx,1\n";
  EXPECT_EQ(CsvTable::Read(path).Text(0, 0), "x");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace rabbit
