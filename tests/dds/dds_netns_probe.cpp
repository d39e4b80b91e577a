// dds_netns_probe: runs a DDS publisher/subscriber pair inside a private network namespace
// whose only other interface is a veth pair (v0 10.254.0.1/24, the default route, so any packet
// not for 127.0.0.0/8 leaves through v0) and a private /dev/shm, and reports:
//   - v0's tx_packets during the run (from /sys/class/net/v0/statistics): what left loopback;
//   - every locator the pair's participants, writers and readers announced, as seen by a third,
//     loopback-only observer participant, and the ones that are not 127.x or SHM;
//   - the sink's verdict (every pose in order, tests/dds/dds_pose_sink.cpp).
// --mode default: both processes on the built-in configuration (loopback only).
// --mode interface: the publisher's config names the veth address instead (a control: the
//   probe must then see packets leave). Needs root (CAP_SYS_ADMIN, CAP_NET_ADMIN).
// One JSON line on stdout. Exit 0 when the measurement ran, 1 when the namespace could not be
// made.
#include <fastrtps/utils/IPLocator.h>
#include <sched.h>
#include <sys/mount.h>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "dds/dds_config.hpp"
#include "dds/participant.hpp"
#include "process.hpp"

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;
using namespace std::chrono_literals;

namespace {

bool write_file(const char* path, const char* text) {
  std::ofstream f(path);
  f << text;
  return static_cast<bool>(f);
}

// tx_packets of `dev` from /proc/net/dev (per network namespace; /sys/class/net would show the
// namespace that mounted /sys). -1 when the device is not there.
long long tx_packets(const char* dev) {
  std::ifstream f("/proc/net/dev");
  const std::string want = std::string(dev) + ":";
  for (std::string line; std::getline(f, line);) {
    std::istringstream in(line);
    std::string name;
    in >> name;
    if (name != want) continue;
    long long v[10] = {};
    for (long long& x : v) in >> x;  // rx: bytes packets errs drop fifo frame compressed mcast
    return v[9];                     // tx: bytes packets ...
  }
  return -1;
}

std::string describe(const rtps::Locator_t& l) {
  if (l.kind == LOCATOR_KIND_SHM) return "SHM:" + std::to_string(l.port);
  return std::string(l.kind == LOCATOR_KIND_UDPv4 ? "UDPv4:"
                                                  : "kind" + std::to_string(l.kind) + ":") +
         rtps::IPLocator::toIPv4string(l) + ":" + std::to_string(l.port);
}

bool on_loopback(const rtps::Locator_t& l) {
  if (l.kind == LOCATOR_KIND_SHM) return true;
  return l.kind == LOCATOR_KIND_UDPv4 && rtps::IPLocator::toIPv4string(l).rfind("127.", 0) == 0;
}

// Records every locator other participants and endpoints announce.
struct Observer : fdds::DomainParticipantListener {
  std::mutex m;
  std::set<std::string> all, off_loopback;
  std::set<std::string> participants;
  template <class List>
  void add(const List& list) {
    for (const rtps::Locator_t& l : list) {
      std::lock_guard g(m);
      all.insert(describe(l));
      if (!on_loopback(l)) off_loopback.insert(describe(l));
    }
  }
  void on_participant_discovery(fdds::DomainParticipant*,
                                rtps::ParticipantDiscoveryInfo&& i) override {
    {
      std::lock_guard g(m);
      participants.insert(i.info.m_participantName.to_string());
    }
    add(i.info.metatraffic_locators.unicast);
    add(i.info.metatraffic_locators.multicast);
    add(i.info.default_locators.unicast);
    add(i.info.default_locators.multicast);
  }
  void on_publisher_discovery(fdds::DomainParticipant*, rtps::WriterDiscoveryInfo&& i) override {
    add(i.info.remote_locators().unicast);
    add(i.info.remote_locators().multicast);
  }
  void on_subscriber_discovery(fdds::DomainParticipant*, rtps::ReaderDiscoveryInfo&& i) override {
    add(i.info.remote_locators().unicast);
    add(i.info.remote_locators().multicast);
  }
};

bool make_namespace(std::string& error) {
  if (unshare(CLONE_NEWNET | CLONE_NEWNS) != 0) {
    error = "unshare(CLONE_NEWNET|CLONE_NEWNS) failed (needs root)";
    return false;
  }
  if (mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
      mount("tmpfs", "/dev/shm", "tmpfs", 0, "size=64m") != 0) {
    error = "private /dev/shm mount failed";
    return false;
  }
  write_file("/proc/sys/net/ipv6/conf/all/disable_ipv6", "1");
  write_file("/proc/sys/net/ipv6/conf/default/disable_ipv6", "1");
  const int rc = std::system(
      "ip link set lo up && ip link add v0 type veth peer name v1 && "
      "ip addr add 10.254.0.1/24 dev v0 && ip link set v1 up && ip link set v0 up && "
      "ip route add default dev v0");
  if (rc != 0) {
    error = "ip link/addr/route setup failed";
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string mode = "default", source, sink, workdir = "/tmp";
  int domain = 164;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--mode")
      mode = argv[i + 1];
    else if (k == "--source")
      source = argv[i + 1];
    else if (k == "--sink")
      sink = argv[i + 1];
    else if (k == "--domain")
      domain = std::atoi(argv[i + 1]);
    else if (k == "--workdir")
      workdir = argv[i + 1];
  }
  std::string error;
  if (!make_namespace(error)) {
    std::printf("%s\n", nlohmann::json{{"error", error}}.dump().c_str());
    return 1;
  }
  const std::string dom = std::to_string(domain);
  nlohmann::json out = {{"mode", mode}};
  try {
    Observer observer;
    vigs::dds::Participant probe(vigs::dds::default_dds_config(domain), "netns_observer",
                                 &observer);
    const long long tx0 = tx_packets("v0");
    if (tx0 < 0) throw std::runtime_error("no v0 in /proc/net/dev");
    int sink_rc = -100, source_rc = -100;
    std::string sink_out, source_out;
    if (mode == "default") {
      vigs::dds::test::ChildProcess sink_p(
          {sink, "--domain", dom, "--count", "40", "--timeout-s", "60"});
      vigs::dds::test::ChildProcess source_p(
          {source, "--domain", dom, "--count", "40", "--rate-hz", "50", "--wait-all", "0"});
      source_rc = source_p.wait(90s);
      sink_rc = sink_p.wait(60s);
      sink_out = sink_p.output();
      source_out = source_p.output();
    } else {
      const std::string cfg = workdir + "/netns_interface.yaml";
      std::ofstream(cfg) << "dds:\n  interface_ip: 10.254.0.1\n  qos_profiles: " << VIGS_SOURCE_DIR
                         << "/firmware_config/dds/qos_profiles.xml\n";
      vigs::dds::test::ChildProcess source_p({source, "--domain", dom, "--count", "20", "--rate-hz",
                                              "50", "--subscribers", "0", "--config", cfg});
      source_rc = source_p.wait(90s);
      source_out = source_p.output();
    }
    std::this_thread::sleep_for(200ms);
    const long long tx1 = tx_packets("v0");
    std::lock_guard g(observer.m);
    out["v0_tx_packets"] = tx1 - tx0;
    out["locators"] = observer.all;
    out["off_loopback_locators"] = observer.off_loopback;
    out["participants"] = observer.participants;
    out["sink_exit"] = sink_rc;
    out["sink"] = sink_out;
    out["source_exit"] = source_rc;
    out["source"] = source_out;
  } catch (const std::exception& e) {
    out["error"] = e.what();
  }
  std::printf("%s\n", out.dump().c_str());
  return 0;
}
