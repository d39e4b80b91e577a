// PinnedStackThread: a joinable thread, configured from an rt ThreadSpec like rt::RtThread, whose
// stack (and so its pthread descriptor, which glibc keeps at the top of the stack) is never
// unmapped, not even after join.
//
// Why: Debian's OpenNI2 2.2 remembers every thread that ever called OpenNI::waitForAnyStream or
// VideoStream::readFrame, and on later calls probes each of them with pthread_kill(thread, 0).
// For a thread that has been joined that is a use of a dead pthread_t, and it crashed here
// (SIGSEGV in pthread_kill under oniWaitForAnyStream, every run, when a second driver thread
// started after a first had been joined in the same process; most likely because glibc had
// unmapped or reused the dead thread's cached stack). On a stack that stays mapped the probe reads
// valid memory (a finished thread's descriptor, or a later thread's), and the crash is gone.
//
// Stacks come from a process-wide free list (mmap'd once, reused by later threads, never
// unmapped): memory is bounded by the most drivers ever running at once.
// Start-up only: the constructor allocates, locks and may mmap; the running thread does not.
#pragma once

#include <pthread.h>

#include <atomic>
#include <cstddef>
#include <functional>
#include <stop_token>

#include "rt/thread_table.hpp"

namespace vigs::drivers {

class PinnedStackThread {
 public:
  static constexpr std::size_t kStackBytes = 1024 * 1024;
  // Bytes of stack touched at thread start so the first deep call does not page-fault.
  static constexpr std::size_t kStackPrefaultBytes = 64 * 1024;

  // Starts `body` on the new thread after applying `spec` (rt::apply_thread_spec, never fails).
  // Returns once the spec is applied. Throws std::system_error if the thread cannot be created.
  PinnedStackThread(const rt::ThreadSpec& spec, std::function<void(std::stop_token)> body);
  // Requests stop and joins.
  ~PinnedStackThread();
  PinnedStackThread(const PinnedStackThread&) = delete;
  PinnedStackThread& operator=(const PinnedStackThread&) = delete;

  void request_stop() noexcept { stop_.request_stop(); }
  // Not from the thread itself. Idempotent.
  void join() noexcept;
  [[nodiscard]] const rt::ThreadApplyStatus& status() const noexcept { return status_; }

 private:
  static void* entry(void* self) noexcept;

  rt::ThreadSpec spec_;
  std::function<void(std::stop_token)> body_;
  rt::ThreadApplyStatus status_;
  std::atomic<bool> started_{false};
  std::stop_source stop_;
  void* stack_ = nullptr;
  pthread_t thread_{};
  bool joinable_ = false;
};

}  // namespace vigs::drivers
