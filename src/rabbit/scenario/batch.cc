#include "rabbit/scenario/batch.h"

#include <re2/re2.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <numeric>
#include <system_error>
#include <thread>

#include "rabbit/io/error.h"

namespace rabbit {

namespace {

RE2::Options FilterOptions() {
  RE2::Options options;
  options.set_log_errors(false);  // the error goes into the InputError instead
  return options;
}

}  // namespace

std::string RegexFilterProblem(const std::string& filter) {
  if (filter.empty()) return "";
  const RE2 re(filter, FilterOptions());
  if (re.ok()) return "";
  return re.error() + " (RE2 syntax: no back-references or look-around, repeats up to {1000})";
}

NameFilter::NameFilter(const std::string& pattern, const std::string& where,
                       const std::string& key) {
  if (pattern.empty()) return;
  auto re = std::make_shared<const RE2>(pattern, FilterOptions());
  if (!re->ok()) {
    throw InputError(where, 0, key,
                     "not a usable regular expression: " + RegexFilterProblem(pattern));
  }
  re_ = std::move(re);
}

bool NameFilter::Matches(const std::string& name) const {
  return re_ == nullptr || RE2::PartialMatch(name, *re_);
}

std::vector<BatchJob> PlanBatch(const Suite& suite, const std::string& filter) {
  const NameFilter pattern(filter, "--filter", filter);
  std::vector<BatchJob> jobs;
  for (const Scenario& s : suite.scenarios) {
    if (!pattern.Matches(s.name)) continue;
    for (const std::string& variant : ScenarioVariants(s)) jobs.push_back({&s, variant});
  }
  return jobs;
}

bool NeedsTrainedPattern(const BatchJob& job) { return job.variant == "multi_cmac"; }

std::vector<size_t> ExecutionOrder(const std::vector<BatchJob>& jobs) {
  // The jobs that need no pattern, then those that do, each in plan order; the first of the
  // latter then moves to the front.
  std::vector<size_t> order(jobs.size());
  std::iota(order.begin(), order.end(), size_t{0});
  const auto plain_end = std::stable_partition(
      order.begin(), order.end(), [&](size_t i) { return !NeedsTrainedPattern(jobs[i]); });
  if (plain_end != order.end()) std::rotate(order.begin(), plain_end, plain_end + 1);
  return order;
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
  const std::vector<size_t> order = ExecutionOrder(jobs);
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::exception_ptr error;
  auto worker = [&] {
    while (!stop) {
      const size_t k = next++;
      if (k >= jobs.size()) return;
      const size_t i = order[k];
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
