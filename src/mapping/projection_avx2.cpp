// Compiled with -mavx2 -mfma -ffp-contract=off (src/mapping/CMakeLists.txt): no product and sum
// may fuse, so each lane rounds as project_gaussian() does in the scalar translation units.
#include "mapping/projection_avx2.hpp"

#include <immintrin.h>

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
  V p[3];
  for (int i = 0; i < 3; ++i)
    p[i] = add(dot3(Wm[3 * i], m0, Wm[3 * i + 1], m1, Wm[3 * i + 2], m2), set(cam.t_c_w[i]));
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
  const V off = _mm256_or_ps(_mm256_or_ps(_mm256_cmp_ps(add(u, r), zero, _CMP_LT_OQ),
                                          _mm256_cmp_ps(sub(u, r), set(cam.max_x), _CMP_GT_OQ)),
                             _mm256_or_ps(_mm256_cmp_ps(add(v, r), zero, _CMP_LT_OQ),
                                          _mm256_cmp_ps(sub(v, r), set(cam.max_y), _CMP_GT_OQ)));
  const V keep = _mm256_andnot_ps(off, ok);
  _mm256_store_ps(&L.conic[0][o], div(c, det));
  _mm256_store_ps(&L.conic[1][o], div(_mm256_xor_ps(b, set(-0.0f)), det));
  _mm256_store_ps(&L.conic[2][o], div(a, det));
  _mm256_store_ps(&L.mean2d[0][o], u);
  _mm256_store_ps(&L.mean2d[1][o], v);
  _mm256_store_ps(&L.depth[o], zc);
  _mm256_store_si256(reinterpret_cast<__m256i*>(&L.radius[o]),
                     _mm256_and_si256(_mm256_cvttps_epi32(r), _mm256_castps_si256(keep)));
}

}  // namespace

void project_lanes_avx2(const ProjectionCamera& cam, ProjectionLanes& lanes, int n) {
  for (int o = 0; o < n; o += 8) project8(cam, lanes, o);
}

}  // namespace vigs::mapping
