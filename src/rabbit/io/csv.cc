#include "rabbit/io/csv.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>
#include <system_error>

#include "rabbit/io/error.h"

namespace rabbit {

std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    out.push_back(Trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

double ParseFiniteNumber(const std::string& text, const std::string& file, int line,
                         const std::string& key) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const std::from_chars_result r = std::from_chars(text.data(), end, value);
  if (text.empty() || r.ec != std::errc() || r.ptr != end) {
    throw InputError(file, line, key, "expected a number, got \"" + text + "\"");
  }
  if (!std::isfinite(value)) {
    throw InputError(file, line, key, "expected a finite number, got \"" + text + "\"");
  }
  return value;
}

std::string FormatCsvCell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return out + "\"";
}

char* WriteCsvNumber(char* out, double v) {
  if (std::isnan(v)) {  // to_chars would write "-nan" for a negative NaN
    std::memcpy(out, "nan", 3);
    return out + 3;
  }
  // Shortest round trip (infinities come out as "inf" and "-inf").
  return std::to_chars(out, out + kMaxCsvNumberChars, v).ptr;
}

std::string FormatCsvNumber(double v) {
  char text[kMaxCsvNumberChars];
  return std::string(text, WriteCsvNumber(text, v));
}

void AppendCsvNumber(double v, std::string* out) {
  char text[kMaxCsvNumberChars];
  out->append(text, WriteCsvNumber(text, v));
}

}  // namespace rabbit
