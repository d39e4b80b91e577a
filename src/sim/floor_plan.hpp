#pragma once
// Procedural floor plans. An office floor is a square grid of corridors; the blocks between
// corridors are cut into rooms, each with its own four walls (back to back with its
// neighbours, so no two surfaces coincide), a door onto a corridor and a few pieces of
// furniture. The camera route is a walk on the corridor grid that first loops around one
// block (a revisit within the first ~100 m) and then wanders without U-turns.
#include <cstdint>
#include <string>
#include <vector>

#include "sim/scene.hpp"

namespace vigs::sim {

struct FloorPlanParams {
  std::string name = "office";
  double size_m = 64.0;  ///< square floor side
  std::vector<double> corridor_centers_m = {6.0, 32.0, 58.0};
  double corridor_width_m = 2.4;
  double wall_height_m = 3.0;
  double wall_thickness_m = 0.08;             ///< per room side (two back to back)
  double room_min_m = 4.0, room_max_m = 7.0;  ///< room widths along a corridor
  double split_block_above_m = 9.0;           ///< deeper blocks get two rows of rooms
  double door_width_m = 1.0, door_height_m = 2.1;
  double route_length_m = 400.0;
};

FloorPlanParams office_params();
FloorPlanParams apartment_params();

/// Builds the scene; deterministic for (params, seed).
Scene generate_floor_plan(const FloorPlanParams& params, std::uint64_t seed);

/// "office" | "apartment"; throws std::invalid_argument otherwise.
Scene make_preset(const std::string& preset, std::uint64_t seed);

}  // namespace vigs::sim
