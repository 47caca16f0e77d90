#include "rabbit/scenario/batch.h"

#include <atomic>
#include <exception>
#include <mutex>
#include <regex>
#include <system_error>
#include <thread>

#include "rabbit/io/error.h"

namespace rabbit {

std::vector<BatchJob> PlanBatch(const Suite& suite, const std::string& filter) {
  std::regex pattern;
  try {
    pattern = std::regex(filter, std::regex::ECMAScript);
  } catch (const std::regex_error& e) {
    throw InputError("--filter", 0, filter, std::string("not a regular expression: ") + e.what());
  }
  std::vector<BatchJob> jobs;
  for (const Scenario& s : suite.scenarios) {
    if (!filter.empty() && !std::regex_search(s.name, pattern)) continue;
    for (const std::string& variant : ScenarioVariants(s)) jobs.push_back({&s, variant});
  }
  return jobs;
}

int BatchThreads(const std::vector<BatchJob>& jobs, int threads) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::min<int>(threads, static_cast<int>(std::max<size_t>(1, jobs.size())));
}

void RunBatch(const std::vector<BatchJob>& jobs, int threads, GaitLibraryCache* shared,
              const std::function<void(size_t, RunOutput&&)>& on_done) {
  threads = BatchThreads(jobs, threads);
  GaitLibraryCache own;
  GaitLibraryCache& libraries = shared != nullptr ? *shared : own;
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::exception_ptr error;
  auto worker = [&] {
    while (!stop) {
      const size_t i = next++;
      if (i >= jobs.size()) return;
      try {
        const BatchJob& job = jobs[i];
        std::shared_ptr<const GaitLibrary> library;
        if (job.scenario->controller == ControllerKind::kFuzzyCmac) {
          library = libraries.Get(job.scenario->pattern);
        }
        RunOutput run = RunScenario(*job.scenario, job.variant, library.get());
        std::lock_guard<std::mutex> lock(mutex);
        on_done(i, std::move(run));
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        stop = true;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) {
    try {
      pool.emplace_back(worker);
    } catch (const std::system_error&) {
      break;  // no more threads to be had: the ones running (and this one) do the work
    }
  }
  worker();
  for (std::thread& t : pool) t.join();
  if (error) std::rethrow_exception(error);
}

}  // namespace rabbit
