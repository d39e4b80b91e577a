// Writes seed inputs for fuzz_ply_reader, fuzz_image_decoders and fuzz_yaml_config into
// CORPUS_ROOT/ply, CORPUS_ROOT/image and CORPUS_ROOT/yaml: a 3-Gaussian 3DGS PLY, small PNGs
// (gray, RGB, RGBA, 16-bit) each behind every decoder-selector byte, and the robot YAML files
// given after the root.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include "core/types/image.hpp"
#include "io/image_io.hpp"
#include "mapping/ply_io.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<char> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_seed(const fs::path& path, const std::vector<char>& bytes, int selector = -1) {
  std::ofstream out(path, std::ios::binary);
  if (selector >= 0) out.put(static_cast<char>(selector));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: fuzz_file_seeds CORPUS_ROOT [ROBOT.yaml...]\n";
    return 2;
  }
  const fs::path root = argv[1];
  for (const char* sub : {"ply", "image", "yaml"}) fs::create_directories(root / sub);
  const fs::path tmp = root / "seed.tmp";

  vigs::mapping::GaussianMap map;
  map.resize(3);
  for (std::size_t i = 0; i < 3; ++i) {
    map.mean_w[3 * i] = static_cast<float>(i);
    map.quat_wxyz[4 * i] = 1.0f;
    map.log_scale[3 * i] = -2.0f;
  }
  vigs::mapping::write_gaussian_ply(tmp.string(), map);
  write_seed(root / "ply" / "seed_0", read_bytes(tmp));

  int index = 0;
  for (const int channels : {1, 3, 4}) {
    vigs::ImageU8 img(5, 3, channels);
    for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = static_cast<std::uint8_t>(i);
    vigs::io::write_png(tmp.string(), img);
    const auto bytes = read_bytes(tmp);
    for (int selector = 0; selector < 4; ++selector)
      write_seed(root / "image" / ("seed_" + std::to_string(index++)), bytes, selector);
  }
  vigs::ImageU16 depth(4, 4, 1);
  for (std::size_t i = 0; i < depth.data.size(); ++i)
    depth.data[i] = static_cast<std::uint16_t>(1000 + i);
  vigs::io::write_png_u16(tmp.string(), depth);
  for (int selector = 0; selector < 4; ++selector)
    write_seed(root / "image" / ("seed_" + std::to_string(index++)), read_bytes(tmp), selector);
  fs::remove(tmp);

  for (int i = 2; i < argc; ++i)
    write_seed(root / "yaml" / ("seed_" + std::to_string(i - 2)), read_bytes(argv[i]));
  std::cout << "fuzz_file_seeds: seeds in " << root.string() << "\n";
  return 0;
}
