#include "rabbit/scenario/rank_batch.h"

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <system_error>
#include <thread>

#include "rabbit/io/atomic_file.h"
#include "rabbit/io/bounded_read.h"
#include "rabbit/io/csv_table.h"
#include "rabbit/io/error.h"
#include "rabbit/scenario/ranks.h"
#include "rabbit/scenario/run_files.h"

namespace rabbit {
namespace {

namespace fs = std::filesystem;

// At most this much reaches rank 0 in one round of the transfer, whatever the number of ranks
// (MPI counts are ints, and rank 0 holds a round in memory).
constexpr size_t kRoundBytes = size_t{256} << 20;

// Messages between ranks: fixed-width numbers and length-prefixed strings in this machine's byte
// order (the ranks of a job run one binary on one kind of machine).
class Packer {
 public:
  void U64(std::uint64_t v) { Raw(&v, sizeof v); }
  void F64(double v) { Raw(&v, sizeof v); }
  void Str(std::string_view s) {
    U64(s.size());
    text_.append(s.data(), s.size());
  }
  size_t size() const { return text_.size(); }
  const std::string& text() const { return text_; }

 private:
  void Raw(const void* data, size_t n) { text_.append(static_cast<const char*>(data), n); }
  std::string text_;
};

class Unpacker {
 public:
  explicit Unpacker(const std::string& text) : text_(text) {}
  std::uint64_t U64() {
    std::uint64_t v = 0;
    Raw(&v, sizeof v);
    return v;
  }
  double F64() {
    double v = 0.0;
    Raw(&v, sizeof v);
    return v;
  }
  std::string Str() {
    const std::uint64_t n = U64();
    Need(n);
    std::string s = text_.substr(pos_, static_cast<size_t>(n));
    pos_ += static_cast<size_t>(n);
    return s;
  }

 private:
  void Need(std::uint64_t n) const {
    if (n > text_.size() - pos_) throw std::runtime_error("MPI: a truncated message between ranks");
  }
  void Raw(void* data, size_t n) {
    Need(n);
    std::memcpy(data, text_.data() + pos_, n);
    pos_ += n;
  }
  const std::string& text_;
  size_t pos_ = 0;
};

std::array<double*, 11> MetricFields(RunMetrics* m) {
  return {&m->duration,    &m->distance,   &m->mean_abs_speed_error, &m->final_abs_speed_error,
          &m->l_step_mean, &m->l_step_min, &m->l_step_max,           &m->l_step_spread,
          &m->saturation,  &m->energy,     &m->cost_of_transport};
}

void PackBrief(const RunBrief& brief, Packer* out) {
  out->U64(brief.job);
  out->Str(brief.run);
  out->Str(brief.summary_row);
  out->U64(static_cast<std::uint64_t>(brief.outcome));
  out->U64(brief.passed ? 1 : 0);
  out->U64(brief.failures.size());
  for (const std::string& f : brief.failures) out->Str(f);
  RunMetrics metrics = brief.metrics;
  for (double* v : MetricFields(&metrics)) out->F64(*v);
  out->U64(static_cast<std::uint64_t>(static_cast<std::int64_t>(metrics.steps)));
  out->U64(metrics.pattern_memory_bytes);
  out->F64(brief.simulated);
}

RunBrief UnpackBrief(Unpacker* in) {
  RunBrief brief;
  brief.job = static_cast<size_t>(in->U64());
  brief.run = in->Str();
  brief.summary_row = in->Str();
  brief.outcome = static_cast<Outcome>(in->U64());
  brief.passed = in->U64() != 0;
  const std::uint64_t failures = in->U64();
  for (std::uint64_t k = 0; k < failures; ++k) brief.failures.push_back(in->Str());
  for (double* v : MetricFields(&brief.metrics)) *v = in->F64();
  brief.metrics.steps = static_cast<int>(static_cast<std::int64_t>(in->U64()));
  brief.metrics.pattern_memory_bytes = static_cast<std::size_t>(in->U64());
  brief.simulated = in->F64();
  return brief;
}

RunBrief Brief(size_t job, const std::string& suite, const RunOutput& run) {
  RunBrief brief;
  brief.job = job;
  brief.run = run.run;
  brief.summary_row = SummaryRow(suite, run);
  brief.outcome = run.sim.outcome;
  brief.passed = run.passed;
  brief.failures = run.failures;
  brief.metrics = run.metrics;
  brief.simulated = run.sim.t_end;
  return brief;
}

std::string ReadFileText(const std::string& path) { return ReadBoundedFile(path, kCsvTableLimits); }

// Written after the run's other files: its presence means they are all there.
void WriteRunMarker(const std::string& dir, const RunBrief& brief) {
  WriteFileAtomically((fs::path(dir) / brief.run / kRunMarker).string(), [&](std::ostream& out) {
    out << SummaryHeader() << "\n" << brief.summary_row << "\n";
  });
}

// Marker files after every other file (see Outbox).
bool TransferOrder(const fs::path& a, const fs::path& b) {
  const bool a_marker = a.filename() == kRunMarker, b_marker = b.filename() == kRunMarker;
  if (a_marker != b_marker) return b_marker;
  return a < b;
}

// A non-root rank's private folder for its runs' files, removed with it.
struct ScratchFolder {
  fs::path path;
  void Create() {
    std::string pattern =
        (fs::temp_directory_path() / ("rabbit-rank" + std::to_string(Ranks::rank()) + "-XXXXXX"))
            .string();
    if (::mkdtemp(pattern.data()) == nullptr) {
      throw std::runtime_error(pattern +
                               ": cannot create a temporary folder: " + std::strerror(errno));
    }
    path = pattern;
  }
  ~ScratchFolder() {
    std::error_code ignored;
    if (!path.empty()) fs::remove_all(path, ignored);
  }
};

// The file through which a rank finds out whether it sees the report folder (WritesIntoReport).
constexpr const char* kRankProbe = ".rabbit-rank-probe";

bool TransferForced() {
  const char* mode = std::getenv("RABBIT_RANK_FILES");
  const std::string text = mode == nullptr ? "auto" : mode;
  if (text == "auto") return false;
  if (text == "transfer") return true;
  throw InputError("environment", 0, "RABBIT_RANK_FILES",
                   "expected \"auto\" or \"transfer\", got \"" + text + "\"");
}

std::string RandomToken() {
  std::random_device random;
  std::string token;
  for (int k = 0; k < 4; ++k) token += std::to_string(random()) + "-";
  return token + std::to_string(::getpid());
}

// Whether this rank writes its runs' folders straight into the report folder `dir`, which rank 0
// creates. Rank 0 does; it writes a probe holding a random token into the folder, and a rank that
// reads the token back sees that folder (ranks on one machine, or a file system the ranks share)
// and writes its folders straight into it, each run's marker last as rank 0 does; a rank that does
// not (or every rank, with RABBIT_RANK_FILES=transfer) writes them into a scratch folder and sends
// them to rank 0 after the runs. Rank 0 removes the probe once every rank has looked. A collective.
bool WritesIntoReport(const fs::path& dir) {
  bool forced = false;
  std::string token;
  RunAgreed([&] {
    forced = TransferForced();
    if (Ranks::rank() != 0) return;
    fs::create_directories(dir);
    token = RandomToken();
    WriteFileAtomically((dir / kRankProbe).string(), [&](std::ostream& out) { out << token; });
  });
  token = Ranks::Broadcast(token);
  bool sees = Ranks::rank() == 0;
  if (!sees && !forced) {
    std::ifstream in(dir / kRankProbe, std::ios::binary);
    std::string read;
    sees = in && std::getline(in, read) && read == token;
  }
  Ranks::AllTrue(true);  // every rank has looked
  RunAgreed([&] {
    if (Ranks::rank() == 0) fs::remove(dir / kRankProbe);
  });
  return sees;
}

// The files of a non-root rank's scratch folder, handed out in pieces. A message is a status
// (0: an error message follows; 1: pieces follow), whether more pieces remain after these, their
// count, then per piece the file's relative path, the offset and the bytes.
class Outbox {
 public:
  explicit Outbox(fs::path base) : base_(std::move(base)) {}

  // Never throws: a failure travels to rank 0 in the message.
  std::string Next(size_t budget) {
    Packer records;
    std::uint64_t count = 0;
    try {
      if (!listed_) List();
      while (next_ < files_.size() && records.size() < budget) {
        const fs::path full = base_ / files_[next_];
        const std::uint64_t size = fs::file_size(full);
        const std::uint64_t take = std::min<std::uint64_t>(size - offset_, budget - records.size());
        std::string bytes(static_cast<size_t>(take), '\0');
        std::ifstream in(full, std::ios::binary);
        in.seekg(static_cast<std::streamoff>(offset_));
        in.read(bytes.data(), static_cast<std::streamsize>(take));
        if (!in) throw std::runtime_error(full.string() + ": cannot read back");
        records.Str(files_[next_].generic_string());
        records.U64(offset_);
        records.Str(bytes);
        ++count;
        offset_ += take;
        if (offset_ >= size) {
          ++next_;
          offset_ = 0;
        }
      }
    } catch (const std::exception& e) {
      Packer failure;
      failure.U64(0);
      failure.Str(e.what());
      return failure.text();
    }
    Packer message;
    message.U64(1);
    message.U64(next_ < files_.size() ? 1 : 0);
    message.U64(count);
    return message.text() + records.text();
  }

 private:
  void List() {
    listed_ = true;
    if (base_.empty()) return;  // this rank wrote into the report itself
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(base_)) {
      if (entry.is_regular_file()) files_.push_back(entry.path().lexically_relative(base_));
    }
    // The run markers go last: a transfer cut short leaves no marker beside a partial folder.
    std::sort(files_.begin(), files_.end(), TransferOrder);
  }

  fs::path base_;
  std::vector<fs::path> files_;
  bool listed_ = false;
  size_t next_ = 0;
  std::uint64_t offset_ = 0;
};

// Rank 0: appends a received piece to its file below dir (pieces of a file arrive in order).
void WritePiece(const fs::path& dir, const std::string& name, std::uint64_t offset,
                const std::string& bytes) {
  const fs::path relative(name);
  bool safe = !relative.empty() && relative.is_relative();
  for (const fs::path& part : relative) safe = safe && part != ".." && part != ".";
  if (!safe) throw std::runtime_error("MPI: a rank sent a file outside the report: " + name);
  const fs::path path = dir / relative;
  if (offset == 0) {
    fs::create_directories(path.parent_path());
  } else if (!fs::exists(path) || fs::file_size(path) != offset) {
    throw std::runtime_error(path.string() + ": pieces from the ranks out of order");
  }
  std::ofstream out(path, std::ios::binary | (offset == 0 ? std::ios::trunc : std::ios::app));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

// Rank 0: writes one round's pieces; returns "more", "done", or the error that stops everyone.
std::string WriteRound(const std::vector<std::string>& messages, const fs::path& dir) {
  bool more = false;
  for (size_t r = 1; r < messages.size(); ++r) {
    try {
      Unpacker in(messages[r]);
      if (in.U64() == 0) return "rank " + std::to_string(r) + ": " + in.Str();
      if (in.U64() != 0) more = true;  // read whatever `more` was already
      const std::uint64_t count = in.U64();
      for (std::uint64_t k = 0; k < count; ++k) {
        const std::string name = in.Str();
        const std::uint64_t offset = in.U64();
        WritePiece(dir, name, offset, in.Str());
      }
    } catch (const std::exception& e) {
      return std::string("rank 0: ") + e.what();
    }
  }
  return more ? "more" : "done";
}

}  // namespace

RunBrief ReadRunMarker(const std::string& path) {
  const CsvTable table = CsvTable::Read(path);
  if (table.num_rows() != 1) throw InputError(path, 0, "", "expected one summary row");
  std::string header;
  for (const std::string& h : table.header()) header += (header.empty() ? "" : ",") + h;
  if (header != SummaryHeader()) {
    throw InputError(path, 1, "", "not this version's summary columns");
  }
  const auto text = [&](const char* column) { return table.Text(0, table.Column(column)); };
  const auto number = [&](const char* column) {
    return table.Number(0, table.Column(column), CsvNumber::kFiniteOrNan);
  };
  RunBrief brief;
  brief.run = text("run");
  const std::string outcome = text("outcome");
  const bool known = ParseOutcome(outcome, &brief.outcome);
  if (!known) throw InputError(path, 2, "outcome", "unknown outcome \"" + outcome + "\"");
  brief.passed = table.Integer(0, table.Column("passed")) != 0;
  // The row is the one this program wrote: its text, not a re-rendering, goes into summary.csv.
  std::istringstream lines(ReadFileText(path));
  std::string line;
  std::getline(lines, line);
  std::getline(lines, brief.summary_row);
  const std::string failed = text("failed_criteria");
  for (size_t start = 0; !failed.empty() && start <= failed.size();) {
    const size_t end = std::min(failed.find(';', start), failed.size());
    brief.failures.push_back(failed.substr(start, end - start));
    start = end + 1;
  }
  RunMetrics& m = brief.metrics;
  m.duration = number("duration_s");
  m.distance = number("distance_m");
  m.steps = table.Integer(0, table.Column("steps"));
  m.mean_abs_speed_error = number("mean_abs_speed_error_m_s");
  m.final_abs_speed_error = number("final_abs_speed_error_m_s");
  m.l_step_mean = number("l_step_mean_m");
  m.l_step_min = number("l_step_min_m");
  m.l_step_max = number("l_step_max_m");
  m.l_step_spread = number("l_step_spread_m");
  m.saturation = number("saturation_s");
  m.energy = number("energy_j");
  m.cost_of_transport = number("cost_of_transport");
  const double memory = table.Number(0, table.Column("pattern_memory_bytes"));
  if (!(memory >= 0.0) || memory != std::floor(memory)) {
    throw InputError(path, 2, "pattern_memory_bytes", "expected a count of bytes");
  }
  m.pattern_memory_bytes = static_cast<std::size_t>(memory);
  brief.simulated = m.duration;
  return brief;
}

namespace {

// Several ranks: this rank's threads take jobs as they become free, from counters all ranks share
// (dynamic dealing: a rank that drew long runs simply takes fewer). The jobs that need a trained
// multi_cmac pattern have a counter of their own, which rank 0 draws from first and the other
// ranks only once every other job is taken: the pattern is trained on rank 0 alone unless the
// other ranks run out of other work (each rank trains its own copy, seconds of CPU). MPI is called
// from this (the main) thread only: it fetches an index whenever a worker asks for one and hands
// it over. on_done(job, run) is called from the workers, serialised. Rethrows the first failure.
void RunDealtJobs(const std::vector<BatchJob>& jobs, int threads, GaitLibraryCache* libraries,
                  const std::function<void(size_t, RunOutput&&)>& on_done) {
  // Two lists in ExecutionOrder, the same on every rank: the jobs that need a trained pattern and
  // the others, each dealt from its own counter (collectives on construction and destruction).
  std::array<std::vector<size_t>, 2> lists;  // [0]: multi_cmac runs, [1]: the others
  for (size_t job : ExecutionOrder(jobs)) {
    lists[NeedsTrainedPattern(jobs[job]) ? 0 : 1].push_back(job);
  }
  std::array<SharedCounter, 2> counters;
  std::array<bool, 2> drained{false, false};
  const int first = Ranks::rank() == 0 ? 0 : 1;  // the list this rank draws from first
  std::mutex mutex;
  std::condition_variable wanted, handed;
  int waiting = 0;            // workers waiting for a job
  std::vector<size_t> queue;  // jobs handed over, not yet taken
  bool exhausted = false;     // no job left (or a failure): workers stop
  std::exception_ptr error;
  std::mutex done_mutex;
  auto worker = [&] {
    while (true) {
      size_t job = 0;
      {
        std::unique_lock<std::mutex> lock(mutex);
        ++waiting;
        wanted.notify_one();
        handed.wait(lock, [&] { return !queue.empty() || exhausted; });
        --waiting;
        if (queue.empty()) return;
        job = queue.back();
        queue.pop_back();
      }
      try {
        // One job on this thread, through the batch runner (the same library cache and run).
        RunBatch({jobs[job]}, 1, libraries, [&](size_t, RunOutput&& run) {
          std::lock_guard<std::mutex> lock(done_mutex);
          on_done(job, std::move(run));
        });
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        exhausted = true;
        handed.notify_all();
        wanted.notify_one();
        return;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    try {
      pool.emplace_back(worker);
    } catch (const std::system_error&) {
      break;  // no more threads to be had: the ones running do the work
    }
  }
  if (pool.empty()) throw std::runtime_error("cannot start a worker thread");
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (!exhausted) {
      wanted.wait(lock, [&] { return (waiting > static_cast<int>(queue.size())) || exhausted; });
      if (exhausted) break;
      lock.unlock();
      long long job = -1;
      for (int k = 0; k < 2 && job < 0; ++k) {
        const int list = k == 0 ? first : 1 - first;
        if (drained[list]) continue;
        const long long next = counters[list].Next();
        if (next >= 0 && static_cast<size_t>(next) < lists[list].size()) {
          job = static_cast<long long>(lists[list][static_cast<size_t>(next)]);
        } else {
          drained[list] = true;
        }
      }
      lock.lock();
      if (job < 0) {
        exhausted = true;
      } else {
        queue.push_back(static_cast<size_t>(job));
      }
      handed.notify_all();
    }
  }
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace

RankBatchResult RunBatchOverRanks(const std::vector<BatchJob>& jobs, const std::string& suite,
                                  int threads, GaitLibraryCache* libraries, const std::string& dir,
                                  const std::function<void(const RunBrief&)>& on_local_done) {
  const int rank = Ranks::rank(), size = Ranks::size();
  RankBatchResult result;
  // Each rank's share is not known in advance: at most all the jobs, shared with the other ranks.
  result.threads = size == 1 ? BatchThreads(jobs, threads)
                             : std::min(BatchThreads(jobs, threads),
                                        static_cast<int>(std::max<size_t>(1, jobs.size() / size)));
  std::vector<RunBrief> briefs;
  ScratchFolder scratch;
  const bool direct = size == 1 || WritesIntoReport(dir);
  RunAgreed([&] {
    std::string out = dir;
    if (rank == 0) {
      fs::create_directories(dir);  // already there with several ranks (WritesIntoReport)
    } else if (!direct) {
      scratch.Create();
      out = scratch.path.string();
    }
    const auto done = [&](size_t job, RunOutput&& run) {
      WriteRunFiles(*jobs[job].scenario, run, out);
      briefs.push_back(Brief(job, suite, run));
      WriteRunMarker(out, briefs.back());
      if (on_local_done) on_local_done(briefs.back());
    };
    if (size == 1) {
      RunBatch(jobs, result.threads, libraries, done);
    } else {
      RunDealtJobs(jobs, result.threads, libraries, done);
    }
  });

  // The briefs are small: one message each. Then the other ranks' folders, in rounds.
  Packer mine_packed;
  mine_packed.U64(briefs.size());
  for (const RunBrief& b : briefs) PackBrief(b, &mine_packed);
  const std::vector<std::string> gathered = Ranks::Gather(mine_packed.text());
  RunAgreed([&] {
    if (rank != 0) return;
    result.runs.resize(jobs.size());
    std::vector<bool> seen(jobs.size(), false);
    for (const std::string& message : gathered) {
      Unpacker in(message);
      const std::uint64_t count = in.U64();
      for (std::uint64_t k = 0; k < count; ++k) {
        RunBrief b = UnpackBrief(&in);
        if (b.job >= jobs.size() || seen[b.job]) throw std::runtime_error("MPI: a stray run");
        seen[b.job] = true;
        result.runs[b.job] = std::move(b);
      }
    }
    if (std::find(seen.begin(), seen.end(), false) != seen.end()) {
      throw std::runtime_error("MPI: a run's results did not arrive");
    }
  });
  if (size == 1) return result;
  const size_t budget =
      std::max<size_t>(size_t{1} << 16, kRoundBytes / static_cast<size_t>(size - 1));
  Outbox outbox(scratch.path);
  while (true) {
    const std::vector<std::string> round = Ranks::Gather(rank == 0 ? "" : outbox.Next(budget));
    const std::string status = Ranks::Broadcast(rank == 0 ? WriteRound(round, dir) : "");
    if (status == "done") break;
    if (status != "more") throw std::runtime_error(status);
  }
  return result;
}

}  // namespace rabbit
