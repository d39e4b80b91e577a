#include "rt/latency_histogram.hpp"

#include <bit>
#include <cmath>
#include <cstdio>

namespace vigs::rt {
namespace {

constexpr std::size_t kSub = std::size_t{1} << kHistogramSubBucketBits;
constexpr std::size_t kOverflowBucket = kHistogramBuckets - 1;

}  // namespace

std::size_t histogram_bucket(std::int64_t ns) noexcept {
  if (ns < 0) ns = 0;
  const auto v = static_cast<std::uint64_t>(ns);
  if (v < kSub) return static_cast<std::size_t>(v);
  const int msb = 63 - std::countl_zero(v);
  if (msb >= kHistogramMaxExponent) return kOverflowBucket;
  const int shift = msb - kHistogramSubBucketBits;
  return static_cast<std::size_t>(shift + 1) * kSub +
         static_cast<std::size_t>((v >> shift) & (kSub - 1));
}

std::int64_t histogram_bucket_lower(std::size_t bucket) noexcept {
  if (bucket < kSub) return static_cast<std::int64_t>(bucket);
  if (bucket >= kOverflowBucket) return std::int64_t{1} << kHistogramMaxExponent;
  const std::size_t shift = bucket / kSub - 1;
  return static_cast<std::int64_t>((kSub + bucket % kSub) << shift);
}

std::int64_t histogram_bucket_upper(std::size_t bucket) noexcept {
  if (bucket < kSub) return static_cast<std::int64_t>(bucket);
  if (bucket >= kOverflowBucket) return std::numeric_limits<std::int64_t>::max();
  const std::size_t shift = bucket / kSub - 1;
  return histogram_bucket_lower(bucket) + (std::int64_t{1} << shift) - 1;
}

std::int64_t HistogramSnapshot::percentile(double q) const noexcept {
  if (count == 0) return 0;
  if (!(q > 0.0)) return min_ns;  // also catches NaN
  if (q >= 1.0) return max_ns;
  auto rank = static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count)));
  if (rank < 1) rank = 1;
  if (rank > count) rank = count;
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < kHistogramBuckets; ++b) {
    seen += buckets[b];
    if (seen >= rank) {
      std::int64_t v = histogram_bucket_upper(b);
      if (v > max_ns) v = max_ns;
      if (v < min_ns) v = min_ns;
      return v;
    }
  }
  return max_ns;
}

double HistogramSnapshot::mean_ns() const noexcept {
  return count == 0 ? 0.0 : static_cast<double>(sum_ns) / static_cast<double>(count);
}

std::string HistogramSnapshot::report(std::string_view name) const {
  std::string out(name);
  out += ": n=" + std::to_string(count);
  if (count == 0) return out;
  out += " mean=" + format_duration_ns(std::llround(mean_ns()));
  out += " min=" + format_duration_ns(min_ns);
  out += " p50=" + format_duration_ns(percentile(0.50));
  out += " p90=" + format_duration_ns(percentile(0.90));
  out += " p99=" + format_duration_ns(percentile(0.99));
  out += " p99.9=" + format_duration_ns(percentile(0.999));
  out += " max=" + format_duration_ns(max_ns);
  return out;
}

void LatencyHistogram::reset() noexcept {
  for (auto& b : buckets_) b.store(0, std::memory_order_relaxed);
  count_.store(0, std::memory_order_relaxed);
  sum_ns_.store(0, std::memory_order_relaxed);
  max_ns_.store(0, std::memory_order_relaxed);
  min_ns_.store(std::numeric_limits<std::int64_t>::max(), std::memory_order_relaxed);
}

std::int64_t LatencyHistogram::min() const noexcept {
  const std::int64_t m = min_ns_.load(std::memory_order_relaxed);
  return m == std::numeric_limits<std::int64_t>::max() ? 0 : m;
}

double LatencyHistogram::mean() const noexcept {
  const std::uint64_t n = count();
  return n == 0 ? 0.0
                : static_cast<double>(sum_ns_.load(std::memory_order_relaxed)) /
                      static_cast<double>(n);
}

HistogramSnapshot LatencyHistogram::snapshot() const noexcept {
  HistogramSnapshot s;
  for (std::size_t b = 0; b < kHistogramBuckets; ++b) {
    s.buckets[b] = buckets_[b].load(std::memory_order_relaxed);
    s.count += s.buckets[b];
  }
  s.sum_ns = sum_ns_.load(std::memory_order_relaxed);
  s.max_ns = max_ns_.load(std::memory_order_relaxed);
  s.min_ns = min();
  return s;
}

std::string format_duration_ns(std::int64_t ns) {
  char buf[32];
  const double a = std::fabs(static_cast<double>(ns));
  if (a < 1e3) {
    std::snprintf(buf, sizeof buf, "%lldns", static_cast<long long>(ns));
  } else if (a < 1e6) {
    std::snprintf(buf, sizeof buf, "%.1fus", static_cast<double>(ns) / 1e3);
  } else if (a < 1e9) {
    std::snprintf(buf, sizeof buf, "%.2fms", static_cast<double>(ns) / 1e6);
  } else {
    std::snprintf(buf, sizeof buf, "%.2fs", static_cast<double>(ns) / 1e9);
  }
  return buf;
}

}  // namespace vigs::rt
