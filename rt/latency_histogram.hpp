// LatencyHistogram: fixed-bucket, log-linear histogram of durations in nanoseconds.
//
// Buckets: exact below 16 ns, then 16 linear sub-buckets per power of two up to 2^34 ns (~17 s),
// so every bucket is at most 6.25 % of its value wide (1 us to 10 s, and the small values too).
// Larger values land in one overflow bucket (their exact maximum is still kept). 497 buckets,
// about 4 KiB, allocated inside the object: nothing allocates after construction.
//
// Threads: record() is for ONE writer thread (the loop that owns the histogram); it is O(1),
// wait-free and uses relaxed loads/stores only (no locked instructions). Any thread may read
// (count(), percentile(), snapshot(), report()) at any time without a data race; a read taken
// while the writer is recording may be off by the samples in flight. report() allocates and
// formats: call it at exit or from a status thread, never on a real-time path.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>

namespace vigs::rt {

inline constexpr int kHistogramSubBucketBits = 4;  // 16 sub-buckets per octave
inline constexpr int kHistogramMaxExponent = 34;   // values < 2^34 ns get a regular bucket
inline constexpr std::size_t kHistogramBuckets =
    (kHistogramMaxExponent - kHistogramSubBucketBits + 1) * (1u << kHistogramSubBucketBits) + 1;

// Bucket arithmetic, exposed for tests and for readers of a snapshot.
[[nodiscard]] std::size_t histogram_bucket(std::int64_t ns) noexcept;
[[nodiscard]] std::int64_t histogram_bucket_lower(std::size_t bucket) noexcept;
[[nodiscard]] std::int64_t histogram_bucket_upper(std::size_t bucket) noexcept;

// A plain copy of a histogram, for statistics and reports off the real-time path.
struct HistogramSnapshot {
  std::array<std::uint64_t, kHistogramBuckets> buckets{};
  std::uint64_t count = 0;  // sum of buckets
  std::int64_t sum_ns = 0;
  std::int64_t min_ns = 0;  // 0 when empty
  std::int64_t max_ns = 0;  // 0 when empty

  // Value at quantile q in [0, 1]: the upper edge of the bucket holding the ceil(q * count)-th
  // smallest sample, clamped to [min, max]; so percentile(0) == min, percentile(1) == max, and
  // otherwise the result is at most one bucket width (6.25 %) above the exact sample. 0 if empty.
  [[nodiscard]] std::int64_t percentile(double q) const noexcept;
  [[nodiscard]] std::int64_t p50() const noexcept { return percentile(0.50); }
  [[nodiscard]] std::int64_t p99() const noexcept { return percentile(0.99); }
  [[nodiscard]] double mean_ns() const noexcept;
  // One line: "<name>: n=... mean=... p50=... p90=... p99=... p99.9=... max=..." with units.
  [[nodiscard]] std::string report(std::string_view name) const;
};

class LatencyHistogram {
 public:
  LatencyHistogram() = default;
  LatencyHistogram(const LatencyHistogram&) = delete;
  LatencyHistogram& operator=(const LatencyHistogram&) = delete;

  // Writer thread only. Negative durations are recorded as 0.
  void record(std::int64_t ns) noexcept {
    if (ns < 0) ns = 0;
    bump(buckets_[histogram_bucket(ns)], 1);
    sum_ns_.store(sum_ns_.load(std::memory_order_relaxed) + ns, std::memory_order_relaxed);
    if (ns > max_ns_.load(std::memory_order_relaxed)) max_ns_.store(ns, std::memory_order_relaxed);
    if (ns < min_ns_.load(std::memory_order_relaxed)) min_ns_.store(ns, std::memory_order_relaxed);
    bump(count_, 1);
  }

  // Writer thread only (or when no thread records).
  void reset() noexcept;

  // Any thread.
  [[nodiscard]] std::uint64_t count() const noexcept {
    return count_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::int64_t max() const noexcept {
    return max_ns_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::int64_t min() const noexcept;
  [[nodiscard]] double mean() const noexcept;
  [[nodiscard]] std::int64_t percentile(double q) const noexcept {
    return snapshot().percentile(q);
  }
  [[nodiscard]] std::int64_t p50() const noexcept { return percentile(0.50); }
  [[nodiscard]] std::int64_t p99() const noexcept { return percentile(0.99); }
  [[nodiscard]] HistogramSnapshot snapshot() const noexcept;
  [[nodiscard]] std::string report(std::string_view name) const { return snapshot().report(name); }

 private:
  static void bump(std::atomic<std::uint64_t>& a, std::uint64_t n) noexcept {
    a.store(a.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
  }

  std::array<std::atomic<std::uint64_t>, kHistogramBuckets> buckets_{};
  std::atomic<std::uint64_t> count_{0};
  std::atomic<std::int64_t> sum_ns_{0};
  std::atomic<std::int64_t> max_ns_{0};
  std::atomic<std::int64_t> min_ns_{std::numeric_limits<std::int64_t>::max()};
};

// "12.3us", "4.56ms", "800ns", "1.20s": a duration with a readable unit (for reports).
[[nodiscard]] std::string format_duration_ns(std::int64_t ns);

}  // namespace vigs::rt
