// Reading a user's file whole, within the limits of its kind (rabbit/io/limits.h): a regular file
// larger than the limit is refused from its size alone; anything else (a FIFO, a device such as
// /dev/zero, a file still growing) is read up to the limit and refused there. Every refusal is an
// InputError naming the file and the limit.
#ifndef RABBIT_IO_BOUNDED_READ_H_
#define RABBIT_IO_BOUNDED_READ_H_

#include <string>
#include <string_view>

#include "rabbit/io/limits.h"

namespace rabbit {

// The file's bytes. InputError(path, 0, "", ...) when it does not exist ("no such file"), is a
// directory, cannot be read, or holds more than limits.max_bytes; InputError(path, line, "", ...)
// for the first line over limits.max_line_bytes or beyond limits.max_lines.
std::string ReadBoundedFile(const std::string& path, const FileLimits& limits);

// The same, but "" when nothing is at the path (for files a writer may not have made yet).
std::string ReadBoundedFileIfExists(const std::string& path, const FileLimits& limits);

// The line and line-count checks alone, on text already in memory (`file` names it in errors).
void CheckLineLimits(std::string_view text, const std::string& file, const FileLimits& limits);

// "4 MiB", "64 KiB", "100 bytes": a limit for messages.
std::string FormatBytes(size_t bytes);

// text, cut to at most max_bytes with a note of how much was left out (for quoting what another
// program printed).
std::string TruncateForMessage(const std::string& text, size_t max_bytes);

}  // namespace rabbit

#endif  // RABBIT_IO_BOUNDED_READ_H_
