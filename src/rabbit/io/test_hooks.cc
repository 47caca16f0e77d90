#include "rabbit/io/test_hooks.h"

#include <fcntl.h>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <string>

namespace rabbit {

void TestKillPoint(const char* phase) {
  const char* kill = std::getenv("RABBIT_TEST_KILL_AT");
  if (kill != nullptr && std::strcmp(kill, phase) == 0) std::raise(SIGKILL);
  const char* pause = std::getenv("RABBIT_TEST_PAUSE_AT");
  const char* fifo = std::getenv("RABBIT_TEST_PAUSE_FIFO");
  if (pause == nullptr || fifo == nullptr || std::strcmp(pause, phase) != 0) return;
  const std::string line = std::string(phase) + " " + std::to_string(::getpid()) + "\n";
  const int out = ::open(fifo, O_WRONLY | O_CLOEXEC);  // blocks until the test reads
  if (out < 0) return;
  if (::write(out, line.data(), line.size()) < 0) {
    // The test will see the FIFO close without a line.
  }
  ::close(out);
  const int in = ::open(fifo, O_RDONLY | O_CLOEXEC);  // blocks until the test lets go
  if (in < 0) return;
  char buffer[64];
  while (::read(in, buffer, sizeof buffer) > 0) {
  }
  ::close(in);
}

}  // namespace rabbit
