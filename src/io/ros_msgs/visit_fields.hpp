#pragma once
// Internal: the field order of every message type, shared by the CDR and ROS 1 codecs
// (archive.hpp), and by the test and benchmark that compare the CDR archive with Fast CDR's
// (fastcdr_archive.hpp). One visit function per type drives every archive, so the layouts
// cannot drift apart.
#include "io/ros_msgs/archive.hpp"

namespace vigs::io::ros_msgs::detail {

template <class Ar, class V>
void visit_vector3(Ar& ar, V& v, const char* x, const char* y, const char* z) {
  ar(x, v.x);
  ar(y, v.y);
  ar(z, v.z);
}

template <class Ar, class Q>
void visit_quaternion(Ar& ar, Q& q) {
  ar("orientation.x", q.x);
  ar("orientation.y", q.y);
  ar("orientation.z", q.z);
  ar("orientation.w", q.w);
}

/// Image's fields before `data` (ImageMeta reads only these).
struct VisitImageMeta {
  template <class Ar, class M>
  void operator()(Ar& ar, M& m) const {
    detail::visit_header(ar, m.header);
    ar("height", m.height);
    ar("width", m.width);
    ar("encoding", m.encoding);
    ar("is_bigendian", m.is_bigendian);
    ar("step", m.step);
  }
};

struct VisitImage {
  template <class Ar, class M>
  void operator()(Ar& ar, M& m) const {
    VisitImageMeta{}(ar, m);
    ar("data", m.data);
  }
};

struct VisitImu {
  template <class Ar, class M>
  void operator()(Ar& ar, M& m) const {
    detail::visit_header(ar, m.header);
    visit_quaternion(ar, m.orientation);
    ar("orientation_covariance", m.orientation_covariance);
    visit_vector3(ar, m.angular_velocity, "angular_velocity.x", "angular_velocity.y",
                  "angular_velocity.z");
    ar("angular_velocity_covariance", m.angular_velocity_covariance);
    visit_vector3(ar, m.linear_acceleration, "linear_acceleration.x", "linear_acceleration.y",
                  "linear_acceleration.z");
    ar("linear_acceleration_covariance", m.linear_acceleration_covariance);
  }
};

struct VisitCameraInfo {
  template <class Ar, class M>
  void operator()(Ar& ar, M& m) const {
    detail::visit_header(ar, m.header);
    ar("height", m.height);
    ar("width", m.width);
    ar("distortion_model", m.distortion_model);
    ar("d", m.d);
    ar("k", m.k);
    ar("r", m.r);
    ar("p", m.p);
    ar("binning_x", m.binning_x);
    ar("binning_y", m.binning_y);
    ar("roi.x_offset", m.roi.x_offset);
    ar("roi.y_offset", m.roi.y_offset);
    ar("roi.height", m.roi.height);
    ar("roi.width", m.roi.width);
    ar("roi.do_rectify", m.roi.do_rectify);
  }
};

struct VisitPoseStamped {
  template <class Ar, class M>
  void operator()(Ar& ar, M& m) const {
    detail::visit_header(ar, m.header);
    visit_vector3(ar, m.pose.position, "pose.position.x", "pose.position.y", "pose.position.z");
    visit_quaternion(ar, m.pose.orientation);
  }
};

struct VisitOdometry {
  template <class Ar, class M>
  void operator()(Ar& ar, M& m) const {
    detail::visit_header(ar, m.header);
    ar("child_frame_id", m.child_frame_id);
    visit_vector3(ar, m.pose.position, "pose.pose.position.x", "pose.pose.position.y",
                  "pose.pose.position.z");
    visit_quaternion(ar, m.pose.orientation);
    ar("pose.covariance", m.pose_covariance);
    visit_vector3(ar, m.linear_velocity, "twist.twist.linear.x", "twist.twist.linear.y",
                  "twist.twist.linear.z");
    visit_vector3(ar, m.angular_velocity, "twist.twist.angular.x", "twist.twist.angular.y",
                  "twist.twist.angular.z");
    ar("twist.covariance", m.twist_covariance);
  }
};

struct VisitSerialChunk {
  template <class Ar, class M>
  void operator()(Ar& ar, M& m) const {
    ar("stamp", m.stamp);
    ar("port", m.port);
    ar("data", m.data);
  }
};

struct VisitTimeReference {
  template <class Ar, class M>
  void operator()(Ar& ar, M& m) const {
    detail::visit_header(ar, m.header);
    ar("time_ref", m.time_ref);
    ar("source", m.source);
  }
};

}  // namespace vigs::io::ros_msgs::detail
