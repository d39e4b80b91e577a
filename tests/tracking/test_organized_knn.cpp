// The image-grid kNN (organized_knn.hpp) against brute force: on real depth (ICL-NUIM,
// uHumans2) at several strides, on synthetic scenes built to break it (isolated points, depth
// edges, grazing surfaces, points near the camera), and the preprocessor's fallback to the
// kd-tree, which must give the kd-tree path's covariances.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "io/image_io.hpp"
#include "tracking/camera_file.hpp"
#include "tracking/gicp.hpp"
#include "tracking/organized_knn.hpp"
#include "tracking/preprocess.hpp"

namespace vigs::tracking {
namespace {

const std::string kData = VIGS_SHARED_DATA_DIR;

// Sorted squared distances from point i to its k nearest (the point itself included).
std::vector<float> brute_force(const std::vector<Eigen::Vector3f>& pts, std::uint32_t i, int k) {
  std::vector<float> d;
  d.reserve(pts.size());
  for (const auto& p : pts) d.push_back((p - pts[i]).squaredNorm());
  std::partial_sort(d.begin(), d.begin() + k, d.end());
  d.resize(static_cast<std::size_t>(k));
  return d;
}

// Checks every certified answer against brute force; returns how many were certified.
int check_all(const GaussianCloud& cloud, const PixelGrid& grid, const OrganizedKnn& knn, int k,
              int step = 1) {
  std::uint32_t idx[64];
  float d2[64];
  int certified = 0;
  for (std::uint32_t i = 0; i < cloud.size(); i += static_cast<std::uint32_t>(step)) {
    const int found = knn.knn(grid, cloud.points_m, i, k, idx, d2);
    if (found < 0) continue;
    ++certified;
    EXPECT_EQ(found, k);
    const std::vector<float> want = brute_force(cloud.points_m, i, k);
    for (int j = 0; j < k; ++j) {
      // Distances agree to rounding (brute force uses Eigen's squaredNorm as well).
      EXPECT_EQ(d2[j], want[static_cast<std::size_t>(j)]) << "point " << i << " rank " << j;
      EXPECT_EQ((cloud.points_m[idx[j]] - cloud.points_m[i]).squaredNorm(), d2[j]);
    }
    if (::testing::Test::HasFailure()) return certified;
  }
  return certified;
}

TEST(OrganizedKnn, MatchesBruteForceOnIclNuimAtSeveralStrides) {
  const ImageF32 depth = io::read_depth_m(kData + "/icl_nuim_livingroom1/depth_00000.png", 0.001);
  const PinholeCamera cam{640, 480, 525.0, 525.0, 319.5, 239.5};
  for (const int stride : {2, 4, 8}) {
    DepthToPoints::Setting s;
    s.pixel_stride = stride;
    GaussianCloud cloud;
    PixelGrid grid;
    DepthToPoints(cam, s).convert(depth, ImageU8{}, cloud, &grid);
    ASSERT_TRUE(grid.describes(cloud.size()));
    const OrganizedKnn knn;
    // Stride 2 has ~67k points: check a sample of them.
    const int step = stride == 2 ? 37 : 1;
    for (const int k : {5, 10, 20}) {
      const int certified = check_all(cloud, grid, knn, k, step);
      const int queried = static_cast<int>((cloud.size() + step - 1) / step);
      EXPECT_GT(certified, queried * 99 / 100) << "stride " << stride << " k " << k;
    }
  }
}

TEST(OrganizedKnn, MatchesBruteForceOnUhumans2) {
  const std::string dir = kData + "/uhumans2_frames/";
  const PinholeCamera cam = load_camera_file(dir + "sensorLeft.yaml");
  const ImageF32 depth = io::read_tiff_f32(dir + "depth_img_0.tiff");
  DepthToPoints::Setting s;
  s.pixel_stride = 4;
  GaussianCloud cloud;
  PixelGrid grid;
  DepthToPoints(cam, s).convert(depth, ImageU8{}, cloud, &grid);
  ASSERT_GT(cloud.size(), 1000u);
  const int certified = check_all(cloud, grid, OrganizedKnn{}, 10);
  EXPECT_GT(certified, static_cast<int>(cloud.size()) * 95 / 100);
}

// A synthetic depth image with what defeats image-space neighbourhoods: a wall seen at a
// grazing angle, a foreground box edge in front of it, isolated flying pixels, a region very
// close to the camera and holes.
ImageF32 hostile_depth(int w, int h) {
  ImageF32 depth(w, h, 1, 0.0f);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> noise(-0.002f, 0.002f);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      float z = 1.0f + 0.08f * static_cast<float>(u);  // grazing wall: depth grows fast with u
      if (u > w / 3 && u < w / 2 && v > h / 4 && v < 3 * h / 4) z = 0.8f;  // box edge
      if (u < w / 8 && v < h / 8) z = 0.12f;                               // near the lens
      if ((u * 7 + v * 13) % 23 == 0) z = 0.0f;                            // holes
      depth.at(u, v) = z + noise(rng);
    }
  }
  for (int i = 0; i < 20; ++i) {  // flying pixels far behind
    depth.at((i * 37) % w, (i * 53) % h) = 6.0f + static_cast<float>(i);
  }
  return depth;
}

TEST(OrganizedKnn, ExactOrUncertifiedOnHostileDepth) {
  const int w = 160, h = 120;
  const PinholeCamera cam{w, h, 120.0, 120.0, 79.5, 59.5};
  DepthToPoints::Setting s;
  s.pixel_stride = 1;
  GaussianCloud cloud;
  PixelGrid grid;
  DepthToPoints(cam, s).convert(hostile_depth(w, h), ImageU8{}, cloud, &grid);
  for (const int max_ring : {2, 10}) {
    const OrganizedKnn knn(max_ring);
    const int certified = check_all(cloud, grid, knn, 10);
    // Flying pixels and grazing-wall points cannot all be certified within 2 rings.
    if (max_ring == 2) {
      EXPECT_LT(certified, static_cast<int>(cloud.size()));
    }
    EXPECT_GT(certified, 0);
  }
}

TEST(OrganizedKnn, FewerPointsThanKIsUncertified) {
  const PinholeCamera cam{4, 4, 10.0, 10.0, 1.5, 1.5};
  ImageF32 depth(4, 4, 1, 0.0f);
  depth.at(1, 1) = 1.0f;
  depth.at(2, 2) = 1.0f;
  DepthToPoints::Setting s;
  s.pixel_stride = 1;
  GaussianCloud cloud;
  PixelGrid grid;
  DepthToPoints(cam, s).convert(depth, ImageU8{}, cloud, &grid);
  std::uint32_t idx[10];
  float d2[10];
  EXPECT_EQ(OrganizedKnn{}.knn(grid, cloud.points_m, 0, 3, idx, d2), -1);
  EXPECT_EQ(OrganizedKnn{}.knn(grid, cloud.points_m, 0, 2, idx, d2), 2);
  EXPECT_EQ(d2[0], 0.0f);
}

// Covariances through the image (with kd-tree fallbacks) equal the kd-tree path's.
TEST(FramePreprocessor, ImageGridCovariancesEqualKdTreeCovariances) {
  const int w = 160, h = 120;
  const PinholeCamera cam{w, h, 120.0, 120.0, 79.5, 59.5};
  const ImageF32 depth = hostile_depth(w, h);
  for (const int threads : {1, 2}) {
    rt::WorkerTeam team(threads);
    FramePreprocessor::Setting s;
    s.depth.pixel_stride = 1;
    s.covariance.knn_search = KnnSearch::kd_tree;
    FramePreprocessor by_tree(cam, s, team);
    s.covariance.knn_search = KnnSearch::image_grid;
    FramePreprocessor by_image(cam, s, team);
    GaussianCloud a, b;
    by_tree.process(depth, ImageU8{}, a);
    by_image.process(depth, ImageU8{}, b);
    EXPECT_EQ(by_tree.last_knn_fallbacks(), 0u);
    EXPECT_GT(by_image.last_knn_fallbacks(), 0u);  // the flying pixels at least
    EXPECT_LT(by_image.last_knn_fallbacks(), a.size() / 10);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      // Equal up to which of several equidistant neighbours was kept (rare on noisy depth).
      ASSERT_LE((a.cov_raw_m2[i] - b.cov_raw_m2[i]).norm(), 1e-6f * (1.0f + a.cov_raw_m2[i].norm()))
          << "point " << i;
    }
  }
}

TEST(FramePreprocessor, ImageGridResultIsTheSameForOneAndTwoThreads) {
  const ImageF32 depth = io::read_depth_m(kData + "/icl_nuim_livingroom1/depth_00000.png", 0.001);
  const PinholeCamera cam{640, 480, 525.0, 525.0, 319.5, 239.5};
  GaussianCloud one, two;
  rt::WorkerTeam t1(1), t2(2);
  FramePreprocessor::Setting s;
  FramePreprocessor(cam, s, t1).process(depth, ImageU8{}, one);
  FramePreprocessor(cam, s, t2).process(depth, ImageU8{}, two);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) {
    ASSERT_EQ(one.cov_m2[i], two.cov_m2[i]);
  }
}

// Correspondence search through the image (CloudTarget with a grid) against the kd-tree alone,
// for queries near the surfaces, off them, projecting outside the image, and behind the camera.
TEST(OrganizedKnn, NearestEqualsTheKdTreesForAnyQuery) {
  const ImageF32 depth = io::read_depth_m(kData + "/icl_nuim_livingroom1/depth_00000.png", 0.001);
  const PinholeCamera cam{640, 480, 525.0, 525.0, 319.5, 239.5};
  rt::WorkerTeam team(1);
  FramePreprocessor::Setting s;
  FramePreprocessor pre(cam, s, team);
  GaussianCloud cloud;
  KdTree tree;
  PixelGrid grid;
  pre.process(depth, ImageU8{}, cloud, tree, &grid);
  ASSERT_TRUE(grid.describes(cloud.size()));
  const CloudTarget by_image{&cloud, &tree, &grid};
  const CloudTarget by_tree{&cloud, &tree, nullptr};
  std::mt19937 rng(21);
  std::normal_distribution<float> n(0.0f, 1.0f);
  std::uniform_int_distribution<std::size_t> pick(0, cloud.size() - 1);
  int compared = 0, certified = 0;
  for (int i = 0; i < 20000; ++i) {
    Eigen::Vector3f q = cloud.points_m[pick(rng)];
    const float scale = i % 4 == 0 ? 0.003f : i % 4 == 1 ? 0.03f : i % 4 == 2 ? 0.1f : 1.0f;
    q += scale * Eigen::Vector3f(n(rng), n(rng), n(rng));
    if (i % 97 == 0) q.z() = -q.z();         // behind the camera
    if (i % 89 == 0) q.x() += 2.0f * q.z();  // far outside the image
    const std::uint32_t hint = i % 3 == 0 ? static_cast<std::uint32_t>(pick(rng)) : KdTree::kNoHint;
    for (const float max_sq : {0.01f, 1e-4f}) {
      std::uint32_t ia = 0, ib = 0;
      float da = -1.0f, db = -1.0f;
      const bool fa = by_image.nearest(q, max_sq, ia, da, hint);
      const bool fb = by_tree.nearest(q, max_sq, ib, db);
      ASSERT_EQ(fa, fb) << "query " << i;
      if (fa) {
        EXPECT_FLOAT_EQ(da, db) << "query " << i;
        EXPECT_FLOAT_EQ((cloud.points_m[ia] - q).squaredNorm(), da);
      }
      if (scale <= 0.03f && q.z() > 0.0f) {  // a correspondence search near the surfaces
        std::uint32_t ic = 0;
        float dc = 0.0f;
        certified += OrganizedKnn::shared().nearest(grid, cloud.points_m, q, max_sq,
                                                    KdTree::kNoHint, ic, dc) >= 0;
        ++compared;
      }
    }
  }
  // Near the surfaces the image search must answer almost every query itself.
  EXPECT_GT(certified, compared * 95 / 100) << certified << " of " << compared;
}

TEST(DepthToPoints, VoxelGridClearsThePixelGrid) {
  const ImageF32 depth = io::read_depth_m(kData + "/icl_nuim_livingroom1/depth_00000.png", 0.001);
  const PinholeCamera cam{640, 480, 525.0, 525.0, 319.5, 239.5};
  DepthToPoints::Setting s;
  s.voxel_size_m = 0.05;
  GaussianCloud cloud;
  PixelGrid grid;
  DepthToPoints(cam, s).convert(depth, ImageU8{}, cloud, &grid);
  EXPECT_FALSE(grid.describes(cloud.size()));
}

}  // namespace
}  // namespace vigs::tracking
