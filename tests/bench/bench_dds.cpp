// bench_dds: publish-to-receive latency of VIGS poses between two processes over Fast DDS,
// through shared memory and through UDP loopback, beside a plain UDP socket round trip on
// 127.0.0.1 measured in the same run. Poses at 20 Hz (the camera rate), 200 per case.
//  - DDS: this process runs the real PosePublisher (PoseSample -> pose, pose quality, odom, tf)
//    and stamps each sample with CLOCK_MONOTONIC just before PosePublisher::run_cycle; a second
//    process (this binary, --child-dds) subscribes with our Subscriber and takes
//    monotonic_ns() - stamp when the pose arrives. Both sides share the machine's monotonic clock,
//    so this is one-way. Iteration time: the publisher's cycle (fill + 4 writes: pose, pose
//    quality, odom, tf).
//  - UDP: a datagram of the pose message's CDR size carries its send time; the second process
//    (--child-udp) takes the one-way latency and echoes it back; iteration time = round trip.
// Counters: p50_us, p99_us, max_us of the one-way latency (and rtt_* for UDP), received.
// Loopback only (built-in config), domain 170/171, /dev/shm cleaned.
#include <arpa/inet.h>
#include <benchmark/benchmark.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "dds/dds_config.hpp"
#include "dds/pose_publisher.hpp"
#include "dds/ros_time.hpp"
#include "dds/subscriber.hpp"
#include "rt/clock.hpp"
#include "tests/dds/pose_pattern.hpp"
#include "tests/dds/process.hpp"
#include "tests/dds/shm_janitor.hpp"

using namespace vigs;

namespace {

constexpr int kSamples = 200;
constexpr auto kPeriod = std::chrono::milliseconds(50);  // 20 Hz
constexpr std::size_t kDatagramBytes = 380;  // ~ CDR size of PoseWithCovarianceStamped, frame "map"
std::string g_self;

void print_latencies(const std::vector<std::int64_t>& v) {
  for (std::int64_t x : v) std::printf("%lld\n", static_cast<long long>(x));
  std::fflush(stdout);
}

int child_dds(int domain, bool shm) {
  dds::DdsConfig cfg = dds::default_dds_config(domain);
  cfg.shared_memory = shm;
  std::mutex m;
  std::vector<std::int64_t> lat;
  lat.reserve(kSamples);
  {
    dds::Subscriber sub(cfg, "bench_dds_sink");
    sub.subscribe<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_>(
        cfg.topics.pose, [&](const auto& msg) {
          const std::int64_t now = rt::monotonic_ns();
          std::lock_guard l(m);
          lat.push_back(now -
                        dds::to_ns(msg.header().stamp().sec(), msg.header().stamp().nanosec()));
        });
    sub.subscribe<nav_msgs::msg::dds_::Odometry_>(cfg.topics.odom, [](const auto&) {});
    sub.subscribe<tf2_msgs::msg::dds_::TFMessage_>(cfg.topics.tf, [](const auto&) {});
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    for (;;) {
      {
        std::lock_guard l(m);
        if (static_cast<int>(lat.size()) >= kSamples) break;
      }
      if (std::chrono::steady_clock::now() > deadline) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  print_latencies(lat);
  return 0;
}

int child_udp(int port) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) return 1;
  timeval tv{10, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  std::vector<std::int64_t> lat;
  char buf[2048];
  while (static_cast<int>(lat.size()) < kSamples) {
    sockaddr_in from{};
    socklen_t len = sizeof from;
    const ssize_t n = recvfrom(fd, buf, sizeof buf, 0, reinterpret_cast<sockaddr*>(&from), &len);
    if (n < static_cast<ssize_t>(sizeof(std::int64_t))) break;
    std::int64_t sent = 0;
    std::memcpy(&sent, buf, sizeof sent);
    lat.push_back(rt::monotonic_ns() - sent);
    sendto(fd, buf, static_cast<std::size_t>(n), 0, reinterpret_cast<sockaddr*>(&from), len);
  }
  close(fd);
  print_latencies(lat);
  return 0;
}

std::vector<std::int64_t> parse(const std::string& text) {
  std::vector<std::int64_t> v;
  std::istringstream in(text);
  for (long long x; in >> x;) v.push_back(x);
  return v;
}

void report(benchmark::State& state, std::vector<std::int64_t> v, const char* prefix) {
  std::sort(v.begin(), v.end());
  auto pct = [&](double p) {
    if (v.empty()) return 0.0;
    return static_cast<double>(v[std::min(v.size() - 1, static_cast<std::size_t>(p * v.size()))]) /
           1e3;
  };
  const std::string p(prefix);
  state.counters[p + "p50_us"] = pct(0.50);
  state.counters[p + "p99_us"] = pct(0.99);
  state.counters[p + "max_us"] = v.empty() ? 0.0 : static_cast<double>(v.back()) / 1e3;
  if (p.empty()) state.counters["received"] = static_cast<double>(v.size());
}

void BM_DdsPublishToReceive(benchmark::State& state) {
  const bool shm = state.range(0) != 0;
  const int domain = shm ? 170 : 171;
  dds::test::ShmJanitor janitor;
  dds::DdsConfig cfg = dds::default_dds_config(domain);
  cfg.shared_memory = shm;
  rt::SpscRing<PoseSample> ring(64);
  std::vector<std::int64_t> lat;
  {
    dds::PosePublisher pub(cfg, ring);
    dds::test::ChildProcess child({g_self, "--child-dds", std::to_string(domain), shm ? "1" : "0"});
    if (!pub.wait_for_subscribers(1, std::chrono::seconds(30))) {
      state.SkipWithError("the subscriber process did not match");
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    std::uint64_t i = 0;
    auto next = std::chrono::steady_clock::now();
    for (auto _ : state) {
      PoseSample s = dds::test::pattern_sample(i++);
      s.t_ns = rt::monotonic_ns();
      const auto t0 = std::chrono::steady_clock::now();
      (void)ring.try_push(s);
      pub.run_cycle(s.t_ns);
      state.SetIterationTime(
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      next += kPeriod;
      std::this_thread::sleep_until(next);
    }
    child.wait(std::chrono::seconds(70));
    lat = parse(child.output());
  }
  report(state, lat, "");
}
BENCHMARK(BM_DdsPublishToReceive)
    ->ArgName("shm")
    ->Arg(1)
    ->Arg(0)
    ->Iterations(kSamples)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

void BM_PlainUdpRoundTrip(benchmark::State& state) {
  const int port = 47000 + static_cast<int>(getpid() % 1000);
  dds::test::ChildProcess child({g_self, "--child-udp", std::to_string(port)});
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval tv{2, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  std::vector<char> buf(kDatagramBytes, 0);
  std::vector<std::int64_t> rtt;
  auto next = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const std::int64_t t0 = rt::monotonic_ns();
    std::memcpy(buf.data(), &t0, sizeof t0);
    sendto(fd, buf.data(), buf.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
    char in[2048];
    const ssize_t n = recv(fd, in, sizeof in, 0);
    const std::int64_t t1 = rt::monotonic_ns();
    if (n > 0) rtt.push_back(t1 - t0);
    state.SetIterationTime(static_cast<double>(t1 - t0) / 1e9);
    next += kPeriod;
    std::this_thread::sleep_until(next);
  }
  close(fd);
  child.wait(std::chrono::seconds(20));
  report(state, parse(child.output()), "");
  report(state, rtt, "rtt_");
}
BENCHMARK(BM_PlainUdpRoundTrip)
    ->Iterations(kSamples)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  g_self = "/proc/self/exe";
  char path[4096];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
  if (n > 0) g_self.assign(path, static_cast<std::size_t>(n));
  if (argc >= 4 && std::strcmp(argv[1], "--child-dds") == 0) {
    return child_dds(std::atoi(argv[2]), std::atoi(argv[3]) != 0);
  }
  if (argc >= 3 && std::strcmp(argv[1], "--child-udp") == 0) return child_udp(std::atoi(argv[2]));
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
