// ImuStamper / ClockMapper: device counter to host CLOCK_MONOTONIC under simulated USB delivery
// (batches, random positive latency, scheduling spikes) and clock drift; counter wraparound,
// gaps, non-advancing counters and device restarts.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "drivers/serial_imu/imu_stamper.hpp"

namespace vigs::drivers {
namespace {

constexpr DeviceClockSpec kXsensClock{10'000.0, 32};

struct Collect final : StampedSampleSink {
  std::vector<ImuSample> out;
  void on_stamped(const ImuSample& s) noexcept override { out.push_back(s); }
};

DeviceImuSample sample(std::uint32_t ticks, double marker = 0.0) {
  DeviceImuSample s;
  s.device_ticks = ticks;
  s.accel_mps2[0] = marker;
  return s;
}

struct SimResult {
  double max_abs_err_ns = 0.0;  // mapped - (true time + minimum latency), after settle_s
  double rms_err_ns = 0.0;
  double naive_rms_err_ns = 0.0;  // receive time used as the stamp
  std::size_t count = 0;
  bool strictly_monotonic = true;
  StamperCounters const* counters = nullptr;
};

// 200 Hz device at `drift_ppm` against the host; the USB adapter delivers in batches every
// 1..8 ms (random), transport latency >= kMinLatency, reader wake-up jitter exponential with
// 5% spikes of 2..10 ms.
SimResult simulate(double drift_ppm, double drift_end_ppm, std::uint32_t stf0, double seconds,
                   double settle_s, std::uint32_t seed) {
  constexpr double kMinLatencyNs = 400'000.0;
  const std::int64_t t0 = 1'000'000'000'000;  // host ns
  const auto n = static_cast<std::size_t>(seconds * 200.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> batch_gap(1e6, 8e6);
  std::exponential_distribution<double> wake(1.0 / 150e3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> spike(2e6, 10e6);

  Collect sink;
  ImuStamper st(kXsensClock, ImuStamperSettings{}, sink);
  std::vector<double> true_ns(n);
  true_ns[0] = static_cast<double>(t0);
  for (std::size_t i = 1; i < n; ++i) {  // device period 5 ms, in host ns, drift varying linearly
    const double ppm = drift_ppm + (drift_end_ppm - drift_ppm) * static_cast<double>(i) / n;
    true_ns[i] = true_ns[i - 1] + 5e6 * (1.0 + ppm * 1e-6);
  }

  SimResult r;
  double naive_sq = 0.0;
  std::size_t next = 0;
  double delivery = static_cast<double>(t0);
  while (next < n) {
    delivery += batch_gap(rng);
    std::size_t end = next;
    while (end < n && true_ns[end] + kMinLatencyNs <= delivery) ++end;
    if (end == next) continue;
    double host = delivery + wake(rng);
    if (unit(rng) < 0.05) host += spike(rng);
    st.begin_read(static_cast<std::int64_t>(host));
    for (std::size_t i = next; i < end; ++i) {
      st.on_sample(sample(stf0 + static_cast<std::uint32_t>(50 * i), static_cast<double>(i)));
      if (true_ns[i] >= true_ns[0] + settle_s * 1e9) {
        const double e = host - (true_ns[i] + kMinLatencyNs);
        naive_sq += e * e;
      }
    }
    st.end_read();
    next = end;
  }
  st.release();

  double sq = 0.0;
  std::size_t counted = 0;
  for (std::size_t k = 0; k < sink.out.size(); ++k) {
    const ImuSample& s = sink.out[k];
    const auto i = static_cast<std::size_t>(s.accel_mps2[0]);
    if (k > 0 && s.t_ns <= sink.out[k - 1].t_ns) r.strictly_monotonic = false;
    if (true_ns[i] < true_ns[0] + settle_s * 1e9) continue;
    const double e = static_cast<double>(s.t_ns) - (true_ns[i] + kMinLatencyNs);
    r.max_abs_err_ns = std::max(r.max_abs_err_ns, std::abs(e));
    sq += e * e;
    ++counted;
  }
  r.count = sink.out.size();
  r.rms_err_ns = std::sqrt(sq / static_cast<double>(counted));
  r.naive_rms_err_ns = std::sqrt(naive_sq / static_cast<double>(counted));
  EXPECT_EQ(st.counters().non_monotonic_stamp.get(), 0u);
  EXPECT_EQ(st.counters().sample_counter_gap.get(), 0u);
  return r;
}

class DriftSim : public ::testing::TestWithParam<double> {};

constexpr std::uint32_t kSeed = 3;

TEST_P(DriftSim, StampsTrackTrueSampleTimeAndAreStrictlyMonotonic) {
  // Starts 5 s before the 32-bit SampleTimeFine wraps.
  const SimResult r = simulate(GetParam(), GetParam(), 0xFFFFFFFFu - 50'000u, 60.0, 0.0, kSeed);
  EXPECT_EQ(r.count, 12'000u);  // every sample, none dropped or invented
  EXPECT_TRUE(r.strictly_monotonic);
  EXPECT_LT(r.max_abs_err_ns, 600e3) << "from the first sample";
  const SimResult settled =
      simulate(GetParam(), GetParam(), 0xFFFFFFFFu - 50'000u, 60.0, 3.0, kSeed);
  std::printf(
      "drift %+.0f ppm: error after 3 s max %.1f us rms %.1f us (from start max %.1f us); "
      "receive-time stamps rms %.1f us\n",
      GetParam(), settled.max_abs_err_ns / 1e3, settled.rms_err_ns / 1e3, r.max_abs_err_ns / 1e3,
      settled.naive_rms_err_ns / 1e3);
  EXPECT_LT(settled.max_abs_err_ns, 300e3);
  EXPECT_LT(settled.rms_err_ns, 120e3);
  // The receive time itself is off by milliseconds: the fit is what removes it.
  EXPECT_GT(settled.naive_rms_err_ns, 10.0 * settled.rms_err_ns);
}

INSTANTIATE_TEST_SUITE_P(Ppm, DriftSim, ::testing::Values(-100.0, 0.0, 100.0));

TEST(ClockMapper, FollowsADriftThatChangesWithTemperature) {
  // -20 ppm to +20 ppm over two minutes (far faster than a crystal warming up): the fit keeps
  // up. Its limit: the least-squares drift lags a ramp by about 16 s times the ramp rate, and the
  // offset absorbs lags up to offset_creep_ppm (10 ppm), so ramps up to ~0.6 ppm/s are tracked.
  const SimResult r = simulate(-20.0, 20.0, 0u, 120.0, 3.0, 11);
  std::printf("drift ramp -20..+20 ppm: error after 3 s max %.1f us rms %.1f us\n",
              r.max_abs_err_ns / 1e3, r.rms_err_ns / 1e3);
  EXPECT_TRUE(r.strictly_monotonic);
  EXPECT_LT(r.max_abs_err_ns, 300e3);
  EXPECT_LT(r.rms_err_ns, 120e3);
}

TEST(ImuStamper, CountsGapsAndMissedSamples) {
  Collect sink;
  ImuStamperSettings s;
  s.warmup_samples = 0;
  ImuStamper st(kXsensClock, s, sink);
  st.begin_read(1'000'000'000);
  for (std::uint32_t t : {100u, 150u, 200u, 350u, 400u, 450u, 700u}) st.on_sample(sample(t));
  st.end_read();
  EXPECT_EQ(sink.out.size(), 7u);
  EXPECT_EQ(st.counters().sample_counter_gap.get(), 2u);
  EXPECT_EQ(st.counters().samples_missed.get(), 2u + 4u);
}

TEST(ImuStamper, WrapsAroundThe32BitCounter) {
  Collect sink;
  ImuStamperSettings s;
  s.warmup_samples = 0;
  ImuStamper st(kXsensClock, s, sink);
  st.begin_read(5'000'000'000);
  st.on_sample(sample(0xFFFFFFCEu));  // 2^32 - 50
  st.on_sample(sample(0u));
  st.on_sample(sample(50u));
  st.end_read();
  ASSERT_EQ(sink.out.size(), 3u);
  EXPECT_EQ(sink.out[1].t_ns - sink.out[0].t_ns, 5'000'000);
  EXPECT_EQ(sink.out[2].t_ns - sink.out[1].t_ns, 5'000'000);
  EXPECT_EQ(st.counters().non_monotonic_stamp.get(), 0u);
  EXPECT_EQ(st.counters().sample_counter_gap.get(), 0u);
}

TEST(ImuStamper, DropsNonAdvancingCountersAndRestartsOnADeviceReset) {
  Collect sink;
  ImuStamperSettings s;
  s.warmup_samples = 0;
  s.reset_after_backward = 4;
  ImuStamper st(kXsensClock, s, sink);
  std::int64_t host = 1'000'000'000;
  auto read = [&](std::uint32_t ticks) {
    host += 5'000'000;
    st.begin_read(host);
    st.on_sample(sample(ticks));
    st.end_read();
  };
  read(1000);
  read(1050);
  read(1050);  // repeated
  read(1020);  // backwards
  read(1100);
  EXPECT_EQ(sink.out.size(), 3u);
  EXPECT_EQ(st.counters().non_monotonic_stamp.get(), 2u);
  // Device restarts its counter: after 4 backward samples the fit starts over.
  for (std::uint32_t t : {0u, 50u, 100u, 150u, 200u, 250u}) read(t);
  EXPECT_EQ(st.counters().clock_resets.get(), 1u);
  EXPECT_EQ(st.counters().non_monotonic_stamp.get(), 2u + 3u);
  ASSERT_EQ(sink.out.size(), 3u + 3u);
  for (std::size_t k = 1; k < sink.out.size(); ++k)
    EXPECT_GT(sink.out[k].t_ns, sink.out[k - 1].t_ns);
}

TEST(ImuStamper, WarmUpHoldsThenReleasesEverySample) {
  Collect sink;
  ImuStamperSettings s;
  s.warmup_samples = 10;
  ImuStamper st(kXsensClock, s, sink);
  for (std::uint32_t i = 0; i < 9; ++i) {
    st.begin_read(2'000'000'000 + 5'000'000 * static_cast<std::int64_t>(i));
    st.on_sample(sample(50 * i));
    st.end_read();
  }
  EXPECT_TRUE(sink.out.empty());
  st.release();  // end of stream before warm-up completed
  EXPECT_EQ(sink.out.size(), 9u);
}

}  // namespace
}  // namespace vigs::drivers
