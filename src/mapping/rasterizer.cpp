#include "mapping/rasterizer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "core/capacity_bytes.hpp"
#include "core/grow_by_eighths.hpp"
#include "mapping/projection.hpp"
#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

namespace {
constexpr int kGradPerGaussian = 10;  // mean2d 2, conic 3, opacity, colour 3, depth
/// Gaussians per claimed item of the per-Gaussian loops (projection, for_ranges): about
/// 50-100 us of work, so a claim's atomic is noise and a preempted member holds little back.
constexpr std::size_t kClaimChunk = 4096;
}  // namespace

template <class T>
Rasterizer<T>::Rasterizer(RasterSettings settings, rt::WorkerTeam* pool)
    : settings_(settings), pool_(pool) {
  const auto n = static_cast<std::size_t>(threads());
  gather_.resize(n);
  tile_grad_.resize(n);
  simd_scratch_.resize(n);
  run_scratch_.resize(n);
}

template <class T>
void Rasterizer<T>::run(const std::function<void(int)>& fn) {
  if (pool_) {
    pool_->run(fn);
  } else {
    fn(0);
  }
}

template <class T>
void Rasterizer<T>::run_claimed(std::size_t n, const std::function<void(int, std::size_t)>& fn) {
  if (pool_) {
    pool_->run_claimed(n, fn);
  } else {
    for (std::size_t i = 0; i < n; ++i) fn(0, i);
  }
}

template <class T>
void Rasterizer<T>::project_all(const GaussianParams<T>& g, const RenderCamera& cam,
                                MapBlocks* blocks) {
  const std::size_t n = g.size();
  resize_by_eighths(proj_.mean2d, 2 * n);  // the map grows a keyframe at a time
  resize_by_eighths(proj_.conic, 3 * n);
  resize_by_eighths(proj_.depth, n);
  resize_by_eighths(proj_.opacity, n);
  resize_by_eighths(proj_.radius, n);
  const T near_m = T(settings_.near_m), eps = T(settings_.eps2d_px2);
  // A Gaussian whose opacity is under min_alpha never reaches it at any pixel (both kernels
  // skip it: its sigma cut-off is negative), so culling it here renders exactly the same; this
  // is how a removed-but-not-yet-compacted Gaussian (kRemovedLogit) leaves the render at once.
  const T min_alpha = T(settings_.min_alpha);
  auto project_range = [&](std::size_t b, std::size_t e) {
    ProjectedGaussian<T> pg;
    for (std::size_t i = b; i < e; ++i) {
      const T opacity = sigmoid(g.opacity_logit[i]);
      if (opacity < min_alpha) {
        proj_.radius[i] = 0;
        continue;
      }
      project_gaussian(cam, &g.mean_w[3 * i], &g.log_scale[3 * i], &g.quat_wxyz[4 * i], near_m, eps,
                       pg);
      proj_.radius[i] = pg.radius;
      if (pg.radius == 0) continue;
      proj_.mean2d[2 * i] = pg.mean2d[0];
      proj_.mean2d[2 * i + 1] = pg.mean2d[1];
      for (int k = 0; k < 3; ++k) proj_.conic[3 * i + k] = pg.conic[k];
      proj_.depth[i] = pg.depth;
      proj_.opacity[i] = opacity;
    }
  };
  culled_blocks_ = 0;
  if constexpr (std::is_same_v<T, float>) {
    if (blocks) {
      blocks->update(g);
      const std::size_t nb = blocks->blocks();
      block_projected_.resize(nb);
      // blocks claimed one at a time: the visible ones are usually a few neighbouring runs
      run_claimed(nb, [&](int, std::size_t b) {
        const auto [lo, hi] = blocks->range(b);
        const bool seen = blocks->may_be_visible(b, cam, settings_);
        block_projected_[b] = seen ? 1 : 0;
        if (seen) {
          project_range(lo, hi);
        } else {
          std::fill(proj_.radius.begin() + static_cast<std::ptrdiff_t>(lo),
                    proj_.radius.begin() + static_cast<std::ptrdiff_t>(hi), 0);
        }
      });
      ranges_.clear();
      for (std::size_t b = 0; b < nb; ++b) {
        if (!block_projected_[b]) {
          ++culled_blocks_;
          continue;
        }
        const auto [lo, hi] = blocks->range(b);
        if (!ranges_.empty() && ranges_.back().second == lo) {
          ranges_.back().second = hi;
        } else {
          ranges_.emplace_back(lo, hi);
        }
      }
      return;
    }
  }
  for_ranges(n, project_range);
  ranges_.assign(1, {0, n});
}

template <class T>
void Rasterizer<T>::bin_tiles(const RenderCamera& cam) {
  tiles_x_ = (cam.width_px + kTilePx - 1) / kTilePx;
  tiles_y_ = (cam.height_px + kTilePx - 1) / kTilePx;
  const int n_tiles = tiles_x_ * tiles_y_;
  const std::size_t n = proj_.radius.size();
  tile_offsets_.assign(static_cast<std::size_t>(n_tiles) + 1, 0);
  // A Gaussian's tiles: those its kernels can blend at all. A pixel contributes only where
  // sigma = d^T conic d / 2 <= sigma_cut (alpha >= min_alpha, tile_kernels.hpp), and that
  // ellipse reaches at most sqrt(2 sigma_cut Sigma_xx) across and sqrt(2 sigma_cut Sigma_yy)
  // down (Sigma = conic^-1), inside the 3-sigma square of the radius. A flat disc seen
  // obliquely (a corridor's walls and floor) is far narrower along one image axis than the
  // square, and each tile it leaves costs every pixel of that tile a test in the forward and
  // backward passes. The render is the same: only tiles where no pixel passes the kernels'
  // test are left out (1 % and 0.01 px of slack for the kernels' rounding).
  // The reach is kept per visible Gaussian for the kernels' row and run skip (gather_tile).
  auto rect_of = [&](std::size_t i, T rx, T ry, int& x0, int& y0, int& x1, int& y1) {
    const T r = T(proj_.radius[i]);
    rx = std::min(r, rx);
    ry = std::min(r, ry);
    const T u = proj_.mean2d[2 * i], v = proj_.mean2d[2 * i + 1];
    x0 = std::max(0, static_cast<int>(std::floor((u - rx) / T(kTilePx))));
    y0 = std::max(0, static_cast<int>(std::floor((v - ry) / T(kTilePx))));
    x1 = std::min(tiles_x_ - 1, static_cast<int>(std::floor((u + rx) / T(kTilePx))));
    y1 = std::min(tiles_y_ - 1, static_cast<int>(std::floor((v + ry) / T(kTilePx))));
  };
  resize_by_eighths(visible_slot_, n);
  resize_by_eighths(visible_ids_, n);
  std::size_t visible = 0;
  for (const auto& [lo, hi] : ranges_)
    for (std::size_t i = lo; i < hi; ++i) visible += proj_.radius[i] != 0 ? 1 : 0;
  resize_by_eighths(reach_, 2 * visible);  // per visible Gaussian, not per Gaussian
  resize_by_eighths(slot_tiles_, 4 * visible);
  resize_by_eighths(slot_pairs_, visible + 1);
  slot_pairs_[0] = 0;
  n_visible_ = 0;
  // Offsets are int (the kernels index with them): the pairs are summed in 64 bits and bounded
  // before they are counted, so a map whose Gaussians cover too many tiles is a clear error, not
  // an overflowed offset.
  // Only the ranges the projection looked at: a culled block's Gaussians have radius 0, and
  // their visible_slot_ entries are never read (every reader checks the radius first).
  std::int64_t pairs = 0;
  for (const auto& [lo, hi] : ranges_)
    for (std::size_t i = lo; i < hi; ++i) {
      if (proj_.radius[i] == 0) {
        visible_slot_[i] = -1;
        continue;
      }
      const auto slot = static_cast<std::size_t>(n_visible_);
      visible_ids_[slot] = static_cast<int>(i);
      visible_slot_[i] = n_visible_++;
      T& rx = reach_[2 * slot];
      T& ry = reach_[2 * slot + 1];
      kernel_reach(&proj_.conic[3 * i], sigma_cutoff(proj_.opacity[i], settings_.min_alpha), rx,
                   ry);
      int x0, y0, x1, y1;
      rect_of(i, rx, ry, x0, y0, x1, y1);
      int* rect = &slot_tiles_[4 * slot];
      rect[0] = x0;
      rect[1] = y0;
      rect[2] = x1;
      rect[3] = y1;
      if (x1 >= x0 && y1 >= y0) pairs += std::int64_t{x1 - x0 + 1} * (y1 - y0 + 1);
      if (pairs > kMaxTilePairs) {
        throw std::length_error("rasterizer: more than " + std::to_string(kMaxTilePairs) +
                                " Gaussian-tile pairs (at Gaussian " + std::to_string(i) + " of " +
                                std::to_string(n) + ", " + std::to_string(n_tiles) + " tiles of " +
                                std::to_string(kTilePx) +
                                " px); the map has too many or too large Gaussians for this view");
      }
      slot_pairs_[slot + 1] = static_cast<int>(pairs);
      for (int ty = y0; ty <= y1; ++ty)
        for (int tx = x0; tx <= x1; ++tx)
          ++tile_offsets_[static_cast<std::size_t>(ty * tiles_x_ + tx) + 1];
    }
  visible_ids_.resize(static_cast<std::size_t>(n_visible_));
  for (int t = 0; t < n_tiles; ++t) tile_offsets_[t + 1] += tile_offsets_[t];
  tile_ids_.resize(static_cast<std::size_t>(tile_offsets_[n_tiles]));
  tile_cursor_.assign(tile_offsets_.begin(), tile_offsets_.end() - 1);
  for (const auto& [lo, hi] : ranges_)
    for (std::size_t i = lo; i < hi; ++i) {
      if (proj_.radius[i] == 0) continue;
      const int* rect = &slot_tiles_[4 * static_cast<std::size_t>(visible_slot_[i])];
      for (int ty = rect[1]; ty <= rect[3]; ++ty)
        for (int tx = rect[0]; tx <= rect[2]; ++tx)
          tile_ids_[static_cast<std::size_t>(tile_cursor_[ty * tiles_x_ + tx]++)] =
              static_cast<int>(i);
    }
  run_claimed(static_cast<std::size_t>(n_tiles), [&](int, std::size_t tile) {
    auto* b = tile_ids_.data() + tile_offsets_[tile];
    auto* e = tile_ids_.data() + tile_offsets_[tile + 1];
    std::sort(b, e, [&](int a, int c) {
      const T da = proj_.depth[a], dc = proj_.depth[c];
      return da < dc || (da == dc && a < c);
    });
  });
}

template <class T>
void Rasterizer<T>::gather_tile(int tile, std::vector<TileGaussian<T>>& buf,
                                const GaussianParams<T>& g) const {
  const int b = tile_offsets_[tile], e = tile_offsets_[tile + 1];
  buf.resize(static_cast<std::size_t>(e - b));
  for (int k = b; k < e; ++k) {
    const auto i = static_cast<std::size_t>(tile_ids_[k]);
    TileGaussian<T>& tg = buf[static_cast<std::size_t>(k - b)];
    tg.x = proj_.mean2d[2 * i];
    tg.y = proj_.mean2d[2 * i + 1];
    tg.ca = proj_.conic[3 * i];
    tg.cb = proj_.conic[3 * i + 1];
    tg.cc = proj_.conic[3 * i + 2];
    tg.opacity = proj_.opacity[i];
    tg.r = g.color_rgb[3 * i];
    tg.g = g.color_rgb[3 * i + 1];
    tg.b = g.color_rgb[3 * i + 2];
    tg.z = proj_.depth[i];
    tg.sigma_cut = sigma_cutoff(tg.opacity, settings_.min_alpha);
    const auto slot = 2 * static_cast<std::size_t>(visible_slot_[i]);
    tg.reach_x = settings_.skip_out_of_reach ? reach_[slot] : std::numeric_limits<T>::infinity();
    tg.reach_y =
        settings_.skip_out_of_reach ? reach_[slot + 1] : std::numeric_limits<T>::infinity();
  }
}

template <class T>
void Rasterizer<T>::forward(const GaussianParams<T>& g, const RenderCamera& cam,
                            RenderResult<T>& out, MapBlocks* blocks) {
  project_all(g, cam, blocks);
  bin_tiles(cam);
  const std::size_t n_px = static_cast<std::size_t>(cam.width_px) * cam.height_px;
  out.width = cam.width_px;
  out.height = cam.height_px;
  out.color.resize(3 * n_px);
  out.depth.resize(n_px);
  out.final_T.resize(n_px);
  out.n_contrib.resize(n_px);
  PixelOutputs<T> po{cam.width_px, out.color.data(), out.depth.data(), out.final_T.data(),
                     out.n_contrib.data()};
  bool simd = false;
  if constexpr (std::is_same_v<T, float>) simd = settings_.use_simd && avx2_kernel_available();
  used_simd_ = simd;
  const auto n_tiles = static_cast<std::size_t>(tiles_x_ * tiles_y_);
  // Each tile writes only its own pixels: which member blends it does not change the render.
  run_claimed(n_tiles, [&](int t, std::size_t tile_index) {
    const int tile = static_cast<int>(tile_index);
    auto& buf = gather_[static_cast<std::size_t>(t)];
    const TileRect rect = tile_rect(tile, cam);
    gather_tile(tile, buf, g);
    const int count = static_cast<int>(buf.size());
    if constexpr (std::is_same_v<T, float>) {
      if (simd) {
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
void Rasterizer<T>::accumulate_gradients(const GaussianParams<T>& g, const RenderCamera& cam,
                                         const RenderResult<T>& out, const T* v_color,
                                         const T* v_depth, const T* v_alpha) {
  const int n_tiles = tiles_x_ * tiles_y_;
  // Accumulated opacity is 1 - T_final: its gradient enters as dL/dalpha.
  bool simd = false;
  if constexpr (std::is_same_v<T, float>) simd = settings_.use_simd && avx2_kernel_available();
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
    gather_tile(tile, buf, g);
    auto& tg = tile_grad_[static_cast<std::size_t>(t)];
    tg.assign(static_cast<std::size_t>(e - b), TileGrad<T>{});
    bool done = false;
    if constexpr (std::is_same_v<T, float>) {
      if (simd) {
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
      const auto slot =
          static_cast<std::size_t>(visible_slot_[static_cast<std::size_t>(tile_ids_[k])]);
      const int* r = &slot_tiles_[4 * slot];
      const int local = (ty - r[1]) * (r[2] - r[0] + 1) + (tx - r[0]);
      pair_grad_[static_cast<std::size_t>(slot_pairs_[slot] + local)] =
          tg[static_cast<std::size_t>(k - b)];
    }
  });
}

template <class T>
void Rasterizer<T>::gaussian_gradient(const GaussianParams<T>& g, const RenderCamera& cam,
                                      std::size_t i, T out[kParamGrads]) const {
  for (int k = 0; k < kParamGrads; ++k) out[k] = T(0);
  if (proj_.radius[i] == 0) return;
  T v[kGradPerGaussian] = {};
  const auto slot = static_cast<std::size_t>(visible_slot_[i]);
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
                       T(settings_.eps2d_px2), &v[0], &v[2], v[9], &out[0], &out[3], &out[6]);
  const T op = proj_.opacity[i];
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
  accumulate_gradients(g, cam, out, v_color, v_depth, v_alpha);
  const std::size_t n = g.size();
  grad.assign_zero(n);
  for_ranges(n, [&](std::size_t b, std::size_t e) {
    T v[kParamGrads];
    for (std::size_t i = b; i < e; ++i) {
      gaussian_gradient(g, cam, i, v);
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
  std::size_t bytes =
      capacity_bytes(proj_.mean2d, proj_.conic, proj_.depth, proj_.opacity, proj_.radius, tile_ids_,
                     visible_slot_, visible_ids_, reach_, slot_tiles_, slot_pairs_, pair_grad_);
  return bytes;
}

template class Rasterizer<float>;
template class Rasterizer<double>;

}  // namespace vigs::mapping
