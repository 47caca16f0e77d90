// Test hooks at named phases of a writing command, so that tests can kill a process at any moment
// it might die, or hold it there while another process runs:
//   RABBIT_TEST_KILL_AT=<phase>     the process raises SIGKILL (no clean-up) on reaching the phase;
//   RABBIT_TEST_PAUSE_AT=<phase>    with RABBIT_TEST_PAUSE_FIFO=<path> (a FIFO the test made), the
//                                   process writes "<phase> <pid>\n" into the FIFO (blocking until
//                                   the test reads it), then blocks reading <path> again until the
//                                   test opens it for writing and closes it.
// Without these variables a phase costs one getenv. Phases are named "<command>-<what>", and each
// command's are listed in docs/file-safety.md.
#ifndef RABBIT_IO_TEST_HOOKS_H_
#define RABBIT_IO_TEST_HOOKS_H_

namespace rabbit {

void TestKillPoint(const char* phase);

}  // namespace rabbit

#endif  // RABBIT_IO_TEST_HOOKS_H_
