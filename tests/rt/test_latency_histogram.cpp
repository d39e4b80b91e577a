#include "rt/latency_histogram.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>

#include "rt/clock.hpp"

namespace vigs::rt {
namespace {

TEST(LatencyHistogram, BucketsCoverEveryValueWithBoundedWidth) {
  std::size_t previous = 0;
  for (std::int64_t v = 0; v < (std::int64_t{1} << kHistogramMaxExponent);
       v = v < 4096 ? v + 1 : v + v / 97) {
    const std::size_t b = histogram_bucket(v);
    ASSERT_LT(b, kHistogramBuckets - 1) << v;
    ASSERT_LE(histogram_bucket_lower(b), v) << v;
    ASSERT_GE(histogram_bucket_upper(b), v) << v;
    ASSERT_GE(b, previous) << "bucket index must not decrease with the value";
    const std::int64_t width = histogram_bucket_upper(b) - histogram_bucket_lower(b) + 1;
    ASSERT_LE(width * 16, std::max<std::int64_t>(histogram_bucket_lower(b), 16)) << v;
    previous = b;
  }
  EXPECT_EQ(histogram_bucket(std::int64_t{1} << kHistogramMaxExponent), kHistogramBuckets - 1);
  EXPECT_EQ(histogram_bucket(-5), 0u);
}

TEST(LatencyHistogram, EmptyHistogramReportsZeros) {
  LatencyHistogram h;
  EXPECT_EQ(h.count(), 0u);
  EXPECT_EQ(h.p50(), 0);
  EXPECT_EQ(h.p99(), 0);
  EXPECT_EQ(h.max(), 0);
  EXPECT_EQ(h.min(), 0);
  EXPECT_EQ(h.mean(), 0.0);
  EXPECT_EQ(h.report("x"), "x: n=0");
}

// 1, 2, ..., 1000 us, once each, shuffled order.
TEST(LatencyHistogram, PercentilesOfKnownData) {
  auto h = std::make_unique<LatencyHistogram>();
  for (std::int64_t i = 0; i < 1000; ++i) h->record(us_to_ns((i * 617) % 1000 + 1));
  EXPECT_EQ(h->count(), 1000u);
  EXPECT_EQ(h->min(), us_to_ns(1));
  EXPECT_EQ(h->max(), us_to_ns(1000));
  EXPECT_DOUBLE_EQ(h->mean(), 500.5e3);
  // Exact answers are 500 us and 990 us; the histogram may round up by one bucket (6.25 %).
  EXPECT_GE(h->p50(), us_to_ns(500));
  EXPECT_LE(h->p50(), us_to_ns(500) * 1.0625);
  EXPECT_GE(h->p99(), us_to_ns(990));
  EXPECT_LE(h->p99(), us_to_ns(990) * 1.0625);
  EXPECT_GE(h->percentile(0.9), us_to_ns(900));
  EXPECT_LE(h->percentile(0.9), us_to_ns(900) * 1.0625);
  EXPECT_EQ(h->percentile(0.0), us_to_ns(1));
  EXPECT_EQ(h->percentile(1.0), us_to_ns(1000));
  EXPECT_LE(h->percentile(0.999), us_to_ns(1000));

  const HistogramSnapshot s = h->snapshot();
  EXPECT_EQ(s.count, 1000u);
  EXPECT_EQ(s.p99(), h->p99());
  const std::string r = h->report("cycle");
  EXPECT_NE(r.find("cycle: n=1000"), std::string::npos) << r;
  EXPECT_NE(r.find("p99="), std::string::npos) << r;
  EXPECT_NE(r.find("max=1.00ms"), std::string::npos) << r;

  h->reset();
  EXPECT_EQ(h->count(), 0u);
  EXPECT_EQ(h->p50(), 0);
}

TEST(LatencyHistogram, SkewedDataAndOverflow) {
  auto h = std::make_unique<LatencyHistogram>();
  for (int i = 0; i < 990; ++i) h->record(us_to_ns(10));
  for (int i = 0; i < 10; ++i) h->record(s_to_ns(std::int64_t{60}));  // beyond the top bucket
  EXPECT_LE(h->p50(), us_to_ns(10) * 1.0625);
  EXPECT_LE(h->p99(), us_to_ns(10) * 1.0625);
  EXPECT_EQ(h->percentile(0.995), s_to_ns(std::int64_t{60}));  // overflow reports the exact max
  EXPECT_EQ(h->max(), s_to_ns(std::int64_t{60}));
  h->record(-3);  // clamped to 0
  EXPECT_EQ(h->min(), 0);
}

TEST(LatencyHistogram, ReaderThreadWhileWriterRecords) {
  auto h = std::make_unique<LatencyHistogram>();
  std::atomic<bool> done{false};
  std::uint64_t last_count = 0;
  bool count_went_back = false;
  std::thread reader([&] {
    while (!done.load(std::memory_order_acquire)) {
      const HistogramSnapshot s = h->snapshot();
      count_went_back |= s.count < last_count;
      last_count = s.count;
      (void)s.p99();
    }
  });
  for (int i = 0; i < 20000; ++i) h->record(i);
  done.store(true, std::memory_order_release);
  reader.join();
  EXPECT_FALSE(count_went_back);
  EXPECT_EQ(h->count(), 20000u);
}

TEST(LatencyHistogram, FormatsDurations) {
  EXPECT_EQ(format_duration_ns(800), "800ns");
  EXPECT_EQ(format_duration_ns(12'345), "12.3us");
  EXPECT_EQ(format_duration_ns(4'560'000), "4.56ms");
  EXPECT_EQ(format_duration_ns(1'200'000'000), "1.20s");
}

}  // namespace
}  // namespace vigs::rt
