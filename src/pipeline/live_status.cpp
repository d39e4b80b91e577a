#include "pipeline/live_status.hpp"

namespace vigs::pipeline {
namespace {

void add_thread(dds::StatusSnapshot& st, const rt::PeriodicTask& task) {
  if (st.thread_count >= dds::StatusSnapshot::kMaxThreads) return;
  dds::ThreadStatusEntry& e = st.threads[st.thread_count++];
  dds::set_name(e.name, task.spec().name.view());
  e.rate_hz = 1e9 / static_cast<double>(task.period_ns());
  e.cycle_p50_ns = task.cycle_time().p50();
  e.cycle_p99_ns = task.cycle_time().p99();
  e.overruns = task.overruns();
  e.missed_deadlines = task.missed_deadlines();
}

template <class Ring>
void add_ring(dds::StatusSnapshot& st, const char* name, const Ring& ring, std::uint64_t drops) {
  if (st.ring_count >= dds::StatusSnapshot::kMaxRings) return;
  dds::RingStatusEntry& e = st.rings[st.ring_count++];
  dds::set_name(e.name, name);
  e.depth = static_cast<std::uint32_t>(ring.size());
  e.capacity = static_cast<std::uint32_t>(ring.capacity());
  e.drops = drops;
}

void add_fault(dds::StatusSnapshot& st, const char* name, std::uint64_t count) {
  if (st.fault_count >= dds::StatusSnapshot::kMaxFaults) return;
  dds::FaultCounterEntry& e = st.faults[st.fault_count++];
  dds::set_name(e.name, name);
  e.count = count;
}

}  // namespace

std::uint64_t total_drops(const LiveStatusSources& s) {
  const LiveTrackerCounters c = s.tracker->counters();
  return c.skipped + c.pose_drops + c.result_drops + c.keyframe_drops;
}

dds::StatusSnapshot make_status_snapshot(const LiveStatusSources& s, std::int64_t now_ns) {
  dds::StatusSnapshot st;
  st.t_ns = now_ns;
  const LiveTrackerCounters c = s.tracker->counters();
  st.frames_tracked = c.frames;
  if (s.pose_quality != nullptr) {
    st.tracking_state = tracking_state(*s.pose_quality);
  } else {
    st.tracking_state =
        c.frames == 0 ? dds::TrackingState::kStarting : dds::TrackingState::kTracking;
  }
  if (s.mapper != nullptr) st.gaussian_count = s.mapper->gaussians();
  add_thread(st, *s.tracker_task);
  if (s.mapper_task != nullptr) add_thread(st, *s.mapper_task);
  add_ring(st, "rgbd->tracker", *s.frames, c.skipped);
  add_ring(st, "imu->tracker", *s.imu, 0);
  add_ring(st, "tracker->dds", *s.poses, c.pose_drops);
  add_fault(st, "tracker.frames_skipped", c.skipped);
  add_fault(st, "tracker.out_of_order", c.out_of_order);
  add_fault(st, "tracker.imu_refused", c.imu_refused);
  add_fault(st, "tracker.imu_unavailable", c.imu_unavailable);
  add_fault(st, "tracker.waiting_imu", c.waiting_imu);
  add_fault(st, "tracker.keyframe_drops", c.keyframe_drops);
  if (s.pose_quality != nullptr) {
    add_fault(st, "tracker.poses_imu_propagated", s.pose_quality->imu_propagated);
    add_fault(st, "tracker.poses_degenerate", s.pose_quality->degenerate);
    add_fault(st, "tracker.map_restarts", s.pose_quality->map_restarts);
  }
  if (s.imu_driver != nullptr) {
    const drivers::SerialImuFaults f = s.imu_driver->faults();
    add_fault(st, "imu.bad_checksum", f.bad_checksum);
    add_fault(st, "imu.resync_bytes_skipped", f.resync_bytes_skipped);
    add_fault(st, "imu.sample_counter_gap", f.sample_counter_gap);
    add_fault(st, "imu.samples_missed", f.samples_missed);
    add_fault(st, "imu.ring_drops", f.ring_drops);
  }
  if (s.camera != nullptr) {
    const drivers::RgbdDriverCounters d = s.camera->counters();
    add_fault(st, "camera.losses", d.losses);
    add_fault(st, "camera.reopens", d.reopens);
    add_fault(st, "camera.ring_drops", d.dropped_ring_full + d.dropped_pool_empty);
    if (const auto m = s.camera->trigger_match_counters()) {  // frame sync
      add_fault(st, "trigger.frames_without_edge", m->frames_without_edge);
      add_fault(st, "trigger.edges_without_frame", m->edges_without_frame);
    }
  }
  return st;
}

}  // namespace vigs::pipeline
