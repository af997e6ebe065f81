// A fixed set of worker threads for the window pipelines of the encoder and the decoder
// (docs/ARCHITECTURE.md "Threads"). Jobs run in the order they were submitted; the caller keeps
// the order of the results itself (each job writes its own slot). Part of the decoder library.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <future>
#include <mutex>
#include <thread>
#include <vector>

namespace capz {

// The worker count `threads` stands for: itself when >= 1, all cores for 0 (at least 1). Throws
// Error(kInvalidParameter) for a negative count or one above 1024.
size_t resolve_threads(int threads);

class ThreadPool {
 public:
  explicit ThreadPool(size_t threads);
  // Jobs not yet started are dropped (their futures report broken_promise); running ones finish.
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  // Runs job on a worker. The future is ready when it has run; get() rethrows what it threw.
  std::future<void> submit(std::function<void()> job);
  size_t size() const { return workers_.size(); }

 private:
  void work();

  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::packaged_task<void()>> jobs_;
  bool stop_ = false;
  std::vector<std::thread> workers_;
};

}  // namespace capz
