// The manifest of a gait database (manifest.csv at its root), written by `rabbit gaits build`:
//   # format = rabbit-gait-manifest/1
//   # generator = rabbit <version>
//   # model_sha256 = <SHA-256 of the model file, or "builtin:" and the built-in model's hash>
//   # simulator_sha256 = <SHA-256 of the simulator settings the gaits were synthesized with>
//   kind,name,file,sha256,seed,inputs_sha256
//   gait,vm_0.30,reference/vm_0.30.csv,<64 hex>,1,<64 hex>    one row per reference gait
//   file,,networks/index.csv,<64 hex>,,                      one row per other file
// Rows sorted by file. inputs_sha256 hashes what a gait was made from (its target, the model,
// the simulator settings, the program version): a resumed build keeps a gait whose inputs and
// file hash are unchanged. No timestamps, no commit ids: the same inputs give the same bytes.
#ifndef RABBIT_OPTIMIZERS_GAIT_MANIFEST_H_
#define RABBIT_OPTIMIZERS_GAIT_MANIFEST_H_

#include <string>
#include <vector>

namespace rabbit {

constexpr const char* kManifestFormat = "rabbit-gait-manifest/1";

struct ManifestRow {
  std::string kind;  // "gait" or "file"
  std::string name;  // the gait's name (gait rows)
  std::string file;  // relative to the database root, '/'-separated
  std::string sha256;
  std::string seed;           // gait rows
  std::string inputs_sha256;  // gait rows
};

struct Manifest {
  std::string generator, model_sha256, simulator_sha256;
  std::vector<ManifestRow> rows;
};

// Whether s is a SHA-256 as the manifest writes it: 64 lowercase hex digits.
bool IsHex64(const std::string& s);

std::string ManifestText(const Manifest& manifest);  // rows in the given order
// Reads root/manifest.csv. Throws InputError (file, line, key) for a missing or wrong format
// line, unknown columns or kinds, a bad hash, a path leaving the root, a file listed twice.
Manifest ReadManifest(const std::string& path);
// Whether the file `rel` (relative to a database's root) is one a writer of rabbit leaves behind
// when killed, and the next one removes or ignores: a lock file (.NAME.rabbit-lock), a pending
// gait or index (.NAME.rabbit-pending), a file of a build's staging folder (.build/) or of a
// marked staging folder of rabbit train (networks.staging/).
bool IsLeftoverOfRabbit(const std::string& root, const std::string& rel);
// Checks that every file the manifest lists exists under root with its hash, and that root holds
// no file it does not list (but README.md, targets files (*.toml) at the root and
// IsLeftoverOfRabbit). Throws InputError naming the first disagreement.
void VerifyManifest(const Manifest& manifest, const std::string& root,
                    const std::string& manifest_path);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_GAIT_MANIFEST_H_
