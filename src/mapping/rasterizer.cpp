#include "mapping/rasterizer.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/capacity_bytes.hpp"
#include "core/grow_by_eighths.hpp"
#include "mapping/depth_key_sort.hpp"
#include "mapping/projection.hpp"
#include "mapping/projection_avx2.hpp"
#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

namespace {
constexpr int kGradPerGaussian = 10;  // mean2d 2, conic 3, opacity, colour 3, depth
/// Gaussians per claimed item of the per-Gaussian loops (projection, for_ranges): about
/// 50-100 us of work, so a claim's atomic is noise and a preempted member holds little back.
constexpr std::size_t kClaimChunk = 4096;
/// Visible Gaussians per claimed chunk of the binning's count and fill passes; each chunk keeps a
/// row of per-tile counts (1350 ints at 720x480), so chunks are larger there.
constexpr std::size_t kSlotChunk = 8192;
}  // namespace

template <class T>
Rasterizer<T>::Rasterizer(RasterSettings settings, rt::WorkerTeam* pool)
    : settings_(settings), pool_(pool) {
  const auto n = static_cast<std::size_t>(threads());
  gather_.resize(n);
  tile_grad_.resize(n);
  simd_scratch_.resize(n);
  run_scratch_.resize(n);
  sort_keys_.resize(n);
  projected_.resize(n);
}

template <class T>
void Rasterizer<T>::run_claimed(std::size_t n, const std::function<void(int, std::size_t)>& fn) {
  if (pool_) {
    pool_->run_claimed(n, fn);
  } else {
    for (std::size_t i = 0; i < n; ++i) fn(0, i);
  }
}

#if defined(VIGS_MAPPING_AVX2)
namespace {
/// project_all()'s loop for float with the AVX2 kernels: a conservative AVX2 pass drops most of
/// the Gaussians that fail the opacity test or may_reach_image() (most of a large map's visible
/// blocks), those tests decide exactly on the rest, and the covariance part of
/// project_gaussian() runs eight at a time (projection_avx2.hpp). The same Projection as the
/// scalar loop, bit for bit. Writes the visible ones of [b, e) to out[0..] in id order and
/// returns how many.
int project_range_lanes(const GaussianParams<float>& g, const RenderCamera& cam,
                        const ProjectionCamera& pc, float near_m, float min_alpha,
                        ProjectedRecord<float>* out, std::size_t b, std::size_t e) {
  constexpr int kLanes = ProjectionLanes::kLanes;
  constexpr std::size_t kSpan = 256;  // Gaussians per candidate pass
  ProjectionLanes lanes;
  std::size_t ids[kLanes];
  std::uint32_t candidates[kSpan];
  const float logit_min = static_cast<float>(std::log(min_alpha / (1.0 - min_alpha)));
  int n = 0, visible = 0;
  const auto flush = [&] {
    const int padded = (n + 7) / 8 * 8;
    for (int l = n; l < padded; ++l) {  // the batch's tail repeats its first Gaussian
      for (int k = 0; k < 3; ++k) lanes.mean_w[k][l] = lanes.mean_w[k][0];
      for (int k = 0; k < 3; ++k) lanes.scale[k][l] = lanes.scale[k][0];
      for (int k = 0; k < 4; ++k) lanes.quat_wxyz[k][l] = lanes.quat_wxyz[k][0];
    }
    project_lanes_avx2(pc, lanes, padded);
    for (int l = 0; l < n; ++l) {
      if (lanes.radius[l] == 0) continue;
      ProjectedRecord<float>& r = out[visible++];
      r.id = static_cast<int>(ids[l]);
      r.p.radius = lanes.radius[l];
      r.p.mean2d[0] = lanes.mean2d[0][l];
      r.p.mean2d[1] = lanes.mean2d[1][l];
      for (int k = 0; k < 3; ++k) r.p.conic[k] = lanes.conic[k][l];
      r.p.depth = lanes.depth[l];
    }
    n = 0;
  };
  for (std::size_t span = b; span < e; span += kSpan) {
    const std::size_t span_end = std::min(e, span + kSpan);
    const int nc = cull_candidates_avx2(pc, near_m, logit_min, g.mean_w.data(), g.log_scale.data(),
                                        g.opacity_logit.data(), span, span_end, candidates);
    for (int c = 0; c < nc; ++c) {
      const std::size_t i = candidates[c];
      const float o = sigmoid(g.opacity_logit[i]);
      const float* mean = &g.mean_w[3 * i];
      const float* log_scale = &g.log_scale[3 * i];
      if (o < min_alpha || !may_reach_image(cam, mean, log_scale, near_m, pc.eps2d)) continue;
      for (int k = 0; k < 3; ++k) lanes.mean_w[k][n] = mean[k];
      for (int k = 0; k < 3; ++k) lanes.scale[k][n] = std::exp(log_scale[k]);
      for (int k = 0; k < 4; ++k) lanes.quat_wxyz[k][n] = g.quat_wxyz[4 * i + k];
      ids[n++] = i;
      if (n == kLanes) flush();
    }
  }
  if (n > 0) flush();
  return visible;
}
}  // namespace
#endif

template <class T>
void Rasterizer<T>::project_all(const GaussianParams<T>& g, const RenderCamera& cam,
                                MapBlocks* blocks) {
  const std::size_t n = g.size();
  for (ThreadRecords& t : projected_) t.used = 0;
  const T near_m = T(settings_.near_m), eps = T(cam.lowpass_px2(settings_.eps2d_px2));
  // A Gaussian whose opacity is under min_alpha never reaches it at any pixel (both kernels
  // skip it: its sigma cut-off is negative), so culling it here renders exactly the same; this
  // is how a removed-but-not-yet-compacted Gaussian (kRemovedLogit) leaves the render at once.
  const T min_alpha = T(settings_.min_alpha);
#if defined(VIGS_MAPPING_AVX2)
  bool lanes = false;
  ProjectionCamera pc{};
  if constexpr (std::is_same_v<T, float>) {
    lanes = settings_.use_simd && avx2_kernel_available();
    if (lanes) pc = ProjectionCamera::from(cam, static_cast<float>(eps));
  }
#endif
  // Projects [b, e) into `member`'s records (room for all of them first, the visible ones
  // kept): the unit's records, visible count and place.
  auto project_range = [&](int member, std::size_t b, std::size_t e) {
    ThreadRecords& mine = projected_[static_cast<std::size_t>(member)];
    const std::size_t first = mine.used;
    if (mine.records.size() < first + (e - b)) resize_by_eighths(mine.records, first + (e - b));
    ProjectedRecord<T>* out = mine.records.data() + first;
    int visible = 0;
#if defined(VIGS_MAPPING_AVX2)
    if constexpr (std::is_same_v<T, float>) {
      if (lanes) visible = project_range_lanes(g, cam, pc, near_m, min_alpha, out, b, e);
    }
    if (!lanes) {
#else
    {
#endif
      ProjectedGaussian<T> pg;
      for (std::size_t i = b; i < e; ++i) {
        const T opacity = sigmoid(g.opacity_logit[i]);
        if (opacity < min_alpha) continue;
        project_gaussian(cam, &g.mean_w[3 * i], &g.log_scale[3 * i], &g.quat_wxyz[4 * i], near_m,
                         eps, pg);
        if (pg.radius == 0) continue;
        out[visible++] = ProjectedRecord<T>{pg, static_cast<int>(i)};
      }
    }
    mine.used = first + static_cast<std::size_t>(visible);
    return ProjectedUnit{b, e, visible, 0, member, first};
  };
  culled_blocks_ = 0;
  if constexpr (std::is_same_v<T, float>) {
    if (blocks) {
      blocks->update(g, pool_);
      const std::size_t nb = blocks->blocks();
      units_.resize(nb);
      // blocks claimed one at a time: the visible ones are usually a few neighbouring runs
      run_claimed(nb, [&](int member, std::size_t b) {
        const auto [lo, hi] = blocks->range(b);
        units_[b] = blocks->may_be_visible(b, cam, settings_)
                        ? project_range(member, lo, hi)
                        : ProjectedUnit{lo, hi, -1, 0, member, 0};
      });
      for (const ProjectedUnit& u : units_) culled_blocks_ += u.visible < 0 ? 1 : 0;
      number_units();
      return;
    }
  }
  units_.resize((n + kClaimChunk - 1) / kClaimChunk);
  run_claimed(units_.size(), [&](int member, std::size_t c) {
    const std::size_t lo = c * kClaimChunk, hi = std::min(n, lo + kClaimChunk);
    units_[c] = project_range(member, lo, hi);
  });
  number_units();
}

template <class T>
void Rasterizer<T>::number_units() {
  // Keep the units with a visible Gaussian, in map order, and give each its first visible slot:
  // slots then ascend with the Gaussian ids, whichever thread projected which unit.
  std::size_t kept = 0;
  int slot = 0;
  for (ProjectedUnit u : units_) {
    if (u.visible <= 0) continue;
    u.first_slot = slot;
    slot += u.visible;
    units_[kept++] = u;
  }
  units_.resize(kept);
  n_visible_ = slot;
}

template <class T>
void Rasterizer<T>::bin_tiles(const GaussianParams<T>& g, const RenderCamera& cam) {
  tiles_x_ = (cam.width_px + kTilePx - 1) / kTilePx;
  tiles_y_ = (cam.height_px + kTilePx - 1) / kTilePx;
  const int n_tiles = tiles_x_ * tiles_y_;
  if (tiles_x_ > std::numeric_limits<std::int16_t>::max() ||
      tiles_y_ > std::numeric_limits<std::int16_t>::max())
    throw std::length_error("rasterizer: a " + std::to_string(cam.width_px) + "x" +
                            std::to_string(cam.height_px) +
                            " px view has more tiles per row or column than 16-bit tile "
                            "coordinates hold");
  const std::size_t n = g.size();
  // A Gaussian's tiles: those its kernels can blend at all. A pixel contributes only where
  // sigma = d^T conic d / 2 <= sigma_cut (alpha >= min_alpha, tile_kernels.hpp), and that
  // ellipse reaches at most sqrt(2 sigma_cut Sigma_xx) across and sqrt(2 sigma_cut Sigma_yy)
  // down (Sigma = conic^-1), inside the 3-sigma square of the radius. A flat disc seen
  // obliquely (a corridor's walls and floor) is far narrower along one image axis than the
  // square, and each tile it leaves costs every pixel of that tile a test in the forward and
  // backward passes. The render is the same: only tiles where no pixel passes the kernels'
  // test are left out (1 % and 0.01 px of slack for the kernels' rounding).
  // Each visible Gaussian's kernel record (TileGaussian: the projection, colour, depth, the
  // kernels' sigma cut and reach for their row and run skip) is packed once per slot here, so
  // a tile's gather copies one record per pair instead of reading six arrays by Gaussian id.
  auto rect_of = [&](const ProjectedGaussian<T>& p, T rx, T ry, int& x0, int& y0, int& x1,
                     int& y1) {
    const T r = T(p.radius);
    rx = std::min(r, rx);
    ry = std::min(r, ry);
    const T u = p.mean2d[0], v = p.mean2d[1];
    x0 = std::max(0, static_cast<int>(std::floor((u - rx) / T(kTilePx))));
    y0 = std::max(0, static_cast<int>(std::floor((v - ry) / T(kTilePx))));
    x1 = std::min(tiles_x_ - 1, static_cast<int>(std::floor((u + rx) / T(kTilePx))));
    y1 = std::min(tiles_y_ - 1, static_cast<int>(std::floor((v + ry) / T(kTilePx))));
  };
  const auto n_vis = static_cast<std::size_t>(n_visible_);
  resize_by_eighths(visible_ids_, n_vis);
  resize_by_eighths(packed_, n_vis);  // per visible Gaussian, not per Gaussian
  resize_by_eighths(slot_tiles_, 4 * n_vis);
  resize_by_eighths(slot_pairs_, n_vis + 1);
  // Every pass below is claimed by whichever thread is free (units, then chunks of slots), and
  // none depends on which thread ran what: tile lists come out as a serial pass would make them.
  // 1. Per unit of projected Gaussians: slots, kernel reach and tile rectangle. Only the units
  // the projection kept, each from its visible Gaussians' records.
  run_claimed(units_.size(), [&](int, std::size_t u) {
    const ProjectedUnit& unit = units_[u];
    const ProjectedRecord<T>* records = this->records(unit);
    for (int k = 0; k < unit.visible; ++k) {
      const ProjectedGaussian<T>& p = records[k].p;
      const auto i = static_cast<std::size_t>(records[k].id);
      const auto s = static_cast<std::size_t>(unit.first_slot + k);
      visible_ids_[s] = records[k].id;
      TileGaussian<T>& tg = packed_[s];
      tg.x = p.mean2d[0];
      tg.y = p.mean2d[1];
      tg.ca = p.conic[0];
      tg.cb = p.conic[1];
      tg.cc = p.conic[2];
      tg.opacity = sigmoid(g.opacity_logit[i]);  // as the projection's cull computed it
      tg.r = g.color_rgb[3 * i];
      tg.g = g.color_rgb[3 * i + 1];
      tg.b = g.color_rgb[3 * i + 2];
      tg.z = p.depth;
      tg.sigma_cut = sigma_cutoff(tg.opacity, settings_.min_alpha);
      T rx = T(0), ry = T(0);
      kernel_reach(p.conic, tg.sigma_cut, rx, ry);
      tg.reach_x = settings_.skip_out_of_reach ? rx : std::numeric_limits<T>::infinity();
      tg.reach_y = settings_.skip_out_of_reach ? ry : std::numeric_limits<T>::infinity();
      int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
      rect_of(p, rx, ry, x0, y0, x1, y1);
      const bool any = x1 >= x0 && y1 >= y0;
      // 16-bit tile coordinates (checked above); an empty rectangle is stored as (0, 0, -1, -1)
      std::int16_t* rect = &slot_tiles_[4 * s];
      rect[0] = static_cast<std::int16_t>(any ? x0 : 0);
      rect[1] = static_cast<std::int16_t>(any ? y0 : 0);
      rect[2] = static_cast<std::int16_t>(any ? x1 : -1);
      rect[3] = static_cast<std::int16_t>(any ? y1 : -1);
      slot_pairs_[s + 1] = any ? (x1 - x0 + 1) * (y1 - y0 + 1) : 0;
    }
  });
  // Offsets are int (the kernels index with them): the pairs are summed in 64 bits and bounded
  // before they are used, so a map whose Gaussians cover too many tiles is a clear error, not an
  // overflowed offset.
  slot_pairs_[0] = 0;
  std::int64_t pairs = 0;
  for (std::size_t s = 0; s < n_vis; ++s) {
    pairs += slot_pairs_[s + 1];
    if (pairs > kMaxTilePairs) {
      throw std::length_error("rasterizer: more than " + std::to_string(kMaxTilePairs) +
                              " Gaussian-tile pairs (at Gaussian " +
                              std::to_string(visible_ids_[s]) + " of " + std::to_string(n) + ", " +
                              std::to_string(n_tiles) + " tiles of " + std::to_string(kTilePx) +
                              " px); the map has too many or too large Gaussians for this view");
    }
    slot_pairs_[s + 1] = static_cast<int>(pairs);
  }
  // 2. Pairs per tile, counted per chunk of slots (each chunk its own row of counts).
  const std::size_t chunks = (n_vis + kSlotChunk - 1) / kSlotChunk;
  const auto tiles = static_cast<std::size_t>(n_tiles);
  chunk_tile_.resize(chunks * tiles);
  run_claimed(chunks, [&](int, std::size_t c) {
    int* count = chunk_tile_.data() + c * tiles;
    std::fill(count, count + tiles, 0);
    for (std::size_t s = c * kSlotChunk, e = std::min(n_vis, s + kSlotChunk); s < e; ++s) {
      const std::int16_t* rect = &slot_tiles_[4 * s];
      for (int ty = rect[1]; ty <= rect[3]; ++ty)
        for (int tx = rect[0]; tx <= rect[2]; ++tx) ++count[ty * tiles_x_ + tx];
    }
  });
  // Tile offsets, and each chunk's first position in each tile (chunks in slot order).
  tile_offsets_.resize(tiles + 1);
  int at = 0;
  for (std::size_t t = 0; t < tiles; ++t) {
    tile_offsets_[t] = at;
    for (std::size_t c = 0; c < chunks; ++c) {
      int& count = chunk_tile_[c * tiles + t];
      const int here = count;
      count = at;  // from now on: the chunk's cursor in tile t
      at += here;
    }
  }
  tile_offsets_[tiles] = at;
  // 3. Fill: each chunk writes its Gaussians at its own cursors, in slot (= id) order.
  tile_ids_.resize(static_cast<std::size_t>(at));
  run_claimed(chunks, [&](int, std::size_t c) {
    int* cursor = chunk_tile_.data() + c * tiles;
    for (std::size_t s = c * kSlotChunk, e = std::min(n_vis, s + kSlotChunk); s < e; ++s) {
      const std::int16_t* rect = &slot_tiles_[4 * s];
      for (int ty = rect[1]; ty <= rect[3]; ++ty)
        for (int tx = rect[0]; tx <= rect[2]; ++tx)
          tile_ids_[static_cast<std::size_t>(cursor[ty * tiles_x_ + tx]++)] = static_cast<int>(s);
    }
  });
  run_claimed(static_cast<std::size_t>(n_tiles), [&](int t, std::size_t tile) {
    int* b = tile_ids_.data() + tile_offsets_[tile];
    int* e = tile_ids_.data() + tile_offsets_[tile + 1];
    if constexpr (std::is_same_v<T, float>) {
      // Near to far, ties by slot (slots ascend with the Gaussian ids: ties by id), sorted as
      // 64-bit keys (depth's bits above the slot): a visible Gaussian's depth is finite and
      // beyond the near plane, and positive floats order as their bit patterns, so this is the
      // comparator's order below without a depth load per compare. The list is in slot order
      // (the fill above), so a stable sort by depth is this order.
      const auto n_keys = static_cast<std::size_t>(e - b);
      std::vector<std::uint64_t>& keys = sort_keys_[static_cast<std::size_t>(t)];
      if (keys.size() < 2 * n_keys) keys.resize(2 * n_keys);  // the keys, then the scratch
      for (std::size_t k = 0; k < n_keys; ++k) {
        const int slot = b[k];
        keys[k] =
            (std::uint64_t{std::bit_cast<std::uint32_t>(packed_[static_cast<std::size_t>(slot)].z)}
             << 32) |
            static_cast<std::uint32_t>(slot);
      }
      sort_depth_keys(keys.data(), keys.data() + n_keys, n_keys);
      for (std::size_t k = 0; k < n_keys; ++k) b[k] = static_cast<int>(keys[k] & 0xffffffffu);
    } else {
      std::sort(b, e, [&](int a, int c) {
        const T da = packed_[static_cast<std::size_t>(a)].z,
                dc = packed_[static_cast<std::size_t>(c)].z;
        return da < dc || (da == dc && a < c);
      });
    }
  });
}

template <class T>
void Rasterizer<T>::gather_tile(int tile, std::vector<TileGaussian<T>>& buf) const {
  const int b = tile_offsets_[tile], e = tile_offsets_[tile + 1];
  buf.resize(static_cast<std::size_t>(e - b));
  for (int k = b; k < e; ++k)
    buf[static_cast<std::size_t>(k - b)] = packed_[static_cast<std::size_t>(tile_ids_[k])];
}

template <class T>
typename Rasterizer<T>::Kernel Rasterizer<T>::blend_kernel() const {
  if constexpr (std::is_same_v<T, float>) {
    if (settings_.use_simd && avx2_kernel_available())
      return settings_.use_avx512 && avx512_kernel_available() ? Kernel::kAvx512 : Kernel::kAvx2;
  }
  return Kernel::kScalar;
}

template <class T>
void Rasterizer<T>::forward(const GaussianParams<T>& g, const RenderCamera& cam,
                            RenderResult<T>& out, MapBlocks* blocks) {
  project_all(g, cam, blocks);
  bin_tiles(g, cam);
  const std::size_t n_px = static_cast<std::size_t>(cam.width_px) * cam.height_px;
  out.width = cam.width_px;
  out.height = cam.height_px;
  out.color.resize(3 * n_px);
  out.depth.resize(n_px);
  out.final_T.resize(n_px);
  out.n_contrib.resize(n_px);
  PixelOutputs<T> po{cam.width_px, out.color.data(), out.depth.data(), out.final_T.data(),
                     out.n_contrib.data()};
  const Kernel kernel = blend_kernel();
  used_simd_ = kernel != Kernel::kScalar;
  used_avx512_ = kernel == Kernel::kAvx512;
  const auto n_tiles = static_cast<std::size_t>(tiles_x_ * tiles_y_);
  // Each tile writes only its own pixels: which member blends it does not change the render.
  run_claimed(n_tiles, [&](int t, std::size_t tile_index) {
    const int tile = static_cast<int>(tile_index);
    auto& buf = gather_[static_cast<std::size_t>(t)];
    const TileRect rect = tile_rect(tile, cam);
    gather_tile(tile, buf);
    const int count = static_cast<int>(buf.size());
    if constexpr (std::is_same_v<T, float>) {
      if (kernel == Kernel::kAvx512) {
        auto& block_lists = run_scratch_[static_cast<std::size_t>(t)];
        block_lists.resize(tile_block_scratch(rect, count));
        forward_tile_avx512(rect, buf.data(), count, settings_, po, block_lists.data());
        return;
      }
      if (kernel == Kernel::kAvx2) {
        auto& runs = run_scratch_[static_cast<std::size_t>(t)];
        runs.resize(tile_run_scratch(rect, count));
        forward_tile_avx2(rect, buf.data(), count, settings_, po, runs.data());
        return;
      }
    }
    forward_tile_scalar(rect, buf.data(), count, settings_, po);
  });
}

template <class T>
void Rasterizer<T>::accumulate_gradients(const RenderCamera& cam, const RenderResult<T>& out,
                                         const T* v_color, const T* v_depth, const T* v_alpha) {
  const int n_tiles = tiles_x_ * tiles_y_;
  // Accumulated opacity is 1 - T_final: its gradient enters as dL/dalpha.
  const Kernel kernel = blend_kernel();
  // Per-pixel reverse pass, tiles claimed by whichever member is free. A tile's gradients go
  // to its own pairs' entries of pair_grad_, which is laid out per Gaussian (slot_pairs_) and,
  // within a Gaussian, by its tiles in row-major order (slot_tiles_): gaussian_gradient() then
  // sums one contiguous run in tile order. No entry is written twice, and the sum's order is
  // the Gaussian's own, so the gradient does not depend on which member blended which tile,
  // nor on the team's size.
  resize_by_eighths(pair_grad_, tile_ids_.size());
  run_claimed(static_cast<std::size_t>(n_tiles), [&](int t, std::size_t tile_index) {
    const int tile = static_cast<int>(tile_index);
    const int b = tile_offsets_[tile], e = tile_offsets_[tile + 1];
    if (b == e) return;
    const TileRect rect = tile_rect(tile, cam);
    auto& buf = gather_[static_cast<std::size_t>(t)];
    gather_tile(tile, buf);
    auto& tg = tile_grad_[static_cast<std::size_t>(t)];
    tg.assign(static_cast<std::size_t>(e - b), TileGrad<T>{});
    bool done = false;
    if constexpr (std::is_same_v<T, float>) {
      if (kernel == Kernel::kAvx512) {
        auto& scratch = simd_scratch_[static_cast<std::size_t>(t)];
        scratch.resize(tile_grad_scratch_avx512(e - b));
        auto& block_lists = run_scratch_[static_cast<std::size_t>(t)];
        block_lists.resize(tile_block_scratch(rect, e - b));
        backward_tile_avx512(rect, buf.data(), e - b, settings_, out.width, out.final_T.data(),
                             out.n_contrib.data(), v_color, v_depth, v_alpha, tg.data(),
                             scratch.data(), block_lists.data());
        done = true;
      } else if (kernel == Kernel::kAvx2) {
        auto& scratch = simd_scratch_[static_cast<std::size_t>(t)];
        scratch.resize(static_cast<std::size_t>(e - b) * 80);
        auto& runs = run_scratch_[static_cast<std::size_t>(t)];
        runs.resize(tile_run_scratch(rect, e - b));
        backward_tile_avx2(rect, buf.data(), e - b, settings_, out.width, out.final_T.data(),
                           out.n_contrib.data(), v_color, v_depth, v_alpha, tg.data(),
                           scratch.data(), runs.data());
        done = true;
      }
    }
    if (!done)
      backward_tile_scalar(rect, buf.data(), settings_, out.width, out.final_T.data(),
                           out.n_contrib.data(), v_color, v_depth, v_alpha, tg.data());
    const int tx = tile % tiles_x_, ty = tile / tiles_x_;
    for (int k = b; k < e; ++k) {
      const auto slot = static_cast<std::size_t>(tile_ids_[k]);
      const std::int16_t* r = &slot_tiles_[4 * slot];
      const int local = (ty - r[1]) * (r[2] - r[0] + 1) + (tx - r[0]);
      pair_grad_[static_cast<std::size_t>(slot_pairs_[slot] + local)] =
          tg[static_cast<std::size_t>(k - b)];
    }
  });
}

template <class T>
int Rasterizer<T>::slot_of(std::size_t i) const {
  const auto end = visible_ids_.begin() + n_visible_;
  const auto it = std::lower_bound(visible_ids_.begin(), end, static_cast<int>(i));
  return it != end && *it == static_cast<int>(i) ? static_cast<int>(it - visible_ids_.begin()) : -1;
}

template <class T>
std::optional<ProjectedGaussian<T>> Rasterizer<T>::projected(std::size_t i) const {
  const int slot = slot_of(i);
  if (slot < 0) return std::nullopt;
  // the unit holding the slot: the last with first_slot <= slot
  const auto unit =
      std::prev(std::upper_bound(units_.begin(), units_.end(), slot,
                                 [](int s, const ProjectedUnit& u) { return s < u.first_slot; }));
  return records(*unit)[slot - unit->first_slot].p;
}

template <class T>
void Rasterizer<T>::gaussian_gradient(const GaussianParams<T>& g, const RenderCamera& cam,
                                      std::size_t i, T out[kParamGrads]) const {
  const int slot = slot_of(i);
  if (slot < 0) {
    for (int k = 0; k < kParamGrads; ++k) out[k] = T(0);
    return;
  }
  slot_gradient(g, cam, static_cast<std::size_t>(slot), out);
}

template <class T>
void Rasterizer<T>::slot_gradient(const GaussianParams<T>& g, const RenderCamera& cam,
                                  std::size_t slot, T out[kParamGrads]) const {
  for (int k = 0; k < kParamGrads; ++k) out[k] = T(0);
  const auto i = static_cast<std::size_t>(visible_ids_[slot]);
  T v[kGradPerGaussian] = {};
  for (int k = slot_pairs_[slot]; k < slot_pairs_[slot + 1]; ++k) {
    const TileGrad<T>& s = pair_grad_[static_cast<std::size_t>(k)];
    v[0] += s.x;
    v[1] += s.y;
    v[2] += s.ca;
    v[3] += s.cb;
    v[4] += s.cc;
    v[5] += s.opacity;
    v[6] += s.r;
    v[7] += s.g;
    v[8] += s.b;
    v[9] += s.z;
  }
  project_gaussian_vjp(cam, &g.mean_w[3 * i], &g.log_scale[3 * i], &g.quat_wxyz[4 * i],
                       T(cam.lowpass_px2(settings_.eps2d_px2)), &v[0], &v[2], v[9], &out[0],
                       &out[3], &out[6]);
  const T op = packed_[slot].opacity;
  out[10] = v[5] * op * (T(1) - op);
  for (int k = 0; k < 3; ++k) out[11 + k] = v[6 + k];
}

template <class T>
void Rasterizer<T>::for_ranges(std::size_t n,
                               const std::function<void(std::size_t, std::size_t)>& fn) {
  run_claimed((n + kClaimChunk - 1) / kClaimChunk,
              [&](int, std::size_t c) { fn(c * kClaimChunk, std::min(n, (c + 1) * kClaimChunk)); });
}

template <class T>
TileRect Rasterizer<T>::tile_rect(int tile, const RenderCamera& cam) const {
  const int tx = tile % tiles_x_, ty = tile / tiles_x_;
  return TileRect{tx * kTilePx, ty * kTilePx, std::min(cam.width_px, (tx + 1) * kTilePx),
                  std::min(cam.height_px, (ty + 1) * kTilePx)};
}

template <class T>
void Rasterizer<T>::backward(const GaussianParams<T>& g, const RenderCamera& cam,
                             const RenderResult<T>& out, const T* v_color, const T* v_depth,
                             const T* v_alpha, GaussianParams<T>& grad) {
  accumulate_gradients(cam, out, v_color, v_depth, v_alpha);
  grad.assign_zero(g.size());  // a culled Gaussian's gradient is zero
  for_ranges(static_cast<std::size_t>(n_visible_), [&](std::size_t b, std::size_t e) {
    T v[kParamGrads];
    for (std::size_t s = b; s < e; ++s) {
      slot_gradient(g, cam, s, v);
      const auto i = static_cast<std::size_t>(visible_ids_[s]);
      for (int k = 0; k < 3; ++k) {
        grad.mean_w[3 * i + k] = v[k];
        grad.log_scale[3 * i + k] = v[3 + k];
        grad.color_rgb[3 * i + k] = v[11 + k];
      }
      for (int k = 0; k < 4; ++k) grad.quat_wxyz[4 * i + k] = v[6 + k];
      grad.opacity_logit[i] = v[10];
    }
  });
}

template <class T>
std::size_t Rasterizer<T>::cache_bytes() const {
  std::size_t bytes = capacity_bytes(tile_ids_, visible_ids_, packed_, slot_tiles_, slot_pairs_,
                                     pair_grad_, units_, chunk_tile_);
  for (const ThreadRecords& t : projected_) bytes += capacity_bytes(t.records);
  return bytes;
}

template class Rasterizer<float>;
template class Rasterizer<double>;

}  // namespace vigs::mapping
