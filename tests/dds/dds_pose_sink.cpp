// dds_pose_sink: a subscribing process for the two-process DDS tests. Subscribes to the pose
// topic with our Subscriber on the built-in (loopback-only) configuration, prints "ready" once
// its reader exists, and exits after `--count` poses (or `--timeout-s`), printing one JSON line:
// {"poses":N,"in_order":B,"pattern":B} where pattern means every stamp and covariance matched
// tests/dds/pose_pattern.hpp. Exit 0 when all `--count` poses arrived in order, 3 otherwise.
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>

#include "dds/dds_config.hpp"
#include "dds/ros_time.hpp"
#include "dds/subscriber.hpp"
#include "pose_pattern.hpp"

using namespace vigs;

int main(int argc, char** argv) {
  int domain = 0, count = 100, timeout_s = 30;
  bool shm = true;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const int v = std::atoi(argv[i + 1]);
    if (k == "--domain")
      domain = v;
    else if (k == "--count")
      count = v;
    else if (k == "--timeout-s")
      timeout_s = v;
    else if (k == "--shm")
      shm = v != 0;
    else {
      std::fprintf(stderr, "dds_pose_sink: unknown option %s\n", k.c_str());
      return 64;
    }
  }
  try {
    dds::DdsConfig cfg = dds::default_dds_config(domain);
    cfg.shared_memory = shm;
    std::atomic<int> received{0};
    std::atomic<bool> in_order{true}, pattern{true};
    std::int64_t last = -1;
    dds::Subscriber sub(cfg, "dds_pose_sink");
    sub.subscribe<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_>(
        cfg.topics.pose, [&](const auto& m) {
          const std::int64_t t = dds::to_ns(m.header().stamp().sec(), m.header().stamp().nanosec());
          const std::int64_t i = dds::test::pattern_index(t);
          if (i < 0 || i <= last) in_order = false;
          if (i >= 0) {
            const PoseSample s = dds::test::pattern_sample(static_cast<std::uint64_t>(i));
            for (int k = 0; k < 36; ++k) {
              if (m.pose().covariance()[static_cast<std::size_t>(k)] != s.covariance[k]) {
                pattern = false;
              }
            }
            if (m.header().frame_id() != cfg.map_frame_id) pattern = false;
          } else {
            pattern = false;
          }
          last = i;
          received.fetch_add(1);
        });
    std::printf("ready\n");
    std::fflush(stdout);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
    while (received.load() < count && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    std::printf("{\"poses\":%d,\"in_order\":%s,\"pattern\":%s}\n", received.load(),
                in_order ? "true" : "false", pattern ? "true" : "false");
    std::fflush(stdout);
    return received.load() == count && in_order && pattern ? 0 : 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dds_pose_sink: %s\n", e.what());
    return 1;
  }
}
