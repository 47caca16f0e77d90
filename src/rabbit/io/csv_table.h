// A CSV file read whole into a table: one header row naming the columns, then rows of cells,
// looked up by column name. Cells are kept as text and parsed on demand, strictly: a cell that is
// not a number, or is not allowed to be missing, is an InputError naming the file, the line and
// the column. RFC 4180 quoting is understood ("a, b" and "say ""hi""" are single cells; a quoted
// cell may span lines); unquoted cells are trimmed as by SplitCsv.
#ifndef RABBIT_IO_CSV_TABLE_H_
#define RABBIT_IO_CSV_TABLE_H_

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "rabbit/io/limits.h"

namespace rabbit {

// What a numeric cell may hold besides a finite number.
enum class CsvNumber {
  kFinite,       // a finite number only
  kFiniteOrNan,  // or `nan` (any case, optional sign): a missing value, returned as quiet NaN
  kAny,          // or `nan`, `inf`, `-inf`, `infinity` (returned as such)
};

class CsvTable {
 public:
  // Parses text; `file` names the source in errors. Throws InputError for an empty text (no
  // header), an empty or duplicate column name, a row whose cell count differs from the
  // header's, an unterminated quote or text after a closing quote. Blank lines are skipped; a
  // UTF-8 byte-order mark and CRLF line ends are accepted.
  static CsvTable Parse(const std::string& text, const std::string& file);
  // Reads and parses the file at path; InputError(path, 0, "", ...) when it cannot be read.
  static CsvTable Read(const std::string& path);  // within kCsvTableLimits
  // Within the given limits (rabbit/io/limits.h), named in the error.
  static CsvTable Read(const std::string& path, const FileLimits& limits);

  const std::string& file() const { return file_; }
  const std::vector<std::string>& header() const { return header_; }
  size_t num_rows() const { return lines_.size(); }
  size_t num_columns() const { return header_.size(); }
  // 1-based line in the file where the row starts (the header is line 1 unless blank lines
  // precede it).
  int line(size_t row) const { return lines_[row]; }

  bool HasColumn(const std::string& name) const;
  // Index of the named column; InputError(file, header line, name, "missing column") when absent.
  size_t Column(const std::string& name) const;
  // Indices of the columns whose name starts with prefix, in file order.
  std::vector<size_t> ColumnsWithPrefix(const std::string& prefix) const;

  std::string_view Cell(size_t row, size_t column) const;
  std::string Text(size_t row, size_t column) const { return std::string(Cell(row, column)); }
  // The cell as a number, as `policy` allows; else InputError(file, line, column name, ...).
  double Number(size_t row, size_t column, CsvNumber policy = CsvNumber::kFinite) const;
  // The cell as an integer (a number with no fractional part, within int range).
  int Integer(size_t row, size_t column) const;
  // The cell as a flag: 1 for `1` or `true`, 0 for `0` or `false`, -1 for a missing value (empty
  // or `nan`) when allow_missing; else InputError(file, line, column name, "expected 1 or 0").
  int Flag(size_t row, size_t column, bool allow_missing = false) const;
  // A whole column by name (Column(name), then Number for every row).
  std::vector<double> Numbers(const std::string& name, CsvNumber policy = CsvNumber::kFinite) const;

 private:
  std::string file_;
  int header_line_ = 1;
  std::vector<std::string> header_;
  std::string cells_;            // every cell's text, unescaped, back to back
  std::vector<size_t> offsets_;  // cell k is cells_[offsets_[k], offsets_[k + 1])
  std::vector<int> lines_;       // per row, its first line
};

}  // namespace rabbit

#endif  // RABBIT_IO_CSV_TABLE_H_
