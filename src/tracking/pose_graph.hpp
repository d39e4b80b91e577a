#pragma once
// A pose graph over camera poses T_w_i: relative-pose edges (odometry between consecutive
// keyframes, loop closures between a keyframe and an old one it re-observed), solved by
// Levenberg–Marquardt on a sparse normal system (Eigen's SimplicialLDLT). Node 0 is held fixed
// (the world frame is the first keyframe's).
//
// Parameterisation: each node is (R_i, p_i), perturbed as R_i Exp(phi_i), p_i + dp_i; the state
// of a node is [phi (rad); dp (m)]. An edge (i, j) with measurement Z = T_i_j and information
// Lambda (6x6, same order) has the residual
//   r_R = Log(R_Z^T R_i^T R_j),   r_p = R_i^T (p_j - p_i) - p_Z,
// the rotation and translation of Z^-1-corrected T_i^-1 T_j, and the cost r^T Lambda r.
// Rotation and translation are kept apart (SO(3) x R^3, as VINS-Mono's and ORB-SLAM's pose
// graphs do) so that the Jacobians are short and exact (edge_jacobians(), checked numerically
// in tests/tracking/test_pose_graph.cpp).
//
// Why not a library: g2o, Ceres and GTSAM are Debian packages, but each would be a large new
// dependency for a graph of a few hundred 6-DoF nodes with one edge type, which Eigen's sparse
// Cholesky (already a dependency) solves in milliseconds.
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "core/geometry/se3.hpp"
#include "tracking/gicp_factor.hpp"  // Matrix6d, Vector6d

namespace vigs::tracking {

struct PoseGraphEdge {
  int i = 0;
  int j = 0;
  geometry::Pose T_i_j = geometry::Pose::Identity();  ///< measured pose of j in i's frame
  Matrix6d information = Matrix6d::Identity();        ///< of [r_R (rad); r_p (m)]
};

struct PoseGraphResult {
  int iterations = 0;
  double initial_cost = 0.0;  ///< sum of r^T Lambda r before
  double final_cost = 0.0;    ///< and after
  bool converged = false;     ///< the last step's largest component fell below 1e-9
};

/// The information of an edge's residual when its measurement Z = T_i_j comes with
/// `information_xi`, the information of a left increment xi = [phi; rho] of Z in i's frame
/// (Z' = Exp(xi) Z, rotation and translation applied separately; GicpResult::information of
/// T_t_s). To first order r = [-R_Z^T phi; [t_Z]x phi - rho], i.e. xi = M r with
/// M = [[-R_Z, 0], [-[t_Z]x R_Z, -I]], so the residual's information is M^T Lambda_xi M.
Matrix6d information_of_left_increment(const Matrix6d& information_xi, const geometry::Pose& Z);

class PoseGraph {
 public:
  /// Adds a node at T_w_i; returns its index (0, 1, ...).
  int add_node(const geometry::Pose& T_w_i);
  /// Throws std::invalid_argument for an unknown node, i == j, or a non-finite or
  /// non-symmetric-positive information.
  void add_edge(const PoseGraphEdge& edge);

  /// Levenberg–Marquardt from the current poses; node 0 stays where it is.
  PoseGraphResult optimize(int max_iterations = 20);

  [[nodiscard]] std::size_t num_nodes() const { return poses_.size(); }
  [[nodiscard]] std::size_t num_edges() const { return edges_.size(); }
  [[nodiscard]] const geometry::Pose& pose(int i) const {
    return poses_[static_cast<std::size_t>(i)];
  }
  [[nodiscard]] const std::vector<PoseGraphEdge>& edges() const { return edges_; }
  [[nodiscard]] double cost() const;

  /// The residual of an edge measured as T_i_j between poses T_w_i and T_w_j.
  static Vector6d residual(const geometry::Pose& T_w_i, const geometry::Pose& T_w_j,
                           const geometry::Pose& T_i_j);
  /// Its Jacobians with respect to node i's and node j's state [phi; dp].
  static void edge_jacobians(const geometry::Pose& T_w_i, const geometry::Pose& T_w_j,
                             const geometry::Pose& T_i_j, Matrix6d& J_i, Matrix6d& J_j);
  /// A node's pose after the state increment [phi; dp].
  static geometry::Pose retract(const geometry::Pose& T_w_i, const Vector6d& delta);

 private:
  std::vector<geometry::Pose> poses_;
  std::vector<PoseGraphEdge> edges_;
};

}  // namespace vigs::tracking
