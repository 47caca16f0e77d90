// Atomic output: write to a temporary file beside the target, then rename over it, so a crash or
// a kill leaves either the old file or the new one, never half of one.
#ifndef RABBIT_IO_ATOMIC_FILE_H_
#define RABBIT_IO_ATOMIC_FILE_H_

#include <functional>
#include <ostream>
#include <string>

namespace rabbit {

// Creates missing parent directories, calls write(stream) on a temporary file and renames it to
// path. Throws std::runtime_error (naming the file) when anything fails; the temporary is removed.
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace rabbit

#endif  // RABBIT_IO_ATOMIC_FILE_H_
