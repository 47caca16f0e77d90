// Adding gaits to a reference folder in one commit: a kill at any moment leaves either the old
// gaits and index or the new ones, or a state the next writer finishes.
//   1. each gait is written beside its file as .NAME.csv.rabbit-pending;
//   2. the new index is written as .index.csv.rabbit-pending: from then on the commit is decided;
//   3. the gaits, then the index, are renamed into place.
// FinishGaitCommit, run by every writer under the database's lock before it writes, finishes a
// decided commit (2 done) and removes the pending gaits of an undecided one: only files of those
// names, which rabbit alone makes. Test kill points: gaits-add-staged, gaits-add-decided,
// gaits-add-renaming, gaits-add-done.
#ifndef RABBIT_GAIT_DATABASE_COMMIT_H_
#define RABBIT_GAIT_DATABASE_COMMIT_H_

#include <string>
#include <vector>

#include "rabbit/gait/gait_database.h"

namespace rabbit {

// The pending name of a file of a reference folder: ".NAME.rabbit-pending".
std::string PendingGaitFile(const std::string& file);

// Finishes or rolls back what a killed writer left in `dir` (see above). Returns true when it
// found something to do.
bool FinishGaitCommit(const std::string& dir);

// Writes or replaces the gaits' files in `dir` and their rows in dir/index.csv (kept sorted as
// AddGaitToDatabase keeps it), in one commit. Two gaits of one name are an error (nothing
// written). Returns the gait files' paths.
std::vector<std::string> AddGaitsToDatabase(const std::vector<GaitRecord>& gaits,
                                            const std::string& dir);

}  // namespace rabbit

#endif  // RABBIT_GAIT_DATABASE_COMMIT_H_
