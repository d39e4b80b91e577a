// Full-ring policies as functions, so every call site states (and counts) what it drops.
// The per-stream policy table is at the top of rt/spsc_ring.hpp.
//
//  push_or_drop(ring, item, drops)           producer: drop the newest when full, count it; never
//                                            blocks. IMU samples, edge stamps.
//  push_or_drop(ring, item, drops, on_drop)  the same, then hands the rejected item to on_drop
//                                            (frame handles: give the slot back to the FramePool).
//  trim_oldest(ring, keep, drops, on_drop)   consumer: while more than `keep` elements are queued,
//                                            pops the oldest, passes it to on_drop (merge or
//                                            skip) and counts it. Keyframes at the mapper.
#pragma once

#include <cstddef>
#include <utility>

#include "rt/counters.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::rt {

// Producer side. Returns true when queued; false when the ring was full (drops incremented).
template <class T, class U, class DropCounter>
bool push_or_drop(SpscRing<T>& ring, U&& item,
                  DropCounter& drops) noexcept(noexcept(ring.try_push(std::forward<U>(item)))) {
  if (ring.try_push(std::forward<U>(item))) return true;
  drops.add(1);
  return false;
}

// Producer side. On a full ring `on_drop(item)` receives the item that was not queued. The item
// is passed as an lvalue so that it is not moved from before the push fails.
template <class T, class DropCounter, class OnDrop>
bool push_or_drop(SpscRing<T>& ring, T& item, DropCounter& drops, OnDrop&& on_drop) {
  if (ring.try_push(std::move(item))) return true;
  // try_push(T&&) constructs nothing when the ring is full, so `item` is intact here.
  drops.add(1);
  std::forward<OnDrop>(on_drop)(item);
  return false;
}

// Consumer side. Pops the oldest elements until at most `keep` remain, handing each to
// `on_drop(T&)` before it is destroyed. Returns how many were dropped (also added to drops).
template <class T, class DropCounter, class OnDrop>
std::size_t trim_oldest(SpscRing<T>& ring, std::size_t keep, DropCounter& drops, OnDrop&& on_drop) {
  std::size_t dropped = 0;
  while (ring.size() > keep) {
    T* oldest = ring.front();
    if (oldest == nullptr) break;
    on_drop(*oldest);
    ring.pop();
    ++dropped;
  }
  if (dropped != 0) drops.add(dropped);
  return dropped;
}

template <class T, class DropCounter>
std::size_t trim_oldest(SpscRing<T>& ring, std::size_t keep, DropCounter& drops) {
  return trim_oldest(ring, keep, drops, [](T&) noexcept {});
}

}  // namespace vigs::rt
