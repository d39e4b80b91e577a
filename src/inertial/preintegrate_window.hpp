#pragma once
// Preintegration of a recorded sample sequence over an exact window [t_i, t_j]: the samples
// straddling each end are interpolated so that the window matches the frame times.
#include <Eigen/Core>
#include <cstdint>
#include <span>

#include "core/types/imu_sample.hpp"
#include "inertial/preintegrator.hpp"

namespace vigs::inertial {

/// Resets `pi` (keeping its scheme and noise) and integrates `samples` (sorted by t_ns) over
/// [t_i_ns, t_j_ns]. Returns false, leaving `pi` unspecified, when the samples do not cover
/// the window or t_j_ns < t_i_ns. Samples that do not advance time are skipped.
bool preintegrate_window(std::span<const ImuSample> samples, std::int64_t t_i_ns,
                         std::int64_t t_j_ns, const Eigen::Vector3d& bias_gyro_rps,
                         const Eigen::Vector3d& bias_accel_mps2, Preintegrator& pi);

/// Largest gap between consecutive samples inside [t_i_ns, t_j_ns] (including the samples
/// straddling the ends), ns; 0 when not covered.
std::int64_t largest_gap_ns(std::span<const ImuSample> samples, std::int64_t t_i_ns,
                            std::int64_t t_j_ns);

}  // namespace vigs::inertial
