#include "mapping/ssim.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <type_traits>

#include "mapping/simd_weighted_rows.hpp"
#include "mapping/ssim_map_row.hpp"

namespace vigs::mapping {

namespace {
/// The longest window (gaussian11): the tap pointers of one output row live on the stack.
constexpr int kMaxTaps = 11;

/// o[i] = sum_k w[k] * rows[k][i]: every filter pass below is made of these (AVX2 for floats
/// where available).
template <class T>
inline void filter_row(T* o, const T* const* rows, const T* w, int n_rows, int n, bool simd,
                       bool avx512) {
  if constexpr (std::is_same_v<T, float>) {
    if (simd) {
      weighted_rows(o, rows, w, n_rows, n, avx512);
      return;
    }
  }
  weighted_rows_plain(o, rows, w, n_rows, n);
}

/// One row of the SSIM map and its derivatives (AVX2 for floats where available).
template <class T>
inline double map_row(const T* const* m, const T* on_mask, const SsimRowTerms<T>& t, T* const* g,
                      int n, bool simd) {
  if constexpr (std::is_same_v<T, float>) {
    if (simd) return ssim_map_row(m, on_mask, t, g, n);
  }
  return ssim_map_row_plain(m, on_mask, t, g, n);
}
}  // namespace

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
Ssim<T>::Ssim(SsimOptions options, rt::WorkerTeam* pool) : opt_(options), pool_(pool) {
  const auto w = ssim_window_1d(options.window);
  if (static_cast<int>(w.size()) > kMaxTaps) throw std::logic_error("SSIM: window too long");
  win_.assign(w.begin(), w.end());
}

template <class T>
void Ssim<T>::for_rows(int rows, const std::function<void(int, int, int, int)>& fn) {
  const auto body = [&](int t, std::size_t b) {
    const int r0 = static_cast<int>(b) * kRowsPerBlock;
    fn(t, static_cast<int>(b), r0, std::min(rows, r0 + kRowsPerBlock));
  };
  const auto blocks = static_cast<std::size_t>(row_blocks(rows));
  if (pool_) {
    pool_->run_claimed(blocks, body);
  } else {
    for (std::size_t b = 0; b < blocks; ++b) body(0, b);
  }
}

template <class T>
T Ssim<T>::evaluate(const T* x, const T* y, int width, int height, int channels, const T* mask,
                    T* grad_x) {
  return run(x, y, width, height, channels, mask, grad_x, false, T(1));
}

template <class T>
T Ssim<T>::evaluate_add_gradient(const T* x, const T* y, int width, int height, int channels,
                                 const T* mask, T* grad, T weight) {
  return run(x, y, width, height, channels, mask, grad, true, weight);
}

template <class T>
T Ssim<T>::run(const T* x, const T* y, int width, int height, int channels, const T* mask,
               T* grad_x, bool add, T weight) {
  const int K = static_cast<int>(win_.size());
  if (width < K || height < K) throw std::invalid_argument("SSIM: image smaller than the window");
  const int wv = width - K + 1, hv = height - K + 1, half = K / 2;
  const std::size_t w = static_cast<std::size_t>(width);
  const std::size_t np = w * static_cast<std::size_t>(height);
  const std::size_t nh = static_cast<std::size_t>(height) * static_cast<std::size_t>(wv);
  const std::size_t nv = static_cast<std::size_t>(wv) * static_cast<std::size_t>(hv);
  const T L = T(opt_.data_range);
  const T C1 = (T(0.01) * L) * (T(0.01) * L), C2 = (T(0.03) * L) * (T(0.03) * L);
  const T cn = opt_.sample_covariance ? T(K * K) / T(K * K - 1) : T(1);
  auto centre_on = [&](int yy, int xx) {
    return !mask ||
           mask[static_cast<std::size_t>(yy + half) * w + static_cast<std::size_t>(xx + half)] >
               T(0);
  };
  // windows whose centre is on, counted per block of rows in parallel (an integer: the same
  // whatever the blocks)
  std::size_t n_valid = nv;
  if (mask) {
    valid_.assign(static_cast<std::size_t>(row_blocks(hv)), 0);
    for_rows(hv, [&](int, int block, int r0, int r1) {
      std::size_t n = 0;
      for (int yy = r0; yy < r1; ++yy)
        for (int xx = 0; xx < wv; ++xx) n += centre_on(yy, xx) ? 1 : 0;
      valid_[static_cast<std::size_t>(block)] = n;
    });
    n_valid = 0;
    for (const std::size_t n : valid_) n_valid += n;
  }
  if (n_valid == 0) {
    // no window: SSIM 1, no gradient (the passes below write every pixel's otherwise)
    if (grad_x && !add) std::fill(grad_x, grad_x + np * static_cast<std::size_t>(channels), T(0));
    return T(1);
  }
  const T inv_n = T(1) / (T(n_valid) * T(channels));
  const SsimRowTerms<T> terms{C1, C2, cn, inv_n};
  const int nt = pool_ ? pool_->size() : 1;
  tmp_.resize(5 * nh);
  maps_.resize(5 * nv);
  if (grad_x) g_.resize(3 * nv);
  rows_.resize(static_cast<std::size_t>(nt) * 5 * w);
  const std::size_t pad_len = w + static_cast<std::size_t>(K);  // wv + 2 (K - 1) <= w + K
  pad_.resize(static_cast<std::size_t>(nt) * pad_len);
  const auto n_blocks = static_cast<std::size_t>(row_blocks(hv));
  partial_.assign(n_blocks * static_cast<std::size_t>(channels), 0.0);
  const T* win = win_.data();
  const bool simd = opt_.use_simd, avx512 = opt_.use_avx512;
  const std::size_t cs = static_cast<std::size_t>(channels);
  for (int c = 0; c < channels; ++c) {
    // horizontal pass of x, y, xx, yy, xy: deinterleave a row into 5 planes, then filter each
    // plane with the tap loop outside so the inner loop is contiguous: tmp (5 x h x wv)
    for_rows(height, [&](int t, int, int r0, int r1) {
      T* rowbuf = rows_.data() + static_cast<std::size_t>(t) * 5 * w;
      for (int r = r0; r < r1; ++r) {
        const T* xr = x + static_cast<std::size_t>(r) * w * cs + static_cast<std::size_t>(c);
        const T* yr = y + static_cast<std::size_t>(r) * w * cs + static_cast<std::size_t>(c);
        for (std::size_t q = 0; q < w; ++q) {
          const T a = xr[q * cs], b = yr[q * cs];
          rowbuf[q] = a;
          rowbuf[w + q] = b;
          rowbuf[2 * w + q] = a * a;
          rowbuf[3 * w + q] = b * b;
          rowbuf[4 * w + q] = a * b;
        }
        for (int m = 0; m < 5; ++m) {
          T* o = tmp_.data() + static_cast<std::size_t>(m) * nh +
                 static_cast<std::size_t>(r) * static_cast<std::size_t>(wv);
          const T* src = rowbuf + static_cast<std::size_t>(m) * w;
          const T* taps[kMaxTaps];
          for (int k = 0; k < K; ++k) taps[k] = src + k;
          filter_row(o, taps, win, K, wv, simd, avx512);
        }
      }
    });
    // vertical pass, then the SSIM map and its partial derivatives
    for_rows(hv, [&](int, int block, int r0, int r1) {
      double sum = 0;
      for (int r = r0; r < r1; ++r) {
        for (int m = 0; m < 5; ++m) {
          T* o = maps_.data() + static_cast<std::size_t>(m) * nv +
                 static_cast<std::size_t>(r) * static_cast<std::size_t>(wv);
          const T* src = tmp_.data() + static_cast<std::size_t>(m) * nh;
          const T* taps[kMaxTaps];
          for (int k = 0; k < K; ++k)
            taps[k] = src + static_cast<std::size_t>(r + k) * static_cast<std::size_t>(wv);
          filter_row(o, taps, win, K, wv, simd, avx512);
        }
        const std::size_t row = static_cast<std::size_t>(r) * static_cast<std::size_t>(wv);
        const T* const moments[5] = {maps_.data() + row, maps_.data() + nv + row,
                                     maps_.data() + 2 * nv + row, maps_.data() + 3 * nv + row,
                                     maps_.data() + 4 * nv + row};
        T* const grads[3] = {g_.data() + row, g_.data() + nv + row, g_.data() + 2 * nv + row};
        const T* on_mask =
            mask ? mask + static_cast<std::size_t>(r + half) * w + static_cast<std::size_t>(half)
                 : nullptr;
        sum += map_row(moments, on_mask, terms, grad_x ? grads : nullptr, wv, simd);
      }
      partial_[static_cast<std::size_t>(block) * cs + static_cast<std::size_t>(c)] = sum;
    });
    if (!grad_x) continue;
    // transposed filters as gathers: vertical into tmp (3 x h x wv), then horizontal per row;
    // dL/dx_q = (W^T g_mu)_q + 2 x_q (W^T g_xx)_q + y_q (W^T g_xy)_q
    for_rows(height, [&](int t, int, int r0, int r1) {
      // the horizontal transpose below reads each row from a copy with K - 1 zeros on either
      // side; the copies overwrite only the middle, so the zeros are written once per block
      T* pad = pad_.data() + static_cast<std::size_t>(t) * pad_len;
      const auto edge = static_cast<std::size_t>(K - 1);
      for (std::size_t q = 0; q < edge; ++q)
        pad[q] = pad[edge + static_cast<std::size_t>(wv) + q] = 0;
      for (int r = r0; r < r1; ++r) {
        for (int m = 0; m < 3; ++m) {
          T* o = tmp_.data() + static_cast<std::size_t>(m) * nh +
                 static_cast<std::size_t>(r) * static_cast<std::size_t>(wv);
          // the taps k whose source row r - k is a valid window row, in order k
          const int k0 = std::max(0, r - hv + 1), k1 = std::min(K - 1, r);
          const T* taps[kMaxTaps];
          for (int k = k0; k <= k1; ++k)
            taps[k - k0] = g_.data() + static_cast<std::size_t>(m) * nv +
                           static_cast<std::size_t>(r - k) * static_cast<std::size_t>(wv);
          filter_row(o, taps, win + k0, k1 - k0 + 1, wv, simd, avx512);
        }
        // horizontal transpose: back[q] = sum_k win[k] src[q - k] over 0 <= q - k < wv
        T* back = rows_.data() + static_cast<std::size_t>(t) * 5 * w;
        for (int m = 0; m < 3; ++m) {
          const T* src = tmp_.data() + static_cast<std::size_t>(m) * nh +
                         static_cast<std::size_t>(r) * static_cast<std::size_t>(wv);
          std::copy(src, src + wv, pad + edge);
          const T* taps[kMaxTaps];
          for (int k = 0; k < K; ++k) taps[k] = pad + edge - static_cast<std::size_t>(k);
          filter_row(back + static_cast<std::size_t>(m) * w, taps, win, K, width, simd, avx512);
        }
        for (std::size_t q = 0; q < w; ++q) {
          const std::size_t i =
              (static_cast<std::size_t>(r) * w + q) * cs + static_cast<std::size_t>(c);
          const T d = back[q] + T(2) * x[i] * back[w + q] + y[i] * back[2 * w + q];
          if (add) {
            grad_x[i] += weight * d;
          } else {
            grad_x[i] = d;
          }
        }
      }
    });
  }
  double total = 0;
  for (int c = 0; c < channels; ++c)
    for (std::size_t b = 0; b < n_blocks; ++b)
      total += partial_[b * cs + static_cast<std::size_t>(c)];
  return T(total / (static_cast<double>(n_valid) * channels));
}

template class Ssim<float>;
template class Ssim<double>;

}  // namespace vigs::mapping
