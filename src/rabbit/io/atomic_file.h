// Atomic output: write to a temporary file beside the target, then rename over it, so a crash or
// a kill leaves either the old file or the new one, never half of one.
#ifndef RABBIT_IO_ATOMIC_FILE_H_
#define RABBIT_IO_ATOMIC_FILE_H_

#include <functional>
#include <ostream>
#include <string>

namespace rabbit {

// Creates missing parent directories, calls write(stream) on a temporary file and renames it to
// path. Only a regular file is ever replaced: a folder, device, FIFO, socket or symbolic link at
// the path is an InputError (naming it), and nothing is written. Throws std::runtime_error (naming
// the file) when anything else fails; the temporary is removed. The temporaries a killed writer of
// the same path left (PATH.tmp.PID.N of a process that no longer runs) are removed first.
void WriteFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// A command's single output file: "-" writes to standard output, anything else atomically.
void WriteOutputFile(const std::string& path, const std::function<void(std::ostream&)>& write);

// Whether a single output file goes to standard output.
inline bool IsStandardOutput(const std::string& path) { return path == "-"; }

}  // namespace rabbit

#endif  // RABBIT_IO_ATOMIC_FILE_H_
