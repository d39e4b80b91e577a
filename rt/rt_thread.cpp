#include "rt/rt_thread.hpp"

namespace vigs::rt {
namespace {

// Touches kStackPrefaultBytes of this thread's stack. noinline so the frame really is that deep.
[[gnu::noinline]] void prefault_stack() noexcept {
  volatile unsigned char buf[RtThread::kStackPrefaultBytes];
  for (std::size_t i = 0; i < sizeof buf; i += 4096) buf[i] = 0;
}

}  // namespace

void RtThread::start_on_new_thread() noexcept {
  status_ = apply_thread_spec(spec_);
  prefault_stack();
  started_.store(true, std::memory_order_release);
  started_.notify_one();
}

void RtThread::wait_until_started() noexcept {
  // Start-up only: a futex wait until the new thread has applied its spec.
  while (!started_.load(std::memory_order_acquire)) started_.wait(false, std::memory_order_acquire);
}

}  // namespace vigs::rt
