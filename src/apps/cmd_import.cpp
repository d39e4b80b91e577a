// `vigs import tum DIR --out F.mcap` and `vigs import euroc DIR --out F.mcap`: the datasets
// users have, converted into a VIGS recording (io/recording_topics.hpp) that `vigs replay`,
// `vigs eval` and `vigs echo` read. Prints a JSON summary; bad input is an error naming the file
// and line.
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "apps/finite_option.hpp"
#include "inertial/euroc_csv.hpp"
#include "io/import/tum_rgbd.hpp"
#include "io/json_text.hpp"
#include "io/output_guard.hpp"
#include "io/recording/recording_writer.hpp"
#include "tracking/camera_file.hpp"

namespace vigs::apps {
namespace {

namespace fs = std::filesystem;

struct ImportArgs {
  std::string dir;
  std::string out;
  std::vector<double> intrinsics;  // fx fy cx cy
  std::string camera_file;
  double depth_factor = 5000.0;
  double max_gap_ms = 20.0;
};

/// The first of `candidates` (relative to dir) that exists, or an error naming them all.
std::string find_file(const fs::path& dir, const std::vector<std::string>& candidates) {
  std::string tried;
  for (const auto& c : candidates) {
    if (fs::is_regular_file(dir / c)) return (dir / c).string();
    tried += (tried.empty() ? "" : ", ") + (dir / c).string();
  }
  throw io::ImportError("none of " + tried + " exists");
}

std::vector<std::string> inputs_under(const fs::path& dir) {
  std::vector<std::string> inputs;
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(dir, ec)) {
    if (e.is_regular_file()) inputs.push_back(e.path().string());
  }
  return inputs;
}

void guard_output(const ImportArgs& a) {
  const auto inputs = inputs_under(a.dir);
  io::refuse_output_over_inputs(a.out, inputs);
  io::refuse_output_over_inputs(a.out + ".partial", inputs);
}

int run_import_tum(const ImportArgs& a) {
  io::TumImportOptions o;
  o.dir = a.dir;
  o.out = a.out;
  if (!a.camera_file.empty()) {
    o.camera = tracking::load_camera_file(a.camera_file);
  } else if (a.intrinsics.size() == 4) {
    o.camera = {0, 0, a.intrinsics[0], a.intrinsics[1], a.intrinsics[2], a.intrinsics[3]};
  } else {
    throw std::invalid_argument("give the intrinsics: --intrinsics fx,fy,cx,cy or --camera FILE");
  }
  o.depth_units_per_m = a.depth_factor;
  o.max_pair_gap_ns = static_cast<std::int64_t>(a.max_gap_ms * 1e6);
  guard_output(a);
  const io::TumImportStats s = io::import_tum_rgbd(o);
  io::Json j;
  j["out"] = a.out;
  j["frames"] = s.frames;
  j["colour_without_depth"] = s.colour_without_depth;
  j["max_pair_gap_ms"] = io::rounded(static_cast<double>(s.max_pair_gap_ns) * 1e-6, 6);
  j["ground_truth"] = s.ground_truth;
  j["accelerometer"] = s.accelerometer;
  std::cout << io::json_lines(j) << "\n";
  return 0;
}

// EuRoC MAV's ADIS16448 (mav0/imu0/sensor.yaml): noise densities, published as variances at
// the sample rate.
constexpr double kEurocGyroNoise = 1.6968e-04;  // rad/s/sqrt(Hz)
constexpr double kEurocAccelNoise = 2.0000e-3;  // m/s^2/sqrt(Hz)
constexpr double kEurocRateHz = 200.0;

int run_import_euroc(const ImportArgs& a) {
  const fs::path dir = a.dir;
  const std::string imu_csv = find_file(dir, {"mav0/imu0/data.csv", "imu0/data.csv", "imu0.csv"});
  const std::string gt_csv =
      find_file(dir, {"mav0/state_groundtruth_estimate0/data.csv",
                      "state_groundtruth_estimate0/data.csv", "groundtruth.csv"});
  const auto imu = inertial::read_euroc_imu_csv(imu_csv);
  const auto gt = inertial::read_euroc_groundtruth_csv(gt_csv);
  guard_output(a);
  io::RecordingWriter writer(a.out, {});
  const double vg = kEurocGyroNoise * kEurocGyroNoise * kEurocRateHz;
  const double va = kEurocAccelNoise * kEurocAccelNoise * kEurocRateHz;
  std::size_t i = 0, k = 0;
  while (i < imu.size() || k < gt.size()) {  // one time-ordered stream, IMU first at a tie
    if (k >= gt.size() || (i < imu.size() && imu[i].t_ns <= gt[k].t_ns)) {
      writer.imu(imu[i++], vg, va);
    } else {
      geometry::Pose T_w_b = geometry::Pose::Identity();
      T_w_b.linear() = gt[k].q_w_b.toRotationMatrix();
      T_w_b.translation() = gt[k].p_w_b_m;
      writer.ground_truth(gt[k].t_ns, T_w_b);
      ++k;
    }
  }
  writer.close();
  io::Json j;
  j["out"] = a.out;
  j["imu"] = imu_csv;
  j["ground_truth"] = gt_csv;
  j["imu_samples"] = imu.size();
  j["ground_truth_poses"] = gt.size();
  std::cout << io::json_lines(j) << "\n";
  return 0;
}

void add_common(CLI::App* cmd, ImportArgs& a) {
  cmd->add_option("dir", a.dir, "dataset folder")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("--out", a.out,
                  "recording to write (.mcap; written as FILE.partial, then renamed)")
      ->required();
}

template <class Fn>
void set_callback(CLI::App* cmd, const char* name, ExitCode& exit_code, Fn run) {
  cmd->callback([&exit_code, name, run] {
    try {
      exit_code.value = run();
    } catch (const std::exception& e) {
      std::cerr << "vigs import " << name << ": " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace

void add_import_command(CLI::App& app, ExitCode& exit_code) {
  static ImportArgs tum_args, euroc_args;
  CLI::App* import = app.add_subcommand(
      "import", "Convert a dataset (TUM RGB-D, EuRoC MAV) into a VIGS recording (.mcap)");
  import->require_subcommand(1);

  CLI::App* tum = import->add_subcommand(
      "tum",
      "TUM RGB-D folder: rgb.txt and depth.txt (paired within --max-gap-ms, stamped at the "
      "colour image), groundtruth.txt (camera pose, as the body pose) and accelerometer.txt "
      "(IMU topic, no gyroscope) when present");
  add_common(tum, tum_args);
  tum->add_option("--intrinsics", tum_args.intrinsics, "fx,fy,cx,cy in pixels")
      ->delimiter(',')
      ->expected(4)
      ->check(kFiniteNumber);
  tum->add_option("--camera", tum_args.camera_file,
                  "camera file instead of --intrinsics (vigs align's forms)")
      ->check(CLI::ExistingFile);
  tum->add_option("--depth-factor", tum_args.depth_factor, "depth PNG units per metre")
      ->check(kFiniteNumber)
      ->check(CLI::Range(1e-3, 1e6))
      ->capture_default_str();
  tum->add_option("--max-gap-ms", tum_args.max_gap_ms, "largest colour-depth stamp difference, ms")
      ->check(kFiniteNumber)
      ->check(CLI::Range(0.0, 1000.0))
      ->capture_default_str();
  set_callback(tum, "tum", exit_code, [] { return run_import_tum(tum_args); });

  CLI::App* euroc = import->add_subcommand(
      "euroc",
      "EuRoC MAV folder (the dataset's folder, mav0, or a flat imu0.csv + groundtruth.csv): "
      "IMU and ground-truth body (IMU) pose");
  add_common(euroc, euroc_args);
  set_callback(euroc, "euroc", exit_code, [] { return run_import_euroc(euroc_args); });
}

}  // namespace vigs::apps
