#pragma once
// 3D Gaussian Splatting PLY files (the layout of the reference implementation, read by common
// splat viewers and converters): binary little-endian float vertex properties
//   x y z  nx ny nz  f_dc_0 f_dc_1 f_dc_2  opacity (logit)  scale_0..2 (log)  rot_0..3 (w x y z)
// Colour is stored as the degree-0 SH coefficient: rgb = 0.5 + C0 * f_dc, C0 = 0.28209479.
#include <stdexcept>
#include <string>

#include "mapping/gaussian_map.hpp"

namespace vigs::mapping {

class PlyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr double kShC0 = 0.28209479177387814;

/// Writes atomically (temporary file in the same folder, then rename). A Gaussian with a
/// non-finite parameter is left out (no NaN reaches a file, and the reader would refuse it);
/// returns how many were left out.
std::size_t write_gaussian_ply(const std::string& path, const GaussianMap& map);

/// Reads a 3DGS PLY; properties may come in any order, extra float properties (f_rest_*) are
/// ignored. Errors name the file and the header line or byte offset.
GaussianMap read_gaussian_ply(const std::string& path);

}  // namespace vigs::mapping
