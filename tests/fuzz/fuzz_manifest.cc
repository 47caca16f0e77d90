// Fuzz target: a gait database's manifest.csv through ReadManifest, then VerifyManifest against a
// small database folder (links to the shipped walker.csv and gait index), so that mutated rows
// reach the file and hash checks. Links, not copies: std::filesystem::copy_file fails now and then
// with EINTR when libFuzzer's timeout alarm interrupts its sendfile.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz_util.h"
#include "gait_manifest.h"
#include "rabbit/io/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  const fs::path path = rabbit_fuzz::Dir().Write("manifest-input.csv", data, size);
  const fs::path db = path.parent_path() / "manifest-db";
  static const bool made = [&db] {
    const fs::path source = fs::path(RABBIT_SOURCE_DIR) / "gaits";
    fs::create_directories(db / "reference");
    fs::create_symlink(source / "walker.csv", db / "walker.csv");
    fs::create_symlink(source / "reference" / "index.csv", db / "reference" / "index.csv");
    return true;
  }();
  (void)made;
  try {
    const rabbit::Manifest manifest = rabbit::ReadManifest(path.string());
    rabbit::VerifyManifest(manifest, db.string(), path.string());
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  return 0;
}
