// The layout of a gait database: one folder (its root holds the manifest) with
//   reference/      the reference gaits (rabbit-gait/1 CSV files) and their index.csv
//   networks/       the trained CMACs and their index.csv
//   gait_pattern.fll  the fuzzy system that merges the gaits
//   walker.csv      per-gait walker settings (walker_settings.h)
//   manifest.csv    what `rabbit gaits build` made, with the SHA-256 of every file
// (docs/gait-database.md).
#ifndef RABBIT_GAIT_DATABASE_LAYOUT_H_
#define RABBIT_GAIT_DATABASE_LAYOUT_H_

#include <string>

namespace rabbit {

constexpr const char* kReferenceDir = "reference";
constexpr const char* kNetworksDir = "networks";
constexpr const char* kGaitPatternFile = "gait_pattern.fll";
constexpr const char* kManifestFile = "manifest.csv";
constexpr const char* kIndexFile = "index.csv";

// The database root that `dir` names: `dir` itself, or its parent when `dir` is a database's
// reference/ folder (holds index.csv, no reference/ of its own, and is named reference), as
// commands took before databases had a root.
std::string GaitDatabaseRoot(const std::string& dir);
// The database a written path belongs to, whose root every writer locks (one lock per database:
// OutputLock(root)): the parent of `path` when `path` is a folder named reference or the parent
// holds reference/ or manifest.csv (a database's networks/, its FLL file, ...); "" otherwise.
std::string DatabaseRootOf(const std::string& path);
// root/reference, root/networks, root/gait_pattern.fll.
std::string ReferenceDirOf(const std::string& root);
std::string NetworksDirOf(const std::string& root);
std::string GaitPatternOf(const std::string& root);

}  // namespace rabbit

#endif  // RABBIT_GAIT_DATABASE_LAYOUT_H_
