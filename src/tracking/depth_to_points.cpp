#include "tracking/depth_to_points.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vigs::tracking {

DepthToPoints::DepthToPoints(const PinholeCamera& camera, const Setting& setting)
    : camera_(camera), setting_(setting) {
  if (setting_.voxel_size_m > 0.0) voxel_keys_.reserve(max_points());
}

std::size_t DepthToPoints::max_points() const {
  const auto stride = static_cast<std::size_t>(std::max(1, setting_.pixel_stride));
  const auto w = static_cast<std::size_t>(std::max(0, camera_.width_px));
  const auto h = static_cast<std::size_t>(std::max(0, camera_.height_px));
  return ((w + stride - 1) / stride) * ((h + stride - 1) / stride);
}

namespace {

void check_sizes(const RgbdView& frame, const PinholeCamera& camera) {
  if (frame.width_px <= 0 || frame.height_px <= 0) {
    throw std::invalid_argument("depth image is empty");
  }
  if (camera.width_px != 0 &&
      (camera.width_px != frame.width_px || camera.height_px != frame.height_px)) {
    throw std::invalid_argument("depth image is " + std::to_string(frame.width_px) + "x" +
                                std::to_string(frame.height_px) + " but the camera is " +
                                std::to_string(camera.width_px) + "x" +
                                std::to_string(camera.height_px));
  }
}

}  // namespace

template <class DepthAt>
DepthToPointsStats DepthToPoints::convert_impl(const RgbdView& frame, DepthAt depth_at,
                                               GaussianCloud& out, PixelGrid* grid) {
  check_sizes(frame, camera_);
  const int width = frame.width_px, height = frame.height_px;
  out.clear();
  const int stride = std::max(1, setting_.pixel_stride);
  out.points_m.reserve(static_cast<std::size_t>((width + stride - 1) / stride) *
                       ((height + stride - 1) / stride));
  out.colors_rgb.reserve(out.points_m.capacity());
  DepthToPointsStats stats;
  if (grid != nullptr) {
    grid->width = (width + stride - 1) / stride;
    grid->height = (height + stride - 1) / stride;
    grid->stride_px = stride;
    grid->camera = camera_;
    grid->point_at.assign(static_cast<std::size_t>(grid->width) * grid->height, -1);
    grid->cell_of.clear();
    grid->cell_of.reserve(grid->point_at.size());
  }
  const double inv_fx = 1.0 / camera_.fx_px;
  const double inv_fy = 1.0 / camera_.fy_px;
  for (int v = 0; v < height; v += stride) {
    for (int u = 0; u < width; u += stride) {
      ++stats.sampled;
      const double z = depth_at(u, v);
      if (!(z > 0.0) || !std::isfinite(z)) {
        ++stats.invalid;
        continue;
      }
      if (z < setting_.near_m) {
        ++stats.too_near;
        continue;
      }
      if (z > setting_.far_m) {
        ++stats.too_far;
        continue;
      }
      out.points_m.emplace_back(static_cast<float>((u - camera_.cx_px) * z * inv_fx),
                                static_cast<float>((v - camera_.cy_px) * z * inv_fy),
                                static_cast<float>(z));
      if (grid != nullptr) {
        const std::size_t cell = static_cast<std::size_t>(v / stride) * grid->width +
                                 static_cast<std::size_t>(u / stride);
        grid->point_at[cell] = static_cast<std::int32_t>(out.points_m.size() - 1);
        grid->cell_of.push_back(static_cast<std::uint32_t>(cell));
      }
      out.colors_rgb.push_back(frame.rgb_at(u, v));
    }
  }
  if (setting_.voxel_size_m > 0.0) {
    voxel_average(out);
    if (grid != nullptr) {
      grid->clear();
    }
  }
  stats.points = static_cast<int>(out.size());
  return stats;
}

DepthToPointsStats DepthToPoints::convert(const RgbdView& frame, GaussianCloud& out,
                                          PixelGrid* grid) {
  return frame.with_depth_m(
      [&](auto depth_at) { return convert_impl(frame, depth_at, out, grid); });
}

// Sort (voxel key, index) pairs and average each run: deterministic, no hash map, and the
// scratch vector keeps its capacity between frames. Output order is by voxel key.
void DepthToPoints::voxel_average(GaussianCloud& out) {
  const double inv = 1.0 / setting_.voxel_size_m;
  constexpr std::int64_t kBias = 1 << 20;  // 21 bits per axis: +-1e6 voxels
  voxel_keys_.clear();
  voxel_keys_.reserve(out.size());
  for (std::uint32_t i = 0; i < out.size(); ++i) {
    const Eigen::Vector3f& p = out.points_m[i];
    const auto cell = [&](float x) {
      return static_cast<std::uint64_t>(std::clamp<std::int64_t>(
          static_cast<std::int64_t>(std::floor(x * inv)) + kBias, 0, (std::int64_t{1} << 21) - 1));
    };
    voxel_keys_.emplace_back((cell(p.x()) << 42) | (cell(p.y()) << 21) | cell(p.z()), i);
  }
  std::sort(voxel_keys_.begin(), voxel_keys_.end());
  // The strided points are moved aside and the averages written back. This path allocates
  // per frame; it is off by default (voxel_size_m = 0).
  std::vector<Eigen::Vector3f>& pts = out.points_m;
  std::vector<std::array<std::uint8_t, 3>>& col = out.colors_rgb;
  std::vector<Eigen::Vector3f> src_pts;
  std::vector<std::array<std::uint8_t, 3>> src_col;
  src_pts.swap(pts);
  src_col.swap(col);
  pts.reserve(src_pts.size());
  col.reserve(src_pts.size());
  for (std::size_t a = 0; a < voxel_keys_.size();) {
    std::size_t b = a;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    Eigen::Vector3d csum = Eigen::Vector3d::Zero();
    while (b < voxel_keys_.size() && voxel_keys_[b].first == voxel_keys_[a].first) {
      const std::uint32_t i = voxel_keys_[b].second;
      sum += src_pts[i].cast<double>();
      csum += Eigen::Vector3d(src_col[i][0], src_col[i][1], src_col[i][2]);
      ++b;
    }
    const double n = static_cast<double>(b - a);
    pts.push_back((sum / n).cast<float>());
    col.push_back({static_cast<std::uint8_t>(std::lround(csum.x() / n)),
                   static_cast<std::uint8_t>(std::lround(csum.y() / n)),
                   static_cast<std::uint8_t>(std::lround(csum.z() / n))});
    a = b;
  }
}

}  // namespace vigs::tracking
