// People out of the map, the mapping side: see-through votes and pruning (see_through.hpp), the
// loss and the far field ignoring pixels marked moving (depth < 0), and the mapper pruning a
// Gaussian that later keyframes see through.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "mapping/far_field.hpp"
#include "mapping/loss.hpp"
#include "mapping/mapper.hpp"
#include "mapping/see_through.hpp"

namespace vigs::mapping {
namespace {

constexpr int kW = 40, kH = 30;

/// A camera at the world origin looking along +z.
RenderCamera camera() {
  const PinholeCamera k{kW, kH, 30.0, 30.0, 19.5, 14.5};
  return RenderCamera::from(k, Eigen::Isometry3d::Identity());
}

void add_gaussian(GaussianMap& map, double x, double y, double z, double opacity = 0.9) {
  const float mean[3] = {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z)};
  const float ls[3] = {std::log(0.02f), std::log(0.02f), std::log(0.02f)};
  const float q[4] = {1, 0, 0, 0};
  const float rgb[3] = {0.5f, 0.5f, 0.5f};
  map.push_back(mean, ls, q, static_cast<float>(std::log(opacity / (1.0 - opacity))), rgb);
}

std::vector<float> flat_depth(float z) {
  return std::vector<float>(kW * kH, z);
}

TEST(SeeThrough, PrunesWhatTwoKeyframesSeeThrough) {
  GaussianMap map;
  add_gaussian(map, 0.0, 0.0, 3.0);  // 0: on the wall
  add_gaussian(map, 0.1, 0.0, 1.5);  // 1: a ghost 1.5 m in front of it
  add_gaussian(map, 0.0, 0.0, 4.0);  // 2: behind the wall (hidden)
  const std::vector<float> wall = flat_depth(3.0f);
  SeeThrough st;  // defaults: 2 keyframes, at least half of the votes
  std::vector<char> keep;
  EXPECT_EQ(st.vote(map, camera(), wall.data(), keep), 0u);  // one vote is not enough
  EXPECT_EQ(st.through(1), 1);
  EXPECT_EQ(st.seen(0), 1);
  EXPECT_EQ(st.through(0), 0);
  EXPECT_EQ(st.seen(2) + st.through(2), 0);  // hidden: no vote
  ASSERT_EQ(st.vote(map, camera(), wall.data(), keep), 1u);
  EXPECT_EQ(keep, (std::vector<char>{1, 0, 1}));
  map.compact(keep);
  st.compact(keep);
  ASSERT_EQ(st.size(), 2u);
  EXPECT_EQ(st.seen(0), 2);  // the wall Gaussian's counts moved with it
  EXPECT_EQ(st.seen(1) + st.through(1), 0);
}

TEST(SeeThrough, OnlyKeyframesSoonAfterTheInsertingOneVote) {
  GaussianMap map;
  add_gaussian(map, 0.1, 0.0, 1.5);  // 0: inserted by keyframe 10
  add_gaussian(map, 0.1, 0.1, 1.5);  // 1: inserted by keyframe 40
  const std::vector<std::uint32_t> anchor = {10, 40};
  const std::vector<float> wall = flat_depth(3.0f);  // both seen through
  SeeThroughSettings s;
  s.max_age_keyframes = 20;
  SeeThrough st(s);
  std::vector<char> keep;
  // keyframe 45: 35 after Gaussian 0's (no vote), 5 after Gaussian 1's
  EXPECT_EQ(st.vote(map, camera(), wall.data(), keep, nullptr, anchor.data(), 45), 0u);
  EXPECT_EQ(st.through(0), 0);
  EXPECT_EQ(st.through(1), 1);
  ASSERT_EQ(st.vote(map, camera(), wall.data(), keep, nullptr, anchor.data(), 60), 1u);
  EXPECT_EQ(keep, (std::vector<char>{1, 0}));
  EXPECT_EQ(st.through(0), 0);
  // without anchors (or with max_age_keyframes 0) every keyframe votes
  SeeThrough all(s);
  all.vote(map, camera(), wall.data(), keep);
  EXPECT_EQ(all.vote(map, camera(), wall.data(), keep), 2u);
}

TEST(SeeThrough, MarginGrowsWithDepth) {
  GaussianMap map;
  add_gaussian(map, 0.0, 0.0, 5.0);  // 0.2 m in front of a surface at 5.2 m
  const std::vector<float> d = flat_depth(5.2f);
  SeeThroughSettings s;
  s.min_count = 1;
  s.margin_per_m = 0.0;  // 0.1 m: seen through
  SeeThrough fixed(s);
  std::vector<char> keep;
  EXPECT_EQ(fixed.vote(map, camera(), d.data(), keep), 1u);
  s.margin_per_m = 0.03;  // 0.1 + 0.15 m at 5 m: on the surface, within the noise
  SeeThrough growing(s);
  EXPECT_EQ(growing.vote(map, camera(), d.data(), keep), 0u);
  EXPECT_EQ(growing.seen(0), 1);
}

TEST(SeeThrough, MovingAndEdgePixelsDoNotVote) {
  GaussianMap map;
  add_gaussian(map, 0.0, 0.0, 1.5);
  const RenderCamera cam = camera();
  const int uc = 20, vc = 15;  // where the Gaussian projects (19.5 + 0, rounded up)
  SeeThroughSettings s;
  s.min_count = 1;
  std::vector<char> keep;
  for (const float mark : {-1.0f, 1.0f}) {
    std::vector<float> d = flat_depth(3.0f);
    d[static_cast<std::size_t>(vc + 1) * kW + uc - 1] = mark;  // one neighbour: moving, or a
    SeeThrough st(s);  // nearer surface (a depth edge beside the Gaussian)
    EXPECT_EQ(st.vote(map, cam, d.data(), keep), 0u) << "mark " << mark;
    EXPECT_EQ(st.through(0), 0);
  }
}

TEST(SeeThrough, MissingDepthIsFarExceptForFarFieldGaussians) {
  GaussianMap map;
  add_gaussian(map, 0.0, 0.0, 1.5);   // 0: a ghost before a corridor's end without depth
  add_gaussian(map, 0.0, 0.0, 15.0);  // 1: a far-field disc standing for it
  std::vector<float> d = flat_depth(0.0f);
  SeeThroughSettings s;
  s.min_count = 1;
  std::vector<char> keep;
  const std::vector<std::uint8_t> far = {0, 1};
  SeeThrough st(s);
  EXPECT_EQ(st.vote(map, camera(), d.data(), keep, nullptr, nullptr, 0, far.data()), 1u);
  EXPECT_EQ(keep, (std::vector<char>{0, 1}));
  EXPECT_EQ(st.seen(1), 1);  // the disc agrees with "no depth"
  s.missing_far = false;     // off: a pixel without depth does not vote
  SeeThrough unknown(s);
  EXPECT_EQ(unknown.vote(map, camera(), d.data(), keep, nullptr, nullptr, 0, far.data()), 0u);
  EXPECT_EQ(unknown.through(0) + unknown.seen(0), 0);
  // a far disc that a later view sees a surface well behind is seen through as any other
  d = flat_depth(25.0f);
  EXPECT_EQ(unknown.vote(map, camera(), d.data(), keep, nullptr, nullptr, 0, far.data()), 2u);
  // without the flags the disc is a Gaussian like any other: "no depth" is behind it
  s.missing_far = true;
  SeeThrough unflagged(s);
  d = flat_depth(0.0f);
  EXPECT_EQ(unflagged.vote(map, camera(), d.data(), keep), 2u);
}

TEST(SeeThrough, KeepsWhatMostViewsSeeOnTheSurface) {
  GaussianMap map;
  add_gaussian(map, 0.0, 0.0, 2.0);
  const std::vector<float> surface = flat_depth(2.0f), behind = flat_depth(3.0f);
  SeeThrough st;
  std::vector<char> keep;
  for (int k = 0; k < 3; ++k) st.vote(map, camera(), surface.data(), keep);
  EXPECT_EQ(st.vote(map, camera(), behind.data(), keep), 0u);
  EXPECT_EQ(st.vote(map, camera(), behind.data(), keep), 0u);  // 2 of 5: kept
  EXPECT_EQ(st.vote(map, camera(), behind.data(), keep), 1u);  // 3 of 6: pruned
}

TEST(SeeThrough, NewGaussiansStartWithoutVotes) {
  GaussianMap map;
  add_gaussian(map, 0.0, 0.0, 1.5);
  const std::vector<float> wall = flat_depth(3.0f);
  SeeThrough st;
  std::vector<char> keep;
  st.vote(map, camera(), wall.data(), keep);
  add_gaussian(map, 0.05, 0.0, 1.5);
  EXPECT_EQ(st.vote(map, camera(), wall.data(), keep), 1u);
  EXPECT_EQ(keep, (std::vector<char>{0, 1}));
  EXPECT_EQ(st.through(1), 1);
}

TEST(MovingMask, LossIgnoresMovingPixelsAlsoWithColourWithoutDepth) {
  constexpr int w = 32, h = 24;
  constexpr std::size_t np = static_cast<std::size_t>(w) * h;
  RenderResult<float> r;
  r.width = w;
  r.height = h;
  r.color.resize(3 * np);
  r.depth.assign(np, 2.0f);
  r.final_T.assign(np, 0.0f);
  std::vector<float> rgb(3 * np), depth(np, 2.1f);
  for (std::size_t p = 0; p < np; ++p) {
    for (int c = 0; c < 3; ++c) {
      r.color[3 * p + c] = 0.5f + 0.2f * std::sin(0.7f * static_cast<float>(p + 5 * c));
      rgb[3 * p + c] = 0.5f + 0.2f * std::cos(0.3f * static_cast<float>(p + 3 * c));
    }
    if (p % w < 10) depth[p] = -1.0f;  // a person over the left third
  }
  for (const bool color_without_depth : {false, true}) {
    PhotometricLoss<float> loss(LossSettings{}, nullptr, color_without_depth);
    std::vector<float> vc(3 * np), vd(np), vc2(3 * np), vd2(np);
    const LossTerms<float> t = loss.evaluate(r, rgb.data(), depth.data(), vc.data(), vd.data());
    EXPECT_GT(t.l1_color, 0.01f);  // the rest of the view is still a target
    EXPECT_LT(t.ssim, 0.99f);
    // the person's colour is no target: another colour there changes nothing
    std::vector<float> other = rgb;
    for (std::size_t p = 0; p < np; ++p)
      if (depth[p] < 0.0f)
        for (int c = 0; c < 3; ++c) other[3 * p + c] = 1.0f - rgb[3 * p + c];
    const LossTerms<float> t2 =
        loss.evaluate(r, other.data(), depth.data(), vc2.data(), vd2.data());
    EXPECT_EQ(t.total, t2.total);
    EXPECT_EQ(t.ssim, t2.ssim);
    EXPECT_EQ(vc, vc2);
    for (std::size_t p = 0; p < np; ++p) {
      if (!(depth[p] < 0.0f)) continue;
      EXPECT_EQ(vd[p], 0.0f);
      for (int c = 0; c < 3; ++c) ASSERT_EQ(vc[3 * p + c], 0.0f) << "pixel " << p;
    }
  }
  // the same pixels without depth (0) are colour targets when color_without_depth is on
  std::vector<float> missing = depth;
  for (float& d : missing) d = std::max(d, 0.0f);
  PhotometricLoss<float> far(LossSettings{}, nullptr, true);
  std::vector<float> vc(3 * np), vd(np);
  far.evaluate(r, rgb.data(), missing.data(), vc.data(), vd.data());
  EXPECT_NE(vc[0], 0.0f);
}

TEST(MovingMask, FarFieldSkipsMovingPixels) {
  const RenderCamera cam = camera();
  std::vector<float> rgb(3 * kW * kH, 0.4f), depth(kW * kH, 0.0f);
  GaussianMap map;
  const FarFieldView view{cam, rgb.data(), depth.data()};
  FarFieldSettings s;
  s.stride_px = 5;
  const std::size_t all = insert_far_field(map, view, nullptr, s, 0.7, 0.9, 0.45, 0.45);
  EXPECT_EQ(all, static_cast<std::size_t>((kW / 5) * (kH / 5)));
  std::fill(depth.begin(), depth.end(), -1.0f);  // a person in front of the whole view
  EXPECT_EQ(insert_far_field(map, view, nullptr, s, 0.7, 0.9, 0.45, 0.45), 0u);
  // a person's pixels (red) beside pixels without depth (grey): a disc of the grey alone
  std::fill(depth.begin(), depth.end(), 0.0f);
  for (std::size_t p = 0; p < depth.size(); ++p) {
    if (p % kW >= 5 || p / kW >= 5) continue;  // the first block, where 3 of 5 columns ...
    if (p % kW < 3) {
      depth[p] = -1.0f;  // ... are a person
      rgb[3 * p] = 1.0f;
    }
  }
  for (std::size_t p = 0; p < depth.size(); ++p)
    if (p % kW >= 5 || p / kW >= 5) depth[p] = 2.0f;  // the other blocks: a wall
  GaussianMap one;
  ASSERT_EQ(insert_far_field(one, view, nullptr, s, 0.7, 0.9, 0.45, 0.45), 1u);
  EXPECT_FLOAT_EQ(one.color_rgb[0], 0.4f);
}

/// A keyframe at the origin, its depth `depth_m`, with no points (the map's content is given).
std::unique_ptr<MapperKeyframe> view_keyframe(std::uint64_t id, const std::vector<float>& depth_m) {
  auto kf = std::make_unique<MapperKeyframe>();
  kf->id = id;
  kf->camera = camera();
  kf->rgb.assign(3 * kW * kH, 0.5f);
  kf->depth_m = depth_m;
  return kf;
}

/// Keyframe `first_id` sees a surface 1.5 m away and inserts one Gaussian on it; keyframes
/// `later_id` and `later_id` + 1 then see a wall 3 m away through it. Returns the mapper's
/// see-through prunes after each of the two.
std::array<std::uint64_t, 2> see_through_twice(Mapper& mapper, KeyframeRing& ring,
                                               std::uint64_t first_id, std::uint64_t later_id) {
  auto kf = view_keyframe(first_id, flat_depth(1.5f));
  kf->gaussians.points_c.emplace_back(0.0f, 0.0f, 1.5f);
  kf->gaussians.covariances_c.push_back(Eigen::Matrix3f::Identity() * 1e-4f);
  kf->gaussians.colors.emplace_back(0.9f, 0.1f, 0.1f);
  EXPECT_TRUE(ring.try_push(std::move(kf)));
  mapper.tick();
  EXPECT_EQ(mapper.map().size(), 1u);
  std::array<std::uint64_t, 2> pruned{};
  for (std::uint64_t k = 0; k < 2; ++k) {
    EXPECT_TRUE(ring.try_push(view_keyframe(later_id + k, flat_depth(3.0f))));
    mapper.tick();
    pruned[k] = mapper.seen_through_pruned();
  }
  return pruned;
}

TEST(SeeThrough, MapperPrunesAGhostOnlyWhenEnabled) {
  for (const bool enabled : {false, true}) {
    config::MappingSettings s;
    s.far_field.depth_m = 0.0;
    s.see_through.enabled = enabled;
    s.prune_every = 5;  // after the three ticks below
    KeyframeRing ring(8);
    Mapper mapper(s, ring, nullptr);
    // a person's Gaussian; the person walked on: two keyframes see the wall through where it stood
    const auto pruned = see_through_twice(mapper, ring, 0, 1);
    EXPECT_EQ(pruned[0], 0u);
    EXPECT_EQ(pruned[1], enabled ? 1u : 0u);
    // removed at once (transparent: culled from every render), compacted at the next prune
    ASSERT_EQ(mapper.map().size(), 1u);
    EXPECT_EQ(mapper.map().opacity_logit[0] == kRemovedLogit, enabled);
    if (enabled) {
      for (int t = 0; t < s.prune_every; ++t) mapper.tick();
      EXPECT_EQ(mapper.map().size(), 0u);
    }
  }
}

TEST(SeeThrough, MapperIgnoresRevisitsLongAfterInsertion) {
  // A surface seen once, then, 40 keyframes later (a revisit whose pose carries the drift
  // between), "through" by two keyframes: kept with a 30-keyframe window, pruned without.
  for (const int window : {0, 30}) {
    config::MappingSettings s;
    s.far_field.depth_m = 0.0;
    s.see_through.max_age_keyframes = window;
    KeyframeRing ring(8);
    Mapper mapper(s, ring, nullptr);
    const auto pruned = see_through_twice(mapper, ring, 100, 140);
    EXPECT_EQ(pruned[1], window == 0 ? 1u : 0u) << "window " << window;
  }
}

}  // namespace
}  // namespace vigs::mapping
