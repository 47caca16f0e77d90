// SHA-256 content hashes (OpenSSL's EVP interface), as lowercase hex: what the gait database's
// manifest records for every file, and what resume and shard fingerprints hash a suite's inputs with.
#ifndef RABBIT_IO_SHA256_H_
#define RABBIT_IO_SHA256_H_

#include <string>
#include <string_view>

namespace rabbit {

// The 64 hex digits of SHA-256(bytes).
std::string Sha256Hex(std::string_view bytes);

// The 64 hex digits of SHA-256 of the file's content. Throws InputError naming the file when it
// cannot be read or is not a regular file.
std::string Sha256OfFile(const std::string& path);

}  // namespace rabbit

#endif  // RABBIT_IO_SHA256_H_
