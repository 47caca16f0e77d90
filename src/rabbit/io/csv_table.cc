#include "rabbit/io/csv_table.h"

#include <cmath>
#include <limits>

#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"

namespace rabbit {
namespace {

bool IsBlank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// s without leading and trailing blanks, as Trim() but without a copy.
std::string_view TrimView(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && IsBlank(s[a])) ++a;
  while (b > a && IsBlank(s[b - 1])) --b;
  return s.substr(a, b - a);
}

// Parses the record that starts at text[*pos]: appends each cell's unescaped text to *out and its
// start offset to *starts, and moves *pos past the record's end of line and *line past its lines.
// Returns the number of cells, or 0 for a blank line (nothing appended).
size_t ParseRecord(const std::string& text, const std::string& file, size_t* pos, int* line,
                   std::string* out, std::vector<size_t>* starts) {
  const size_t size = text.size();
  size_t i = *pos;
  size_t cells = 0;
  bool blank = true;
  while (true) {
    starts->push_back(out->size());
    ++cells;
    size_t j = i;
    while (j < size && (text[j] == ' ' || text[j] == '\t')) ++j;
    if (j < size && text[j] == '"') {
      blank = false;
      const int open_line = *line;
      ++j;
      while (true) {
        if (j >= size) throw InputError(file, open_line, "", "unterminated quoted cell");
        const char c = text[j];
        if (c == '"') {
          if (j + 1 < size && text[j + 1] == '"') {
            out->push_back('"');
            j += 2;
            continue;
          }
          ++j;
          break;
        }
        if (c == '\n') ++*line;
        out->push_back(c);
        ++j;
      }
      while (j < size && IsBlank(text[j])) ++j;
      if (j < size && text[j] != ',' && text[j] != '\n') {
        throw InputError(file, *line, "", "text after the closing quote of a cell");
      }
      i = j;
    } else {
      size_t end = i;
      while (end < size && text[end] != ',' && text[end] != '\n') ++end;
      const std::string_view cell = TrimView(std::string_view(text).substr(i, end - i));
      if (!cell.empty()) blank = false;
      out->append(cell.data(), cell.size());
      i = end;
    }
    if (i >= size) break;
    if (text[i] == ',') {
      blank = false;
      ++i;
      continue;
    }
    ++i;  // the newline
    ++*line;
    break;
  }
  *pos = i;
  if (blank && cells == 1) {
    starts->pop_back();
    return 0;
  }
  return cells;
}

bool EqualsIgnoreCase(std::string_view a, const char* b) {
  size_t k = 0;
  for (; k < a.size() && b[k] != '\0'; ++k) {
    const char c = a[k] >= 'A' && a[k] <= 'Z' ? static_cast<char>(a[k] - 'A' + 'a') : a[k];
    if (c != b[k]) return false;
  }
  return k == a.size() && b[k] == '\0';
}

}  // namespace

CsvTable CsvTable::Parse(const std::string& text, const std::string& file) {
  CsvTable table;
  table.file_ = file;
  size_t pos = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  int line = 1;
  // Header.
  std::string header_text;
  std::vector<size_t> header_starts;
  size_t columns = 0;
  while (pos < text.size() && columns == 0) {
    table.header_line_ = line;
    columns = ParseRecord(text, file, &pos, &line, &header_text, &header_starts);
  }
  if (columns == 0) throw InputError(file, 0, "", "empty file: expected a header row");
  header_starts.push_back(header_text.size());
  for (size_t k = 0; k < columns; ++k) {
    const std::string name =
        Trim(header_text.substr(header_starts[k], header_starts[k + 1] - header_starts[k]));
    if (name.empty()) {
      throw InputError(file, table.header_line_, "",
                       "empty column name (column " + std::to_string(k + 1) + ")");
    }
    for (const std::string& seen : table.header_) {
      if (seen == name) throw InputError(file, table.header_line_, name, "duplicate column");
    }
    table.header_.push_back(name);
  }
  // Rows.
  table.cells_.reserve(text.size() - pos);
  while (pos < text.size()) {
    const int row_line = line;
    const size_t before = table.offsets_.size();
    const size_t cells = ParseRecord(text, file, &pos, &line, &table.cells_, &table.offsets_);
    if (cells == 0) continue;
    if (cells != columns) {
      table.offsets_.resize(before);
      throw InputError(file, row_line, "",
                       "expected " + std::to_string(columns) + " cells (as the header), got " +
                           std::to_string(cells));
    }
    table.lines_.push_back(row_line);
  }
  table.offsets_.push_back(table.cells_.size());
  return table;
}

CsvTable CsvTable::Read(const std::string& path) { return Read(path, kCsvTableLimits); }

CsvTable CsvTable::Read(const std::string& path, const FileLimits& limits) {
  return Parse(ReadBoundedFile(path, limits), path);
}

bool CsvTable::HasColumn(const std::string& name) const {
  for (const std::string& h : header_) {
    if (h == name) return true;
  }
  return false;
}

size_t CsvTable::Column(const std::string& name) const {
  for (size_t k = 0; k < header_.size(); ++k) {
    if (header_[k] == name) return k;
  }
  throw InputError(file_, header_line_, name, "missing column");
}

std::vector<size_t> CsvTable::ColumnsWithPrefix(const std::string& prefix) const {
  std::vector<size_t> out;
  for (size_t k = 0; k < header_.size(); ++k) {
    if (header_[k].compare(0, prefix.size(), prefix) == 0) out.push_back(k);
  }
  return out;
}

std::string_view CsvTable::Cell(size_t row, size_t column) const {
  const size_t k = row * header_.size() + column;
  return std::string_view(cells_).substr(offsets_[k], offsets_[k + 1] - offsets_[k]);
}

double CsvTable::Number(size_t row, size_t column, CsvNumber policy) const {
  const std::string_view cell = Cell(row, column);
  if (policy != CsvNumber::kFinite && !cell.empty()) {
    const bool negative = cell[0] == '-';
    const std::string_view body = cell[0] == '-' || cell[0] == '+' ? cell.substr(1) : cell;
    if (EqualsIgnoreCase(body, "nan")) return std::numeric_limits<double>::quiet_NaN();
    if (policy == CsvNumber::kAny &&
        (EqualsIgnoreCase(body, "inf") || EqualsIgnoreCase(body, "infinity"))) {
      return negative ? -std::numeric_limits<double>::infinity()
                      : std::numeric_limits<double>::infinity();
    }
  }
  return ParseFiniteNumber(std::string(cell), file_, line(row), header_[column]);
}

int CsvTable::Integer(size_t row, size_t column) const {
  const double value = Number(row, column);
  if (value != std::floor(value) || std::abs(value) > std::numeric_limits<int>::max()) {
    throw InputError(file_, line(row), header_[column],
                     "expected an integer, got \"" + Text(row, column) + "\"");
  }
  return static_cast<int>(value);
}

int CsvTable::Flag(size_t row, size_t column, bool allow_missing) const {
  const std::string_view text = Cell(row, column);
  if (text == "1" || text == "true") return 1;
  if (text == "0" || text == "false") return 0;
  if (allow_missing && (text.empty() || text == "nan")) return -1;
  throw InputError(file_, line(row), header_[column],
                   "expected 1 or 0, got \"" + std::string(text) + "\"");
}

std::vector<double> CsvTable::Numbers(const std::string& name, CsvNumber policy) const {
  const size_t column = Column(name);
  std::vector<double> out(num_rows());
  for (size_t row = 0; row < num_rows(); ++row) out[row] = Number(row, column, policy);
  return out;
}

}  // namespace rabbit
