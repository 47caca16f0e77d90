// Fuzz target: a networks folder's index.csv through LoadGaitNetworks, beside links to the shipped
// network files, so that mutated rows reach the files they name (and the check that a file's own
// gait and output are the row's). The input is written straight to <dir>/index.csv: copying it
// there with std::filesystem::copy_file fails now and then with EINTR (its sendfile is not retried
// when libFuzzer's timeout alarm interrupts it), a harness crash that is not the reader's.
#include <cstddef>
#include <cstdint>
#include <filesystem>

#include "fuzz_util.h"
#include "rabbit/io/error.h"
#include "rabbit/learn/gait_pattern.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace fs = std::filesystem;
  static const fs::path dir = rabbit_fuzz::Dir().Path("networks-input");
  static const bool linked = [] {
    fs::create_directory(dir);
    for (const fs::directory_entry& e :
         fs::directory_iterator(fs::path(RABBIT_SOURCE_DIR) / "gaits" / "networks")) {
      if (e.path().filename() != "index.csv") {
        fs::create_symlink(e.path(), dir / e.path().filename());
      }
    }
    return true;
  }();
  (void)linked;
  rabbit_fuzz::Dir().Write("networks-input/index.csv", data, size);
  try {
    rabbit::LoadGaitNetworks(dir.string(), nullptr);
  } catch (const rabbit::InputError& e) {
    rabbit_fuzz::Refused(e);
  }
  return 0;
}
