#include "drivers/openni2/pinned_stack_thread.hpp"

#include <sys/mman.h>

#include <mutex>
#include <system_error>
#include <vector>

namespace vigs::drivers {
namespace {

// Process-wide free list of thread stacks; they are never unmapped (see the header).
std::mutex g_stacks_mutex;
std::vector<void*>& free_stacks() {
  static auto* stacks = new std::vector<void*>();  // never destroyed: outlives every thread
  return *stacks;
}

void* take_stack() {
  {
    const std::lock_guard lock(g_stacks_mutex);
    if (!free_stacks().empty()) {
      void* s = free_stacks().back();
      free_stacks().pop_back();
      return s;
    }
  }
  void* s = ::mmap(nullptr, PinnedStackThread::kStackBytes, PROT_READ | PROT_WRITE,
                   MAP_PRIVATE | MAP_ANONYMOUS | MAP_STACK, -1, 0);
  if (s == MAP_FAILED) throw std::system_error(errno, std::generic_category(), "mmap thread stack");
  return s;
}

void give_back_stack(void* s) {
  const std::lock_guard lock(g_stacks_mutex);
  free_stacks().push_back(s);
}

[[gnu::noinline]] void prefault_stack() noexcept {
  volatile unsigned char buf[PinnedStackThread::kStackPrefaultBytes];
  for (std::size_t i = 0; i < sizeof buf; i += 4096) buf[i] = 0;
}

}  // namespace

PinnedStackThread::PinnedStackThread(const rt::ThreadSpec& spec,
                                     std::function<void(std::stop_token)> body)
    : spec_(spec), body_(std::move(body)), stack_(take_stack()) {
  pthread_attr_t attr;
  ::pthread_attr_init(&attr);
  ::pthread_attr_setstack(&attr, stack_, kStackBytes);
  const int rc = ::pthread_create(&thread_, &attr, &PinnedStackThread::entry, this);
  ::pthread_attr_destroy(&attr);
  if (rc != 0) {
    give_back_stack(stack_);
    throw std::system_error(rc, std::generic_category(), "pthread_create");
  }
  joinable_ = true;
  // Start-up only: a futex wait until the new thread has applied its spec.
  while (!started_.load(std::memory_order_acquire)) started_.wait(false, std::memory_order_acquire);
}

PinnedStackThread::~PinnedStackThread() {
  request_stop();
  join();
}

void PinnedStackThread::join() noexcept {
  if (!joinable_) return;
  ::pthread_join(thread_, nullptr);
  joinable_ = false;
  give_back_stack(stack_);  // reused by a later thread, never unmapped
}

void* PinnedStackThread::entry(void* self) noexcept {
  auto* t = static_cast<PinnedStackThread*>(self);
  t->status_ = rt::apply_thread_spec(t->spec_);
  prefault_stack();
  t->started_.store(true, std::memory_order_release);
  t->started_.notify_one();
  t->body_(t->stop_.get_token());
  return nullptr;
}

}  // namespace vigs::drivers
