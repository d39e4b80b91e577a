#include "record/recorder.hpp"

#include <algorithm>
#include <cstring>

#include "io/io_error.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/serial_chunk.hpp"
#include "io/ros_msgs/time_reference.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "rt/thread_table.hpp"

namespace vigs::record {

namespace msgs = io::ros_msgs;

// Channel ids and the messages reused between writes (their vectors keep their capacity).
struct Recorder::Channels {
  std::uint16_t rgb = 0, depth = 0, info = 0, imu = 0, serial = 0, trigger = 0, pose = 0,
                imu_used = 0;
  msgs::Image rgb_msg, depth_msg;
  msgs::CameraInfo info_msg;
  msgs::Imu imu_msg;
  msgs::SerialChunk chunk_msg;
  msgs::TimeReference edge_msg;
  msgs::PoseStamped pose_msg;
  msgs::TimeReference imu_used_msg;
  std::vector<std::uint8_t> scratch;
};

Recorder::Recorder(std::string path, io::mcap::McapWriterOptions options)
    : path_(std::move(path)), options_(std::move(options)) {}

Recorder::~Recorder() {
  try {
    stop();
  } catch (...) {  // destructor: the error stays in error(); call stop() to see it
  }
}

void Recorder::add_frames(rt::FramePool& pool, rt::SpscRing<rt::FrameHandle>& tap,
                          const CameraIntrinsics& intrinsics) {
  pool_ = &pool;
  frames_ = &tap;
  intrinsics_ = intrinsics;
}
void Recorder::add_imu(rt::SpscRing<ImuSample>& tap) {
  imu_ = &tap;
}
void Recorder::add_serial(rt::SpscRing<drivers::SerialBytes>& tap, std::string port) {
  serial_ = &tap;
  serial_port_ = std::move(port);
}
void Recorder::add_edges(rt::SpscRing<drivers::TriggerEdge>& tap, std::string source) {
  edges_ = &tap;
  edge_source_ = std::move(source);
}

void Recorder::add_poses(rt::SpscRing<RecordedPose>& tap, std::string frame_id) {
  poses_ = &tap;
  pose_frame_id_ = std::move(frame_id);
}

void Recorder::start() {
  if (task_) return;
  open();
  task_.emplace(rt::thread_spec("recorder"), [this] { drain_once(); });
  task_->start();
}

void Recorder::open() {
  if (writer_) return;
  writer_ = std::make_unique<io::mcap::McapWriter>(path_, options_);
  ch_ = std::make_unique<Channels>();
  Channels& c = *ch_;
  if (frames_ != nullptr) {
    c.info = msgs::add_channel<msgs::CameraInfo>(*writer_, kCameraInfoTopic);
    c.rgb = msgs::add_channel<msgs::Image>(*writer_, kRgbTopic);
    c.depth = msgs::add_channel<msgs::Image>(*writer_, kDepthTopic);
    const rt::FramePoolSettings& p = pool_->settings();
    c.info_msg.header.frame_id = "camera";
    c.info_msg.width = p.width;
    c.info_msg.height = p.height;
    c.info_msg.distortion_model = "plumb_bob";
    c.info_msg.d.assign(5, 0.0);
    c.info_msg.k = {
        intrinsics_.fx_px, 0, intrinsics_.cx_px, 0, intrinsics_.fy_px, intrinsics_.cy_px, 0, 0, 1};
    c.info_msg.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    c.info_msg.p = {intrinsics_.fx_px,
                    0,
                    intrinsics_.cx_px,
                    0,
                    0,
                    intrinsics_.fy_px,
                    intrinsics_.cy_px,
                    0,
                    0,
                    0,
                    1,
                    0};
    for (msgs::Image* m : {&c.rgb_msg, &c.depth_msg}) {
      m->header.frame_id = "camera";
      m->width = p.width;
      m->height = p.height;
    }
    c.rgb_msg.encoding = p.colour_channels == 3 ? "rgb8" : "mono8";
    c.rgb_msg.step = p.width * p.colour_channels;
    c.depth_msg.encoding = "16UC1";
    c.depth_msg.step = p.width * 2;
  }
  if (imu_ != nullptr) {
    c.imu = msgs::add_channel<msgs::Imu>(*writer_, kImuTopic);
    c.imu_msg.header.frame_id = "imu";
    c.imu_msg.orientation_covariance[0] = -1;  // no orientation
  }
  if (serial_ != nullptr) {
    c.serial = msgs::add_channel<msgs::SerialChunk>(*writer_, kSerialTopic);
    c.chunk_msg.port = serial_port_;
  }
  if (edges_ != nullptr) {
    c.trigger = msgs::add_channel<msgs::TimeReference>(*writer_, kTriggerTopic);
    c.edge_msg.header.frame_id = "camera";
    c.edge_msg.source = edge_source_;
  }
  if (poses_ != nullptr) {
    c.pose = msgs::add_channel<msgs::PoseStamped>(*writer_, kPoseTopic);
    c.pose_msg.header.frame_id = pose_frame_id_;
    c.imu_used = msgs::add_channel<msgs::TimeReference>(*writer_, kTrackerImuTopic);
    c.imu_used_msg.source = "imu";
    c.imu_used_msg.header.frame_id = "camera";
  }
  writer_->flush();  // the channel records reach the file before the first message
}

void Recorder::write_frame(rt::FrameHandle h) {
  Channels& c = *ch_;
  const rt::Frame& f = pool_->frame(h);
  const auto t = static_cast<std::uint64_t>(f.t_ns);
  const msgs::Time stamp = msgs::Time::from_ns(f.t_ns);
  const auto seq = static_cast<std::uint32_t>(f.sequence);
  c.info_msg.header.stamp = stamp;
  c.info_msg.header.seq = seq;
  msgs::write_message(*writer_, c.info, t, c.info_msg, c.scratch);
  c.rgb_msg.header.stamp = stamp;
  c.rgb_msg.header.seq = seq;
  c.rgb_msg.data.assign(f.colour.begin(), f.colour.end());
  msgs::write_message(*writer_, c.rgb, t, c.rgb_msg, c.scratch);
  c.depth_msg.header.stamp = stamp;
  c.depth_msg.header.seq = seq;
  const auto* d = reinterpret_cast<const std::uint8_t*>(f.depth.data());
  c.depth_msg.data.assign(d, d + f.depth.size_bytes());  // little-endian host: 16UC1 as is
  msgs::write_message(*writer_, c.depth, t, c.depth_msg, c.scratch);
}

void Recorder::drain_once() {
  if (!writer_ || failed_.load(std::memory_order_relaxed)) return;
  Channels& c = *ch_;
  try {
    rt::FrameHandle h;
    while (frames_ != nullptr && frames_->try_pop(h)) {
      if (!h.valid()) continue;  // a driver's end marker is not for the tap
      try {
        write_frame(h);
      } catch (...) {
        pool_->release(h);
        throw;
      }
      pool_->release(h);
      frames_n_.fetch_add(1, std::memory_order_relaxed);
    }
    ImuSample s;
    while (imu_ != nullptr && imu_->try_pop(s)) {
      c.imu_msg.header.stamp = msgs::Time::from_ns(s.t_ns);
      c.imu_msg.angular_velocity = {s.gyro_rps[0], s.gyro_rps[1], s.gyro_rps[2]};
      c.imu_msg.linear_acceleration = {s.accel_mps2[0], s.accel_mps2[1], s.accel_mps2[2]};
      msgs::write_message(*writer_, c.imu, static_cast<std::uint64_t>(s.t_ns), c.imu_msg,
                          c.scratch);
      imu_n_.fetch_add(1, std::memory_order_relaxed);
    }
    while (serial_ != nullptr) {
      drivers::SerialBytes* b = serial_->front();
      if (b == nullptr) break;
      c.chunk_msg.stamp = msgs::Time::from_ns(b->t_ns);
      c.chunk_msg.data.assign(b->data.begin(), b->data.begin() + b->size);
      const auto t = static_cast<std::uint64_t>(b->t_ns);
      serial_bytes_n_.fetch_add(b->size, std::memory_order_relaxed);
      serial_->pop();
      msgs::write_message(*writer_, c.serial, t, c.chunk_msg, c.scratch);
      chunks_n_.fetch_add(1, std::memory_order_relaxed);
    }
    drivers::TriggerEdge e;
    while (edges_ != nullptr && edges_->try_pop(e)) {
      c.edge_msg.header.stamp = msgs::Time::from_ns(e.t_ns);
      c.edge_msg.header.seq = static_cast<std::uint32_t>(e.sequence);
      c.edge_msg.time_ref = c.edge_msg.header.stamp;
      msgs::write_message(*writer_, c.trigger, static_cast<std::uint64_t>(e.t_ns), c.edge_msg,
                          c.scratch);
      edges_n_.fetch_add(1, std::memory_order_relaxed);
    }
    RecordedPose rp;
    while (poses_ != nullptr && poses_->try_pop(rp)) {
      const PoseSample& p = rp.pose;
      c.pose_msg.header.stamp = msgs::Time::from_ns(p.t_ns);
      c.pose_msg.header.seq = static_cast<std::uint32_t>(p.frame_index);
      c.pose_msg.pose.position = {p.p_w_m[0], p.p_w_m[1], p.p_w_m[2]};
      c.pose_msg.pose.orientation = {p.q_w_xyzw[0], p.q_w_xyzw[1], p.q_w_xyzw[2], p.q_w_xyzw[3]};
      msgs::write_message(*writer_, c.pose, static_cast<std::uint64_t>(p.t_ns), c.pose_msg,
                          c.scratch);
      c.imu_used_msg.header.stamp = c.pose_msg.header.stamp;
      c.imu_used_msg.header.seq = c.pose_msg.header.seq;
      c.imu_used_msg.time_ref = msgs::Time::from_ns(std::max<std::int64_t>(rp.imu_t_ns, 0));
      msgs::write_message(*writer_, c.imu_used, static_cast<std::uint64_t>(p.t_ns), c.imu_used_msg,
                          c.scratch);
      poses_n_.fetch_add(1, std::memory_order_relaxed);
    }
    bytes_written_.store(writer_->stats().bytes_written, std::memory_order_relaxed);
    mcap_chunks_.store(writer_->stats().chunk_count, std::memory_order_relaxed);
  } catch (const std::exception& ex) {
    std::lock_guard lock(error_mutex_);
    error_ = ex.what();
    failed_.store(true, std::memory_order_relaxed);
  }
}

void Recorder::stop() {
  if (task_) {
    task_->stop();
    task_.reset();
  }
  if (!writer_) return;
  drain_once();  // what arrived after the last tick
  // Frames left in a tap after a failure still hold slots: give them back.
  rt::FrameHandle h;
  while (frames_ != nullptr && frames_->try_pop(h)) pool_->release(h);
  try {
    writer_->close();
    bytes_written_.store(writer_->stats().bytes_written, std::memory_order_relaxed);
    mcap_chunks_.store(writer_->stats().chunk_count, std::memory_order_relaxed);
  } catch (const std::exception& ex) {
    std::lock_guard lock(error_mutex_);
    if (error_.empty()) error_ = ex.what();
    failed_.store(true, std::memory_order_relaxed);
  }
  writer_.reset();
  const std::string e = error();
  if (!e.empty()) throw io::IoError(e);
}

RecorderStats Recorder::stats() const noexcept {
  return {.frames = frames_n_.load(std::memory_order_relaxed),
          .imu_samples = imu_n_.load(std::memory_order_relaxed),
          .serial_chunks = chunks_n_.load(std::memory_order_relaxed),
          .serial_bytes = serial_bytes_n_.load(std::memory_order_relaxed),
          .edges = edges_n_.load(std::memory_order_relaxed),
          .poses = poses_n_.load(std::memory_order_relaxed),
          .bytes_written = bytes_written_.load(std::memory_order_relaxed),
          .chunks = mcap_chunks_.load(std::memory_order_relaxed)};
}

std::string Recorder::error() const {
  std::lock_guard lock(error_mutex_);
  return error_;
}

}  // namespace vigs::record
