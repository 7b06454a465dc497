#include "stages/evaluate/worker_threads.h"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <sstream>
#include <thread>
#include <vector>

namespace syn {
namespace {

// A positive integer, or 0 when `text` is not one.
int PositiveInteger(const std::string& text) {
  if (text.empty() || text.size() > 6 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return 0;
  }
  return std::stoi(text);
}

// make's job count from MAKEFLAGS: -1 when make does not run jobs in parallel (or MAKEFLAGS is absent),
// 0 for an unlimited -j, else N. GNU make exports "-jN" as its own word (after the single-letter flags
// word, before --jobserver-auth=...).
int MakeJobs(const std::string& makeflags) {
  std::istringstream words(makeflags);
  std::string word;
  int jobs = -1;
  while (words >> word) {
    if (word == "--") break;  // variable assignments follow
    if (word.rfind("-j", 0) == 0) {
      jobs = word.size() == 2 ? 0 : PositiveInteger(word.substr(2));
    } else if (word.rfind("--jobs=", 0) == 0) {
      jobs = PositiveInteger(word.substr(7));
    }
  }
  return jobs;
}

}  // namespace

int DefaultThreadCount(const std::string& syn_threads, const std::string& makeflags, unsigned cores) {
  if (const int threads = PositiveInteger(syn_threads); threads > 0) return threads;
  const int all = std::max(1, static_cast<int>(cores));
  const int jobs = MakeJobs(makeflags);
  if (jobs == 0) return 1;
  if (jobs > 1) return std::max(1, all / jobs);
  return all;
}

int DefaultThreadCount() {
  const char* syn_threads = std::getenv("SYN_THREADS");
  const char* makeflags = std::getenv("MAKEFLAGS");
  return DefaultThreadCount(syn_threads ? syn_threads : "", makeflags ? makeflags : "", std::thread::hardware_concurrency());
}

void RunTasks(int64_t tasks, int workers, const std::function<void(int worker, int64_t task)>& run) {
  const int threads = static_cast<int>(std::clamp<int64_t>(tasks, 1, std::max(1, workers)));
  if (threads == 1) {
    for (int64_t task = 0; task < tasks; ++task) run(0, task);
    return;
  }
  std::atomic<int64_t> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first_error;
  std::mutex error_mutex;
  auto work = [&](int worker) {
    for (int64_t task = next++; task < tasks && !failed; task = next++) {
      try {
        run(worker, task);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!first_error) first_error = std::current_exception();
        failed = true;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int worker = 1; worker < threads; ++worker) pool.emplace_back(work, worker);
  work(0);
  for (std::thread& thread : pool) thread.join();
  if (first_error) std::rethrow_exception(first_error);
}

}  // namespace syn
