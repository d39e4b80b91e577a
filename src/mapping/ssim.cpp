#include "mapping/ssim.hpp"

#include <cmath>
#include <stdexcept>

namespace vigs::mapping {

SsimWindow parse_ssim_window(const std::string& name) {
  if (name == "gaussian11") return SsimWindow::kGaussian11;
  if (name == "uniform7") return SsimWindow::kUniform7;
  throw std::invalid_argument("unknown SSIM window '" + name +
                              "' (expected gaussian11 or uniform7)");
}

std::vector<double> ssim_window_1d(SsimWindow w) {
  if (w == SsimWindow::kUniform7) return std::vector<double>(7, 1.0 / 7.0);
  std::vector<double> g(11);
  double sum = 0;
  for (int i = 0; i < 11; ++i) {
    const double d = i - 5;
    g[static_cast<std::size_t>(i)] = std::exp(-d * d / (2.0 * 1.5 * 1.5));
    sum += g[static_cast<std::size_t>(i)];
  }
  for (auto& v : g) v /= sum;
  return g;
}

template <class T>
Ssim<T>::Ssim(SsimOptions options) : opt_(options) {
  const auto w = ssim_window_1d(options.window);
  win_.assign(w.begin(), w.end());
}

namespace {

/// Valid separable correlation of `n_maps` planes (each h x w, contiguous) into hv x wv.
template <class T>
void filter_valid(const T* in, int n_maps, int w, int h, const std::vector<T>& win, T* tmp,
                  T* out) {
  const int K = static_cast<int>(win.size());
  const int wv = w - K + 1, hv = h - K + 1;
  for (int m = 0; m < n_maps; ++m) {
    const T* src = in + static_cast<std::size_t>(m) * w * h;
    for (int y = 0; y < h; ++y) {
      T* row = tmp + static_cast<std::size_t>(y) * wv;
      const T* s = src + static_cast<std::size_t>(y) * w;
      for (int x = 0; x < wv; ++x) row[x] = 0;
      for (int k = 0; k < K; ++k) {
        const T c = win[static_cast<std::size_t>(k)];
        for (int x = 0; x < wv; ++x) row[x] += c * s[x + k];
      }
    }
    T* dst = out + static_cast<std::size_t>(m) * wv * hv;
    for (int y = 0; y < hv; ++y) {
      T* row = dst + static_cast<std::size_t>(y) * wv;
      for (int x = 0; x < wv; ++x) row[x] = 0;
      for (int k = 0; k < K; ++k) {
        const T c = win[static_cast<std::size_t>(k)];
        const T* s = tmp + static_cast<std::size_t>(y + k) * wv;
        for (int x = 0; x < wv; ++x) row[x] += c * s[x];
      }
    }
  }
}

/// Transpose of filter_valid for one plane: hv x wv -> h x w (accumulated into out).
template <class T>
void filter_valid_transposed(const T* in, int w, int h, const std::vector<T>& win, T* tmp, T* out) {
  const int K = static_cast<int>(win.size());
  const int wv = w - K + 1, hv = h - K + 1;
  // vertical: tmp (h x wv)
  for (std::size_t i = 0; i < static_cast<std::size_t>(h) * wv; ++i) tmp[i] = 0;
  for (int y = 0; y < hv; ++y) {
    const T* s = in + static_cast<std::size_t>(y) * wv;
    for (int k = 0; k < K; ++k) {
      const T c = win[static_cast<std::size_t>(k)];
      T* row = tmp + static_cast<std::size_t>(y + k) * wv;
      for (int x = 0; x < wv; ++x) row[x] += c * s[x];
    }
  }
  // horizontal: out (h x w)
  for (int y = 0; y < h; ++y) {
    const T* s = tmp + static_cast<std::size_t>(y) * wv;
    T* row = out + static_cast<std::size_t>(y) * w;
    for (int k = 0; k < K; ++k) {
      const T c = win[static_cast<std::size_t>(k)];
      for (int x = 0; x < wv; ++x) row[x + k] += c * s[x];
    }
  }
}

}  // namespace

template <class T>
T Ssim<T>::evaluate(const T* x, const T* y, int width, int height, int channels, const T* mask,
                    T* grad_x) {
  const int K = static_cast<int>(win_.size());
  if (width < K || height < K) throw std::invalid_argument("SSIM: image smaller than the window");
  const int wv = width - K + 1, hv = height - K + 1, half = K / 2;
  const std::size_t np = static_cast<std::size_t>(width) * height;
  const std::size_t nv = static_cast<std::size_t>(wv) * hv;
  const T L = T(opt_.data_range);
  const T C1 = (T(0.01) * L) * (T(0.01) * L), C2 = (T(0.03) * L) * (T(0.03) * L);
  const T cn = opt_.sample_covariance ? T(K * K) / T(K * K - 1) : T(1);
  // position weights: 1 where the window centre is unmasked
  std::size_t n_valid = 0;
  for (int yy = 0; yy < hv; ++yy)
    for (int xx = 0; xx < wv; ++xx)
      if (!mask || mask[static_cast<std::size_t>(yy + half) * width + xx + half] > T(0)) ++n_valid;
  if (grad_x) {
    for (std::size_t i = 0; i < np * channels; ++i) grad_x[i] = 0;
  }
  if (n_valid == 0) return T(1);
  const T inv_n = T(1) / (T(n_valid) * T(channels));
  xs_.resize(5 * np);
  tmp_.resize(static_cast<std::size_t>(height) * wv);
  maps_.resize(5 * nv);
  if (grad_x) {
    g_.resize(3 * nv);
    back_.resize(np);
  }
  double total = 0;
  for (int c = 0; c < channels; ++c) {
    T* px = xs_.data();
    T* py = px + np;
    T* pxx = py + np;
    T* pyy = pxx + np;
    T* pxy = pyy + np;
    for (std::size_t i = 0; i < np; ++i) {
      const T a = x[i * channels + c], b = y[i * channels + c];
      px[i] = a;
      py[i] = b;
      pxx[i] = a * a;
      pyy[i] = b * b;
      pxy[i] = a * b;
    }
    filter_valid(xs_.data(), 5, width, height, win_, tmp_.data(), maps_.data());
    const T* mx = maps_.data();
    const T* my = mx + nv;
    const T* exx = my + nv;
    const T* eyy = exx + nv;
    const T* exy = eyy + nv;
    T* g_mu = grad_x ? g_.data() : nullptr;
    T* g_xx = grad_x ? g_.data() + nv : nullptr;
    T* g_xy = grad_x ? g_.data() + 2 * nv : nullptr;
    for (int yy = 0; yy < hv; ++yy) {
      for (int xx = 0; xx < wv; ++xx) {
        const std::size_t p = static_cast<std::size_t>(yy) * wv + xx;
        const bool on =
            !mask || mask[static_cast<std::size_t>(yy + half) * width + xx + half] > T(0);
        const T ux = mx[p], uy = my[p];
        const T vx = cn * (exx[p] - ux * ux), vy = cn * (eyy[p] - uy * uy);
        const T vxy = cn * (exy[p] - ux * uy);
        const T N1 = T(2) * ux * uy + C1, N2 = T(2) * vxy + C2;
        const T D1 = ux * ux + uy * uy + C1, D2 = vx + vy + C2;
        const T S = (N1 * N2) / (D1 * D2);
        if (on) total += static_cast<double>(S);
        if (grad_x) {
          const T wgt = on ? inv_n : T(0);
          g_mu[p] = wgt * S *
                    (T(2) * uy / N1 - T(2) * cn * uy / N2 - T(2) * ux / D1 + T(2) * cn * ux / D2);
          g_xx[p] = wgt * (-S * cn / D2);
          g_xy[p] = wgt * (S * T(2) * cn / N2);
        }
      }
    }
    if (grad_x) {
      // dL/dx_q = (W^T g_mu)_q + 2 x_q (W^T g_xx)_q + y_q (W^T g_xy)_q
      for (int m = 0; m < 3; ++m) {
        for (std::size_t i = 0; i < np; ++i) back_[i] = 0;
        filter_valid_transposed(g_.data() + m * nv, width, height, win_, tmp_.data(), back_.data());
        for (std::size_t i = 0; i < np; ++i) {
          const T f = m == 0 ? T(1) : (m == 1 ? T(2) * px[i] : py[i]);
          grad_x[i * channels + c] += f * back_[i];
        }
      }
    }
  }
  return T(total / (static_cast<double>(n_valid) * channels));
}

template class Ssim<float>;
template class Ssim<double>;

}  // namespace vigs::mapping
