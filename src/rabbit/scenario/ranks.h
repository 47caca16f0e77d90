// The processes of a distributed job: MPI_COMM_WORLD when rabbit is built with MPI (OpenMPI from
// Debian, found by CMake) and started by mpirun; otherwise a single process (rank 0 of 1). Work is
// dealt by index, statically (item i to rank i mod size) or to the ranks as they ask for it
// (SharedCounter), and results are gathered back in index order, so a job's results never depend
// on the number of ranks or on which rank ran what. Collectives are called from the main thread
// only (MPI_THREAD_FUNNELED); every rank must make the same calls in the same order.
//
// Also the --shard I/N option of batch schedulers without MPI: shard I of N (1-based) takes the
// items i with i mod N = I - 1.
#ifndef RABBIT_SCENARIO_RANKS_H_
#define RABBIT_SCENARIO_RANKS_H_

#include <functional>
#include <string>
#include <vector>

namespace rabbit {

class Ranks {
 public:
  // Once, first thing in main(): MPI_Init_thread when built with MPI and started by a launcher
  // (mpirun, srun: OMPI_COMM_WORLD_SIZE, PMIX_RANK, PMI_SIZE or PMI_RANK set); else a no-op.
  static void Init(int* argc, char*** argv);
  // Once, before main() returns.
  static void Finalize();
  static int rank();
  static int size();
  // The ranks on this machine (MPI_COMM_TYPE_SHARED), which share its cores.
  static int local_size();
  static bool root() { return rank() == 0; }
  static bool built_with_mpi();
  // Every rank's string, in rank order (a collective).
  static std::vector<std::string> AllGather(const std::string& mine);
  // Every rank's string, in rank order, on rank 0; an empty vector elsewhere (a collective).
  static std::vector<std::string> Gather(const std::string& mine);
  // Rank 0's string on every rank (a collective).
  static std::string Broadcast(const std::string& from_root);
  // The logical AND over ranks (a collective): e.g. "every rank loaded its input".
  static bool AllTrue(bool mine);
  // Ends every rank (MPI_Abort) after a failure that only some ranks saw; exits otherwise.
  [[noreturn]] static void Abort(int code);
};

// A counter shared by all ranks, held by rank 0: Next() hands out 0, 1, 2, ... over the whole job,
// each value to exactly one caller on one rank, for dealing items to ranks as they become free
// (an MPI one-sided fetch-and-add; on one machine OpenMPI serves it from shared memory without
// involving rank 0's CPU). Construction and destruction are collectives; Next() is called from
// the main thread only. One process: a plain counter.
class SharedCounter {
 public:
  SharedCounter();
  ~SharedCounter();
  SharedCounter(const SharedCounter&) = delete;
  SharedCounter& operator=(const SharedCounter&) = delete;
  long long Next();

 private:
  long long local_ = 0;     // one process
  void* window_ = nullptr;  // the MPI window (owned), when there are several ranks
};

// Runs step() on every rank and agrees on how it went (a collective): when it threw on any rank,
// it throws on every rank (its own exception where it failed; elsewhere a std::runtime_error with
// the first failing rank's message, which rank 0 prints), so a rank that failed alone cannot leave
// the others waiting in a later collective. One process: step() as is.
void RunAgreed(const std::function<void()>& step);

// Threads per rank for --jobs N (0: the default). One process takes all cores; under mpirun the
// ranks of a machine share its cores, and a rank that mpirun bound to some cores (its default for
// up to 2 ranks: one core each) takes only those rather than crowd threads onto them.
int ThreadsPerRank(int jobs);

struct Shard {
  int index = 1, count = 1;  // 1-based: shard `index` of `count`
  bool active() const { return count > 1; }
  bool Owns(size_t item) const { return static_cast<int>(item % count) == index - 1; }
};
// Parses "I/N" (1 <= I <= N <= 100000); false with *error set otherwise.
bool ParseShard(const std::string& text, Shard* shard, std::string* error);

}  // namespace rabbit

#endif  // RABBIT_SCENARIO_RANKS_H_
