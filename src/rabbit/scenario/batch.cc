#include "rabbit/scenario/batch.h"

#include <atomic>
#include <cctype>
#include <exception>
#include <mutex>
#include <regex>
#include <system_error>
#include <thread>

#include "rabbit/io/error.h"

namespace rabbit {

std::string RegexFilterProblem(const std::string& filter) {
  // The digits from position i on: false when they are a number above the limit.
  auto number_ok = [&filter](std::size_t i) {
    long value = 0;
    for (; i < filter.size() && std::isdigit(static_cast<unsigned char>(filter[i])); ++i) {
      value = value * 10 + (filter[i] - '0');
      if (value > kMaxRegexNumber) return false;
    }
    return true;
  };
  const std::string problem = "numbers in back-references and {n,m} repeats must be at most " +
                              std::to_string(kMaxRegexNumber);
  bool in_braces = false;
  for (std::size_t i = 0; i < filter.size(); ++i) {
    const char c = filter[i];
    if (c == '\\') {
      if (!number_ok(i + 1)) return problem;
      ++i;  // the escaped character is no brace
    } else if (c == '{') {
      in_braces = true;
      if (!number_ok(i + 1)) return problem;
    } else if (c == ',' && in_braces) {
      if (!number_ok(i + 1)) return problem;
    } else if (c == '}') {
      in_braces = false;
    }
  }
  return "";
}

std::vector<BatchJob> PlanBatch(const Suite& suite, const std::string& filter) {
  const std::string problem = RegexFilterProblem(filter);
  if (!problem.empty()) {
    throw InputError("--filter", 0, filter, "not a usable regular expression: " + problem);
  }
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
