// libFuzzer target: mapping::read_gaussian_ply on any byte string returns a map or throws
// PlyError naming the file; never a crash, an out-of-bounds read, an allocation the file size
// does not justify, or a non-finite value in the returned map. Seeds: fuzz_file_seeds.
#include <cmath>
#include <cstdint>

#include "mapping/ply_io.hpp"
#include "tests/fuzz/fuzz_memfd.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vigs::fuzz::as_file(data, size);
  if (path.empty()) return 0;
  try {
    const vigs::mapping::GaussianMap map = vigs::mapping::read_gaussian_ply(path);
    for (const float v : map.mean_w)
      if (!std::isfinite(v)) __builtin_trap();
    for (const float v : map.log_scale)
      if (!std::isfinite(v)) __builtin_trap();
  } catch (const vigs::mapping::PlyError&) {
  }
  return 0;
}
