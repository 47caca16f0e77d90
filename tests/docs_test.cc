// The documentation against the code.
//
// 1. Keys: every key that a key table of docs/ documents is known to the readers, and every key
//    the readers accept is documented. The readers' keys are recorded (TomlKeyRecording) while the
//    shipped scenarios, suites, model file and tuning jobs and the inputs of tests/docs_coverage/
//    load; the targets file's keys come from `rabbit gaits generate`'s own "unknown key (expected
//    one of: ...)" message. A key table is a Markdown table right after a line `<!-- keys -->`;
//    the first cell of each row holds one or more key paths in backticks (array elements as
//    `name[]`, a segment `<...>` for any name, and `<...>` last for any rest of the path).
// 2. Product docs (README.md, docs/, bench/README.md, gaits/, scenarios/, optimizers/): no issue
//    numbers, no file outside the repository, every relative link and every repository path in
//    backticks names a file or folder that exists.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "gait_synthesis.h"
#include "rabbit/io/toml_reader.h"
#include "rabbit/scenario/scenario.h"
#include "rabbit/scenario/suite.h"
#include "tune_job.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

const std::string kRoot = RABBIT_SOURCE_DIR;

std::string Relative(const fs::path& path) { return fs::relative(path, kRoot).generic_string(); }

std::vector<fs::path> Files(const std::string& dir, const std::string& extension, bool recursive) {
  std::vector<fs::path> out;
  const fs::path root = fs::path(kRoot) / dir;
  if (!fs::is_directory(root)) return out;
  auto add = [&](const fs::directory_entry& e) {
    if (e.is_regular_file() && e.path().extension() == extension) out.push_back(e.path());
  };
  if (recursive) {
    for (const auto& e : fs::recursive_directory_iterator(root)) add(e);
  } else {
    for (const auto& e : fs::directory_iterator(root)) add(e);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> Lines(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

std::vector<std::string> Split(const std::string& path, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(path);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(part);
  return parts;
}

bool IsWildcard(const std::string& segment) {
  return segment.size() >= 2 && segment.front() == '<' && segment.back() == '>';
}

// Whether documented segment `d` names recorded segment `r` ("obstacles[]" also names the array
// "obstacles" itself).
bool SegmentMatches(const std::string& d, const std::string& r) {
  if (IsWildcard(d) || d == r) return true;
  return d.size() > 2 && d.compare(d.size() - 2, 2, "[]") == 0 && d.substr(0, d.size() - 2) == r;
}

// Whether the documented key `doc` covers the recorded key `rec`: `rec` is `doc`, lies under a
// trailing wildcard of it, or is a table on the way to it.
bool Covers(const std::vector<std::string>& doc, const std::vector<std::string>& rec) {
  for (size_t i = 0; i < rec.size(); ++i) {
    if (i >= doc.size()) return false;
    if (i + 1 == doc.size() && IsWildcard(doc[i])) return true;  // the rest of the path
    if (!SegmentMatches(doc[i], rec[i])) return false;
  }
  return true;
}

// Whether the documented key `doc` is known: it names a recorded key or a table above one.
bool Known(const std::vector<std::string>& doc, const std::vector<std::string>& rec) {
  if (rec.size() < doc.size()) {
    // A trailing wildcard needs at least one segment of its own.
    return false;
  }
  for (size_t i = 0; i < doc.size(); ++i) {
    if (i + 1 == doc.size() && IsWildcard(doc[i])) return true;
    if (!SegmentMatches(doc[i], rec[i])) return false;
  }
  return true;
}

struct DocumentedKey {
  std::string key;
  std::string where;  // docs/formats/scenario.md:42
};

// Every key of every key table in docs/**/*.md.
std::vector<DocumentedKey> DocumentedKeys() {
  std::vector<DocumentedKey> keys;
  const std::regex code("`([^`]+)`");
  for (const fs::path& file : Files("docs", ".md", true)) {
    const std::vector<std::string> lines = Lines(file);
    for (size_t i = 0; i < lines.size(); ++i) {
      // The marker is a line of its own (a mention of it in the text is not one).
      const size_t first = lines[i].find_first_not_of(" \t");
      const size_t last = lines[i].find_last_not_of(" \t\r");
      if (first == std::string::npos ||
          lines[i].substr(first, last - first + 1) != "<!-- keys -->") {
        continue;
      }
      size_t j = i + 1;
      while (j < lines.size() && lines[j].empty()) ++j;
      int row = 0;
      for (; j < lines.size() && !lines[j].empty() && lines[j][0] == '|'; ++j, ++row) {
        if (row < 2) continue;  // header and separator
        const std::string line = lines[j];
        const size_t end = line.find('|', 1);
        const std::string cell =
            line.substr(1, end == std::string::npos ? std::string::npos : end - 1);
        for (std::sregex_iterator m(cell.begin(), cell.end(), code), none; m != none; ++m) {
          keys.push_back({(*m)[1].str(), Relative(file) + ":" + std::to_string(j + 1)});
        }
      }
    }
  }
  return keys;
}

std::string RunCli(const std::string& args) {
  const std::string command = std::string(RABBIT_CLI_PATH) + " " + args + " 2>&1";
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return output;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
  pclose(pipe);
  return output;
}

// The targets file's keys, as `rabbit gaits generate` lists them when a table holds a key it does
// not know: a file with every key, and a probe key in one table at a time.
void RecordTargetKeys(std::map<std::string, std::string>* keys) {
  const fs::path dir = fs::temp_directory_path() / ("rabbit_docs_test_" + std::to_string(getpid()));
  fs::create_directories(dir);
  std::string bounds;
  const auto defaults = DefaultSynthesisBounds();  // valid bounds for every parameter
  for (int i = 0; i < kSynthesisParams; ++i) {
    bounds += std::string(kSynthesisParamNames[i]) + " = [" + std::to_string(defaults[i].first) +
              ", " + std::to_string(defaults[i].second) + "]\n";
  }
  std::string start;  // a valid start for every parameter: its default lower bound
  for (int i = 0; i < kSynthesisParams; ++i) {
    start +=
        std::string(kSynthesisParamNames[i]) + " = " + std::to_string(defaults[i].first) + "\n";
  }
  const std::array<std::string, 5> tables = {"", "bounds", "gait[]", "gait[].bounds",
                                             "gait[].start"};
  for (const std::string& probe_in : tables) {
    auto probe = [&](const std::string& table) {
      return table == probe_in ? std::string("zz_probe = 1\n") : std::string();
    };
    const std::string text = probe("") + "[bounds]\n" + bounds + probe("bounds") +
                             "[[gait]]\nv_m = 0.5\nl_step = 0.3\nseed = 1\nbudget = 10\n" +
                             probe("gait[]") + "[gait.bounds]\n" + bounds + probe("gait[].bounds") +
                             "[gait.start]\n" + start + probe("gait[].start");
    const fs::path file = dir / "targets.toml";
    std::ofstream(file) << text;
    const std::string output =
        RunCli("gaits generate " + file.string() + " --dir " + (dir / "out").string());
    const std::smatch m = [&] {
      std::smatch match;
      std::regex_search(output, match, std::regex("unknown key \\(expected one of: ([^)]*)\\)"));
      return match;
    }();
    ASSERT_FALSE(m.empty()) << "rabbit gaits generate did not refuse the probe key in table '"
                            << probe_in << "' of a targets file with an unknown-key message:\n"
                            << output;
    for (std::string key : Split(m[1].str(), ',')) {
      key.erase(0, key.find_first_not_of(' '));
      keys->emplace(probe_in.empty() ? key : probe_in + "." + key, "gaits/targets.toml");
    }
  }
  fs::remove_all(dir);
}

// Every key the readers accepted while reading the shipped files and the coverage inputs.
std::map<std::string, std::string> AcceptedKeys() {
  std::map<std::string, std::string> keys;
  {
    TomlKeyRecording recording;
    for (const std::string dir : {"scenarios", "tests/docs_coverage"}) {
      for (const fs::path& file : Files(dir, ".toml", false)) {
        if (file.filename() == "model.toml") {
          LoadModelFile(file.string());
          continue;
        }
        EXPECT_NO_THROW(LoadSuite(file.string())) << file;
      }
    }
    for (const fs::path& file : Files("optimizers/jobs", ".toml", false)) {
      EXPECT_NO_THROW(LoadTuneJob(file.string())) << file;
    }
    for (const auto& [key, file] : recording.keys()) keys.emplace(key, Relative(file));
  }
  RecordTargetKeys(&keys);
  return keys;
}

TEST(DocsTest, EveryDocumentedKeyIsKnownAndEveryKnownKeyIsDocumented) {
  const std::vector<DocumentedKey> documented = DocumentedKeys();
  ASSERT_GT(documented.size(), 100u) << "no key tables found under docs/ (<!-- keys -->)";
  const std::map<std::string, std::string> accepted = AcceptedKeys();
  ASSERT_GT(accepted.size(), 100u);

  std::vector<std::vector<std::string>> doc_paths;  // split once: the loops below are quadratic
  for (const DocumentedKey& d : documented) doc_paths.push_back(Split(d.key, '.'));
  std::vector<std::pair<std::vector<std::string>, std::string>> rec;
  for (const auto& [key, file] : accepted) rec.emplace_back(Split(key, '.'), key);

  for (size_t i = 0; i < documented.size(); ++i) {
    const DocumentedKey& d = documented[i];
    const std::vector<std::string>& doc = doc_paths[i];
    bool known = false;
    for (const auto& r : rec) known = known || Known(doc, r.first);
    EXPECT_TRUE(known) << d.where << ": documents the key `" << d.key
                       << "`, which no reader accepts (read: scenarios/*.toml, "
                          "optimizers/jobs/*.toml, gaits/targets.toml keys, "
                          "tests/docs_coverage/*.toml). Correct the doc, or, if the key is read "
                          "only in some cases, add an input that sets it to tests/docs_coverage/.";
  }
  for (const auto& [key, file] : accepted) {
    const std::vector<std::string> r = Split(key, '.');
    bool covered = false;
    for (const auto& doc : doc_paths) covered = covered || Covers(doc, r);
    EXPECT_TRUE(covered) << "the readers accept the key `" << key << "` (read in " << file
                         << "), but no key table of docs/ documents it: add a row "
                            "| `"
                         << key
                         << "` | ... | to the <!-- keys --> table of its format in "
                            "docs/formats/ (scenario.md, suite.md, tune-job.md, targets.md, "
                            "model.md).";
  }
}

// Product documentation: the files a user reads.
std::vector<fs::path> ProductDocs() {
  std::vector<fs::path> out = {fs::path(kRoot) / "README.md"};
  for (const auto& [dir, ext, recursive] :
       std::vector<std::tuple<std::string, std::string, bool>>{{"docs", ".md", true},
                                                               {"bench", ".md", false},
                                                               {"gaits", ".md", false},
                                                               {"gaits", ".toml", false},
                                                               {"gaits", ".fll", false},
                                                               {"scenarios", ".toml", true},
                                                               {"optimizers", ".md", false},
                                                               {"optimizers/jobs", ".toml", false},
                                                               {"reports", ".md", false}}) {
    for (const fs::path& f : Files(dir, ext, recursive)) {
      out.push_back(f);
    }
  }
  return out;
}

// GitHub's anchor of a Markdown heading: lower case, punctuation dropped but '-' and '_', spaces
// to '-'.
std::string Anchor(const std::string& heading) {
  std::string out;
  for (const char c : heading) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (std::isalnum(u) || c == '-' || c == '_') {
      out += static_cast<char>(std::tolower(u));
    } else if (c == ' ') {
      out += '-';
    }
  }
  return out;
}

// The anchors of a Markdown file's headings.
std::set<std::string> Anchors(const fs::path& file) {
  std::set<std::string> anchors;
  bool in_code = false;
  for (const std::string& line : Lines(file)) {
    if (line.rfind("```", 0) == 0) in_code = !in_code;
    if (in_code || line.empty() || line[0] != '#') continue;
    const size_t text = line.find_first_not_of('#');
    if (text == std::string::npos || line[text] != ' ') continue;
    anchors.insert(Anchor(line.substr(text + 1)));
  }
  return anchors;
}

bool ExistsInRepo(const std::string& relative) { return fs::exists(fs::path(kRoot) / relative); }

TEST(DocsTest, ProductDocsCiteNoIssueNumberAndOnlyFilesThatExist) {
  const std::regex issue("\\bissues?\\s*#?\\s*[0-9]+", std::regex::icase);
  const std::regex design("DESIGN\\.md|/work/");
  const std::regex link("\\]\\(([^)\\s]+)\\)");
  // A repository path in backticks: a top-level folder of the repository, then a path.
  const std::regex path(
      "`((?:src|tests|scenarios|gaits|optimizers|bench|docs|\\.ci)/[A-Za-z0-9_./-]*)`");
  const std::vector<fs::path> docs = ProductDocs();
  ASSERT_GT(docs.size(), 10u);
  for (const fs::path& file : docs) {
    const std::vector<std::string> lines = Lines(file);
    const std::string name = Relative(file);
    for (size_t i = 0; i < lines.size(); ++i) {
      const std::string& line = lines[i];
      const std::string where = name + ":" + std::to_string(i + 1);
      std::smatch m;
      EXPECT_FALSE(std::regex_search(line, m, issue))
          << where << ": cites an issue number (\"" << m.str()
          << "\"): say what the text means instead";
      EXPECT_FALSE(std::regex_search(line, m, design))
          << where << ": cites \"" << m.str() << "\", which is not in the repository";
      if (file.extension() != ".md") continue;
      for (std::sregex_iterator it(line.begin(), line.end(), link), none; it != none; ++it) {
        std::string target = (*it)[1].str();
        if (target.rfind("http://", 0) == 0 || target.rfind("https://", 0) == 0 ||
            target.rfind("mailto:", 0) == 0) {
          continue;
        }
        if (target[0] == '#') {  // a section of this file
          EXPECT_EQ(Anchors(file).count(target.substr(1)), 1u)
              << where << ": the link (" << target << ") names a section this file does not have";
          continue;
        }
        const size_t hash = target.find('#');
        const std::string anchor = hash == std::string::npos ? "" : target.substr(hash + 1);
        target = target.substr(0, hash);
        const std::string resolved =
            fs::path(Relative(file.parent_path() / target)).lexically_normal().generic_string();
        EXPECT_TRUE(ExistsInRepo(resolved))
            << where << ": the link (" << (*it)[1].str() << ") names " << resolved
            << ", which is not in the repository";
        const fs::path linked = fs::path(kRoot) / resolved;
        if (!anchor.empty() && linked.extension() == ".md" && fs::is_regular_file(linked)) {
          EXPECT_EQ(Anchors(linked).count(anchor), 1u)
              << where << ": the link (" << (*it)[1].str() << ") names the section #" << anchor
              << ", which " << resolved << " does not have";
        }
      }
      for (std::sregex_iterator it(line.begin(), line.end(), path), none; it != none; ++it) {
        std::string target = (*it)[1].str();
        if (target.find("...") != std::string::npos) continue;
        while (!target.empty() && (target.back() == '.' || target.back() == '/')) {
          target.pop_back();
        }
        EXPECT_TRUE(ExistsInRepo(target))
            << where << ": names `" << (*it)[1].str() << "`, which is not in the repository";
      }
    }
  }
}

}  // namespace
}  // namespace rabbit
