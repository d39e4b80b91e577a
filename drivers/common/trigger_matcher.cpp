#include "drivers/common/trigger_matcher.hpp"

#include <stdexcept>

namespace vigs::drivers {

TriggerMatcher::TriggerMatcher(rt::SpscRing<TriggerEdge>& edges,
                               const TriggerMatchSettings& settings)
    : edges_(edges), settings_(settings) {
  if (settings.tolerance_ns <= 0) {
    throw std::invalid_argument("TriggerMatcher: tolerance_ns must be > 0");
  }
}

void TriggerMatcher::erase(std::size_t i) noexcept {
  for (std::size_t k = i + 1; k < size_; ++k) window_[k - 1] = window_[k];
  --size_;
}

void TriggerMatcher::pull() noexcept {
  TriggerEdge e;
  while (edges_.try_pop(e)) {
    if (size_ == kWindow) {
      erase(0);
      edges_without_frame_.add();
    }
    window_[size_++] = e.t_ns;
  }
}

std::optional<std::int64_t> TriggerMatcher::match(std::int64_t t_frame_ns) noexcept {
  pull();
  const std::int64_t target = t_frame_ns - settings_.offset_ns;
  // Edges too old for this frame are too old for every later one.
  while (size_ > 0 && window_[0] < target - settings_.tolerance_ns) {
    erase(0);
    edges_without_frame_.add();
  }
  std::size_t best = size_;
  std::int64_t best_err = settings_.tolerance_ns + 1;
  for (std::size_t i = 0; i < size_; ++i) {
    const std::int64_t err = window_[i] > target ? window_[i] - target : target - window_[i];
    if (err < best_err) {
      best_err = err;
      best = i;
    }
  }
  if (best == size_) {
    frames_without_edge_.add();
    return std::nullopt;
  }
  const std::int64_t t_edge = window_[best];
  // Older edges than the matched one can match no later frame either.
  for (std::size_t i = 0; i < best; ++i) edges_without_frame_.add();
  for (std::size_t i = 0; i <= best; ++i) erase(0);
  matched_.add();
  return t_edge;
}

void TriggerMatcher::finish() noexcept {
  pull();
  edges_without_frame_.add(size_);
  size_ = 0;
}

TriggerMatchCounters TriggerMatcher::counters() const noexcept {
  return {.matched = matched_.get(),
          .frames_without_edge = frames_without_edge_.get(),
          .edges_without_frame = edges_without_frame_.get()};
}

io::Json to_json_value(const TriggerMatchCounters& c) {
  return {{"matched", c.matched},
          {"frames_without_edge", c.frames_without_edge},
          {"edges_without_frame", c.edges_without_frame}};
}

}  // namespace vigs::drivers
