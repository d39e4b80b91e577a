#include "mapping/voxel_occupancy.hpp"

#include <cmath>

namespace vigs::mapping {

VoxelOccupancy::Voxel VoxelOccupancy::voxel(double x_m, double y_m, double z_m) const {
  auto cell = [&](double v) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / voxel_m_)) +
                                      (std::int64_t{1} << 20)) &
           0x1FFFFFu;
  };
  const std::uint64_t cx = cell(x_m), cy = cell(y_m), cz = cell(z_m);
  return Voxel{(cx >> 2) | ((cy >> 2) << 19) | ((cz >> 2) << 38),
               std::uint64_t{1} << ((cx & 3u) | ((cy & 3u) << 2) | ((cz & 3u) << 4))};
}

bool VoxelOccupancy::insert(double x_m, double y_m, double z_m) {
  const Voxel v = voxel(x_m, y_m, z_m);
  std::uint64_t& mask = bricks_[v.brick];
  if (mask & v.bit) return false;
  mask |= v.bit;
  ++voxels_;
  return true;
}

void VoxelOccupancy::erase(double x_m, double y_m, double z_m) {
  const Voxel v = voxel(x_m, y_m, z_m);
  const auto it = bricks_.find(v.brick);
  if (it == bricks_.end() || !(it->second & v.bit)) return;
  it->second &= ~v.bit;
  --voxels_;
  if (it->second == 0) bricks_.erase(it);
}

bool VoxelOccupancy::contains(double x_m, double y_m, double z_m) const {
  const Voxel v = voxel(x_m, y_m, z_m);
  const auto it = bricks_.find(v.brick);
  return it != bricks_.end() && (it->second & v.bit) != 0;
}

void VoxelOccupancy::clear() {
  bricks_ = {};
  voxels_ = 0;
}

}  // namespace vigs::mapping
