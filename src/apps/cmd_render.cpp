// `vigs render --map map.ply --camera CAMERA.yaml --pose "tx ty tz qx qy qz qw" --out img.png`:
// colour PNG and a 16-bit depth PNG of a Gaussian map from any camera-to-world pose.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>

#include "apps/commands.hpp"
#include "apps/frame_list.hpp"
#include "core/config/yaml_loader.hpp"
#include "io/image_io.hpp"
#include "io/json_text.hpp"
#include "io/output_guard.hpp"
#include "mapping/ply_io.hpp"
#include "mapping/rasterizer.hpp"

namespace vigs::apps {

namespace {
std::string default_depth_path(const std::string& out) {
  const auto dot = out.rfind('.');
  return (dot == std::string::npos ? out : out.substr(0, dot)) + "_depth.png";
}
}  // namespace

void add_render_command(CLI::App& app, ExitCode& exit_code) {
  auto* cmd = app.add_subcommand(
      "render", "Render colour and depth PNGs of a Gaussian map (3DGS PLY) from a pose");
  static std::string map_path, camera_path, pose_text, out_path, depth_path;
  static int threads = 2;
  cmd->add_option("--map", map_path, "3DGS PLY map")->required();
  cmd->add_option("--camera", camera_path,
                  "robot YAML whose camera section gives the intrinsics and depth scale")
      ->required();
  cmd->add_option("--pose", pose_text, "camera-to-world pose 'tx ty tz qx qy qz qw'")->required();
  cmd->add_option("--out", out_path, "colour PNG (RGB, 8-bit)")->required();
  cmd->add_option("--depth-out", depth_path,
                  "depth PNG, 16-bit in the camera's depth units (default: <out>_depth.png); "
                  "depth is sum(z alpha T) / (1 - T), 0 where accumulated opacity < 0.5");
  cmd->add_option("--threads", threads, "rasterizer threads")->check(CLI::Range(1, 64));
  cmd->callback([&exit_code] {
    try {
      if (depth_path.empty()) depth_path = default_depth_path(out_path);
      if (depth_path == out_path)
        throw std::runtime_error(out_path + ": --out and --depth-out are the same file");
      for (const std::string* out : {&out_path, &depth_path})
        io::refuse_output_over_inputs(*out, {map_path, camera_path});
      const auto cfg = config::load_config_file(camera_path);
      const PinholeCamera k = PinholeCamera::from_settings(cfg.camera);
      const Eigen::Isometry3d T_w_c = parse_pose_text(pose_text);
      const mapping::GaussianMap map = mapping::read_gaussian_ply(map_path);
      vigs::rt::WorkerTeam pool(threads, vigs::rt::ThreadSpec{.name = "mapper_w1"});
      mapping::Rasterizer<float> ras(mapping::RasterSettings{}, &pool);
      mapping::RenderResult<float> r;
      ras.forward(map, mapping::RenderCamera::from(k, T_w_c), r);
      ImageU8 color(k.width_px, k.height_px, 3);
      ImageU16 depth(k.width_px, k.height_px, 1);
      const double scale = cfg.camera.depth_scale_m;
      for (std::size_t p = 0; p < r.depth.size(); ++p) {
        for (int c = 0; c < 3; ++c)
          color.data[3 * p + c] = static_cast<std::uint8_t>(
              std::lround(255.0 * std::clamp(r.color[3 * p + c], 0.0f, 1.0f)));
        const double a = 1.0 - r.final_T[p];
        const double z = a >= 0.5 ? r.depth[p] / a : 0.0;
        depth.data[p] = static_cast<std::uint16_t>(std::clamp(std::lround(z / scale), 0L, 65535L));
      }
      io::write_png(out_path, color);
      io::write_png_u16(depth_path, depth);
      io::Json j;
      j["map"] = map_path;
      j["gaussians"] = map.size();
      j["visible_tile_pairs"] = ras.tile_pairs();
      j["color"] = out_path;
      j["depth"] = depth_path;
      j["depth_scale_m"] = io::rounded(scale, 10);
      std::cout << io::json_line(j) << "\n";
    } catch (const std::exception& e) {
      std::cerr << "vigs render: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
