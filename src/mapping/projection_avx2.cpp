// Compiled with -mavx2 -mfma -ffp-contract=off (src/mapping/CMakeLists.txt): no product and sum
// may fuse, so each lane rounds as project_gaussian() does in the scalar translation units.
#include "mapping/projection_avx2.hpp"

#include <immintrin.h>

#include "mapping/avx2_math.hpp"

namespace vigs::mapping {

namespace {

using V = __m256;

inline V add(V a, V b) {
  return _mm256_add_ps(a, b);
}
inline V sub(V a, V b) {
  return _mm256_sub_ps(a, b);
}
inline V mul(V a, V b) {
  return _mm256_mul_ps(a, b);
}
inline V div(V a, V b) {
  return _mm256_div_ps(a, b);
}
inline V set(float x) {
  return _mm256_set1_ps(x);
}
/// (a0 b0 + a1 b1) + a2 b2, the order of the scalar code's three-term sums.
inline V dot3(V a0, V b0, V a1, V b1, V a2, V b2) {
  return add(add(mul(a0, b0), mul(a1, b1)), mul(a2, b2));
}
/// std::clamp(v, lo, hi): v < lo ? lo : (hi < v ? hi : v); a NaN stays NaN.
inline V clamp(V v, V lo, V hi) {
  V r = _mm256_blendv_ps(v, hi, _mm256_cmp_ps(hi, v, _CMP_LT_OQ));
  return _mm256_blendv_ps(r, lo, _mm256_cmp_ps(v, lo, _CMP_LT_OQ));
}

/// Camera-frame coordinate `row` (0 x, 1 y, 2 z) of world points m: R_c_w's row times m plus t.
inline V camera_coord(const ProjectionCamera& cam, int row, V m0, V m1, V m2) {
  return add(dot3(set(cam.R_c_w[3 * row]), m0, set(cam.R_c_w[3 * row + 1]), m1,
                  set(cam.R_c_w[3 * row + 2]), m2),
             set(cam.t_c_w[row]));
}
/// Lanes whose square of half-width r about pixel (u, v) lies wholly outside the image.
inline V off_screen(const ProjectionCamera& cam, V u, V v, V r) {
  const V zero = _mm256_setzero_ps();
  return _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(add(u, r), zero, _CMP_LT_OQ),
                                   _mm256_cmp_ps(sub(u, r), set(cam.max_x), _CMP_GT_OQ)),
                      _mm256_or_ps(_mm256_cmp_ps(add(v, r), zero, _CMP_LT_OQ),
                                   _mm256_cmp_ps(sub(v, r), set(cam.max_y), _CMP_GT_OQ)));
}

void project8(const ProjectionCamera& cam, ProjectionLanes& L, int o) {
  const V m0 = _mm256_load_ps(&L.mean_w[0][o]), m1 = _mm256_load_ps(&L.mean_w[1][o]),
          m2 = _mm256_load_ps(&L.mean_w[2][o]);
  const V s[3] = {_mm256_load_ps(&L.scale[0][o]), _mm256_load_ps(&L.scale[1][o]),
                  _mm256_load_ps(&L.scale[2][o])};
  const V q0 = _mm256_load_ps(&L.quat_wxyz[0][o]), q1 = _mm256_load_ps(&L.quat_wxyz[1][o]),
          q2 = _mm256_load_ps(&L.quat_wxyz[2][o]), q3 = _mm256_load_ps(&L.quat_wxyz[3][o]);
  // projection_state(): normalised quaternion, R, M = R S
  const V qnorm = _mm256_sqrt_ps(add(add(add(mul(q0, q0), mul(q1, q1)), mul(q2, q2)), mul(q3, q3)));
  const V w = div(q0, qnorm), x = div(q1, qnorm), y = div(q2, qnorm), z = div(q3, qnorm);
  const V one = set(1.0f), two = set(2.0f);
  V R[9];
  R[0] = sub(one, mul(two, add(mul(y, y), mul(z, z))));
  R[1] = mul(two, sub(mul(x, y), mul(w, z)));
  R[2] = mul(two, add(mul(x, z), mul(w, y)));
  R[3] = mul(two, add(mul(x, y), mul(w, z)));
  R[4] = sub(one, mul(two, add(mul(x, x), mul(z, z))));
  R[5] = mul(two, sub(mul(y, z), mul(w, x)));
  R[6] = mul(two, sub(mul(x, z), mul(w, y)));
  R[7] = mul(two, add(mul(y, z), mul(w, x)));
  R[8] = sub(one, mul(two, add(mul(x, x), mul(y, y))));
  V M[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) M[3 * i + j] = mul(R[3 * i + j], s[j]);
  V Wm[9];
  for (int k = 0; k < 9; ++k) Wm[k] = set(cam.R_c_w[k]);
  const V p[3] = {camera_coord(cam, 0, m0, m1, m2), camera_coord(cam, 1, m0, m1, m2),
                  camera_coord(cam, 2, m0, m1, m2)};
  V WM[9], S[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      WM[3 * i + j] = dot3(Wm[3 * i], M[j], Wm[3 * i + 1], M[3 + j], Wm[3 * i + 2], M[6 + j]);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      S[3 * i + j] =
          dot3(WM[3 * i], WM[3 * j], WM[3 * i + 1], WM[3 * j + 1], WM[3 * i + 2], WM[3 * j + 2]);
  const V fx = set(cam.fx), fy = set(cam.fy), zc = p[2];
  const V lim_x = set(cam.lim_x), lim_y = set(cam.lim_y);
  const V neg_x = set(-cam.lim_x), neg_y = set(-cam.lim_y);
  const V tx = mul(clamp(div(p[0], zc), neg_x, lim_x), zc);
  const V ty = mul(clamp(div(p[1], zc), neg_y, lim_y), zc);
  const V zz = mul(zc, zc), zero = _mm256_setzero_ps();
  const V J[6] = {div(fx, zc), zero,        div(mul(set(-cam.fx), tx), zz),
                  zero,        div(fy, zc), div(mul(set(-cam.fy), ty), zz)};
  V JS[6];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
      JS[3 * i + j] = dot3(J[3 * i], S[j], J[3 * i + 1], S[3 + j], J[3 * i + 2], S[6 + j]);
  const V cov0 = dot3(JS[0], J[0], JS[1], J[1], JS[2], J[2]);
  const V cov1 = dot3(JS[0], J[3], JS[1], J[4], JS[2], J[5]);
  const V cov2 = dot3(JS[3], J[3], JS[4], J[4], JS[5], J[5]);
  // project_gaussian() after projection_state()
  const V eps = set(cam.eps2d);
  const V a = add(cov0, eps), b = cov1, c = add(cov2, eps);
  const V det = sub(mul(a, c), mul(b, b));
  const V ok = _mm256_cmp_ps(det, zero, _CMP_GT_OQ);
  const V u = add(div(mul(fx, p[0]), zc), set(cam.cx));
  const V v = add(div(mul(fy, p[1]), zc), set(cam.cy));
  const V mid = mul(set(0.5f), add(a, c));
  // std::max(0.1f, x) is x only when 0.1f < x (a NaN gives 0.1f): _mm256_max_ps(x, 0.1f)
  const V lambda_max = add(mid, _mm256_sqrt_ps(_mm256_max_ps(sub(mul(mid, mid), det), set(0.1f))));
  const V r = _mm256_round_ps(mul(set(3.0f), _mm256_sqrt_ps(lambda_max)),
                              _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
  const V keep = _mm256_andnot_ps(off_screen(cam, u, v, r), ok);
  _mm256_store_ps(&L.conic[0][o], div(c, det));
  _mm256_store_ps(&L.conic[1][o], div(_mm256_xor_ps(b, set(-0.0f)), det));
  _mm256_store_ps(&L.conic[2][o], div(a, det));
  _mm256_store_ps(&L.mean2d[0][o], u);
  _mm256_store_ps(&L.mean2d[1][o], v);
  _mm256_store_ps(&L.depth[o], zc);
  _mm256_store_si256(reinterpret_cast<__m256i*>(&L.radius[o]),
                     _mm256_and_si256(_mm256_cvttps_epi32(r), _mm256_castps_si256(keep)));
}

/// exp(x), relative error about 1e-7, for x up to 88 (above: exp(88)); an upper or lower bound
/// only up to that error, which the cull's margins cover.
inline V exp_ps(V x) {
  const V big = set(88.0f);
  const V pos = _mm256_cmp_ps(x, _mm256_setzero_ps(), _CMP_GT_OQ);
  // exp(x) = 1 / exp(-x) for x > 0
  const V neg = _mm256_blendv_ps(x, sub(_mm256_setzero_ps(), _mm256_min_ps(x, big)), pos);
  const V e = avx2::exp_neg_ps(neg);
  return _mm256_blendv_ps(e, div(set(1.0f), e), pos);
}

/// Mask of the eight Gaussians from `i` that may pass (see cull_candidates_avx2).
inline int may_pass8(const ProjectionCamera& cam, V near_lo, V near_hi, V logit_min,
                     const float* mean_w, const float* log_scale, const float* logit,
                     std::size_t i) {
  const __m256i stride3 = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
  const float* m = mean_w + 3 * i;
  const float* l = log_scale + 3 * i;
  const V m0 = _mm256_i32gather_ps(m, stride3, 4), m1 = _mm256_i32gather_ps(m + 1, stride3, 4),
          m2 = _mm256_i32gather_ps(m + 2, stride3, 4);
  const V lmax = _mm256_max_ps(
      _mm256_max_ps(_mm256_i32gather_ps(l, stride3, 4), _mm256_i32gather_ps(l + 1, stride3, 4)),
      _mm256_i32gather_ps(l + 2, stride3, 4));
  const V faint = _mm256_cmp_ps(_mm256_loadu_ps(logit + i), logit_min, _CMP_LT_OQ);
  const V z = camera_coord(cam, 2, m0, m1, m2);
  const V behind = _mm256_cmp_ps(z, near_lo, _CMP_LT_OQ);
  const V x = camera_coord(cam, 0, m0, m1, m2), y = camera_coord(cam, 1, m0, m1, m2);
  const V rx = clamp(div(x, z), set(-cam.lim_x), set(cam.lim_x));
  const V ry = clamp(div(y, z), set(-cam.lim_y), set(cam.lim_y));
  const V one = set(1.0f);
  const V j2 = div(add(mul(set(cam.fx * cam.fx), add(one, mul(rx, rx))),
                       mul(set(cam.fy * cam.fy), add(one, mul(ry, ry)))),
                   mul(z, z));
  const V s2 = exp_ps(add(lmax, lmax));
  const V r =
      add(mul(set(3.003f), _mm256_sqrt_ps(add(mul(j2, s2), set(cam.eps2d + 0.32f)))), set(1.5f));
  const V u = add(div(mul(set(cam.fx), x), z), set(cam.cx));
  const V v = add(div(mul(set(cam.fy), y), z), set(cam.cy));
  // off-screen is trusted only in front of the near plane's margin (x / z is tame there)
  const V in_front = _mm256_cmp_ps(z, near_hi, _CMP_GT_OQ);
  const V fails =
      _mm256_or_ps(_mm256_or_ps(faint, behind), _mm256_and_ps(in_front, off_screen(cam, u, v, r)));
  return ~_mm256_movemask_ps(fails) & 0xff;
}

}  // namespace

int cull_candidates_avx2(const ProjectionCamera& cam, float near_m, float logit_min,
                         const float* mean_w, const float* log_scale, const float* opacity_logit,
                         std::size_t b, std::size_t e, std::uint32_t* candidates) {
  const V near_lo = set(near_m - 1e-3f), near_hi = set(near_m + 1e-3f);
  const V logit_lo = set(logit_min - 0.01f * (logit_min < 0 ? -logit_min : logit_min) - 1e-3f);
  int n = 0;
  std::size_t i = b;
  for (; i + 8 <= e; i += 8) {
    int mask = may_pass8(cam, near_lo, near_hi, logit_lo, mean_w, log_scale, opacity_logit, i);
    while (mask != 0) {
      const int lane = __builtin_ctz(static_cast<unsigned>(mask));
      candidates[n++] = static_cast<std::uint32_t>(i + static_cast<std::size_t>(lane));
      mask &= mask - 1;
    }
  }
  for (; i < e; ++i) candidates[n++] = static_cast<std::uint32_t>(i);
  return n;
}

void project_lanes_avx2(const ProjectionCamera& cam, ProjectionLanes& lanes, int n) {
  for (int o = 0; o < n; o += 8) project8(cam, lanes, o);
}

}  // namespace vigs::mapping
