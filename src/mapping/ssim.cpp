#include "mapping/ssim.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <type_traits>

#include "mapping/row_blocks.hpp"
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
    valid_.assign(row_block_count(hv, kRowsPerBlock), 0);
    for_row_blocks(pool_, hv, kRowsPerBlock, [&](int, int block, int r0, int r1) {
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
  const std::size_t cs = static_cast<std::size_t>(channels);
  const std::size_t wvs = static_cast<std::size_t>(wv);
  // Per thread: a strip's horizontally filtered rows (5 planes of kStripRows + K - 1 rows), one
  // row's window moments (5 x wv), a deinterleaved input row (5 x w), the transposed filters'
  // vertical rows (3 x wv) and the zero-padded row of the horizontal transpose.
  const auto strip_in = static_cast<std::size_t>(kStripRows + K - 1);
  const std::size_t hbuf_len = 5 * strip_in * wvs;
  const std::size_t pad_len = w + static_cast<std::size_t>(K);  // wv + 2 (K - 1) <= w + K
  const std::size_t scratch_len = hbuf_len + 5 * wvs + 5 * w + 3 * wvs + pad_len;
  scratch_.resize(static_cast<std::size_t>(nt) * scratch_len);
  if (grad_x) g_.resize(cs * 3 * nv);
  const std::size_t n_strips = row_block_count(hv, kStripRows);
  partial_.assign(n_strips * cs, 0.0);
  const T* win = win_.data();
  const bool simd = opt_.use_simd, avx512 = opt_.use_avx512;
  // Forward, a strip of kStripRows window rows at a time (every channel): the horizontal pass of
  // x, y, xx, yy, xy over the strip's input rows (deinterleave a row into 5 planes, then filter
  // each plane with the tap loop outside so the inner loop is contiguous), then per window row the
  // vertical pass, the SSIM map and its partial derivatives (g_, per channel). A strip's rows stay
  // in cache between the passes; the K - 1 rows it shares with the next strip are filtered twice.
  for_row_blocks(pool_, hv, kStripRows, [&](int t, int strip, int r0, int r1) {
    T* hbuf = scratch_.data() + static_cast<std::size_t>(t) * scratch_len;
    T* moments_row = hbuf + hbuf_len;
    T* rowbuf = moments_row + 5 * wvs;
    const int in0 = r0, in1 = r1 + K - 1;
    const auto plane = [&](int m, int r) {  // strip row r (an input row) of plane m
      return hbuf +
             (static_cast<std::size_t>(m) * strip_in + static_cast<std::size_t>(r - in0)) * wvs;
    };
    for (std::size_t c = 0; c < cs; ++c) {
      for (int r = in0; r < in1; ++r) {
        const T* xr = x + static_cast<std::size_t>(r) * w * cs + c;
        const T* yr = y + static_cast<std::size_t>(r) * w * cs + c;
        for (std::size_t q = 0; q < w; ++q) {
          const T a = xr[q * cs], b = yr[q * cs];
          rowbuf[q] = a;
          rowbuf[w + q] = b;
          rowbuf[2 * w + q] = a * a;
          rowbuf[3 * w + q] = b * b;
          rowbuf[4 * w + q] = a * b;
        }
        for (int m = 0; m < 5; ++m) {
          const T* src = rowbuf + static_cast<std::size_t>(m) * w;
          const T* taps[kMaxTaps];
          for (int k = 0; k < K; ++k) taps[k] = src + k;
          filter_row(plane(m, r), taps, win, K, wv, simd, avx512);
        }
      }
      double sum = 0;
      for (int r = r0; r < r1; ++r) {
        for (int m = 0; m < 5; ++m) {
          const T* taps[kMaxTaps];
          for (int k = 0; k < K; ++k) taps[k] = plane(m, r + k);
          filter_row(moments_row + static_cast<std::size_t>(m) * wvs, taps, win, K, wv, simd,
                     avx512);
        }
        const T* const moments[5] = {moments_row, moments_row + wvs, moments_row + 2 * wvs,
                                     moments_row + 3 * wvs, moments_row + 4 * wvs};
        T* const g = g_.data() + c * 3 * nv + static_cast<std::size_t>(r) * wvs;
        T* const grads[3] = {g, g + nv, g + 2 * nv};
        const T* on_mask =
            mask ? mask + static_cast<std::size_t>(r + half) * w + static_cast<std::size_t>(half)
                 : nullptr;
        sum += map_row(moments, on_mask, terms, grad_x ? grads : nullptr, wv, simd);
      }
      partial_[static_cast<std::size_t>(strip) * cs + c] = sum;
    }
  });
  if (grad_x) {
    // transposed filters as gathers, per pixel row: vertical (3 x wv), then horizontal;
    // dL/dx_q = (W^T g_mu)_q + 2 x_q (W^T g_xx)_q + y_q (W^T g_xy)_q
    for_row_blocks(pool_, height, kRowsPerBlock, [&](int t, int, int r0, int r1) {
      T* const base = scratch_.data() + static_cast<std::size_t>(t) * scratch_len;
      T* back = base + hbuf_len + 5 * wvs;
      T* vert = back + 5 * w;
      // the horizontal transpose below reads each row from a copy with K - 1 zeros on either
      // side; the copies overwrite only the middle, so the zeros are written once per block
      T* pad = vert + 3 * wvs;
      const auto edge = static_cast<std::size_t>(K - 1);
      for (std::size_t q = 0; q < edge; ++q) pad[q] = pad[edge + wvs + q] = 0;
      for (std::size_t c = 0; c < cs; ++c) {
        const T* gc = g_.data() + c * 3 * nv;
        for (int r = r0; r < r1; ++r) {
          // the taps k whose source row r - k is a valid window row, in order k
          const int k0 = std::max(0, r - hv + 1), k1 = std::min(K - 1, r);
          for (int m = 0; m < 3; ++m) {
            const T* taps[kMaxTaps];
            for (int k = k0; k <= k1; ++k)
              taps[k - k0] =
                  gc + static_cast<std::size_t>(m) * nv + static_cast<std::size_t>(r - k) * wvs;
            filter_row(vert + static_cast<std::size_t>(m) * wvs, taps, win + k0, k1 - k0 + 1, wv,
                       simd, avx512);
          }
          // horizontal transpose: back[q] = sum_k win[k] src[q - k] over 0 <= q - k < wv
          for (int m = 0; m < 3; ++m) {
            const T* src = vert + static_cast<std::size_t>(m) * wvs;
            std::copy(src, src + wv, pad + edge);
            const T* taps[kMaxTaps];
            for (int k = 0; k < K; ++k) taps[k] = pad + edge - static_cast<std::size_t>(k);
            filter_row(back + static_cast<std::size_t>(m) * w, taps, win, K, width, simd, avx512);
          }
          for (std::size_t q = 0; q < w; ++q) {
            const std::size_t i = (static_cast<std::size_t>(r) * w + q) * cs + c;
            const T d = back[q] + T(2) * x[i] * back[w + q] + y[i] * back[2 * w + q];
            if (add) {
              grad_x[i] += weight * d;
            } else {
              grad_x[i] = d;
            }
          }
        }
      }
    });
  }
  double total = 0;
  for (std::size_t c = 0; c < cs; ++c)
    for (std::size_t b = 0; b < n_strips; ++b) total += partial_[b * cs + c];
  return T(total / (static_cast<double>(n_valid) * channels));
}

template class Ssim<float>;
template class Ssim<double>;

}  // namespace vigs::mapping
