// dds_pose_source: the publishing process of the two-process DDS tests. Runs a real
// PosePublisher on the built-in (loopback-only) configuration, waits for `--subscribers`
// matched readers (on pose, odom and tf; with --wait-all 0 on pose only; with --wait-quality 1
// on pose_quality too), then pushes the pose
// pattern (tests/dds/pose_pattern.hpp) into the ring at
// `--rate-hz`, a status snapshot every 20 poses, and exits once every matched reader has
// acknowledged what was written (or 10 s passed). Prints one JSON line of counters. Exit 0 on
// success, 2 when no subscriber came.
#include <fastdds/dds/publisher/DataWriter.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "core/config/yaml_loader.hpp"
#include "dds/dds_config.hpp"
#include "dds/pose_publisher.hpp"
#include "pose_pattern.hpp"
#include "rt/clock.hpp"

using namespace vigs;

int main(int argc, char** argv) {
  int domain = -1, count = 100, subscribers = 1, wait_s = 20;
  double rate_hz = 100;
  bool shm = true;
  bool wait_all = true;       // wait for readers on pose, odom and tf (else on pose only)
  bool wait_quality = false;  // and on pose_quality
  std::string config_file, iface;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const char* v = argv[i + 1];
    if (k == "--domain")
      domain = std::atoi(v);
    else if (k == "--count")
      count = std::atoi(v);
    else if (k == "--rate-hz")
      rate_hz = std::atof(v);
    else if (k == "--subscribers")
      subscribers = std::atoi(v);
    else if (k == "--wait-s")
      wait_s = std::atoi(v);
    else if (k == "--shm")
      shm = std::atoi(v) != 0;
    else if (k == "--wait-all")
      wait_all = std::atoi(v) != 0;
    else if (k == "--wait-quality")
      wait_quality = std::atoi(v) != 0;
    else if (k == "--config")
      config_file = v;
    else {
      std::fprintf(stderr, "dds_pose_source: unknown option %s\n", k.c_str());
      return 64;
    }
  }
  try {
    dds::DdsConfig cfg;
    if (config_file.empty()) {
      cfg = dds::default_dds_config(domain < 0 ? 0 : domain);
    } else {
      auto s = config::load_config_file(config_file).dds;
      if (domain >= 0) s.domain_id = domain;
      cfg = dds::resolve_dds_config(s, config_file);
    }
    cfg.shared_memory = shm;
    rt::SpscRing<PoseSample> ring(64);
    dds::PosePublisher::StatusMailbox status(1);
    dds::PosePublisher pub(cfg, ring, &status, "test_robot");
    pub.start();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(wait_s);
    if (!wait_all) {
      while (pub.pose_subscribers() < subscribers && std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    }
    if (wait_quality) {
      while (pub.pose_quality_subscribers() < subscribers &&
             std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    }
    if (subscribers > 0 &&
        ((wait_all ? !pub.wait_for_subscribers(subscribers, std::chrono::seconds(wait_s))
                   : pub.pose_subscribers() < subscribers) ||
         (wait_quality && pub.pose_quality_subscribers() < subscribers))) {
      std::fprintf(stderr, "dds_pose_source: no subscriber within %d s\n", wait_s);
      return 2;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // let discovery settle
    const auto period = std::chrono::nanoseconds(static_cast<std::int64_t>(1e9 / rate_hz));
    auto next = std::chrono::steady_clock::now();
    std::uint64_t dropped = 0;
    for (int i = 0; i < count; ++i) {
      if (!ring.try_push(dds::test::pattern_sample(static_cast<std::uint64_t>(i)))) ++dropped;
      if (i % 20 == 0) {
        dds::StatusSnapshot snap;
        snap.t_ns = dds::test::pattern_sample(static_cast<std::uint64_t>(i)).t_ns;
        snap.tracking_state = dds::TrackingState::kTracking;
        snap.frames_tracked = static_cast<std::uint64_t>(i);
        snap.thread_count = 1;
        dds::set_name(snap.threads[0].name, "tracker");
        snap.threads[0].rate_hz = 20;
        status.push(snap);
      }
      next += period;
      std::this_thread::sleep_until(next);
    }
    pub.stop();
    const bool acked = pub.wait_for_acknowledgments(std::chrono::seconds(10));
    const auto st = pub.stats();
    std::printf(
        "{\"pushed\":%d,\"ring_drops\":%llu,\"published\":%llu,\"keyframes\":%llu,"
        "\"status\":%llu,\"rejected\":%llu,\"write_errors\":%llu,\"acked\":%s}\n",
        count, static_cast<unsigned long long>(dropped),
        static_cast<unsigned long long>(st.poses_published),
        static_cast<unsigned long long>(st.keyframes_published),
        static_cast<unsigned long long>(st.status_published),
        static_cast<unsigned long long>(st.rejected),
        static_cast<unsigned long long>(st.write_errors), acked ? "true" : "false");
    std::fflush(stdout);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dds_pose_source: %s\n", e.what());
    return 1;
  }
}
