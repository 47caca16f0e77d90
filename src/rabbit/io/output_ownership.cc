#include "rabbit/io/output_ownership.h"

#include <fcntl.h>
#include <stdio.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/error.h"
#include "rabbit/io/limits.h"
#include "rabbit/io/test_hooks.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

constexpr const char* kGaitIndexHeader = "name,file,target_v_m,";
constexpr const char* kMarkerPrefix = ".rabbit-";

// The first line of a regular file (at most 256 characters of it; empty when it is not one or
// cannot be read); with skip_comments, the first of the first 1000 lines not starting with '#'.
std::string FirstLine(const fs::path& path, bool skip_comments = false) {
  std::error_code ec;
  if (!fs::is_regular_file(fs::symlink_status(path, ec))) return "";
  std::ifstream in(path, std::ios::binary);
  for (int n = 0; n < 1000 && in; ++n) {
    std::string line;
    char c;
    while (in.get(c) && c != '\n') {
      if (line.size() < 256) line += c;
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!skip_comments || line.empty() || line[0] != '#') return line;
  }
  return "";
}

std::string Kind(fs::file_type type) {
  switch (type) {
    case fs::file_type::regular:
      return "a file";
    case fs::file_type::directory:
      return "a folder";
    case fs::file_type::symlink:
      return "a symbolic link";
    case fs::file_type::block:
    case fs::file_type::character:
      return "a device";
    case fs::file_type::fifo:
      return "a FIFO";
    case fs::file_type::socket:
      return "a socket";
    default:
      return "not a regular file";
  }
}

// A folder whose entries are all pending files of a killed gait commit (".NAME.rabbit-pending":
// a new database's first gaits): rabbit's own, and the next writer finishes or removes them.
bool HoldsOnlyPendingFiles(const fs::path& dir) {
  constexpr const char* kPending = ".rabbit-pending";
  const size_t n = std::strlen(kPending);
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() <= n + 1 || name[0] != '.' || name.compare(name.size() - n, n, kPending) != 0 ||
        !fs::is_regular_file(fs::symlink_status(entry.path()))) {
      return false;
    }
  }
  return true;
}

}  // namespace

bool IsReservedGaitName(const std::string& name) { return name == "index" || name == "manifest"; }

bool IsGaitDatabase(const std::string& dir) {
  const fs::path root(dir);
  if (FirstLine(root / kGaitManifest) == kGaitManifestFormat) return true;
  return FirstLine(root / "index.csv").rfind(kGaitIndexHeader, 0) == 0;
}

bool HasMarker(const fs::path& dir, const std::vector<std::string>& markers) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return false;
  for (const std::string& m : markers) {
    if (fs::is_regular_file(fs::symlink_status(dir / m, ec))) return true;
  }
  return false;
}

std::string SymbolicLinkRefusal(const fs::path& path, const std::string& what) {
  if (!fs::is_symlink(fs::symlink_status(path))) return "";
  return "is a symbolic link, not " + what +
         ": refusing to replace it or write through it; give the folder it points to, or another "
         "path";
}

void CheckOutputParents(const std::string& flag, const fs::path& path) {
  std::error_code ec;
  fs::path normal = path.lexically_normal();
  if (normal.filename().empty()) normal = normal.parent_path();  // "dir/" -> "dir"
  for (fs::path up = normal.parent_path(); !up.empty() && up != up.root_path();
       up = up.parent_path()) {
    const fs::file_status status = fs::status(up, ec);  // a link to a folder is a folder here
    if (!fs::exists(status)) continue;
    if (fs::is_directory(status)) return;
    throw InputError(
        flag, 0, path.string(),
        "cannot be written: " + up.string() + " is " + Kind(status.type()) + ", not a folder");
  }
}

void CheckOwnedFolder(const std::string& flag, const fs::path& path,
                      const std::vector<std::string>& markers, const std::string& what) {
  CheckOutputParents(flag, path);
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(path, ec);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status)) {
    throw InputError(flag, 0, path.string(),
                     "is " + Kind(status.type()) + ", not " + what + ": refusing to replace it");
  }
  if (fs::is_empty(path, ec)) return;
  if (HasMarker(path, markers)) {
    CheckInventory(flag, path);
    return;
  }
  throw InputError(flag, 0, path.string(),
                   "exists and is not " + what + " (no " + markers.front() +
                       "): refusing to touch it; give another path or remove it yourself");
}

void CheckGaitDatabaseOutput(const std::string& flag, const std::string& dir) {
  CheckOutputParents(flag, dir);
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(dir, ec);
  if (!fs::exists(status) || IsGaitDatabase(dir)) return;
  if (fs::is_directory(status) && (fs::is_empty(dir, ec) || HoldsOnlyPendingFiles(dir))) return;
  // A new database whose first commit was decided (its pending index written) and then killed.
  if (FirstLine(fs::path(dir) / ".index.csv.rabbit-pending").rfind(kGaitIndexHeader, 0) == 0)
    return;
  throw InputError(flag, 0, dir,
                   fs::is_directory(status)
                       ? std::string("is not a gait database (no ") + kGaitManifest +
                             " of rabbit, nor a gait index.csv): refusing to write into it"
                       : "is " + Kind(status.type()) + ", not a gait database");
}

void CheckOwnedFile(const std::string& flag, const fs::path& path, const std::string& first_line,
                    const std::string& what, bool skip_comments) {
  CheckReplaceableFile(flag, path);
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(path, ec)) ||
      FirstLine(path, skip_comments).rfind(first_line, 0) == 0) {
    return;
  }
  throw InputError(flag, 0, path.string(),
                   "exists and is not " + what + " (no line starting \"" + first_line +
                       "\" where rabbit writes one): refusing to replace it");
}

void CheckReplaceableFile(const std::string& flag, const fs::path& path) {
  CheckOutputParents(flag, path);
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(path, ec);
  if (!fs::exists(status) || fs::is_regular_file(status)) return;
  throw InputError(flag, 0, flag == path.string() ? "" : path.string(),
                   "is " + Kind(status.type()) +
                       ": rabbit only creates or replaces regular files (use - for standard output "
                       "where the output is one file)");
}

namespace {

// Every entry below `dir` (not the inventory), by its path relative to `dir`, folders with a
// trailing '/' (an empty folder a user made is theirs too). `flag` names the output in errors.
std::set<std::string> EntriesBelow(const std::string& flag, const fs::path& dir) {
  std::set<std::string> entries;
  std::error_code ec;
  fs::recursive_directory_iterator it(dir, ec), end;
  for (; !ec && it != end; it.increment(ec)) {
    std::string rel = it->path().lexically_relative(dir).generic_string();
    if (rel == kInventory) continue;
    if (fs::is_directory(it->symlink_status())) rel += '/';
    entries.insert(rel);
  }
  if (ec) {
    throw InputError(flag, 0, dir.string(), "cannot list its files: " + ec.message());
  }
  return entries;
}

// The entries an inventory lists (empty when `dir` has none; *found says whether it has one).
std::set<std::string> Listed(const fs::path& dir, bool* found) {
  std::error_code ec;
  *found = fs::is_regular_file(fs::symlink_status(dir / kInventory, ec));
  std::set<std::string> listed;
  if (!*found) return listed;
  std::istringstream in(ReadBoundedFile((dir / kInventory).string(), kInventoryFileLimits));
  std::string line;
  std::getline(in, line);  // the format line
  while (std::getline(in, line)) listed.insert(line);
  return listed;
}

}  // namespace

void WriteInventory(const fs::path& dir) {
  const std::set<std::string> entries = EntriesBelow(dir.string(), dir);
  WriteFileAtomically((dir / kInventory).string(), [&entries](std::ostream& out) {
    out << "rabbit-inventory/1\n";
    for (const std::string& rel : entries) out << rel << '\n';
  });
}

void CheckInventory(const std::string& flag, const fs::path& dir) {
  bool found = false;
  const std::set<std::string> listed = Listed(dir, &found);
  if (!found) return;
  // The shards a sharded run wrote into an earlier report's folder: each against its own
  // inventory (rabbit report merges them).
  std::map<std::string, std::pair<bool, std::set<std::string>>> shards;
  for (const std::string& rel : EntriesBelow(flag, dir)) {
    if (listed.count(rel) != 0 || rel == "shards/") continue;
    if (rel.rfind("shards/", 0) == 0) {
      const size_t slash = rel.find('/', 7);
      if (slash == std::string::npos) continue;  // a shard's folder itself
      const std::string shard = rel.substr(0, slash);
      auto at = shards.find(shard);
      if (at == shards.end()) {
        bool has = false;
        std::set<std::string> own = Listed(dir / shard, &has);
        at = shards.emplace(shard, std::make_pair(has, std::move(own))).first;
      }
      const std::string inner = rel.substr(slash + 1);  // "": the shard's folder
      if (!at->second.first || inner.empty() || inner == kInventory ||
          at->second.second.count(inner) != 0) {
        continue;
      }
    }
    throw InputError(flag, 0, dir.string(),
                     "holds " + rel + ", which is not one of the files rabbit wrote there (its " +
                         kInventory +
                         " lists them): rabbit replaces or rewrites this whole folder, so move it "
                         "out first (or remove the folder yourself)");
  }
}

void RemoveOwnedFolder(const fs::path& dir) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return;
  std::vector<fs::path> markers;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    if (entry.path().filename().string().rfind(kMarkerPrefix, 0) == 0) {
      markers.push_back(entry.path());
    } else {
      fs::remove_all(entry.path());
    }
  }
  for (const fs::path& m : markers) fs::remove_all(m);
  fs::remove(dir);
}

void ReplaceFolder(const fs::path& staging, const fs::path& target) {
  std::error_code ec;
  if (fs::exists(fs::symlink_status(target, ec))) {
    if (::renameat2(AT_FDCWD, staging.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE) == 0) {
      RemoveOwnedFolder(staging);  // the old content
      return;
    }
    if (errno != EINVAL && errno != ENOSYS) {
      throw std::system_error(errno, std::generic_category(),
                              "cannot put " + staging.string() + " in place of " + target.string());
    }
    RemoveOwnedFolder(target);
  }
  if (!target.parent_path().empty()) fs::create_directories(target.parent_path());
  fs::rename(staging, target);
}

OutputLock ClaimMarkedFolder(const std::string& flag, const fs::path& out, const fs::path& staging,
                             const std::string& marker, const std::string& what,
                             const fs::path& lock_on) {
  CheckOwnedFolder(flag, out, {marker}, what);
  CheckOwnedFolder(flag, staging, {marker}, "a staging folder of rabbit");
  OutputLock lock(lock_on.empty() ? out : lock_on, flag);
  CheckOwnedFolder(flag, out, {marker}, what);
  return lock;
}

void WriteMarkedFolder(const fs::path& staging, const fs::path& out, const std::string& marker,
                       const std::string& phase, const std::function<void()>& write) {
  RemoveOwnedFolder(staging);  // a killed run's
  fs::create_directories(staging);
  WriteFileAtomically((staging / marker).string(),
                      [&marker](std::ostream& o) { o << marker.substr(1) << "/1\n"; });
  TestKillPoint((phase + "-staging").c_str());
  write();
  TestKillPoint((phase + "-written").c_str());
  WriteInventory(staging);
  ReplaceFolder(staging, out);
  TestKillPoint((phase + "-replaced").c_str());
}

fs::path OutputLock::LockPath(const fs::path& output) {
  fs::path out = output.lexically_normal();
  if (out.filename().empty()) out = out.parent_path();
  return out.parent_path() / ("." + out.filename().string() + ".rabbit-lock");
}

OutputLock::OutputLock(const fs::path& output, const std::string& flag) {
  const fs::path path = LockPath(output);
  CheckOutputParents(flag, output);
  if (!path.parent_path().empty()) fs::create_directories(path.parent_path());
  CheckReplaceableFile(flag, path);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) {
      throw InputError(
          flag, 0, output.string(),
          "cannot create its lock file " + path.string() + ": " + std::strerror(errno));
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      char text[32] = {0};
      const ssize_t n = ::pread(fd, text, sizeof text - 1, 0);
      ::close(fd);
      std::string pid = n > 0 ? std::string(text, static_cast<size_t>(n)) : "";
      while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
      throw InputError(flag, 0, output.string(),
                       "is being written by another rabbit" +
                           (pid.empty() ? std::string() : " (pid " + pid + ")") +
                           ": wait for it to end, or give another output");
    }
    // The file may have been removed by the holder we waited behind: lock the one at the path.
    struct stat held, now;
    if (::fstat(fd, &held) == 0 && ::stat(path.c_str(), &now) == 0 && held.st_ino == now.st_ino &&
        held.st_dev == now.st_dev) {
      const std::string pid = std::to_string(::getpid()) + "\n";
      if (::ftruncate(fd, 0) == 0 && ::pwrite(fd, pid.data(), pid.size(), 0) < 0) {
        // The pid is for the message only.
      }
      path_ = path;
      fd_ = fd;
      return;
    }
    ::close(fd);
  }
  throw InputError(flag, 0, output.string(), "cannot take its lock " + path.string());
}

OutputLock::OutputLock(OutputLock&& other) noexcept
    : path_(std::move(other.path_)), fd_(other.fd_) {
  other.fd_ = -1;
}

OutputLock& OutputLock::operator=(OutputLock&& other) noexcept {
  if (this != &other) {
    Release();
    path_ = std::move(other.path_);
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

OutputLock::~OutputLock() { Release(); }

void OutputLock::Release() {
  if (fd_ < 0) return;
  ::unlink(path_.c_str());  // while still held: a waiter then finds it gone and retries
  ::close(fd_);
  fd_ = -1;
}

}  // namespace rabbit
