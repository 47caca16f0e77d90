// Trained SISO CMACs as CSV files (docs/formats/networks.md, gaits/networks/):
//   # format = rabbit-cmac/1
//   # layers = 6                  structure: layers, quantum_rad, width, x_min, x_max,
//   # quantum_rad = 0.00436...    hash_table_size, hash_seed (all required)
//   ...
//   # gait = vm_0.60              free metadata (any other keys), e.g. gait and output names
//   index,weight
//   0,0.0123...                   one row per weight, index 0, 1, ... in order
// Numbers are written in the shortest form that reads back to the same double, so a file
// round-trips exactly. The reader refuses anything malformed with an InputError naming the file
// and line.
#ifndef RABBIT_LEARN_NETWORK_IO_H_
#define RABBIT_LEARN_NETWORK_IO_H_

#include <map>
#include <string>

#include "rabbit/learn/cmac.h"

namespace rabbit {

constexpr const char* kCmacFormat = "rabbit-cmac/1";

// Writes the network atomically (temporary file beside `path`, then rename). Metadata keys must
// be non-empty, free of '=' and line breaks, without surrounding blanks, and neither a
// structure key or "format"; values free of line breaks and surrounding blanks (so that they
// read back unchanged): otherwise std::invalid_argument. std::runtime_error when the file
// cannot be written.
void WriteCmacFile(const Cmac& cmac, const std::map<std::string, std::string>& metadata,
                   const std::string& path);

// Reads a network written by WriteCmacFile; the free metadata goes to `metadata` (may be null).
// Throws InputError (file, line, key) for: a missing or wrong format tag, a missing, repeated or
// non-numeric structure key (NaN and infinities included; integers where integers are due), a
// structure that CmacOptions::IsValid refuses, a header row other than "index,weight", a
// malformed row or out-of-order index, and a weight count other than the structure implies.
Cmac ReadCmacFile(const std::string& path, std::map<std::string, std::string>* metadata);

}  // namespace rabbit

#endif  // RABBIT_LEARN_NETWORK_IO_H_
