// The one rule every command that writes follows: rabbit creates, replaces or deletes only what it
// made, and recognises what it made by a marker file it writes into it (or, for a gait database,
// its manifest). Anything else at an output path is refused with an InputError (exit 2) naming the
// path, before anything is touched. One writer at a time per output: OutputLock.
#ifndef RABBIT_IO_OUTPUT_OWNERSHIP_H_
#define RABBIT_IO_OUTPUT_OWNERSHIP_H_

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace rabbit {

// The markers. Every marker's name starts with ".rabbit-": RemoveOwnedFolder deletes them last.
constexpr const char* kNetworksMarker = ".rabbit-networks";       // rabbit train --out
constexpr const char* kGaitReportMarker = ".rabbit-gait-report";  // rabbit gaits report --out
constexpr const char* kTuneMarker = ".rabbit-tune";               // a tuning job's folder
constexpr const char* kInventory = ".rabbit-inventory";           // every file of a finished folder
constexpr const char* kGaitManifest = "manifest.csv";
constexpr const char* kGaitManifestFormat = "# format = rabbit-gait-manifest/1";

// Names a gait may not take: the database's own files (index.csv, manifest.csv).
bool IsReservedGaitName(const std::string& name);

// A gait database: `dir/manifest.csv` whose first line is kGaitManifestFormat, or (the databases
// made before the manifest) `dir/index.csv` whose first line is the gait index's header.
bool IsGaitDatabase(const std::string& dir);

// Whether `dir` is a folder holding one of `markers` (a file of that name at its root).
bool HasMarker(const std::filesystem::path& dir, const std::vector<std::string>& markers);

// Throws InputError(flag, 0, path, ...) unless the folder `path` may be replaced or written as
// rabbit's own: missing, an empty folder, or a folder holding one of `markers`. `what` names the
// kind of folder in the message ("a report of rabbit run").
void CheckOwnedFolder(const std::string& flag, const std::filesystem::path& path,
                      const std::vector<std::string>& markers, const std::string& what);

// Throws InputError unless `dir` may receive gaits: missing, an empty folder, a gait database
// (IsGaitDatabase), or a folder holding only the pending files of a killed first commit, or its
// decided pending index (rabbit/gait/database_commit.h).
void CheckGaitDatabaseOutput(const std::string& flag, const std::string& dir);

// Throws InputError unless `path` is missing or a regular file of the kind rabbit writes there,
// recognised by how its first line starts (e.g. "# format = rabbit-gait/1"; with skip_comments,
// its first line not starting with '#', e.g. an FLL file's "Engine:").
void CheckOwnedFile(const std::string& flag, const std::filesystem::path& path,
                    const std::string& first_line, const std::string& what,
                    bool skip_comments = false);

// Throws InputError unless `path` is missing or a regular file (a single output file: a device,
// FIFO, socket, folder or symbolic link there is refused).
void CheckReplaceableFile(const std::string& flag, const std::filesystem::path& path);

// When `path` itself is a symbolic link (dangling or not): the reason a command that writes the
// folder `what` at that path refuses it (it would replace the link, or write through it where the
// user did not ask); "" otherwise.
std::string SymbolicLinkRefusal(const std::filesystem::path& path, const std::string& what);

// Throws InputError unless every existing folder above `path` is a folder (or a link to one):
// nothing can be written below a file (`--out notes.txt/report`).
void CheckOutputParents(const std::string& flag, const std::filesystem::path& path);

// The inventory of a finished output folder: the path of every file (and symbolic link) below
// `dir`, written as `dir/.rabbit-inventory` once rabbit has written the folder, and again after
// rabbit report rewrites its pages in place.
void WriteInventory(const std::filesystem::path& dir);

// Throws InputError (naming `flag`) when the folder `dir`, which rabbit is about to replace or
// rewrite, holds a file its inventory does not list (one a user added: not rabbit's to delete).
// The shards of a sharded run below it are rabbit's. No inventory (a folder made before
// inventories): no check.
void CheckInventory(const std::string& flag, const std::filesystem::path& dir);

// Removes a folder rabbit made: every entry whose name does not start with ".rabbit-" first, then
// the markers, then the folder; so a kill part-way leaves a folder still recognised by its marker.
// A missing folder is no error.
void RemoveOwnedFolder(const std::filesystem::path& dir);

// Puts the finished folder `staging` at `target` in one atomic step: exchanges the two when
// `target` exists (renameat2 RENAME_EXCHANGE), so that `target` is never missing, then removes the
// old content (now at `staging`) with RemoveOwnedFolder. Falls back to remove-then-rename where the
// file system cannot exchange. The caller has checked that `target` is its own.
void ReplaceFolder(const std::filesystem::path& staging, const std::filesystem::path& target);

class OutputLock;

// For a command that writes a whole folder `out` through a staging folder beside it (named by the
// caller): checks that both are rabbit's own (CheckOwnedFolder with `marker`), takes the output's
// lock (of `lock_on` when given: the database `out` belongs to), and checks `out` again under it.
// Throws InputError, nothing touched, when not.
OutputLock ClaimMarkedFolder(const std::string& flag, const std::filesystem::path& out,
                             const std::filesystem::path& staging, const std::string& marker,
                             const std::string& what, const std::filesystem::path& lock_on = {});

// Then: removes a staging folder a killed run left, creates it with `marker` first (so that a kill
// at any moment leaves a folder the next run recognises and removes), calls write(), and puts it
// in place of `out` (ReplaceFolder). Test kill points: "<phase>-staging", "<phase>-written",
// "<phase>-replaced".
void WriteMarkedFolder(const std::filesystem::path& staging, const std::filesystem::path& out,
                       const std::string& marker, const std::string& phase,
                       const std::function<void()>& write);

// An exclusive lock on one output (flock on a hidden file beside it: for `reports/paper`,
// `reports/.paper.rabbit-lock`), held until destruction; the kernel releases it when the process
// dies, so a kill leaves no stale lock. The lock file holds the holder's pid and is removed by the
// holder at the end (a waiter that locked a removed file retries).
class OutputLock {
 public:
  OutputLock() = default;
  // Takes the lock, creating the output's parent folder if needed. Throws InputError(flag, 0,
  // output, "... is being written by another rabbit (pid N) ...") when another process holds it.
  OutputLock(const std::filesystem::path& output, const std::string& flag);
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&& other) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;
  ~OutputLock();
  bool held() const { return fd_ >= 0; }

  // The lock file of an output.
  static std::filesystem::path LockPath(const std::filesystem::path& output);

 private:
  void Release();
  std::filesystem::path path_;
  int fd_ = -1;
};

}  // namespace rabbit

#endif  // RABBIT_IO_OUTPUT_OWNERSHIP_H_
