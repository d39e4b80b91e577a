// Interoperability: a PLY map written by VIGS opens in a common third-party splat converter,
// @playcanvas/splat-transform (pinned in tests/mapping/splat_tool/package.json; install with
// `npm ci --prefix tests/mapping/splat_tool`). The converter re-exports it as CSV, whose values
// must be ours, and converts it to SPZ. Skipped (with the reason) when node or the package is
// not installed.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../common/temp_files.hpp"
#include "mapping/ply_io.hpp"
#include "test_scene.hpp"

namespace vigs::mapping {
namespace {

TEST(MappingSplatTool, PlyOpensInPlaycanvasSplatTransform) {
  const std::filesystem::path cli = std::filesystem::path(VIGS_SOURCE_DIR) /
                                    "tests/mapping/splat_tool/node_modules/@playcanvas/"
                                    "splat-transform/bin/cli.mjs";
  if (std::system("node --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "node not installed";
  if (!std::filesystem::exists(cli))
    GTEST_SKIP() << "run `npm ci --prefix tests/mapping/splat_tool` to install splat-transform";
  vigs::test::TempFiles files("vigs_splat");  // the folder goes however the test ends
  const std::filesystem::path dir = files.path("dir");
  std::filesystem::create_directories(dir);
  const GaussianMap g = test::random_gaussians<float>(25, 13);
  const std::string ply = (dir / "map.ply").string(), csv = (dir / "map.csv").string();
  write_gaussian_ply(ply, g);
  const std::string node = "node " + cli.string() + " ";
  ASSERT_EQ(std::system((node + ply + " " + csv + " > /dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(
      std::system((node + ply + " " + (dir / "map.spz").string() + " > /dev/null 2>&1").c_str()),
      0);
  EXPECT_GT(std::filesystem::file_size(dir / "map.spz"), 0u);

  std::ifstream f(csv);
  std::string header;
  ASSERT_TRUE(std::getline(f, header));
  EXPECT_EQ(header,
            "x,y,z,nx,ny,nz,f_dc_0,f_dc_1,f_dc_2,opacity,scale_0,scale_1,scale_2,rot_0,rot_1,"
            "rot_2,rot_3");
  std::string line;
  std::size_t i = 0;
  while (std::getline(f, line) && !line.empty()) {
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
    ASSERT_EQ(v.size(), 17u);
    ASSERT_LT(i, g.size());
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(v[static_cast<std::size_t>(k)], g.mean_w[3 * i + k], 1e-6);
      EXPECT_NEAR(0.5 + kShC0 * v[static_cast<std::size_t>(6 + k)], g.color_rgb[3 * i + k], 1e-6);
      EXPECT_NEAR(v[static_cast<std::size_t>(10 + k)], g.log_scale[3 * i + k], 1e-6);
    }
    EXPECT_NEAR(v[9], g.opacity_logit[i], 1e-6);
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(v[static_cast<std::size_t>(13 + k)], g.quat_wxyz[4 * i + k], 1e-6);
    ++i;
  }
  EXPECT_EQ(i, g.size());
}

}  // namespace
}  // namespace vigs::mapping
