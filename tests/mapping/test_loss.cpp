// The training loss's per-pixel passes on a worker team: the same bits whatever the team, and
// the same sums as one plain pass over the image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <vector>

#include "mapping/loss.hpp"
#include "rt/worker_team.hpp"

namespace vigs::mapping {
namespace {

struct Views {
  RenderResult<float> render;
  std::vector<float> rgb, depth_m;
};

// 100 x 70 (a partial last block of 16 rows): smooth colours, depth with holes (0) and a moving
// object (< 0).
Views views() {
  Views v;
  const int w = 100, h = 70;
  const std::size_t np = static_cast<std::size_t>(w) * h;
  v.render.width = w;
  v.render.height = h;
  v.render.color.resize(3 * np);
  v.render.depth.resize(np);
  v.render.final_T.assign(np, 0.0f);
  v.rgb.resize(3 * np);
  v.depth_m.resize(np);
  for (std::size_t p = 0; p < np; ++p) {
    for (int c = 0; c < 3; ++c) {
      v.render.color[3 * p + c] = 0.5f + 0.3f * std::sin(0.07f * static_cast<float>(p + 11 * c));
      v.rgb[3 * p + c] = 0.5f + 0.3f * std::cos(0.05f * static_cast<float>(p + 7 * c));
    }
    v.render.depth[p] = 2.0f + 0.1f * std::sin(0.01f * static_cast<float>(p));
    const std::size_t u = p % static_cast<std::size_t>(w), row = p / static_cast<std::size_t>(w);
    v.depth_m[p] = u < 8 ? 0.0f : 2.05f + 0.1f * std::cos(0.02f * static_cast<float>(p));
    if (u >= 40 && u < 55 && row >= 20 && row < 50) v.depth_m[p] = -1.0f;  // a person
  }
  return v;
}

TEST(MappingLoss, AnyTeamSizeGivesTheSameBits) {
  const Views v = views();
  const std::size_t np = v.depth_m.size();
  for (const bool color_without_depth : {false, true}) {
    PhotometricLoss<float> one(LossSettings{}, nullptr, color_without_depth);
    std::vector<float> vc1(3 * np), vd1(np);
    const LossTerms<float> t1 =
        one.evaluate(v.render, v.rgb.data(), v.depth_m.data(), vc1.data(), vd1.data());
    for (const int members : {2, 3}) {
      rt::WorkerTeam team(members);
      PhotometricLoss<float> many(LossSettings{}, &team, color_without_depth);
      for (int round = 0; round < 2; ++round) {
        std::vector<float> vc(3 * np, 9.0f), vd(np, 9.0f);  // stale values are overwritten
        const LossTerms<float> t =
            many.evaluate(v.render, v.rgb.data(), v.depth_m.data(), vc.data(), vd.data());
        ASSERT_EQ(t.total, t1.total) << members;
        ASSERT_EQ(t.l1_color, t1.l1_color);
        ASSERT_EQ(t.ssim, t1.ssim);
        ASSERT_EQ(t.l1_depth_m, t1.l1_depth_m);
        ASSERT_EQ(vc, vc1);
        ASSERT_EQ(vd, vd1);
      }
    }
  }
}

// The L1 terms against one plain pass written here: mean |colour error| over the masked pixels
// (3 channels), mean |depth error| over the pixels with depth, divided by the same count; the
// depth gradient is zero wherever the target has no depth or a moving object.
TEST(MappingLoss, L1TermsAreThePlainMeans) {
  const Views v = views();
  const std::size_t np = v.depth_m.size();
  rt::WorkerTeam team(2);
  for (const bool color_without_depth : {false, true}) {
    PhotometricLoss<float> loss(LossSettings{}, &team, color_without_depth);
    std::vector<float> vc(3 * np), vd(np);
    const LossTerms<float> t =
        loss.evaluate(v.render, v.rgb.data(), v.depth_m.data(), vc.data(), vd.data());
    double l1 = 0, l1d = 0;
    std::size_t n = 0;
    for (std::size_t p = 0; p < np; ++p) {
      const float d = v.depth_m[p];
      if (!(d > 0.0f || (color_without_depth && !(d < 0.0f)))) continue;
      ++n;
      for (int c = 0; c < 3; ++c) l1 += std::abs(v.render.color[3 * p + c] - v.rgb[3 * p + c]);
      if (d > 0.0f) l1d += std::abs(v.render.depth[p] - d);
    }
    EXPECT_NEAR(t.l1_color, l1 / (3.0 * static_cast<double>(n)), 1e-6);
    EXPECT_NEAR(t.l1_depth_m, l1d / static_cast<double>(n), 1e-6);
    EXPECT_GT(t.l1_depth_m, 0.01f);
    const LossSettings s;
    for (std::size_t p = 0; p < np; ++p) {
      if (v.depth_m[p] > 0.0f) {
        ASSERT_NEAR(std::abs(vd[p]), s.lambda_depth / static_cast<double>(n), 1e-9) << p;
      } else {
        ASSERT_EQ(vd[p], 0.0f) << p;
      }
    }
  }
}

}  // namespace
}  // namespace vigs::mapping
