#include "rt/frame_pool.hpp"

#include <cassert>
#include <cstring>
#include <new>
#include <stdexcept>

namespace vigs::rt {
namespace {

constexpr std::size_t round_up(std::size_t n, std::size_t to) {
  return (n + to - 1) / to * to;
}

}  // namespace

FramePool::FramePool(const FramePoolSettings& settings) : settings_(settings) {
  const std::size_t pixels = std::size_t{settings.width} * settings.height;
  if (settings.slots == 0 || pixels == 0 || settings.colour_channels == 0 ||
      settings.slots >= kNil) {
    throw std::invalid_argument("FramePool needs slots > 0 and a non-empty image size");
  }
  const std::size_t colour_stride = round_up(pixels * settings.colour_channels, kCacheLineSize);
  const std::size_t depth_stride = round_up(pixels * sizeof(std::uint16_t), kCacheLineSize);
  colour_bytes_ = colour_stride * settings.slots;
  depth_bytes_ = depth_stride * settings.slots;
  colour_storage_ =
      static_cast<std::uint8_t*>(::operator new (colour_bytes_, std::align_val_t{kCacheLineSize}));
  depth_storage_ =
      static_cast<std::uint16_t*>(::operator new (depth_bytes_, std::align_val_t{kCacheLineSize}));
  // Touch every page now so that no real-time thread takes the first-touch page fault.
  std::memset(colour_storage_, 0, colour_bytes_);
  std::memset(static_cast<void*>(depth_storage_), 0, depth_bytes_);

  frames_ = std::make_unique<Frame[]>(settings.slots);
  refs_ = std::make_unique<std::atomic<std::uint32_t>[]>(settings.slots);
  next_free_ = std::make_unique<std::atomic<std::uint32_t>[]>(settings.slots);
  for (std::uint32_t i = 0; i < settings.slots; ++i) {
    frames_[i].colour = {colour_storage_ + i * colour_stride, pixels * settings.colour_channels};
    frames_[i].depth = {depth_storage_ + i * (depth_stride / sizeof(std::uint16_t)), pixels};
    refs_[i].store(0, std::memory_order_relaxed);
  }
  // Push in reverse so that the first acquire() returns slot 0.
  for (std::uint32_t i = settings.slots; i-- > 0;) push_free(i);
}

FramePool::~FramePool() {
  ::operator delete (colour_storage_, std::align_val_t{kCacheLineSize});
  ::operator delete (static_cast<void*>(depth_storage_), std::align_val_t{kCacheLineSize});
}

FrameHandle FramePool::acquire() noexcept {
  std::uint64_t head = free_head_.load(std::memory_order_acquire);
  for (;;) {
    const auto index = static_cast<std::uint32_t>(head);
    if (index == kNil) {
      exhausted_.add();
      return FrameHandle{};
    }
    // May read a stale link if another thread pops `index` meanwhile; the tag then makes the
    // compare-exchange fail and the loop retries with the fresh head.
    const std::uint32_t next = next_free_[index].load(std::memory_order_relaxed);
    const std::uint64_t new_head = pack(next, static_cast<std::uint32_t>(head >> 32) + 1);
    if (free_head_.compare_exchange_weak(head, new_head, std::memory_order_acq_rel,
                                         std::memory_order_acquire)) {
      free_count_.fetch_sub(1, std::memory_order_relaxed);
      refs_[index].store(1, std::memory_order_relaxed);
      return FrameHandle{index};
    }
  }
}

void FramePool::retain(FrameHandle h) noexcept {
  assert(h.valid() && h.index < settings_.slots);
  [[maybe_unused]] const std::uint32_t before =
      refs_[h.index].fetch_add(1, std::memory_order_relaxed);
  assert(before > 0 && "retain() of a free FramePool slot");
}

void FramePool::release(FrameHandle h) noexcept {
  if (!h.valid()) return;
  assert(h.index < settings_.slots);
  const std::uint32_t before = refs_[h.index].fetch_sub(1, std::memory_order_acq_rel);
  assert(before > 0 && "release() of a free FramePool slot (double release)");
  if (before == 1) push_free(h.index);
}

void FramePool::push_free(std::uint32_t index) noexcept {
  // Count before publishing (and acquire() uncounts after taking), so available() never dips
  // below zero.
  free_count_.fetch_add(1, std::memory_order_relaxed);
  std::uint64_t head = free_head_.load(std::memory_order_relaxed);
  std::uint64_t new_head;
  do {
    next_free_[index].store(static_cast<std::uint32_t>(head), std::memory_order_relaxed);
    new_head = pack(index, static_cast<std::uint32_t>(head >> 32) + 1);
  } while (!free_head_.compare_exchange_weak(head, new_head, std::memory_order_release,
                                             std::memory_order_relaxed));
}

}  // namespace vigs::rt
