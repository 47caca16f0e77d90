// The staging folder of `rabbit gaits build` (DIR/.build): what a build makes before it replaces
// the database's files, how a build finishes the commit a killed one left or drops an incomplete
// staging folder, and the list of synthesized gaits a build stopped after its synthesis leaves to
// the next build of the folder. See docs/gait-database.md ("Resume") and docs/file-safety.md.
#ifndef RABBIT_OPTIMIZERS_GAIT_BUILD_STAGING_H_
#define RABBIT_OPTIMIZERS_GAIT_BUILD_STAGING_H_

#include <filesystem>
#include <map>
#include <set>
#include <string>

#include "gait_manifest.h"

namespace rabbit {

// The staging folder's name inside the database.
constexpr const char* kStagingDir = ".build";

// A gait an unfinished build synthesized: its inputs' hash and its file's text.
struct SynthesizedGait {
  std::string inputs_sha256;
  std::string text;
};

// Moves a finished staging folder's files into the database `out`, removes the files the old
// manifest listed (old_files) that the new one does not, then moves the manifest (until then the
// commit is finished again from the staging folder's manifest), then removes the staging folder.
void CommitStaging(const std::filesystem::path& out, const std::set<std::string>& old_files);

// The state of `out` before a build: true and *manifest when it is a database, false when it is
// new or empty. On rank 0, a staging folder left by an interrupted build is first committed
// (complete) or dropped (incomplete); the gaits an incomplete one lists as synthesized, with their
// files, go to *synthesized. Throws InputError (nothing written) when `out` is neither empty nor a
// database, or is a database whose manifest, index and files disagree.
bool InspectOut(const std::filesystem::path& out, Manifest* manifest,
                std::map<std::string, SynthesizedGait>* synthesized);

// Writes the staging folder's list of synthesized gaits (name, inputs' hash, file's hash), so
// that a build stopped before its manifest leaves them to the next one.
void WriteSynthesizedList(const std::filesystem::path& staging,
                          const std::map<std::string, SynthesizedGait>& gaits);
// Removes the list (it is never part of a database).
void RemoveSynthesizedList(const std::filesystem::path& staging);

}  // namespace rabbit

#endif  // RABBIT_OPTIMIZERS_GAIT_BUILD_STAGING_H_
