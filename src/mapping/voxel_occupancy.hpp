#pragma once
// The set of voxels that hold a Gaussian (insertion skips a point whose voxel is in it), kept
// as 4 x 4 x 4-voxel bricks: a hash map from the brick's coordinates to a 64-bit mask of its
// occupied voxels.
//
// Why not a hash set of voxel keys (what this replaced): a mapped surface is a sheet of voxels,
// so the voxels of one brick come together. A set holds one 8-byte key (and a control byte) per
// voxel and, at Abseil's load factor between 7/16 and 7/8, 10-20 bytes per voxel: 8 % of the
// live mapper's bytes per Gaussian, and a jump of ten bytes per Gaussian at each doubling. A
// brick holds its voxels in one 16-byte slot. The membership is the same, voxel for voxel.
// Abseil's flat_hash_map (libabsl-dev) for the table, as before; the bricks on top are a few
// lines and no Debian library offers them.
#include <cstddef>
#include <cstdint>

#include <absl/container/flat_hash_map.h>

namespace vigs::mapping {

class VoxelOccupancy {
 public:
  /// `voxel_m` > 0: the edge of a voxel. Coordinates wrap every 2^21 voxels per axis (42 km at
  /// 2 cm), as the voxel keys did.
  explicit VoxelOccupancy(double voxel_m) : voxel_m_(voxel_m) {}

  /// Marks the voxel holding (x, y, z) (metres, world frame); false when it was already marked.
  bool insert(double x_m, double y_m, double z_m);
  /// Unmarks the voxel holding (x, y, z); a brick left empty is dropped.
  void erase(double x_m, double y_m, double z_m);
  [[nodiscard]] bool contains(double x_m, double y_m, double z_m) const;
  /// Unmarks everything and frees the table.
  void clear();
  /// Makes room for `bricks` bricks without growing the table on the way.
  void reserve(std::size_t bricks) { bricks_.reserve(bricks); }

  [[nodiscard]] std::size_t voxels() const { return voxels_; }
  [[nodiscard]] std::size_t bricks() const { return bricks_.size(); }
  /// Bytes held by the table: one key, one mask and one control byte per slot, and a group's
  /// worth of control bytes more (absl raw_hash_set.h, AllocSize: the sentinel and the 15 cloned
  /// bytes of a 16-wide SSE2 group, before alignment).
  [[nodiscard]] std::size_t bytes() const {
    const std::size_t slots = bricks_.capacity();
    return slots == 0 ? 0 : slots * (2 * sizeof(std::uint64_t) + 1) + 1 + 15;
  }

 private:
  struct Voxel {
    std::uint64_t brick;  ///< the brick's three 19-bit coordinates
    std::uint64_t bit;    ///< the voxel's bit in the brick's mask
  };
  [[nodiscard]] Voxel voxel(double x_m, double y_m, double z_m) const;

  double voxel_m_;
  absl::flat_hash_map<std::uint64_t, std::uint64_t> bricks_;
  std::size_t voxels_ = 0;
};

}  // namespace vigs::mapping
