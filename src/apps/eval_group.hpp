#pragma once
// The `vigs eval` group: each accuracy tool (`eval imu`, `eval ate`, `eval image`, ...)
// registers itself under one shared `eval` subcommand, whichever registers first creates it.
#include <CLI/CLI.hpp>

namespace vigs::apps {

/// Returns the existing `eval` subcommand of `app`, or creates it.
inline CLI::App* eval_group(CLI::App& app) {
  try {
    return app.get_subcommand("eval");
  } catch (const CLI::OptionNotFound&) {
  }
  CLI::App* eval = app.add_subcommand("eval", "Measure accuracy against ground truth");
  eval->require_subcommand(1);
  return eval;
}

}  // namespace vigs::apps
