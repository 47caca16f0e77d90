#include "gait_manifest.h"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/io/sha256.h"

namespace rabbit {
namespace {

const char* const kColumns[] = {"kind", "name", "file", "sha256", "seed", "inputs_sha256"};

}  // namespace

bool IsHex64(const std::string& s) {
  return s.size() == 64 && s.find_first_not_of("0123456789abcdef") == std::string::npos;
}

std::string ManifestText(const Manifest& m) {
  std::ostringstream out;
  out << "# format = " << kManifestFormat << "\n";
  out << "# generator = " << m.generator << "\n";
  out << "# model_sha256 = " << m.model_sha256 << "\n";
  out << "# simulator_sha256 = " << m.simulator_sha256 << "\n";
  out << "kind,name,file,sha256,seed,inputs_sha256\n";
  for (const ManifestRow& r : m.rows) {
    out << r.kind << ',' << FormatCsvCell(r.name) << ',' << FormatCsvCell(r.file) << ',' << r.sha256
        << ',' << r.seed << ',' << r.inputs_sha256 << "\n";
  }
  return out.str();
}

Manifest ReadManifest(const std::string& path) {
  const std::vector<std::string> lines = SplitLines(ReadBoundedFile(path, kManifestFileLimits));
  Manifest m;
  std::string table;  // the CSV part, comment lines left blank so that line numbers hold
  bool format_seen = false;
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    const int number = static_cast<int>(i) + 1;
    if (!line.empty() && line[0] == '#') {
      const size_t eq = line.find('=');
      const std::string key = eq == std::string::npos ? "" : Trim(line.substr(1, eq - 1));
      const std::string value = eq == std::string::npos ? "" : Trim(line.substr(eq + 1));
      if (i == 0) {
        if (key != "format" || value != kManifestFormat) {
          throw InputError(path, 1, "format",
                           std::string("expected '# format = ") + kManifestFormat + "'");
        }
        format_seen = true;
      } else if (key == "generator") {
        m.generator = value;
      } else if (key == "model_sha256") {
        m.model_sha256 = value;
      } else if (key == "simulator_sha256") {
        m.simulator_sha256 = value;
      } else {
        throw InputError(path, number, key, "unknown manifest key");
      }
      table += "\n";
      continue;
    }
    table += line + "\n";
  }
  if (!format_seen) {
    throw InputError(path, 1, "format",
                     std::string("expected '# format = ") + kManifestFormat + "'");
  }
  const CsvTable t = CsvTable::Parse(table, path);
  if (t.header() != std::vector<std::string>(std::begin(kColumns), std::end(kColumns))) {
    throw InputError(path, 0, "", "expected the columns kind,name,file,sha256,seed,inputs_sha256");
  }
  std::set<std::string> files;
  for (size_t r = 0; r < t.num_rows(); ++r) {
    ManifestRow row{t.Text(r, 0), t.Text(r, 1), t.Text(r, 2),
                    t.Text(r, 3), t.Text(r, 4), t.Text(r, 5)};
    if (row.kind != "gait" && row.kind != "file") {
      throw InputError(path, t.line(r), "kind", "expected gait or file");
    }
    const std::filesystem::path p(row.file);
    if (row.file.empty() || p.is_absolute() || row.file.find("..") != std::string::npos) {
      throw InputError(path, t.line(r), "file", "a path inside the database");
    }
    if (!IsHex64(row.sha256)) throw InputError(path, t.line(r), "sha256", "64 hex digits");
    if (row.kind == "gait" && (row.name.empty() || !IsHex64(row.inputs_sha256))) {
      throw InputError(path, t.line(r), "inputs_sha256", "a gait row needs a name and its inputs");
    }
    if (!files.insert(row.file).second) {
      throw InputError(path, t.line(r), "file", "\"" + row.file + "\" listed twice");
    }
    m.rows.push_back(row);
  }
  return m;
}

bool IsLeftoverOfRabbit(const std::string& root, const std::string& rel) {
  namespace fs = std::filesystem;
  const fs::path path(rel);
  const std::string name = path.filename().string();
  auto ends_with = [&name](const std::string& suffix) {
    return name.size() > suffix.size() &&
           name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  if (rel.rfind(".build/", 0) == 0) return true;  // a build's staging folder
  if (name[0] == '.' && (ends_with(".rabbit-lock") || ends_with(".rabbit-pending"))) return true;
  // A staging folder of rabbit train at the root (networks.staging), recognised by its marker.
  const std::string top = path.begin()->string();
  std::error_code error;
  return top.size() > 8 && top.compare(top.size() - 8, 8, ".staging") == 0 &&
         fs::is_regular_file(fs::path(root) / top / ".rabbit-networks", error);
}

void VerifyManifest(const Manifest& m, const std::string& root, const std::string& manifest_path) {
  namespace fs = std::filesystem;
  std::set<std::string> listed;
  for (const ManifestRow& r : m.rows) {
    const fs::path p = fs::path(root) / r.file;
    std::error_code unreadable;  // e.g. a name too long for the file system: not listed either
    if (!fs::is_regular_file(p, unreadable)) {
      throw InputError(manifest_path, 0, r.file, "listed, but the database has no such file");
    }
    if (Sha256OfFile(p.string()) != r.sha256) {
      throw InputError(manifest_path, 0, r.file, "the file differs from its hash in the manifest");
    }
    listed.insert(r.file);
  }
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
    if (!e.is_regular_file()) continue;
    const std::string rel = fs::relative(e.path(), root).generic_string();
    if (rel == "manifest.csv" || rel == "README.md") continue;
    // Targets files kept beside the database (gaits/targets.toml): inputs, not made by the build.
    if (rel.find('/') == std::string::npos && fs::path(rel).extension() == ".toml") continue;
    if (IsLeftoverOfRabbit(root, rel)) continue;  // a killed writer's lock, staging or build folder
    if (listed.count(rel) == 0) {
      throw InputError(manifest_path, 0, rel,
                       "the database holds a file its manifest does not list");
    }
  }
}

}  // namespace rabbit
