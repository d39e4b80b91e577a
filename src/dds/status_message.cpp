#include "dds/status_message.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "dds/ros_time.hpp"

namespace vigs::dds {
namespace {

double finite_or_zero(double v) {
  return std::isfinite(v) ? v : 0.0;
}

std::string name_of(const char (&n)[kStatusNameLength]) {
  return std::string(n, strnlen(n, kStatusNameLength));
}

}  // namespace

bool fill_status(const StatusSnapshot& s, const std::string& robot, const std::string& frame_id,
                 vigs_msgs::msg::dds_::Status_& out) {
  const auto t = to_ros_time(s.t_ns);
  if (!t) return false;
  out.header().stamp().sec(t->sec);
  out.header().stamp().nanosec(t->nanosec);
  out.header().frame_id(frame_id);
  out.robot(robot);
  out.tracking_state(static_cast<std::uint8_t>(s.tracking_state));
  out.frames_tracked(s.frames_tracked);
  out.gaussian_count(s.gaussian_count);
  out.mapping_budget_used(finite_or_zero(s.mapping_budget_used));

  const std::size_t nt = std::min<std::size_t>(s.thread_count, StatusSnapshot::kMaxThreads);
  out.threads().resize(nt);
  for (std::size_t i = 0; i < nt; ++i) {
    const ThreadStatusEntry& e = s.threads[i];
    auto& m = out.threads()[i];
    m.name(name_of(e.name));
    m.rate_hz(finite_or_zero(e.rate_hz));
    m.cycle_p50_ns(e.cycle_p50_ns);
    m.cycle_p99_ns(e.cycle_p99_ns);
    m.overruns(e.overruns);
    m.missed_deadlines(e.missed_deadlines);
  }
  const std::size_t nr = std::min<std::size_t>(s.ring_count, StatusSnapshot::kMaxRings);
  out.rings().resize(nr);
  for (std::size_t i = 0; i < nr; ++i) {
    const RingStatusEntry& e = s.rings[i];
    auto& m = out.rings()[i];
    m.name(name_of(e.name));
    m.depth(e.depth);
    m.capacity(e.capacity);
    m.drops(e.drops);
  }
  const std::size_t nf = std::min<std::size_t>(s.fault_count, StatusSnapshot::kMaxFaults);
  out.faults().resize(nf);
  for (std::size_t i = 0; i < nf; ++i) {
    out.faults()[i].name(name_of(s.faults[i].name));
    out.faults()[i].count(s.faults[i].count);
  }
  return true;
}

}  // namespace vigs::dds
