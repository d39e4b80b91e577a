// The dds: section and the QoS XML: every bad input is a start-up error naming the key or the
// file; relative QoS paths resolve against the config file; the profiles really reach Fast DDS.
// Domains 153-155.
#include <gtest/gtest.h>

#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/config/yaml_loader.hpp"
#include "dds/dds_config.hpp"
#include "dds/participant.hpp"
#include "shm_janitor.hpp"

namespace vigs::dds {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

class DdsConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("vigs_dds_config_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Expects resolve_dds_config to throw a DdsConfigError whose message contains every needle.
  static void expect_error(const config::DdsSettings& s, const std::string& config_path,
                           std::initializer_list<std::string> needles) {
    try {
      resolve_dds_config(s, config_path);
      FAIL() << "no error";
    } catch (const DdsConfigError& e) {
      for (const std::string& n : needles) {
        EXPECT_NE(std::string(e.what()).find(n), std::string::npos) << e.what() << " / " << n;
      }
    }
  }

  fs::path dir_;
};

TEST_F(DdsConfigTest, DomainIdOutOfRangeNamesTheKey) {
  config::DdsSettings s;
  s.domain_id = 233;
  expect_error(s, "", {"dds.domain_id", "233", "232"});
  s.domain_id = -1;
  expect_error(s, "", {"dds.domain_id"});
}

// dds.shm_peer_check_ms reaches the shared-memory transport as its healthy-check timeout (the
// bound on how long a write waits on a stopped reader; test_dds_never_blocks.cpp).
TEST_F(DdsConfigTest, ShmPeerCheckReachesTheSharedMemoryTransport) {
  config::DdsSettings s;
  s.shm_peer_check_ms = 37;
  const DdsConfig c = resolve_dds_config(s, "");
  const auto q = make_participant_qos(c, "shm_check");
  int found = 0;
  for (const auto& t : q.transport().user_transports) {
    const auto* shm =
        dynamic_cast<const eprosima::fastdds::rtps::SharedMemTransportDescriptor*>(t.get());
    if (shm == nullptr) continue;
    ++found;
    EXPECT_EQ(shm->healthy_check_timeout_ms(), 37u);
  }
  EXPECT_EQ(found, 1);
}

TEST_F(DdsConfigTest, InterfaceThisMachineDoesNotHaveNamesTheKey) {
  config::DdsSettings s;
  s.interface_ip = "10.254.254.254";
  expect_error(
      s, "", {"dds.interface_ip", "10.254.254.254", "not an address of this machine", "127.0.0.1"});
  s.interface_ip = "eth0";
  expect_error(s, "", {"dds.interface_ip", "not an IPv4 address"});
}

TEST_F(DdsConfigTest, BadInitialPeerAndEmptyFrameNameTheKey) {
  config::DdsSettings s;
  s.initial_peers = "127.0.0.1, localhost";
  expect_error(s, "", {"dds.initial_peers", "localhost"});
  s = {};
  s.camera_frame_id = "";
  expect_error(s, "", {"dds.camera_frame_id"});
  s = {};
  s.topic_prefix = "rt/vigs/";
  expect_error(s, "", {"dds.topic_prefix"});
}

TEST_F(DdsConfigTest, MissingQosFileNamesTheResolvedPath) {
  config::DdsSettings s;
  s.qos_profiles = "missing.xml";
  const fs::path cfg = dir_ / "robots" / "r.yaml";
  expect_error(s, cfg.string(), {(dir_ / "robots" / "missing.xml").string(), "dds.qos_profiles"});
}

TEST_F(DdsConfigTest, MalformedXmlNamesFileAndLine) {
  write(dir_ / "bad.xml",
        "<?xml version=\"1.0\"?>\n<dds>\n  <profiles>\n    <data_writer profile_name=\"a\">\n"
        "  </profiles>\n</dds>\n");
  config::DdsSettings s;
  s.qos_profiles = "bad.xml";
  expect_error(s, (dir_ / "r.yaml").string(), {(dir_ / "bad.xml").string() + ":", "malformed"});
  write(dir_ / "notdds.xml", "<?xml version=\"1.0\"?>\n<html/>\n");
  s.qos_profiles = "notdds.xml";
  expect_error(s, (dir_ / "r.yaml").string(), {"notdds.xml:2", "not a Fast DDS profiles file"});
}

TEST_F(DdsConfigTest, UnknownProfileNameNamesKeyAndListsTheFilesProfiles) {
  config::DdsSettings s;
  s.pose_qos_profile = "no_such_profile";
  expect_error(s, "",
               {"dds.pose_qos_profile", "no_such_profile", kBuiltinQosName, "vigs_pose_writer"});
  s = {};
  s.reader_qos_profile = "vigs_pose_writer";  // exists, but as a writer profile
  expect_error(s, "", {"dds.reader_qos_profile", "data_reader"});
}

TEST_F(DdsConfigTest, RelativeQosPathResolvesAgainstTheConfigFile) {
  const fs::path xml = fs::path(VIGS_SOURCE_DIR) / "firmware_config/dds/qos_profiles.xml";
  write(dir_ / "dds" / "mine.xml", read(xml));
  write(dir_ / "robots" / "r.yaml", "dds:\n  qos_profiles: ../dds/mine.xml\n");
  const fs::path cwd = fs::current_path();
  fs::current_path(fs::temp_directory_path());  // the working directory must not matter
  const auto cfg_file = (dir_ / "robots" / "r.yaml").string();
  const DdsConfig c = resolve_dds_config(config::load_config_file(cfg_file).dds, cfg_file);
  fs::current_path(cwd);
  EXPECT_EQ(c.qos_source, (dir_ / "dds" / "mine.xml").string());
  EXPECT_EQ(c.qos_xml, read(xml));
}

TEST_F(DdsConfigTest, ShippedRobotFilesUseTheShippedQosFile) {
  const fs::path root(VIGS_SOURCE_DIR);
  const auto file = (root / "firmware_config/robots/sim_office.yaml").string();
  const DdsConfig c = resolve_dds_config(config::load_config_file(file).dds, file);
  EXPECT_EQ(fs::canonical(c.qos_source),
            fs::canonical(root / "firmware_config/dds/qos_profiles.xml"));
  EXPECT_TRUE(c.loopback_only);
  ASSERT_EQ(c.initial_peers.size(), 1u);
  EXPECT_EQ(c.initial_peers[0], "127.0.0.1");
  EXPECT_EQ(c.topics.pose, "rt/vigs/pose");
  EXPECT_EQ(c.topics.tf, "rt/tf");
  // The built-in default carries the same file, compiled in.
  const DdsConfig b = default_dds_config(153);
  EXPECT_EQ(b.qos_source, kBuiltinQosName);
  EXPECT_EQ(b.qos_xml, read(root / "firmware_config/dds/qos_profiles.xml"));
  EXPECT_EQ(b.domain_id, 153);
}

// Profiles of a test-only file (unique names: Fast DDS keeps one profile table per process).
const char* kCustomXml = R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <data_writer profile_name="t_pose">
      <qos><reliability><kind>BEST_EFFORT</kind></reliability></qos>
      <topic><historyQos><kind>KEEP_LAST</kind><depth>7</depth></historyQos></topic>
    </data_writer>
    <data_writer profile_name="t_key"/>
    <data_writer profile_name="t_status"/>
    <data_reader profile_name="t_reader"/>
  </profiles>
</dds>
)";

config::DdsSettings custom_settings(int domain) {
  config::DdsSettings s;
  s.domain_id = domain;
  s.qos_profiles = "custom.xml";
  s.pose_qos_profile = "t_pose";
  s.keyframe_qos_profile = "t_key";
  s.status_qos_profile = "t_status";
  s.reader_qos_profile = "t_reader";
  return s;
}

TEST_F(DdsConfigTest, ProfilesFromTheFileReachFastDds) {
  test::ShmJanitor janitor;
  write(dir_ / "custom.xml", kCustomXml);
  const DdsConfig c = resolve_dds_config(custom_settings(154), (dir_ / "r.yaml").string());
  Participant p(c, "test_profiles");
  auto* pub = p->create_publisher(eprosima::fastdds::dds::PUBLISHER_QOS_DEFAULT);
  ASSERT_NE(pub, nullptr);
  eprosima::fastdds::dds::DataWriterQos q;
  ASSERT_EQ(pub->get_datawriter_qos_from_profile("t_pose", q), ReturnCode_t::RETCODE_OK);
  EXPECT_EQ(q.history().depth, 7);
  EXPECT_EQ(q.reliability().kind, eprosima::fastdds::dds::BEST_EFFORT_RELIABILITY_QOS);

  // Another file that redefines an already loaded profile differently is refused by name.
  std::string other = kCustomXml;
  other.replace(other.find("<depth>7"), 8, "<depth>9");
  write(dir_ / "other.xml", other);
  config::DdsSettings s = custom_settings(155);
  s.qos_profiles = "other.xml";
  const DdsConfig c2 = resolve_dds_config(s, (dir_ / "r.yaml").string());
  try {
    Participant p2(c2, "test_profiles_2");
    FAIL() << "redefined profile accepted";
  } catch (const DdsConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("other.xml"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("t_pose"), std::string::npos) << e.what();
  }
}

TEST_F(DdsConfigTest, WellFormedXmlFastDdsRejectsNamesTheFile) {
  write(dir_ / "wrong.xml", R"(<?xml version="1.0"?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <data_writer profile_name="w_pose">
      <qos><reliability><kind>SOMETIMES</kind></reliability></qos>
    </data_writer>
    <data_writer profile_name="w_key"/>
    <data_writer profile_name="w_status"/>
    <data_reader profile_name="w_reader"/>
  </profiles>
</dds>
)");
  config::DdsSettings s;
  s.domain_id = 155;
  s.qos_profiles = "wrong.xml";
  s.pose_qos_profile = "w_pose";
  s.keyframe_qos_profile = "w_key";
  s.status_qos_profile = "w_status";
  s.reader_qos_profile = "w_reader";
  const DdsConfig c = resolve_dds_config(s, (dir_ / "r.yaml").string());
  try {
    Participant p(c, "test_rejected");
    FAIL() << "Fast DDS accepted reliability SOMETIMES";
  } catch (const DdsConfigError& e) {
    EXPECT_NE(std::string(e.what()).find((dir_ / "wrong.xml").string()), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace vigs::dds
