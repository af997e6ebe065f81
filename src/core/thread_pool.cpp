// The worker threads (thread_pool.h). Part of the decoder library.
#include "core/thread_pool.h"

#include <string>
#include <utility>

#include "capz/error.h"

namespace capz {

size_t resolve_threads(int threads) {
  if (threads < 0 || threads > 1024)
    fail(ErrorCode::kInvalidParameter, "",
         "threads must be 0 (all cores) .. 1024, got " + std::to_string(threads));
  if (threads > 0) return static_cast<size_t>(threads);
  const unsigned cores = std::thread::hardware_concurrency();
  return cores > 0 ? cores : 1;
}

ThreadPool::ThreadPool(size_t threads) {
  workers_.reserve(threads);
  try {
    for (size_t i = 0; i < threads; ++i) workers_.emplace_back([this] { work(); });
  } catch (const std::system_error& e) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    for (std::thread& t : workers_) t.join();
    fail(ErrorCode::kInternal, "", std::string("cannot start a worker thread: ") + e.what());
  }
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = true;
    jobs_.clear();
  }
  cv_.notify_all();
  for (std::thread& t : workers_) t.join();
}

std::future<void> ThreadPool::submit(std::function<void()> job) {
  std::packaged_task<void()> task(std::move(job));
  std::future<void> done = task.get_future();
  {
    std::lock_guard<std::mutex> lock(mu_);
    jobs_.push_back(std::move(task));
  }
  cv_.notify_one();
  return done;
}

void ThreadPool::work() {
  for (;;) {
    std::packaged_task<void()> task;
    {
      std::unique_lock<std::mutex> lock(mu_);
      cv_.wait(lock, [this] { return stop_ || !jobs_.empty(); });
      if (stop_) return;
      task = std::move(jobs_.front());
      jobs_.pop_front();
    }
    task();  // an exception goes into the task's future
  }
}

}  // namespace capz
