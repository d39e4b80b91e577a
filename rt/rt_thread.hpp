// RtThread: a std::thread that takes its name, priority and CPU from a ThreadSpec.
//
// The new thread first applies the spec (apply_thread_spec, which never fails) and pre-faults
// part of its stack, then runs the body. The constructor returns once the spec has been applied,
// so status() is valid immediately. The body may take a std::stop_token; request_stop() sets it.
// Never detached: the destructor requests stop and joins (like std::jthread), so a thread cannot
// outlive the objects it uses. Not copyable or movable (the running thread refers to *this);
// hold it in std::optional or std::unique_ptr to create it later.
#pragma once

#include <atomic>
#include <cstddef>
#include <stop_token>
#include <thread>
#include <type_traits>
#include <utility>

#include "rt/thread_table.hpp"

namespace vigs::rt {

class RtThread {
 public:
  // Bytes of stack touched at thread start so the first deep call does not page-fault.
  static constexpr std::size_t kStackPrefaultBytes = 64 * 1024;

  // body: callable as body(std::stop_token) or body().
  template <class F>
  RtThread(const ThreadSpec& spec, F&& body) : spec_(spec) {
    using Fn = std::decay_t<F>;
    static_assert(std::is_invocable_v<Fn&, std::stop_token> || std::is_invocable_v<Fn&>,
                  "RtThread body must be callable as f(std::stop_token) or f()");
    thread_ = std::thread([this, fn = Fn(std::forward<F>(body))]() mutable {
      start_on_new_thread();
      if constexpr (std::is_invocable_v<Fn&, std::stop_token>) {
        fn(stop_.get_token());
      } else {
        fn();
      }
    });
    wait_until_started();
  }

  ~RtThread() {
    request_stop();
    join();
  }

  RtThread(const RtThread&) = delete;
  RtThread& operator=(const RtThread&) = delete;
  RtThread(RtThread&&) = delete;
  RtThread& operator=(RtThread&&) = delete;

  // Any thread, including the body itself.
  void request_stop() noexcept { stop_.request_stop(); }
  [[nodiscard]] bool stop_requested() const noexcept { return stop_.stop_requested(); }
  // Not from the body's own thread.
  void join() {
    if (thread_.joinable()) thread_.join();
  }
  [[nodiscard]] bool joinable() const noexcept { return thread_.joinable(); }

  [[nodiscard]] const ThreadSpec& spec() const noexcept { return spec_; }
  // What apply_thread_spec achieved on the new thread.
  [[nodiscard]] const ThreadApplyStatus& status() const noexcept { return status_; }

 private:
  void start_on_new_thread() noexcept;  // apply spec, pre-fault stack, signal the constructor
  void wait_until_started() noexcept;

  ThreadSpec spec_;
  ThreadApplyStatus status_;
  std::atomic<bool> started_{false};
  std::stop_source stop_;
  std::thread thread_;
};

}  // namespace vigs::rt
