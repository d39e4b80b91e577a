#include "tracking/fork_join.hpp"

#include <algorithm>

namespace vigs::tracking {

ForkJoin::ForkJoin(int num_threads) : num_threads_(std::max(1, num_threads)) {
  threads_.reserve(static_cast<std::size_t>(num_threads_ - 1));
  for (int t = 1; t < num_threads_; ++t) {
    threads_.emplace_back([this, t] { worker(t); });
  }
}

ForkJoin::~ForkJoin() {
  stop_.store(true, std::memory_order_release);
  generation_.fetch_add(1, std::memory_order_acq_rel);
  generation_.notify_all();
  for (auto& th : threads_) {
    th.join();
  }
}

void ForkJoin::dispatch() {
  pending_.store(num_threads_ - 1, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_acq_rel);  // publishes task_ and call_
  generation_.notify_all();
  call_(task_, 0);
  int left = pending_.load(std::memory_order_acquire);
  while (left != 0) {
    pending_.wait(left, std::memory_order_acquire);
    left = pending_.load(std::memory_order_acquire);
  }
}

void ForkJoin::worker(int t) {
  std::uint32_t seen = 0;
  for (;;) {
    generation_.wait(seen, std::memory_order_acquire);
    seen = generation_.load(std::memory_order_acquire);
    if (stop_.load(std::memory_order_acquire)) {
      return;
    }
    call_(task_, t);
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      pending_.notify_one();
    }
  }
}

}  // namespace vigs::tracking
