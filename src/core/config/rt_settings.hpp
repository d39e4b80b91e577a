#pragma once
#include "core/config/visitor.hpp"

namespace vigs::config {

/// Real-time behaviour of the process. Priorities and CPUs per thread live in rt/'s
/// thread table; these switches decide whether they are requested at all.
struct RtSettings {
  bool lock_memory = true;             ///< mlockall(MCL_CURRENT | MCL_FUTURE)
  bool realtime_priorities = true;     ///< request SCHED_FIFO from the thread table
  bool pin_cpus = true;                ///< apply the table's CPU affinities
  int imu_ring_capacity = 1024;        ///< samples (power of two)
  int frame_pool_slots = 16;           ///< preallocated RGB-D frames
  bool tracker_phase_lock = true;      ///< slide the tracker's ticks to the frames' arrival
  double tracker_phase_lead_ms = 2.0;  ///< target tick - frame arrival (rt/phase_lock.hpp)

  void visit(Visitor& v) {
    v.field("lock_memory", lock_memory, "mlockall at start-up; warns once if refused");
    v.field("realtime_priorities", realtime_priorities,
            "SCHED_FIFO per the thread table; warns once if refused");
    v.field("pin_cpus", pin_cpus, "pin threads to the thread table's CPUs");
    v.field("imu_ring_capacity", imu_ring_capacity,
            {"samples", 16, 65536, "IMU driver to tracker ring; full = drop newest, counted"});
    v.field("frame_pool_slots", frame_pool_slots,
            {"frames", 2, 256,
             "preallocated RGB-D frame slots: the driver's, the tracker's, 2 in the mapper's "
             "hands, the frames of keyframes held for the moving test "
             "(tracking.moving_window_frames + 1) and the frame ring (the rest, rounded down "
             "to a power of two)"});
    v.field("tracker_phase_lock", tracker_phase_lock,
            "real time: phase-lock the tracker's fixed-rate ticks to the camera frames' arrival "
            "(false: ticks at an arbitrary phase, each frame waits up to one period)");
    v.field("tracker_phase_lead_ms", tracker_phase_lead_ms,
            {"ms", 0.0, 1000.0,
             "phase lock: the tick's target delay after a frame's arrival (the arrival "
             "jitter's margin)"});
    v.require((imu_ring_capacity & (imu_ring_capacity - 1)) == 0, "imu_ring_capacity",
              "must be a power of two");
  }
};

}  // namespace vigs::config
