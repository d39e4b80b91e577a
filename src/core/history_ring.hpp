#pragma once
// A bounded first-in-first-out buffer for one thread: the newest samples of a stream, the oldest
// falling off when it is full. The storage is allocated once, at construction, so pushing and
// popping never allocate (the real-time rule for the tracker thread); std::deque allocates per
// block as it grows, and Boost's circular_buffer would add Boost for these thirty lines. For
// handing samples between threads use rt/spsc_ring.hpp instead.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace vigs {

template <class T>
class HistoryRing {
 public:
  /// Holds up to max(1, capacity) elements.
  explicit HistoryRing(std::size_t capacity) : slots_(std::max<std::size_t>(1, capacity)) {}

  [[nodiscard]] std::size_t size() const { return count_; }
  [[nodiscard]] std::size_t capacity() const { return slots_.size(); }
  [[nodiscard]] bool empty() const { return count_ == 0; }
  [[nodiscard]] bool full() const { return count_ == slots_.size(); }

  /// The i-th oldest element, 0 <= i < size().
  [[nodiscard]] const T& operator[](std::size_t i) const {
    return slots_[(head_ + i) % slots_.size()];
  }
  [[nodiscard]] const T& front() const { return (*this)[0]; }

  /// Appends x; when full, the oldest element is dropped first. Returns whether one was.
  bool push_back(const T& x) {
    const bool dropped = full();
    if (dropped) pop_front();
    slots_[(head_ + count_) % slots_.size()] = x;
    ++count_;
    return dropped;
  }

  /// Drops the oldest element; the ring must not be empty.
  void pop_front() {
    head_ = (head_ + 1) % slots_.size();
    --count_;
  }

 private:
  std::vector<T> slots_;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
};

}  // namespace vigs
