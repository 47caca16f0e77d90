// InputError: what the user gave us is wrong. Carries the file, the line (0 when unknown) and the
// key, so every message can point at the place to fix. The CLI maps it to exit code 2.
#ifndef RABBIT_IO_ERROR_H_
#define RABBIT_IO_ERROR_H_

#include <stdexcept>
#include <string>

namespace rabbit {

class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, int line, const std::string& key, const std::string& message);
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
};

// A number for messages, as %g writes it: "3600", "2e+06", "0.5".
std::string FormatLimit(double v);

}  // namespace rabbit

#endif  // RABBIT_IO_ERROR_H_
