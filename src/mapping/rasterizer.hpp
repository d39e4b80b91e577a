#pragma once
// Differentiable tiled splatting on the CPU: project every Gaussian, bin them into 16x16 tiles
// in depth order, blend front to back (colour, depth = sum z alpha T, accumulated opacity), and
// in backward traverse each pixel's contributors in reverse. Tiles (and chunks of Gaussians) are
// claimed one at a time by whichever member of a rt::WorkerTeam is free, so a member that is
// preempted does not hold the others up. Every claimed item writes only its own outputs; backward
// writes one gradient per Gaussian-tile pair, grouped by Gaussian, and sums each Gaussian's in
// the order of its tiles (no atomics on floats), so results are bit-identical run to run and do
// not depend on the team's size.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "core/capacity_bytes.hpp"
#include "mapping/gaussian_map.hpp"
#include "mapping/map_blocks.hpp"
#include "mapping/projection.hpp"
#include "mapping/raster_settings.hpp"
#include "mapping/render_camera.hpp"
#include "mapping/tile_kernels.hpp"
#include "rt/worker_team.hpp"

namespace vigs::mapping {

template <class T>
struct RenderResult {
  int width = 0;
  int height = 0;
  std::vector<T> color;        ///< 3 per pixel, RGB
  std::vector<T> depth;        ///< metres, sum z_i alpha_i T_i (not normalised)
  std::vector<T> final_T;      ///< transmittance left; accumulated opacity = 1 - final_T
  std::vector<int> n_contrib;  ///< per pixel, last contributor (+1) in its tile's list
  [[nodiscard]] T alpha(int p) const { return T(1) - final_T[static_cast<std::size_t>(p)]; }
  /// Bytes held by the per-pixel arrays (their capacities).
  [[nodiscard]] std::size_t capacity_bytes() const {
    return vigs::capacity_bytes(color, depth, final_T, n_contrib);
  }
};

/// One Gaussian the last forward pass did not cull, as it projected it, and its id in the map.
template <class T>
struct ProjectedRecord {
  ProjectedGaussian<T> p;
  int id;
};

template <class T>
class Rasterizer {
 public:
  /// `pool` may be null (single thread); it must outlive the rasterizer.
  explicit Rasterizer(RasterSettings settings = {}, rt::WorkerTeam* pool = nullptr);

  [[nodiscard]] const RasterSettings& settings() const { return settings_; }
  RasterSettings& settings() { return settings_; }

  /// With `blocks` (float maps only) whole blocks of Gaussians the camera cannot see are culled
  /// before projection (map_blocks.hpp); the render is the same. forward() brings them up to
  /// date with `g` first.
  void forward(const GaussianParams<T>& g, const RenderCamera& cam, RenderResult<T>& out,
               MapBlocks* blocks = nullptr);

  /// Gradients of a loss with respect to every parameter, given dL/d(colour), dL/d(depth) and
  /// dL/d(accumulated opacity) per pixel (depth and alpha may be null). Must follow forward()
  /// with the same map and camera. `grad` is overwritten (resized to the map).
  void backward(const GaussianParams<T>& g, const RenderCamera& cam, const RenderResult<T>& out,
                const T* v_color, const T* v_depth, const T* v_alpha, GaussianParams<T>& grad);

  /// The two halves of backward() for fused optimisers. accumulate_gradients() runs the
  /// per-pixel reverse pass over the last forward()'s Gaussians (their kernel records were
  /// packed there, colour included: the map must not change in between); gaussian_gradient() then
  /// gives Gaussian i's parameter gradients in the order mean (3), log-scale (3), quaternion (4),
  /// opacity logit, colour (3); zeros when it was culled. gaussian_gradient() only reads, so
  /// threads may call it for different i.
  static constexpr int kParamGrads = 14;
  void accumulate_gradients(const RenderCamera& cam, const RenderResult<T>& out, const T* v_color,
                            const T* v_depth, const T* v_alpha);
  void gaussian_gradient(const GaussianParams<T>& g, const RenderCamera& cam, std::size_t i,
                         T out[kParamGrads]) const;
  /// gaussian_gradient() of the Gaussian in visible slot `slot` (visible_ids()[slot]), without
  /// looking the slot up: what the fused optimiser calls for each visible Gaussian.
  void slot_gradient(const GaussianParams<T>& g, const RenderCamera& cam, std::size_t slot,
                     T out[kParamGrads]) const;

  /// Runs fn(begin, end) over consecutive chunks of [0, n), each chunk claimed by whichever of
  /// the rasterizer's threads is free; fn must write only what its range owns.
  void for_ranges(std::size_t n, const std::function<void(std::size_t, std::size_t)>& fn);

  /// Gaussian i as the last forward pass projected it; empty when it was culled.
  [[nodiscard]] std::optional<ProjectedGaussian<T>> projected(std::size_t i) const;
  /// Ids of the Gaussians the last forward pass did not cull, ascending; a Gaussian's index
  /// here is its visible slot.
  [[nodiscard]] const std::vector<int>& visible_ids() const { return visible_ids_; }
  /// Gaussian i's visible slot in the last forward pass, or -1 (a binary search of
  /// visible_ids(): for the dense optimiser and tests, not per pixel).
  [[nodiscard]] int slot_of(std::size_t i) const;
  [[nodiscard]] std::size_t tile_pairs() const { return tile_ids_.size(); }
  /// Blocks the last forward pass culled whole (0 without blocks).
  [[nodiscard]] std::size_t culled_blocks() const { return culled_blocks_; }
  /// Most Gaussian-tile pairs one forward pass takes (1 GiB of tile ids, 10 GiB more of
  /// backward's pair gradients: the cap guards the int offsets, not memory); more throws
  /// std::length_error naming the counts (bin_tiles sums in 64 bits).
  static constexpr std::int64_t kMaxTilePairs = std::int64_t{1} << 28;
  /// Bytes held by this rasterizer's caches, from the current capacities: tile lists and
  /// backward's gradients (4 + 40 B per Gaussian-tile pair in float), projection record (32 B in
  /// float, per thread's share), kernel record (52 B in float), id, tile rectangle and pair
  /// offsets (per visible Gaussian). Nothing per Gaussian of the map. Not the per-tile offsets
  /// nor the per-thread tile scratch (sized by the fullest tile, not by the map).
  [[nodiscard]] std::size_t cache_bytes() const;
  /// True when the last forward used SIMD kernels, AVX2 or AVX-512 (backward uses the same ones:
  /// blend_kernel()).
  [[nodiscard]] bool used_simd() const { return used_simd_; }
  /// Whether the last forward() used the AVX-512 kernels (RasterSettings::use_avx512).
  [[nodiscard]] bool used_avx512() const { return used_avx512_; }

 private:
  enum class Kernel { kScalar, kAvx2, kAvx512 };
  /// The blending kernels forward() and backward use: AVX-512 with settings().use_simd and
  /// use_avx512, float, and a CPU with AVX-512 F + DQ; else AVX2 with use_simd, float, and a CPU
  /// with AVX2 and FMA; else scalar.
  [[nodiscard]] Kernel blend_kernel() const;
  void project_all(const GaussianParams<T>& g, const RenderCamera& cam, MapBlocks* blocks);
  void number_units();
  void bin_tiles(const GaussianParams<T>& g, const RenderCamera& cam);
  void gather_tile(int tile, std::vector<TileGaussian<T>>& buf) const;
  /// fn(member, item) for every item in [0, n), claimed by whichever member is free.
  void run_claimed(std::size_t n, const std::function<void(int, std::size_t)>& fn);
  [[nodiscard]] TileRect tile_rect(int tile, const RenderCamera& cam) const;
  [[nodiscard]] int threads() const { return pool_ ? pool_->size() : 1; }

  RasterSettings settings_;
  rt::WorkerTeam* pool_;
  /// Per thread: the projection records of the units it projected, each unit's visible
  /// Gaussians together in id order (ProjectedUnit says where). Only what a view sees is kept:
  /// a cache per Gaussian of the map (28 B, and 4 B of visible slot) was 14 % of the live
  /// mapper's bytes per Gaussian on a map of a million, for the tenth of it one view sees.
  /// `used` of them hold this pass's records; the rest is room kept (growing records only when
  /// a pass needs more, so a pass writes only what it projects). One cache line per thread.
  struct alignas(64) ThreadRecords {
    std::vector<ProjectedRecord<T>> records;
    std::size_t used = 0;
  };
  std::vector<ThreadRecords> projected_;
  int tiles_x_ = 0, tiles_y_ = 0;
  std::vector<int> tile_offsets_;  ///< tiles + 1
  std::vector<int> tile_ids_;      ///< visible slots per tile, near to far
  /// binning: per chunk of slots, its pair count, then its cursor, per tile
  std::vector<int> chunk_tile_;
  std::vector<std::vector<TileGaussian<T>>> gather_;  ///< per thread
  std::vector<std::vector<TileGrad<T>>> tile_grad_;   ///< per thread, one tile's gradients
  int n_visible_ = 0;
  std::vector<int> visible_ids_;  ///< slot -> Gaussian id
  /// per visible slot: its kernel record (projection, colour, depth, sigma cut, reach), which a
  /// tile's gather copies per pair
  std::vector<TileGaussian<T>> packed_;
  /// 4 per visible slot: its tiles x0, y0, x1, y1 (inclusive), 16 bits each
  std::vector<std::int16_t> slot_tiles_;
  std::vector<int> slot_pairs_;  ///< visible + 1: offsets of each slot's pairs in pair_grad_
  /// backward: per Gaussian-tile pair, grouped by visible slot, row-major tile order within one
  std::vector<TileGrad<T>> pair_grad_;
  std::vector<std::vector<float>> simd_scratch_;  ///< per thread, AVX2 backward sums
  std::vector<std::vector<int>> run_scratch_;     ///< per thread, AVX2 per-run Gaussian lists
  /// per thread: one tile's depth keys, then as many again of the radix sort's scratch
  std::vector<std::vector<std::uint64_t>> sort_keys_;
  bool used_simd_ = false;
  bool used_avx512_ = false;
  std::size_t culled_blocks_ = 0;
  /// Ranges of Gaussians the last projection kept (a block, or a chunk without blocks) that hold
  /// a visible Gaussian, in map order, with their first visible slot.
  struct ProjectedUnit {
    std::size_t lo, hi;
    int visible;  ///< -1: a block culled whole
    int first_slot;
    int member;          ///< the thread whose projected_ holds its records
    std::size_t record;  ///< its first record there
  };
  /// The records of unit u (visible of them, in id order).
  [[nodiscard]] const ProjectedRecord<T>* records(const ProjectedUnit& u) const {
    return projected_[static_cast<std::size_t>(u.member)].records.data() + u.record;
  }
  std::vector<ProjectedUnit> units_;
};

extern template class Rasterizer<float>;
extern template class Rasterizer<double>;

}  // namespace vigs::mapping
