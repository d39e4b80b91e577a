#include "sim/mcap_sink.hpp"

namespace vigs::sim {

McapSink::McapSink(const std::string& path, const McapSinkOptions& options)
    : opt_(options),
      writer_(path, io::RecordingWriterOptions{options.depth_encoding, options.depth_scale_m,
                                               options.zstd_level}) {}

void McapSink::frame(std::int64_t t_ns, const PinholeCamera& camera, const RgbdFrame& f) {
  writer_.frame(t_ns, camera, f.color, f.gray, f.depth_m);
  // After the frame's depth, so a reader pairs it with the pending frame.
  if (!f.dynamic_mask.empty()) writer_.dynamic_mask(t_ns, f.width, f.height, f.dynamic_mask);
}

void McapSink::imu(const ImuSample& s) {
  const double vg = opt_.imu.gyro_noise_density * opt_.imu.gyro_noise_density * opt_.imu.rate_hz;
  const double va = opt_.imu.accel_noise_density * opt_.imu.accel_noise_density * opt_.imu.rate_hz;
  writer_.imu(s, vg, va);
}

void McapSink::ground_truth(std::int64_t t_ns, const geometry::Pose& T_w_b) {
  writer_.ground_truth(t_ns, T_w_b);
}

void McapSink::close() {
  writer_.close();
}

}  // namespace vigs::sim
