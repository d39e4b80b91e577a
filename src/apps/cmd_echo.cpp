// `vigs echo [TOPIC] [--domain N] [--count N] [--config F] [--timeout S]`: subscribe to VIGS's
// DDS topics and print each sample as one JSON line, {"topic": ..., "type": ..., "msg": {...}}
// with ROS 2's field names, like `ros2 topic echo`, for users without ROS. Without TOPIC: all
// six VIGS topics (subscribed pose last: a publisher waiting for a pose reader, as `vigs run`
// does, has then discovered the others too, since a participant announces its readers in
// order). TOPIC may be a wire name (rt/vigs/pose) or a ROS 2 name (/vigs/pose); a
// topic outside the VIGS set is echoed when its discovered type is one of VIGS's types.
// --receipt adds "received_ns": CLOCK_MONOTONIC when the sample reached this process (a pose
// stamped in the same host clock, as `vigs run` live or --through-drivers stamps it, then gives
// the frame-to-receipt latency).
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <iostream>
#include <mutex>
#include <string>
#include <thread>

#include "apps/commands.hpp"
#include "apps/dds_options.hpp"
#include "dds/json_sample.hpp"
#include "dds/subscriber.hpp"
#include "dds/topic_catalog.hpp"
#include "rt/clock.hpp"

namespace vigs::apps {
namespace {

struct EchoOptions {
  std::string topic;
  std::string config_file;
  int domain = kNoDomainOverride;
  int count = 0;         // 0: until interrupted
  double timeout_s = 0;  // 0: none
  bool receipt = false;
};

std::atomic<bool> g_interrupted{false};
extern "C" void on_signal(int) {
  g_interrupted.store(true);
}

class Printer {
 public:
  Printer(int count, bool receipt) : count_(count), receipt_(receipt) {}
  template <class Msg>
  std::function<void(const Msg&)> callback(const std::string& topic, const std::string& type) {
    return [this, topic, type](const Msg& m) {
      const std::int64_t received_ns = rt::monotonic_ns();
      std::lock_guard l(mutex_);
      if (count_ > 0 && printed_ >= count_) return;
      nlohmann::json line = {{"topic", topic}, {"type", type}, {"msg", dds::to_json(m)}};
      if (receipt_) line["received_ns"] = received_ns;
      std::cout << line.dump() << '\n' << std::flush;
      ++printed_;
      if (count_ > 0 && printed_ >= count_) done_.notify_all();
    };
  }
  // Waits for `count` samples, an interrupt or the timeout. True when `count` were printed.
  bool wait(double timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::milliseconds(static_cast<std::int64_t>(timeout_s * 1e3));
    std::unique_lock l(mutex_);
    for (;;) {
      if (count_ > 0 && printed_ >= count_) return true;
      if (g_interrupted.load()) return count_ == 0;
      if (timeout_s > 0 && std::chrono::steady_clock::now() >= deadline) return false;
      done_.wait_for(l, std::chrono::milliseconds(50));
    }
  }

 private:
  std::mutex mutex_;
  std::condition_variable done_;
  int count_;
  bool receipt_;
  int printed_ = 0;
};

// Subscribes `topic` as the VIGS message type whose DDS type name is `type`; false if none is.
bool subscribe_typed(dds::Subscriber& sub, Printer& p, const std::string& topic,
                     const std::string& type) {
  using namespace geometry_msgs::msg::dds_;
  const std::string ros = dds::ros_type_name(type);
  if (type == "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_") {
    sub.subscribe<PoseWithCovarianceStamped_>(topic,
                                              p.callback<PoseWithCovarianceStamped_>(topic, ros));
  } else if (type == "geometry_msgs::msg::dds_::PoseStamped_") {
    sub.subscribe<PoseStamped_>(topic, p.callback<PoseStamped_>(topic, ros));
  } else if (type == "nav_msgs::msg::dds_::Odometry_") {
    sub.subscribe<nav_msgs::msg::dds_::Odometry_>(
        topic, p.callback<nav_msgs::msg::dds_::Odometry_>(topic, ros));
  } else if (type == "tf2_msgs::msg::dds_::TFMessage_") {
    sub.subscribe<tf2_msgs::msg::dds_::TFMessage_>(
        topic, p.callback<tf2_msgs::msg::dds_::TFMessage_>(topic, ros));
  } else if (type == "vigs_msgs::msg::dds_::Status_") {
    sub.subscribe<vigs_msgs::msg::dds_::Status_>(
        topic, p.callback<vigs_msgs::msg::dds_::Status_>(topic, ros));
  } else if (type == "vigs_msgs::msg::dds_::PoseQuality_") {
    sub.subscribe<vigs_msgs::msg::dds_::PoseQuality_>(
        topic, p.callback<vigs_msgs::msg::dds_::PoseQuality_>(topic, ros));
  } else {
    return false;
  }
  return true;
}

int run_echo(const EchoOptions& o) {
  const dds::DdsConfig cfg = load_dds_config(o.config_file, o.domain);
  const dds::TopicNames& t = cfg.topics;
  const std::pair<std::string, std::string> known[] = {
      {t.pose_quality, "vigs_msgs::msg::dds_::PoseQuality_"},
      {t.odom, "nav_msgs::msg::dds_::Odometry_"},
      {t.tf, "tf2_msgs::msg::dds_::TFMessage_"},
      {t.keyframe, "geometry_msgs::msg::dds_::PoseStamped_"},
      {t.status, "vigs_msgs::msg::dds_::Status_"},
      {t.pose, "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_"}};

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  Printer printer(o.count, o.receipt);
  dds::Subscriber sub(cfg, "vigs_echo");
  if (o.topic.empty()) {
    for (const auto& [name, type] : known) subscribe_typed(sub, printer, name, type);
  } else {
    const std::string wire = dds::to_wire_topic(o.topic);
    std::string type;
    for (const auto& [name, ktype] : known) {
      if (name == wire) type = ktype;
    }
    if (type.empty()) {
      // Not a VIGS topic name: find its type from discovery.
      dds::TopicCatalog catalog(cfg);
      const double wait_s = o.timeout_s > 0 ? o.timeout_s : 5.0;
      const auto deadline = std::chrono::steady_clock::now() +
                            std::chrono::milliseconds(static_cast<std::int64_t>(wait_s * 1e3));
      while (type.empty() && std::chrono::steady_clock::now() < deadline && !g_interrupted) {
        for (const dds::DiscoveredTopic& d : catalog.topics()) {
          if (d.name == wire && d.writers > 0) type = d.type;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      if (type.empty()) {
        std::cerr << "vigs echo: no writer of topic " << wire << " on domain " << cfg.domain_id
                  << " within " << wait_s << " s\n";
        return 1;
      }
    }
    if (!subscribe_typed(sub, printer, wire, type)) {
      std::cerr << "vigs echo: topic " << wire << " has type " << type
                << ", which vigs echo cannot decode (it knows the VIGS types: "
                   "PoseWithCovarianceStamped, PoseStamped, Odometry, TFMessage, Status, "
                   "PoseQuality)\n";
      return 1;
    }
  }
  if (!printer.wait(o.timeout_s)) {
    std::cerr << "vigs echo: fewer than " << o.count << " samples within " << o.timeout_s << " s\n";
    return 1;
  }
  return 0;
}

}  // namespace

void add_echo_command(CLI::App& app, ExitCode& exit_code) {
  auto o = std::make_shared<EchoOptions>();
  CLI::App* cmd = app.add_subcommand(
      "echo", "print DDS samples of VIGS topics as JSON lines (like ros2 topic echo)");
  cmd->add_option("topic", o->topic,
                  "topic, e.g. rt/vigs/pose or /vigs/pose (default: all VIGS topics)");
  cmd->add_option("--domain", o->domain, "DDS domain id (default: the config's dds.domain_id)");
  cmd->add_option("--count", o->count, "exit after N samples (0: until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--config", o->config_file,
                  "robot YAML whose dds: section to use (default: built-in)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--timeout", o->timeout_s, "give up after S seconds, exit 1 (0: never)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--receipt", o->receipt,
                "add \"received_ns\": CLOCK_MONOTONIC at the sample's arrival, ns");
  cmd->callback([o, &exit_code] {
    try {
      exit_code.value = run_echo(*o);
    } catch (const std::exception& e) {
      std::cerr << "vigs echo: " << e.what() << '\n';
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
