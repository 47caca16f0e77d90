// Small CSV helpers shared by the project's readers: trimming, splitting a row, and strict number
// parsing that throws InputError naming the file, line and column or key.
#ifndef RABBIT_IO_CSV_H_
#define RABBIT_IO_CSV_H_

#include <string>
#include <vector>

namespace rabbit {

// The lines of a text (without their newline characters).
std::vector<std::string> SplitLines(const std::string& text);
// s without leading and trailing blanks (space, tab, carriage return).
std::string Trim(const std::string& s);
// The comma-separated cells of a row, trimmed; a trailing comma gives a last empty cell.
std::vector<std::string> SplitCsv(const std::string& line);
// The whole of text as a finite double; else InputError(file, line, key, ...).
double ParseFiniteNumber(const std::string& text, const std::string& file, int line,
                         const std::string& key);

// Writing: a cell's text (as is without commas, quotes or newlines; else quoted, quotes doubled,
// newlines as spaces) and a number in the shortest form that reads back as the same double
// (std::to_chars; `nan`, `inf`, `-inf` spelled out).
std::string FormatCsvCell(const std::string& text);
std::string FormatCsvNumber(double v);
// The longest text FormatCsvNumber gives ("-2.2250738585072014e-308" and the like).
constexpr int kMaxCsvNumberChars = 32;
// Writes FormatCsvNumber(v) at `out`, which has room for kMaxCsvNumberChars characters, and
// returns the end: the allocation-free form for files with many numbers per row.
char* WriteCsvNumber(char* out, double v);
// Appends FormatCsvNumber(v) to *out.
void AppendCsvNumber(double v, std::string* out);

}  // namespace rabbit

#endif  // RABBIT_IO_CSV_H_
