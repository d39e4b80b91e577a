// Visible-only Adam (mapping.adam_visible_only, Adam::step_selected): an iteration leaves the
// Gaussians its view does not see exactly as they were, parameters and moments, where the dense
// step still moves them by their momentum; where the view sees every Gaussian the two steps are
// the same step; and a Gaussian seen again resumes with the moments the dense step would have
// decayed over the steps it skipped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "mapping/map_optimizer.hpp"
#include "test_scene.hpp"

namespace vigs::mapping {
namespace {

constexpr double kApartM = 100.0;  // group B lies this far along world x from group A

/// Group A in front of small_camera(), group B the same Gaussians kApartM further along x.
GaussianMap two_groups(int n_each) {
  GaussianMap g = test::random_gaussians<float>(n_each, 21);
  const GaussianMap a = g;
  for (std::size_t i = 0; i < a.size(); ++i) {
    float mean[3] = {a.mean_w[3 * i] + static_cast<float>(kApartM), a.mean_w[3 * i + 1],
                     a.mean_w[3 * i + 2]};
    g.push_back(mean, &a.log_scale[3 * i], &a.quat_wxyz[4 * i], a.opacity_logit[i],
                &a.color_rgb[3 * i]);
  }
  return g;
}

/// small_camera() moved kApartM along world x: it sees group B as small_camera() sees group A.
RenderCamera shifted_camera(const RenderCamera& cam) {
  RenderCamera c = cam;
  for (int r = 0; r < 3; ++r) c.t_c_w[r] -= cam.R_c_w[3 * r] * kApartM;
  return c;
}

struct Target {
  std::vector<float> rgb, depth;
};

/// What the map renders at `cam`, brightened: every visible Gaussian gets a colour gradient.
Target target_at(const GaussianMap& g, const RenderCamera& cam) {
  Rasterizer<float> ras;
  RenderResult<float> r;
  ras.forward(g, cam, r);
  Target t{r.color, r.depth};
  for (float& c : t.rgb) c = std::min(1.0f, c + 0.2f);
  return t;
}

config::MappingSettings settings(bool visible_only) {
  config::MappingSettings s;
  s.adam.lr_mean = 1e-3;
  s.adam.visible_only = visible_only;
  s.prune_every = 100000;
  return s;
}

TEST(SelectiveAdam, GaussiansOutOfViewKeepParametersAndMoments) {
  const int n = 30;
  const GaussianMap start = two_groups(n);
  const RenderCamera cam_a = test::small_camera(64, 48, 60.0);
  const RenderCamera cam_b = shifted_camera(cam_a);
  const Target ta = target_at(start, cam_a), tb = target_at(start, cam_b);
  const TrainingView view_a{cam_a, ta.rgb.data(), ta.depth.data()};
  const TrainingView view_b{cam_b, tb.rgb.data(), tb.depth.data()};

  // group A trains on view A (so it has momentum), then one iteration on view B
  auto run = [&](bool visible_only, GaussianMap& before_b) {
    rt::WorkerTeam pool(2);
    MapOptimizer opt(settings(visible_only), &pool);
    GaussianMap g = start;
    for (int it = 0; it < 3; ++it) (void)opt.iterate(g, view_a);
    before_b = g;
    (void)opt.iterate(g, view_b);
    // view B saw exactly group B
    const std::vector<int>& seen = opt.rasterizer().visible_ids();
    EXPECT_EQ(seen.size(), static_cast<std::size_t>(n));
    for (int id : seen) EXPECT_GE(id, n);
    return g;
  };
  GaussianMap sel_before, dense_before;
  const GaussianMap sel = run(true, sel_before);
  const GaussianMap dense = run(false, dense_before);
  auto group_a = [&](const std::vector<float>& v, int per) {
    return std::vector<float>(v.begin(), v.begin() + per * n);
  };
  // visible-only: group A is bit for bit what view A's iterations left
  EXPECT_EQ(group_a(sel.mean_w, 3), group_a(sel_before.mean_w, 3));
  EXPECT_EQ(group_a(sel.color_rgb, 3), group_a(sel_before.color_rgb, 3));
  EXPECT_EQ(group_a(sel.opacity_logit, 1), group_a(sel_before.opacity_logit, 1));
  EXPECT_EQ(group_a(sel.log_scale, 3), group_a(sel_before.log_scale, 3));
  EXPECT_EQ(group_a(sel.quat_wxyz, 4), group_a(sel_before.quat_wxyz, 4));
  // dense: momentum still moves group A although view B does not see it
  EXPECT_NE(group_a(dense.color_rgb, 3), group_a(dense_before.color_rgb, 3));
  // both moved group B
  EXPECT_NE(std::vector<float>(sel.color_rgb.begin() + 3 * n, sel.color_rgb.end()),
            std::vector<float>(sel_before.color_rgb.begin() + 3 * n, sel_before.color_rgb.end()));
}

TEST(SelectiveAdam, SameStepAsDenseWhereTheViewSeesEveryGaussian) {
  const GaussianMap start = test::random_gaussians<float>(50, 4);
  const RenderCamera cam = test::small_camera(64, 48, 60.0);
  const Target t = target_at(start, cam);
  const TrainingView view{cam, t.rgb.data(), t.depth.data()};
  auto run = [&](bool visible_only) {
    rt::WorkerTeam pool(2);
    MapOptimizer opt(settings(visible_only), &pool);
    GaussianMap g = start;
    for (int it = 0; it < 5; ++it) (void)opt.iterate(g, view);
    EXPECT_EQ(opt.rasterizer().visible_ids().size(), g.size());
    return g;
  };
  const GaussianMap sel = run(true), dense = run(false);
  EXPECT_EQ(sel.mean_w, dense.mean_w);
  EXPECT_EQ(sel.log_scale, dense.log_scale);
  EXPECT_EQ(sel.quat_wxyz, dense.quat_wxyz);
  EXPECT_EQ(sel.opacity_logit, dense.opacity_logit);
  EXPECT_EQ(sel.color_rgb, dense.color_rgb);
  EXPECT_NE(sel.color_rgb, start.color_rgb);
}

/// Runs ranges(n, f) as one range: Adam's split over threads, on this thread.
const auto kOneRange = [](std::size_t n, auto&& f) { f(std::size_t{0}, n); };

TEST(SelectiveAdam, ASkippedGaussianResumesWithDecayedMoments) {
  // Gaussian A trains 4 steps with a unit gradient, is left out of 30 steps (B is stepped), then
  // stepped once with a zero gradient: it moves by its momentum alone. The dense step with zero
  // gradients in the gap decays the moments the same way (and also moves A in the gap); the last
  // step's move must match it, not the stale moments'. A third run has a Gaussian before A,
  // never stepped, pruned in the gap: A's record of its last step must move with its moments.
  constexpr int kTrain = 4, kGap = 30;
  enum class Run { kSelective, kDense, kSelectivePruned };
  auto last_move = [&](Run run) {
    const bool pruned = run == Run::kSelectivePruned;
    const GaussianMap start = test::random_gaussians<float>(pruned ? 3 : 2, 7);
    const int a = pruned ? 1 : 0, b = a + 1;
    auto unit_on = [](int id) {
      return [id](std::size_t i, float gr[14]) {
        std::fill(gr, gr + 14, static_cast<int>(i) == id ? 1.0f : 0.0f);
      };
    };
    Adam adam;
    GaussianMap g = start;
    const std::vector<int> only_a{a}, only_b{b};
    // step_selected's gradient callback takes the index into the id list
    for (int s = 0; s < kTrain; ++s) adam.step_selected(g, only_a, unit_on(0), kOneRange);
    for (int s = 0; s < kGap; ++s) {
      if (run == Run::kDense)
        adam.step_fused(g, unit_on(b), kOneRange);  // A gets a zero gradient
      else
        adam.step_selected(g, only_b, unit_on(0), kOneRange);
    }
    int a_now = a;
    if (pruned) {
      const std::vector<bool> keep{false, true, true};
      g.compact(keep);
      adam.compact(keep);
      a_now = 0;
    }
    const float before = g.color_rgb[3 * a_now];
    adam.step_selected(g, std::vector<int>{a_now}, unit_on(-1), kOneRange);
    return g.color_rgb[3 * a_now] - before;
  };
  const float selective = last_move(Run::kSelective), dense = last_move(Run::kDense);
  ASSERT_LT(dense, 0.0f);  // the momentum of a positive gradient lowers the colour
  // bfloat16 rounding differs (one multiply by β1^30 against thirty by β1)
  EXPECT_NEAR(selective, dense, 0.02 * std::abs(dense));
  // the stale moments would move it β1·m / √(β2·v) instead of β1^31·m / √(β2^31·v): 23 times
  // as far
  EXPECT_LT(std::abs(selective), 2.0f * std::abs(dense));
  // with the pruned neighbour's record in its place A would decay over 34 steps, not 30
  EXPECT_NEAR(last_move(Run::kSelectivePruned), dense, 0.02 * std::abs(dense));
}

}  // namespace
}  // namespace vigs::mapping
