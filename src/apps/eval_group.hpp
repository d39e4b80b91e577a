#pragma once
#include <CLI/CLI.hpp>

namespace vigs::apps {

inline CLI::App* eval_group(CLI::App& app) {
  for (auto* s : app.get_subcommands({}))
    if (s->get_name() == "eval") return s;
  auto* e = app.add_subcommand("eval", "Evaluate trajectories, IMU data and images");
  e->require_subcommand(1);
  return e;
}

}  // namespace vigs::apps
