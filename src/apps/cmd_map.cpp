// `vigs map --camera CAMERA.yaml --frames LIST.txt [--iterations N] --out map.ply`: builds a
// Gaussian map offline from posed RGB-D frames with the mapping back end alone.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <iostream>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "apps/frame_list.hpp"
#include "core/config/yaml_loader.hpp"
#include "io/image_io.hpp"
#include "io/json_text.hpp"
#include "io/output_guard.hpp"
#include "mapping/compact_kept.hpp"
#include "mapping/far_field.hpp"
#include "mapping/insertion.hpp"
#include "mapping/insertion_gate.hpp"
#include "mapping/map_optimizer.hpp"
#include "mapping/ply_io.hpp"
#include "mapping/rgbd_keyframe.hpp"

namespace vigs::apps {

namespace {

struct LoadedFrame {
  mapping::TrainingView view;
  std::vector<float> rgb, depth_m;
};

}  // namespace

void add_map_command(CLI::App& app, ExitCode& exit_code) {
  auto* cmd = app.add_subcommand(
      "map", "Build a Gaussian map offline from posed RGB-D frames (poses from elsewhere)");
  static std::string camera_path, frames_path, out_path;
  static int iterations = 2000, stride = 4;
  static bool quiet = false;
  cmd->add_option("--camera", camera_path,
                  "robot YAML: camera intrinsics and depth scale, and the mapping section")
      ->required();
  cmd->add_option("--frames", frames_path,
                  "list: timestamp colour depth tx ty tz qx qy qz qw (camera-to-world)")
      ->required();
  cmd->add_option("--iterations", iterations, "optimisation iterations")
      ->check(CLI::Range(0, 10000000))
      ->capture_default_str();
  cmd->add_option("--stride", stride, "insert one Gaussian per stride x stride pixels")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--out", out_path, "output 3DGS PLY (written atomically)")->required();
  cmd->add_flag("--quiet", quiet, "no progress on stderr");
  cmd->callback([&exit_code] {
    try {
      const auto t0 = std::chrono::steady_clock::now();
      const auto list = read_frame_list(frames_path);
      std::vector<std::string> inputs = {camera_path, frames_path};
      for (const auto& f : list) {
        inputs.push_back(f.color_path);
        inputs.push_back(f.depth_path);
      }
      io::refuse_output_over_inputs(out_path, inputs);
      const auto cfg = config::load_config_file(camera_path);
      const PinholeCamera k = PinholeCamera::from_settings(cfg.camera);
      mapping::GaussianMap map;
      mapping::GaussianInserter inserter(cfg.mapping.insert);
      std::vector<LoadedFrame> frames(list.size());
      mapping::Rasterizer<float> far_raster;
      mapping::RenderResult<float> far_render;
      std::size_t far = 0;
      std::vector<std::uint8_t> far_flag;  // per Gaussian: 1 for the far field's
      mapping::RgbdSampling sampling;
      sampling.stride_px = stride;
      sampling.min_depth_m = cfg.camera.min_depth_m;
      sampling.max_depth_m = cfg.camera.max_depth_m;
      for (std::size_t i = 0; i < list.size(); ++i) {
        const auto rgb = io::read_rgb(list[i].color_path);
        auto depth = io::read_depth_m(list[i].depth_path, cfg.camera.depth_scale_m);
        if (rgb.width != k.width_px || rgb.height != k.height_px)
          throw std::runtime_error(list[i].color_path + ": image is " + std::to_string(rgb.width) +
                                   "x" + std::to_string(rgb.height) + " but the camera is " +
                                   std::to_string(k.width_px) + "x" + std::to_string(k.height_px));
        if (depth.width != rgb.width || depth.height != rgb.height)
          throw std::runtime_error(list[i].depth_path + ": depth size differs from colour");
        std::size_t valid = 0;
        for (auto& z : depth.data) {
          if (!(z >= cfg.camera.min_depth_m && z <= cfg.camera.max_depth_m)) z = 0.0f;
          valid += z > 0.0f;
        }
        // A frame with no usable depth would silently give no Gaussians (NaN, Inf, 0 or
        // out-of-range everywhere): an error naming the file, not an empty map.
        if (valid == 0)
          throw std::runtime_error(list[i].depth_path + ": no depth pixel in [" +
                                   std::to_string(cfg.camera.min_depth_m) + ", " +
                                   std::to_string(cfg.camera.max_depth_m) +
                                   "] m (all 0, NaN, Inf or out of range)");
        LoadedFrame& f = frames[i];
        f.rgb.resize(rgb.data.size());
        for (std::size_t j = 0; j < rgb.data.size(); ++j) f.rgb[j] = rgb.data[j] / 255.0f;
        f.depth_m = depth.data;
        f.view = {mapping::RenderCamera::from(k, list[i].T_w_c), f.rgb.data(), f.depth_m.data()};
        // far Gaussians only where the map, as it was before this frame, renders nothing
        const bool gated = map.size() > 0;
        if (gated) far_raster.forward(map, f.view.camera, far_render);
        inserter.insert(map, mapping::keyframe_from_rgbd(k, rgb, depth, list[i].T_w_c, sampling));
        far_flag.resize(map.size(), 0);
        far += mapping::insert_far_field(
            map, {f.view.camera, f.view.rgb, f.view.depth_m}, gated ? &far_render : nullptr,
            cfg.mapping.far_field, cfg.mapping.insert.cover, cfg.mapping.insert.opacity,
            mapping::GateSettings{}.max_alpha, 0.9 * cfg.mapping.prune.max_scale_m);
        far_flag.resize(map.size(), 1);
      }
      const std::size_t inserted = map.size();
      if (inserted == 0)
        throw std::runtime_error(frames_path + ": the frames inserted no Gaussian (stride " +
                                 std::to_string(stride) + ")");
      vigs::rt::WorkerTeam pool(cfg.mapping.threads, vigs::rt::ThreadSpec{.name = "mapper_w1"});
      mapping::MapOptimizer opt(cfg.mapping, &pool);
      std::vector<std::size_t> order(frames.size());
      std::iota(order.begin(), order.end(), 0);
      std::mt19937 rng(0);
      mapping::LossTerms<float> last{};
      std::size_t pruned = 0;
      for (int it = 0; it < iterations; ++it) {
        const auto slot = static_cast<std::size_t>(it) % order.size();
        if (slot == 0) std::shuffle(order.begin(), order.end(), rng);
        std::size_t removed = 0;
        last = opt.iterate(map, frames[order[slot]].view, &removed,
                           cfg.mapping.far_field.fixed_geometry ? far_flag.data() : nullptr);
        if (removed > 0) mapping::compact_kept(far_flag, opt.last_prune_keep());  // follow the map
        pruned += removed;
        if (!quiet && (it + 1) % 100 == 0)
          std::cerr << "vigs map: iteration " << it + 1 << "/" << iterations << " loss "
                    << last.total << " gaussians " << map.size() << "\n";
      }
      const std::size_t not_finite = mapping::write_gaussian_ply(out_path, map);
      const double secs =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      io::Json j;
      j["frames"] = frames.size();
      j["inserted"] = inserted;
      j["far_field"] = far;
      j["pruned"] = pruned;
      j["gaussians"] = map.size() - not_finite;
      j["not_finite"] = not_finite;  // left out of the file (write_gaussian_ply)
      j["nonfinite_gradients"] = opt.nonfinite_gradients();
      j["iterations"] = iterations;
      j["last_loss"] = io::rounded(last.total, 10);
      j["last_ssim"] = io::rounded(last.ssim, 10);
      j["bytes_per_gaussian"] = io::rounded(opt.bytes_per_gaussian(map), 10);
      j["seconds"] = io::rounded(secs, 10);
      j["out"] = out_path;
      std::cout << io::json_line(j) << "\n";
    } catch (const std::exception& e) {
      std::cerr << "vigs map: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
