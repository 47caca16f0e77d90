#include "rabbit/io/error.h"

#include <cstdio>

namespace rabbit {

std::string FormatLimit(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

namespace {

std::string Format(const std::string& file, int line, const std::string& key,
                   const std::string& message) {
  std::string out = file;
  if (line > 0) out += ":" + std::to_string(line);
  out += ": ";
  if (!key.empty()) out += "'" + key + "': ";
  return out + message;
}

}  // namespace

InputError::InputError(const std::string& file, int line, const std::string& key,
                       const std::string& message)
    : std::runtime_error(Format(file, line, key, message)), file_(file), line_(line), key_(key) {}

}  // namespace rabbit
