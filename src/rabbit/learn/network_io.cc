#include "rabbit/learn/network_io.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv.h"
#include "rabbit/io/error.h"

namespace rabbit {
namespace {

const char* const kStructureKeys[] = {"layers", "quantum_rad",     "width",    "x_min",
                                      "x_max",  "hash_table_size", "hash_seed"};
const char* const kHeaderRow = "index,weight";

bool IsStructureKey(const std::string& key) {
  if (key == "format") return true;
  for (const char* k : kStructureKeys) {
    if (key == k) return true;
  }
  return false;
}

// Shortest text that reads back to the same double.
std::string FormatDouble(double value) {
  char buffer[32];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, r.ptr);
}

template <typename Int>
Int ParseInteger(const std::string& text, const std::string& file, int line,
                 const std::string& key) {
  Int value = 0;
  const char* end = text.data() + text.size();
  const std::from_chars_result r = std::from_chars(text.data(), end, value);
  if (text.empty() || r.ec == std::errc::result_out_of_range) {
    throw InputError(file, line, key, "integer out of range: \"" + text + "\"");
  }
  if (r.ec != std::errc() || r.ptr != end) {
    throw InputError(file, line, key, "expected an integer, got \"" + text + "\"");
  }
  return value;
}

void CheckMetadata(const std::map<std::string, std::string>& metadata) {
  auto blank_edged = [](const std::string& s) {
    return !s.empty() && (Trim(s).size() != s.size());
  };
  for (const auto& [key, value] : metadata) {
    if (key.empty() || key.find_first_of("=\n\r") != std::string::npos || blank_edged(key)) {
      throw std::invalid_argument("WriteCmacFile: metadata key \"" + key +
                                  "\" must be non-empty, free of '=' and line breaks, and "
                                  "without surrounding blanks");
    }
    if (IsStructureKey(key)) {
      throw std::invalid_argument("WriteCmacFile: metadata key \"" + key +
                                  "\" is reserved for the network's structure");
    }
    if (value.find_first_of("\n\r") != std::string::npos || blank_edged(value)) {
      throw std::invalid_argument("WriteCmacFile: the value of metadata key \"" + key +
                                  "\" must be free of line breaks and surrounding blanks");
    }
  }
}

struct Entry {
  std::string value;
  int line = 0;
};

}  // namespace

void WriteCmacFile(const Cmac& cmac, const std::map<std::string, std::string>& metadata,
                   const std::string& path) {
  CheckMetadata(metadata);
  const CmacOptions& o = cmac.options();
  WriteFileAtomically(path, [&](std::ostream& out) {
    out << "# format = " << kCmacFormat << "\n";
    out << "# layers = " << o.layers << "\n";
    out << "# quantum_rad = " << FormatDouble(o.quantum) << "\n";
    out << "# width = " << o.width << "\n";
    out << "# x_min = " << FormatDouble(o.x_min) << "\n";
    out << "# x_max = " << FormatDouble(o.x_max) << "\n";
    out << "# hash_table_size = " << o.hash_table_size << "\n";
    out << "# hash_seed = " << o.hash_seed << "\n";
    for (const auto& [key, value] : metadata) out << "# " << key << " = " << value << "\n";
    out << kHeaderRow << "\n";
    const std::vector<double>& w = cmac.weights();
    for (size_t i = 0; i < w.size(); ++i) out << i << ',' << FormatDouble(w[i]) << "\n";
  });
}

Cmac ReadCmacFile(const std::string& path, std::map<std::string, std::string>* metadata) {
  std::istringstream in(ReadBoundedFile(path, kNetworkFileLimits));
  std::map<std::string, Entry> meta;
  std::string line;
  int number = 0;
  int header_line = 0;
  std::optional<Cmac> cmac;  // built once the structure is known
  size_t expected = 0;       // weight count the structure implies
  size_t rows = 0;           // weight rows seen
  int first_extra_line = 0;  // line of the first row beyond `expected`
  CmacOptions options;

  auto entry = [&](const std::string& key) -> const Entry& {
    const auto it = meta.find(key);
    if (it == meta.end()) {
      throw InputError(path, header_line, key,
                       "missing '# " + key + " = ...' before the header row");
    }
    return it->second;
  };
  auto read_structure = [&]() {
    const auto format = meta.find("format");
    if (format == meta.end()) {
      throw InputError(path, 1, "format", "missing '# format = " + std::string(kCmacFormat) + "'");
    }
    if (format->second.value != kCmacFormat) {
      throw InputError(
          path, format->second.line, "format",
          "unsupported format \"" + format->second.value + "\" (expected " + kCmacFormat + ")");
    }
    for (const char* key : kStructureKeys) entry(key);  // all present, else refused here
    const Entry& layers = entry("layers");
    options.layers = ParseInteger<int>(layers.value, path, layers.line, "layers");
    if (options.layers < 1 || options.layers > kMaxCmacLayers) {
      throw InputError(
          path, layers.line, "layers",
          "must be in [1, " + std::to_string(kMaxCmacLayers) + "], got " + layers.value);
    }
    const Entry& quantum = entry("quantum_rad");
    options.quantum = ParseFiniteNumber(quantum.value, path, quantum.line, "quantum_rad");
    if (!(options.quantum > 0.0)) {
      throw InputError(path, quantum.line, "quantum_rad", "must be > 0, got " + quantum.value);
    }
    const Entry& width = entry("width");
    options.width = ParseInteger<int>(width.value, path, width.line, "width");
    if (options.width < 1) {
      throw InputError(path, width.line, "width", "must be >= 1, got " + width.value);
    }
    if (options.layers > options.width) {
      throw InputError(path, layers.line, "layers",
                       "must be <= width (" + width.value + "), got " + layers.value);
    }
    const Entry& x_min = entry("x_min");
    options.x_min = ParseFiniteNumber(x_min.value, path, x_min.line, "x_min");
    const Entry& x_max = entry("x_max");
    options.x_max = ParseFiniteNumber(x_max.value, path, x_max.line, "x_max");
    if (!(options.x_min < options.x_max)) {
      throw InputError(path, x_max.line, "x_max",
                       "must be > x_min (" + x_min.value + "), got " + x_max.value);
    }
    const Entry& size = entry("hash_table_size");
    options.hash_table_size = ParseInteger<int>(size.value, path, size.line, "hash_table_size");
    if (options.hash_table_size < 0) {
      throw InputError(path, size.line, "hash_table_size",
                       "must be >= 0 (0: direct storage), got " + size.value);
    }
    const Entry& seed = entry("hash_seed");
    options.hash_seed = ParseInteger<std::uint64_t>(seed.value, path, seed.line, "hash_seed");
    std::string error;
    if (!options.IsValid(&error)) throw InputError(path, quantum.line, "quantum_rad", error);
    cmac.emplace(options);
    expected = cmac->weights().size();
  };

  while (std::getline(in, line)) {
    ++number;
    const std::string trimmed = Trim(line);
    if (trimmed.empty()) continue;
    if (trimmed[0] == '#') {
      if (header_line > 0) throw InputError(path, number, "", "comment after the header row");
      const size_t eq = trimmed.find('=');
      if (eq == std::string::npos) continue;  // a free comment
      const std::string key = Trim(trimmed.substr(1, eq - 1));
      if (key.empty()) throw InputError(path, number, "", "'# = ...' without a key");
      const auto [it, inserted] = meta.insert({key, {Trim(trimmed.substr(eq + 1)), number}});
      if (!inserted) {
        throw InputError(path, number, key,
                         "repeated key (first on line " + std::to_string(it->second.line) + ")");
      }
      continue;
    }
    if (header_line == 0) {
      header_line = number;
      read_structure();
      const std::vector<std::string> names = SplitCsv(trimmed);
      if (names.size() != 2 || names[0] != "index" || names[1] != "weight") {
        throw InputError(
            path, number, "",
            "expected the header row \"" + std::string(kHeaderRow) + "\", got \"" + trimmed + "\"");
      }
      continue;
    }
    const std::vector<std::string> cells = SplitCsv(trimmed);
    if (cells.size() != 2) {
      throw InputError(path, number, "",
                       "expected 2 cells (index,weight), got " + std::to_string(cells.size()));
    }
    const long long index = ParseInteger<long long>(cells[0], path, number, "index");
    if (index != static_cast<long long>(rows)) {
      throw InputError(path, number, "index",
                       "expected index " + std::to_string(rows) + ", got " + cells[0]);
    }
    const double weight = ParseFiniteNumber(cells[1], path, number, "weight");
    // A CMAC output is a sum of N_l weights: keep every sum far from overflow.
    constexpr double kMaxWeight = 1e6;
    if (std::abs(weight) > kMaxWeight) {
      throw InputError(path, number, "weight", "|weight| above 1e6: not a trained network");
    }
    if (rows < expected) {
      (*cmac->mutable_weights())[rows] = weight;
    } else if (first_extra_line == 0) {
      first_extra_line = number;
    }
    ++rows;
  }
  if (header_line == 0) {
    throw InputError(path, number, "", "no header row \"" + std::string(kHeaderRow) + "\"");
  }
  if (rows != expected) {
    const std::string why =
        "expected " + std::to_string(expected) + " weights (from the structure: " +
        (options.hash_table_size > 0 ? "hash_table_size" : "the detectors over the range") +
        "), got " + std::to_string(rows);
    throw InputError(path, rows > expected ? first_extra_line : number, "weight", why);
  }

  if (metadata != nullptr) {
    metadata->clear();
    for (const auto& [key, e] : meta) {
      if (!IsStructureKey(key)) (*metadata)[key] = e.value;
    }
  }
  return std::move(*cmac);
}

}  // namespace rabbit
