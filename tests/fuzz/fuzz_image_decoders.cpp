// libFuzzer target: the image decoders (PNG 8/16-bit, JPEG, float TIFF, depth) on any byte
// string return an image whose buffer matches its size, or throw ImageIoError naming the file;
// never a crash, a longjmp out of libpng/libjpeg into freed state, or an out-of-bounds write.
// The first byte selects the decoder. Seeds: fuzz_file_seeds (small PNGs, a JPEG, a TIFF).
#include <cstdint>

#include "io/image_io.hpp"
#include "tests/fuzz/fuzz_memfd.hpp"

namespace {

template <class Image>
void check(const Image& img) {
  const auto n = static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height) *
                 static_cast<std::size_t>(img.channels);
  if (img.width < 0 || img.height < 0 || img.data.size() != n) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::string path = vigs::fuzz::as_file(data + 1, size - 1);
  if (path.empty()) return 0;
  try {
    switch (data[0] % 4) {
      case 0:
        check(vigs::io::read_image_u8(path));
        break;
      case 1:
        check(vigs::io::read_png_u16(path));
        break;
      case 2:
        check(vigs::io::read_tiff_f32(path));
        break;
      default:
        check(vigs::io::read_depth_m(path, 0.001));
        break;
    }
  } catch (const vigs::io::ImageIoError&) {
  }
  return 0;
}
