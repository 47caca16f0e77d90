#include "rabbit/scenario/suite_inputs.h"

#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <system_error>

#include "rabbit/io/sha256.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

// The regular files at the root of a folder (marker and lock files aside).
void AddFolder(const std::string& dir, std::set<std::string>* files) {
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    if (it->is_regular_file(ec)) files->insert(it->path().lexically_normal().string());
  }
}

}  // namespace

std::vector<std::string> SuiteInputFiles(const Suite& suite) {
  auto normal = [](const std::string& p) { return fs::path(p).lexically_normal().string(); };
  std::set<std::string> files = {normal(suite.file)};
  for (const Scenario& s : suite.scenarios) {
    if (!s.model_file.empty()) files.insert(normal(s.model_file));
    if (!s.pattern.fll.empty()) files.insert(normal(s.pattern.fll));
    if (!s.pattern.networks.empty()) AddFolder(s.pattern.networks, &files);
    if (!s.pattern.gaits.empty()) AddFolder(s.pattern.gaits, &files);
  }
  return {files.begin(), files.end()};
}

std::vector<InputFile> HashInputFiles(const std::vector<std::string>& paths) {
  std::vector<InputFile> out;
  for (const std::string& p : paths) out.push_back({p, Sha256OfFile(p)});
  return out;
}

std::string InputLines(const std::vector<InputFile>& inputs) {
  std::string out;
  for (const InputFile& f : inputs) out += "input = " + f.sha256 + " " + f.path + "\n";
  return out;
}

std::string ChangedInputs(const std::string& marker_text, const std::vector<InputFile>& now) {
  std::map<std::string, std::string> recorded;
  std::istringstream in(marker_text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("input = ", 0) != 0 || line.size() < 8 + 64 + 2) continue;
    recorded[line.substr(8 + 64 + 1)] = line.substr(8, 64);
  }
  for (const InputFile& f : now) {
    const auto found = recorded.find(f.path);
    if (found == recorded.end()) return f.path + " is read now but was not when the run began";
    if (found->second != f.sha256) return f.path + " changed since the run began (content hash)";
    recorded.erase(found);
  }
  if (!recorded.empty()) {
    return recorded.begin()->first + " was read when the run began but is not read now";
  }
  return "";
}

}  // namespace rabbit
