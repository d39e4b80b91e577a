#include "pipeline/keyframe_handoff.hpp"

#include <stdexcept>

namespace vigs::pipeline {

KeyframeHandoff::KeyframeHandoff(std::size_t slots, std::size_t points)
    : slots_(slots), free_(slots), full_(2 * slots) {
  for (std::size_t i = 0; i < slots; ++i) {
    tracking::Keyframe& kf = slots_[i].keyframe;
    kf.cloud_c.reserve(points);
    kf.moving.reserve(points);
    if (!free_.try_push(static_cast<std::uint32_t>(i)))
      throw std::logic_error("KeyframeHandoff: free list smaller than its slots");
  }
}

KeyframeSlot* KeyframeHandoff::acquire() noexcept {
  std::uint32_t i = 0;
  return free_.try_pop(i) ? &slots_[i] : nullptr;
}

void KeyframeHandoff::publish(KeyframeSlot* slot) noexcept {
  const auto i = static_cast<std::uint32_t>(slot - slots_.data());
  (void)full_.try_push(i);  // holds 2 * slots: every slot and the end marker always fit
}

void KeyframeHandoff::give_back(std::uint32_t index) noexcept {
  (void)free_.try_push(index);  // holds every slot
}

}  // namespace vigs::pipeline
