// No DDS packet leaves loopback with the default configuration. The publisher/subscriber pair
// runs in a private network namespace that also has a veth interface holding the default route
// (tests/dds/dds_netns_probe.cpp): with the default config v0 sends nothing, every announced
// locator is 127.x or SHM, and every pose still arrives. The control run names the veth
// address in the config and must show packets on v0 and its locators, so the check can fail.
// Needs root for the namespace (CI runs as root). Domains 164, 165.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "../common/temp_files.hpp"
#include "process.hpp"

namespace vigs::dds {
namespace {

using namespace std::chrono_literals;

nlohmann::json probe(const char* mode, int domain) {
  // The probe writes its config file there; the folder goes when the probe is done.
  vigs::test::TempFiles files("dds_netns");
  const std::string workdir = files.path(mode);
  std::filesystem::create_directories(workdir);
  test::ChildProcess p({VIGS_DDS_NETNS_PROBE, "--mode", mode, "--domain", std::to_string(domain),
                        "--source", VIGS_DDS_POSE_SOURCE, "--sink", VIGS_DDS_POSE_SINK, "--workdir",
                        workdir});
  const int rc = p.wait(180s);
  EXPECT_EQ(rc, 0) << p.output();
  return nlohmann::json::parse(p.output());
}

TEST(DdsLoopbackOnly, DefaultConfigSendsNothingOffLoopback) {
  ASSERT_EQ(geteuid(), 0u) << "this test makes a network namespace and needs root";
  const nlohmann::json r = probe("default", 164);
  ASSERT_FALSE(r.contains("error")) << r.dump(2);
  EXPECT_EQ(r["sink_exit"], 0) << r.dump(2);
  EXPECT_EQ(r["source_exit"], 0) << r.dump(2);
  EXPECT_EQ(r["v0_tx_packets"], 0) << r.dump(2);
  EXPECT_TRUE(r["off_loopback_locators"].empty()) << r.dump(2);
  EXPECT_FALSE(r["locators"].empty()) << r.dump(2);  // the observer did see the pair
  bool udp_loopback = false;
  for (const auto& l : r["locators"]) {
    udp_loopback = udp_loopback || l.get<std::string>().rfind("UDPv4:127.0.0.1:", 0) == 0;
  }
  EXPECT_TRUE(udp_loopback) << r.dump(2);
}

TEST(DdsLoopbackOnly, ControlNamingAnotherInterfaceIsSeen) {
  ASSERT_EQ(geteuid(), 0u) << "this test makes a network namespace and needs root";
  const nlohmann::json r = probe("interface", 165);
  ASSERT_FALSE(r.contains("error")) << r.dump(2);
  EXPECT_EQ(r["source_exit"], 0) << r.dump(2);
  EXPECT_GT(r["v0_tx_packets"].get<long long>(), 0) << r.dump(2);
}

}  // namespace
}  // namespace vigs::dds
