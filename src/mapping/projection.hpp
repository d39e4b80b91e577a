#pragma once
// EWA projection of one 3D Gaussian to the image and its vector-Jacobian product, following
// gsplat's conventions: q = (w, x, y, z) normalised, S = diag(exp(log_scale)), Sigma = R S S^T
// R^T, Sigma_c = W Sigma W^T, Sigma_2D = J Sigma_c J^T + eps2d I (pinhole Jacobian J with the
// 1.3 x half-FOV clamp), conic = Sigma_2D^-1, radius = ceil(3 sqrt(lambda_max)).
// Templated on the scalar so that gradient checks can run the same code in double.
#include <algorithm>
#include <cmath>

#include "mapping/render_camera.hpp"

namespace vigs::mapping {

template <class T>
struct ProjectedGaussian {
  T mean2d[2];  ///< pixel coordinates
  T conic[3];   ///< upper triangle (a, b, c) of Sigma_2D^-1
  T depth;      ///< camera z, metres
  int radius;   ///< pixels; 0 = culled
};

namespace detail {

template <class T>
inline void quat_to_rot(const T q[4], T R[9]) {
  const T w = q[0], x = q[1], y = q[2], z = q[3];
  R[0] = 1 - 2 * (y * y + z * z);
  R[1] = 2 * (x * y - w * z);
  R[2] = 2 * (x * z + w * y);
  R[3] = 2 * (x * y + w * z);
  R[4] = 1 - 2 * (x * x + z * z);
  R[5] = 2 * (y * z - w * x);
  R[6] = 2 * (x * z - w * y);
  R[7] = 2 * (y * z + w * x);
  R[8] = 1 - 2 * (x * x + y * y);
}

/// C = A * B for 3x3 row-major.
template <class T>
inline void mul33(const T* A, const T* B, T* C) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}
/// C = A * B^T for 3x3 row-major.
template <class T>
inline void mul33_bt(const T* A, const T* B, T* C) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      C[3 * i + j] =
          A[3 * i] * B[3 * j] + A[3 * i + 1] * B[3 * j + 1] + A[3 * i + 2] * B[3 * j + 2];
}
/// C = A^T * B for 3x3 row-major.
template <class T>
inline void mul33_at(const T* A, const T* B, T* C) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      C[3 * i + j] = A[i] * B[j] + A[3 + i] * B[3 + j] + A[6 + i] * B[6 + j];
}

/// Everything the forward pass computes that the backward pass needs again.
template <class T>
struct ProjectionState {
  T qn[4], qnorm;
  T R[9], s[3], M[9];  // M = R S
  T Wm[9];             // world -> camera rotation
  T p_c[3];
  T Sigma_c[9];
  T J[6];  // 2x3 row-major
  bool clamped_x, clamped_y;
  T cov2d[3];  // a, b, c of Sigma_2D (with eps)
};

template <class T>
inline void projection_state(const RenderCamera& cam, const T mean[3], const T log_scale[3],
                             const T quat[4], ProjectionState<T>& st) {
  st.qnorm =
      std::sqrt(quat[0] * quat[0] + quat[1] * quat[1] + quat[2] * quat[2] + quat[3] * quat[3]);
  for (int k = 0; k < 4; ++k) st.qn[k] = quat[k] / st.qnorm;
  quat_to_rot(st.qn, st.R);
  for (int k = 0; k < 3; ++k) st.s[k] = std::exp(log_scale[k]);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) st.M[3 * i + j] = st.R[3 * i + j] * st.s[j];
  for (int k = 0; k < 9; ++k) st.Wm[k] = T(cam.R_c_w[k]);
  for (int i = 0; i < 3; ++i)
    st.p_c[i] = st.Wm[3 * i] * mean[0] + st.Wm[3 * i + 1] * mean[1] + st.Wm[3 * i + 2] * mean[2] +
                T(cam.t_c_w[i]);
  // Sigma_c = (W M)(W M)^T
  T WM[9];
  mul33(st.Wm, st.M, WM);
  mul33_bt(WM, WM, st.Sigma_c);
  const T fx = T(cam.fx_px), fy = T(cam.fy_px);
  const T z = st.p_c[2];
  const T tan_x = T(0.5 * cam.width_px / cam.fx_px), tan_y = T(0.5 * cam.height_px / cam.fy_px);
  const T lim_x = T(1.3) * tan_x, lim_y = T(1.3) * tan_y;
  const T rx = st.p_c[0] / z, ry = st.p_c[1] / z;
  st.clamped_x = rx < -lim_x || rx > lim_x;
  st.clamped_y = ry < -lim_y || ry > lim_y;
  const T tx = std::clamp(rx, -lim_x, lim_x) * z;
  const T ty = std::clamp(ry, -lim_y, lim_y) * z;
  st.J[0] = fx / z;
  st.J[1] = 0;
  st.J[2] = -fx * tx / (z * z);
  st.J[3] = 0;
  st.J[4] = fy / z;
  st.J[5] = -fy * ty / (z * z);
  // cov2d = J Sigma_c J^T
  T JS[6];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
      JS[3 * i + j] = st.J[3 * i] * st.Sigma_c[j] + st.J[3 * i + 1] * st.Sigma_c[3 + j] +
                      st.J[3 * i + 2] * st.Sigma_c[6 + j];
  st.cov2d[0] = JS[0] * st.J[0] + JS[1] * st.J[1] + JS[2] * st.J[2];
  st.cov2d[1] = JS[0] * st.J[3] + JS[1] * st.J[4] + JS[2] * st.J[5];
  st.cov2d[2] = JS[3] * st.J[3] + JS[4] * st.J[4] + JS[5] * st.J[5];
}

}  // namespace detail

/// project_gaussian()'s first test: false when the Gaussian is behind `near_m` or, by a bound
/// on its radius, entirely off-screen. Conservative: the radius project_gaussian() computes never
/// exceeds ceil(3 sqrt(|J|_F^2 s_max^2 + eps2d + 0.32)), so culling with that bound gives exactly
/// the same result as the full test while skipping the covariance work (most of a large map).
template <class T>
inline bool may_reach_image(const RenderCamera& cam, const T mean[3], const T log_scale[3],
                            T near_m, T eps2d) {
  const T z = T(cam.R_c_w[6]) * mean[0] + T(cam.R_c_w[7]) * mean[1] + T(cam.R_c_w[8]) * mean[2] +
              T(cam.t_c_w[2]);
  if (!(z > near_m)) return false;
  const T x = T(cam.R_c_w[0]) * mean[0] + T(cam.R_c_w[1]) * mean[1] + T(cam.R_c_w[2]) * mean[2] +
              T(cam.t_c_w[0]);
  const T y = T(cam.R_c_w[3]) * mean[0] + T(cam.R_c_w[4]) * mean[1] + T(cam.R_c_w[5]) * mean[2] +
              T(cam.t_c_w[1]);
  const T fx = T(cam.fx_px), fy = T(cam.fy_px);
  const T lim_x = T(1.3 * 0.5 * cam.width_px / cam.fx_px);
  const T lim_y = T(1.3 * 0.5 * cam.height_px / cam.fy_px);
  const T rx = std::clamp(x / z, -lim_x, lim_x), ry = std::clamp(y / z, -lim_y, lim_y);
  const T j2 = (fx * fx * (T(1) + rx * rx) + fy * fy * (T(1) + ry * ry)) / (z * z);
  const T s_max = std::exp(std::max(log_scale[0], std::max(log_scale[1], log_scale[2])));
  const T r_bound = std::ceil(T(3) * std::sqrt(j2 * s_max * s_max + eps2d + T(0.32)));
  const T u = fx * x / z + T(cam.cx_px), v = fy * y / z + T(cam.cy_px);
  return !(u + r_bound < T(0) || u - r_bound > T(cam.width_px - 1) || v + r_bound < T(0) ||
           v - r_bound > T(cam.height_px - 1));
}

/// Projects one Gaussian. Returns false (radius 0) when it is behind `near_m`, degenerate or
/// entirely off-screen. The float AVX2 path (projection_avx2.hpp) computes the same, bit for bit,
/// for eight Gaussians that passed may_reach_image() at a time.
template <class T>
inline bool project_gaussian(const RenderCamera& cam, const T mean[3], const T log_scale[3],
                             const T quat[4], T near_m, T eps2d, ProjectedGaussian<T>& out) {
  out.radius = 0;
  if (!may_reach_image(cam, mean, log_scale, near_m, eps2d)) return false;
  detail::ProjectionState<T> st;
  detail::projection_state(cam, mean, log_scale, quat, st);
  const T z = st.p_c[2];
  const T a = st.cov2d[0] + eps2d, b = st.cov2d[1], c = st.cov2d[2] + eps2d;
  const T det = a * c - b * b;
  if (!(det > T(0))) return false;
  out.conic[0] = c / det;
  out.conic[1] = -b / det;
  out.conic[2] = a / det;
  out.mean2d[0] = T(cam.fx_px) * st.p_c[0] / z + T(cam.cx_px);
  out.mean2d[1] = T(cam.fy_px) * st.p_c[1] / z + T(cam.cy_px);
  out.depth = z;
  const T mid = T(0.5) * (a + c);
  const T lambda_max = mid + std::sqrt(std::max(T(0.1), mid * mid - det));
  const T r = std::ceil(T(3) * std::sqrt(lambda_max));
  if (out.mean2d[0] + r < T(0) || out.mean2d[0] - r > T(cam.width_px - 1) ||
      out.mean2d[1] + r < T(0) || out.mean2d[1] - r > T(cam.height_px - 1))
    return false;
  out.radius = static_cast<int>(r);
  return true;
}

/// Vector-Jacobian product of project_gaussian: from gradients on (mean2d, conic, depth) to
/// gradients on (mean, log_scale, quat). Only valid for Gaussians that were not culled.
template <class T>
inline void project_gaussian_vjp(const RenderCamera& cam, const T mean[3], const T log_scale[3],
                                 const T quat[4], T eps2d, const T v_mean2d[2], const T v_conic[3],
                                 T v_depth, T v_mean[3], T v_log_scale[3], T v_quat[4]) {
  using namespace detail;
  ProjectionState<T> st;
  projection_state(cam, mean, log_scale, quat, st);
  const T fx = T(cam.fx_px), fy = T(cam.fy_px);
  const T x = st.p_c[0], y = st.p_c[1], z = st.p_c[2];
  const T a = st.cov2d[0] + eps2d, b = st.cov2d[1], c = st.cov2d[2] + eps2d;
  const T det = a * c - b * b;
  const T Ci[4] = {c / det, -b / det, -b / det, a / det};
  // Conic is used as 0.5 d^T C d with packed b counted twice: symmetric gradient G.
  const T G[4] = {v_conic[0], T(0.5) * v_conic[1], T(0.5) * v_conic[1], v_conic[2]};
  // v_cov2d = -C G C
  T CG[4], V2[4];
  CG[0] = Ci[0] * G[0] + Ci[1] * G[2];
  CG[1] = Ci[0] * G[1] + Ci[1] * G[3];
  CG[2] = Ci[2] * G[0] + Ci[3] * G[2];
  CG[3] = Ci[2] * G[1] + Ci[3] * G[3];
  V2[0] = -(CG[0] * Ci[0] + CG[1] * Ci[2]);
  V2[1] = -(CG[0] * Ci[1] + CG[1] * Ci[3]);
  V2[2] = -(CG[2] * Ci[0] + CG[3] * Ci[2]);
  V2[3] = -(CG[2] * Ci[1] + CG[3] * Ci[3]);
  // cov2d = J Sigma_c J^T: v_Sigma_c = J^T V2 J, v_J = 2 V2 J Sigma_c (V2, Sigma_c symmetric)
  const T* J = st.J;
  T V2J[6];  // 2x3
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j) V2J[3 * i + j] = V2[2 * i] * J[j] + V2[2 * i + 1] * J[3 + j];
  T v_Sc[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v_Sc[3 * i + j] = J[i] * V2J[j] + J[3 + i] * V2J[3 + j];
  T v_J[6];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j)
      v_J[3 * i + j] = 2 * (V2J[3 * i] * st.Sigma_c[j] + V2J[3 * i + 1] * st.Sigma_c[3 + j] +
                            V2J[3 * i + 2] * st.Sigma_c[6 + j]);
  // J(x, y, z) and mean2d(x, y, z)
  T v_p[3] = {0, 0, v_depth};
  const T z2 = z * z, z3 = z2 * z;
  v_p[0] += fx / z * v_mean2d[0];
  v_p[1] += fy / z * v_mean2d[1];
  v_p[2] += -fx * x / z2 * v_mean2d[0] - fy * y / z2 * v_mean2d[1];
  v_p[2] += -fx / z2 * v_J[0] - fy / z2 * v_J[4];
  if (st.clamped_x) {
    v_p[2] += (-J[2] / z) * v_J[2];  // J02 = -fx * r / z with r fixed
  } else {
    v_p[0] += -fx / z2 * v_J[2];
    v_p[2] += 2 * fx * x / z3 * v_J[2];
  }
  if (st.clamped_y) {
    v_p[2] += (-J[5] / z) * v_J[5];
  } else {
    v_p[1] += -fy / z2 * v_J[5];
    v_p[2] += 2 * fy * y / z3 * v_J[5];
  }
  // p_c = W mean + t
  const T* W = st.Wm;
  for (int k = 0; k < 3; ++k) v_mean[k] = W[k] * v_p[0] + W[3 + k] * v_p[1] + W[6 + k] * v_p[2];
  // Sigma_c = W Sigma W^T: v_Sigma = W^T v_Sc W
  T tmp[9], v_S[9];
  mul33_at(W, v_Sc, tmp);
  mul33(tmp, W, v_S);
  // Sigma = M M^T: v_M = (v_S + v_S^T) M
  T v_Ssym[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v_Ssym[3 * i + j] = v_S[3 * i + j] + v_S[3 * j + i];
  T v_M[9];
  mul33(v_Ssym, st.M, v_M);
  // M = R diag(s)
  T v_R[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) v_R[3 * i + j] = v_M[3 * i + j] * st.s[j];
  for (int j = 0; j < 3; ++j) {
    const T v_s = v_M[j] * st.R[j] + v_M[3 + j] * st.R[3 + j] + v_M[6 + j] * st.R[6 + j];
    v_log_scale[j] = v_s * st.s[j];
  }
  // R(q) with q normalised
  const T w = st.qn[0], qx = st.qn[1], qy = st.qn[2], qz = st.qn[3];
  T v_qn[4];
  v_qn[0] = 2 * (qx * (v_R[7] - v_R[5]) + qy * (v_R[2] - v_R[6]) + qz * (v_R[3] - v_R[1]));
  v_qn[1] = 2 * (-2 * qx * (v_R[4] + v_R[8]) + qy * (v_R[3] + v_R[1]) + qz * (v_R[6] + v_R[2]) +
                 w * (v_R[7] - v_R[5]));
  v_qn[2] = 2 * (qx * (v_R[3] + v_R[1]) - 2 * qy * (v_R[0] + v_R[8]) + qz * (v_R[7] + v_R[5]) +
                 w * (v_R[2] - v_R[6]));
  v_qn[3] = 2 * (qx * (v_R[6] + v_R[2]) + qy * (v_R[7] + v_R[5]) - 2 * qz * (v_R[0] + v_R[4]) +
                 w * (v_R[3] - v_R[1]));
  const T dot = v_qn[0] * w + v_qn[1] * qx + v_qn[2] * qy + v_qn[3] * qz;
  for (int k = 0; k < 4; ++k) v_quat[k] = (v_qn[k] - st.qn[k] * dot) / st.qnorm;
}

}  // namespace vigs::mapping
