#include "sim/imu_synth.hpp"

#include <cmath>

namespace vigs::sim {

ImuSynthesizer::ImuSynthesizer(const config::ImuSettings& settings, std::uint64_t seed, bool noisy)
    : s_(settings), rng_(seed, 0x1A0), noisy_(noisy), dt_s_(1.0 / settings.rate_hz) {}

ImuSample ImuSynthesizer::measure(const BodyState& st, std::int64_t t_ns) {
  const Eigen::Vector3d g_w(0.0, 0.0, -s_.gravity_mps2);
  Eigen::Vector3d gyro = st.omega_b_rps;
  Eigen::Vector3d accel = st.R_w_b.transpose() * (st.a_w_mps2 - g_w);
  if (noisy_) {
    const double sg = s_.gyro_noise_density / std::sqrt(dt_s_);
    const double sa = s_.accel_noise_density / std::sqrt(dt_s_);
    for (int i = 0; i < 3; ++i) {
      gyro[i] += b_g_[i] + sg * rng_.normal();
      accel[i] += b_a_[i] + sa * rng_.normal();
    }
    const double wg = s_.gyro_random_walk * std::sqrt(dt_s_);
    const double wa = s_.accel_random_walk * std::sqrt(dt_s_);
    for (int i = 0; i < 3; ++i) {
      b_g_[i] += wg * rng_.normal();
      b_a_[i] += wa * rng_.normal();
    }
  }
  ImuSample out;
  out.t_ns = t_ns;
  for (int i = 0; i < 3; ++i) {
    out.gyro_rps[i] = gyro[i];
    out.accel_mps2[i] = accel[i];
  }
  return out;
}

}  // namespace vigs::sim
