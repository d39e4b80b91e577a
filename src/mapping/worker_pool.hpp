#pragma once
// A fixed set of worker threads that run one job at a time: run(fn) calls fn(thread_index) on
// every thread (the caller is thread 0) and returns when all are done. Threads are created once
// and joined in the destructor; nothing allocates per job. Work split is static (decided by the
// job from thread_index), so results are bit-identical from run to run.
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace vigs::mapping {

class WorkerPool {
 public:
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  [[nodiscard]] int threads() const { return threads_; }

  /// Runs fn(t) for t in [0, threads()) and waits for all of them.
  void run(const std::function<void(int)>& fn);

 private:
  void worker_loop(int index);

  int threads_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_cv_;
  std::condition_variable done_cv_;
  const std::function<void(int)>* job_ = nullptr;
  unsigned long generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
};

}  // namespace vigs::mapping
