// `vigs topics [--domain N] [--config F] [--wait S] [--json]`: list the DDS topics discovered on
// the domain (from any DDS vendor): topic, type (ROS 2 name), writers and readers.
#include <chrono>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "apps/commands.hpp"
#include "apps/dds_options.hpp"
#include "dds/topic_catalog.hpp"

namespace vigs::apps {
namespace {

struct TopicsOptions {
  std::string config_file;
  int domain = kNoDomainOverride;
  double wait_s = 2.0;
  bool json = false;
};

int run_topics(const TopicsOptions& o) {
  const dds::DdsConfig cfg = load_dds_config(o.config_file, o.domain);
  dds::TopicCatalog catalog(cfg);
  std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<std::int64_t>(o.wait_s * 1e3)));
  const auto topics = catalog.topics();
  for (const dds::DiscoveredTopic& t : topics) {
    if (o.json) {
      std::cout << nlohmann::json{{"topic", t.name},
                                  {"type", dds::ros_type_name(t.type)},
                                  {"dds_type", t.type},
                                  {"writers", t.writers},
                                  {"readers", t.readers}}
                       .dump()
                << '\n';
    } else {
      std::cout << std::left << std::setw(28) << t.name << ' ' << std::setw(44)
                << dds::ros_type_name(t.type) << " writers " << t.writers << ", readers "
                << t.readers << '\n';
    }
  }
  if (topics.empty() && !o.json) {
    std::cout << "no topics on domain " << cfg.domain_id << " within " << o.wait_s << " s\n";
  }
  return 0;
}

}  // namespace

void add_topics_command(CLI::App& app, ExitCode& exit_code) {
  auto o = std::make_shared<TopicsOptions>();
  CLI::App* cmd = app.add_subcommand("topics", "list the DDS topics and types discovered");
  cmd->add_option("--domain", o->domain, "DDS domain id (default: the config's dds.domain_id)");
  cmd->add_option("--config", o->config_file,
                  "robot YAML whose dds: section to use (default: built-in)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--wait", o->wait_s, "seconds of discovery before listing")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--json", o->json, "one JSON line per topic");
  cmd->callback([o, &exit_code] {
    try {
      exit_code.value = run_topics(*o);
    } catch (const std::exception& e) {
      std::cerr << "vigs topics: " << e.what() << '\n';
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
