#include "rabbit/scenario/ranks.h"

#include <sched.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <thread>

#ifdef RABBIT_WITH_MPI
#include <mpi.h>
#endif

namespace rabbit {
namespace {

int g_rank = 0;
int g_size = 1;
int g_local_size = 1;
[[maybe_unused]] bool g_initialised = false;  // we called MPI_Init_thread (and so must finalise)

}  // namespace

bool Ranks::built_with_mpi() {
#ifdef RABBIT_WITH_MPI
  return true;
#else
  return false;
#endif
}

void Ranks::Init(int* argc, char*** argv) {
#ifdef RABBIT_WITH_MPI
  // Started by mpirun (OpenMPI, or a PMI launcher such as srun)? Otherwise stay a single process:
  // MPI's singleton start costs about 0.3 s and may warn about the network on a laptop.
  if (std::getenv("OMPI_COMM_WORLD_SIZE") == nullptr && std::getenv("PMIX_RANK") == nullptr &&
      std::getenv("PMI_SIZE") == nullptr && std::getenv("PMI_RANK") == nullptr) {
    return;
  }
  int already = 0;
  MPI_Initialized(&already);
  if (already == 0) {
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    g_initialised = true;
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  MPI_Comm local;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &local);
  MPI_Comm_size(local, &g_local_size);
  MPI_Comm_free(&local);
#else
  (void)argc;
  (void)argv;
#endif
}

void Ranks::Finalize() {
#ifdef RABBIT_WITH_MPI
  if (g_initialised) {
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (finalised == 0) MPI_Finalize();
    g_initialised = false;
  }
#endif
}

int Ranks::rank() { return g_rank; }
int Ranks::size() { return g_size; }
int Ranks::local_size() { return g_local_size; }

std::vector<std::string> Ranks::AllGather(const std::string& mine) {
  if (g_size == 1) return {mine};
#ifdef RABBIT_WITH_MPI
  const long long length = static_cast<long long>(mine.size());
  std::vector<long long> lengths(static_cast<size_t>(g_size));
  MPI_Allgather(&length, 1, MPI_LONG_LONG, lengths.data(), 1, MPI_LONG_LONG, MPI_COMM_WORLD);
  std::vector<int> counts(static_cast<size_t>(g_size)), offsets(static_cast<size_t>(g_size));
  long long total = 0;
  for (int r = 0; r < g_size; ++r) {
    if (lengths[r] > (1LL << 30)) throw std::runtime_error("MPI: a rank's results exceed 1 GiB");
    counts[r] = static_cast<int>(lengths[r]);
    offsets[r] = static_cast<int>(total);
    total += lengths[r];
  }
  if (total > (1LL << 31) - 1) throw std::runtime_error("MPI: gathered results exceed 2 GiB");
  std::string all(static_cast<size_t>(total), '\0');
  MPI_Allgatherv(mine.data(), static_cast<int>(length), MPI_CHAR, all.data(), counts.data(),
                 offsets.data(), MPI_CHAR, MPI_COMM_WORLD);
  std::vector<std::string> out;
  for (int r = 0; r < g_size; ++r) out.push_back(all.substr(offsets[r], counts[r]));
  return out;
#else
  return {mine};
#endif
}

std::vector<std::string> Ranks::Gather(const std::string& mine) {
  if (g_size == 1) return {mine};
#ifdef RABBIT_WITH_MPI
  // Every rank learns every length, so that all of them refuse an oversized gather together
  // (a throw on rank 0 alone would leave the others inside MPI_Gatherv).
  const long long length = static_cast<long long>(mine.size());
  std::vector<long long> lengths(static_cast<size_t>(g_size));
  MPI_Allgather(&length, 1, MPI_LONG_LONG, lengths.data(), 1, MPI_LONG_LONG, MPI_COMM_WORLD);
  std::vector<int> counts(static_cast<size_t>(g_size)), offsets(static_cast<size_t>(g_size));
  long long total = 0;
  for (int r = 0; r < g_size; ++r) {
    if (lengths[r] > (1LL << 30)) throw std::runtime_error("MPI: a rank's results exceed 1 GiB");
    counts[r] = static_cast<int>(lengths[r]);
    offsets[r] = static_cast<int>(total);
    total += lengths[r];
  }
  if (total > (1LL << 31) - 1) throw std::runtime_error("MPI: gathered results exceed 2 GiB");
  std::string all(g_rank == 0 ? static_cast<size_t>(total) : 0, '\0');
  MPI_Gatherv(mine.data(), static_cast<int>(length), MPI_CHAR, all.data(), counts.data(),
              offsets.data(), MPI_CHAR, 0, MPI_COMM_WORLD);
  std::vector<std::string> out;
  if (g_rank != 0) return out;
  for (int r = 0; r < g_size; ++r) out.push_back(all.substr(offsets[r], counts[r]));
  return out;
#else
  return {mine};
#endif
}

std::string Ranks::Broadcast(const std::string& from_root) {
  if (g_size == 1) return from_root;
#ifdef RABBIT_WITH_MPI
  long long length = static_cast<long long>(from_root.size());
  MPI_Bcast(&length, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  std::string text = g_rank == 0 ? from_root : std::string(static_cast<size_t>(length), '\0');
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, MPI_COMM_WORLD);
  return text;
#else
  return from_root;
#endif
}

bool Ranks::AllTrue(bool mine) {
  if (g_size == 1) return mine;
#ifdef RABBIT_WITH_MPI
  int in = mine ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LAND, MPI_COMM_WORLD);
  return out != 0;
#else
  return mine;
#endif
}

void Ranks::Abort(int code) {
#ifdef RABBIT_WITH_MPI
  if (g_size > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

SharedCounter::SharedCounter() {
#ifdef RABBIT_WITH_MPI
  if (g_size == 1) return;
  auto* window = new MPI_Win;
  long long* base = nullptr;
  const MPI_Aint bytes = g_rank == 0 ? sizeof(long long) : 0;
  if (g_local_size == g_size) {
    // One machine: a shared-memory window, whose atomics never wait for rank 0 to enter MPI.
    MPI_Win_allocate_shared(bytes, sizeof(long long), MPI_INFO_NULL, MPI_COMM_WORLD, &base, window);
  } else {
    MPI_Win_allocate(bytes, sizeof(long long), MPI_INFO_NULL, MPI_COMM_WORLD, &base, window);
  }
  if (g_rank == 0) {
    MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, *window);
    *base = 0;
    MPI_Win_unlock(0, *window);
  }
  MPI_Barrier(MPI_COMM_WORLD);  // the counter is 0 before anyone asks
  MPI_Win_lock_all(MPI_MODE_NOCHECK, *window);
  window_ = window;
#endif
}

SharedCounter::~SharedCounter() {
#ifdef RABBIT_WITH_MPI
  if (window_ == nullptr) return;
  auto* window = static_cast<MPI_Win*>(window_);
  MPI_Win_unlock_all(*window);
  MPI_Win_free(window);  // a collective
  delete window;
#endif
}

long long SharedCounter::Next() {
#ifdef RABBIT_WITH_MPI
  if (window_ != nullptr) {
    auto* window = static_cast<MPI_Win*>(window_);
    const long long one = 1;
    long long got = 0;
    MPI_Fetch_and_op(&one, &got, MPI_LONG_LONG, 0, 0, MPI_SUM, *window);
    MPI_Win_flush(0, *window);
    return got;
  }
#endif
  return local_++;
}

void RunAgreed(const std::function<void()>& step) {
  std::exception_ptr error;
  std::string message;
  try {
    step();
  } catch (const std::exception& e) {
    error = std::current_exception();
    message = e.what();
  } catch (...) {
    error = std::current_exception();
  }
  if (Ranks::AllTrue(!error)) return;
  if (message.empty() && error) message = "unknown error";
  const std::vector<std::string> messages = Ranks::AllGather(message);
  if (error) std::rethrow_exception(error);
  for (size_t r = 0; r < messages.size(); ++r) {
    if (!messages[r].empty())
      throw std::runtime_error("rank " + std::to_string(r) + ": " + messages[r]);
  }
  throw std::runtime_error("another rank failed");
}

int ThreadsPerRank(int jobs) {
  if (jobs > 0 || Ranks::size() == 1) return jobs;
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  int threads = cores / Ranks::local_size();
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (::sched_getaffinity(0, sizeof mask, &mask) == 0) {
    threads = std::min(threads, CPU_COUNT(&mask));
  }
  return std::max(1, threads);
}

bool ParseShard(const std::string& text, Shard* shard, std::string* error) {
  const size_t slash = text.find('/');
  auto number = [](const std::string& s, long* value) {
    if (s.empty() || s.size() > 6 || s.find_first_not_of("0123456789") != std::string::npos) {
      return false;
    }
    *value = std::stol(s);
    return true;
  };
  long i = 0, n = 0;
  if (slash == std::string::npos || !number(text.substr(0, slash), &i) ||
      !number(text.substr(slash + 1), &n) || n < 1 || n > 100000 || i < 1 || i > n) {
    *error = "--shard expects I/N with 1 <= I <= N (e.g. 2/8), got \"" + text + "\"";
    return false;
  }
  shard->index = static_cast<int>(i);
  shard->count = static_cast<int>(n);
  return true;
}

}  // namespace rabbit
