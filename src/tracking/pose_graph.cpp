#include "tracking/pose_graph.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/geometry/so3.hpp"

namespace vigs::tracking {

Matrix6d information_of_left_increment(const Matrix6d& information_xi, const geometry::Pose& Z) {
  Matrix6d M = Matrix6d::Zero();
  M.topLeftCorner<3, 3>() = -Z.linear();
  M.bottomLeftCorner<3, 3>() = -geometry::hat<double>(Z.translation()) * Z.linear();
  M.bottomRightCorner<3, 3>() = -Eigen::Matrix3d::Identity();
  const Matrix6d L = M.transpose() * information_xi * M;
  return 0.5 * (L + L.transpose());
}

int PoseGraph::add_node(const geometry::Pose& T_w_i) {
  poses_.push_back(T_w_i);
  return static_cast<int>(poses_.size()) - 1;
}

void PoseGraph::add_edge(const PoseGraphEdge& edge) {
  const int n = static_cast<int>(poses_.size());
  if (edge.i < 0 || edge.j < 0 || edge.i >= n || edge.j >= n || edge.i == edge.j) {
    throw std::invalid_argument("pose graph edge " + std::to_string(edge.i) + " -> " +
                                std::to_string(edge.j) + ": unknown node or a self edge");
  }
  const Matrix6d& L = edge.information;
  if (!L.allFinite() || !L.isApprox(L.transpose(), 1e-9) || L.ldlt().info() != Eigen::Success ||
      (L.ldlt().vectorD().array() <= 0.0).any()) {
    throw std::invalid_argument("pose graph edge " + std::to_string(edge.i) + " -> " +
                                std::to_string(edge.j) +
                                ": information is not finite, symmetric and positive definite");
  }
  edges_.push_back(edge);
}

Vector6d PoseGraph::residual(const geometry::Pose& T_w_i, const geometry::Pose& T_w_j,
                             const geometry::Pose& T_i_j) {
  const Eigen::Matrix3d R_i = T_w_i.linear();
  Vector6d r;
  r.head<3>() =
      geometry::so3_log<double>(T_i_j.linear().transpose() * R_i.transpose() * T_w_j.linear());
  r.tail<3>() = R_i.transpose() * (T_w_j.translation() - T_w_i.translation()) - T_i_j.translation();
  return r;
}

void PoseGraph::edge_jacobians(const geometry::Pose& T_w_i, const geometry::Pose& T_w_j,
                               const geometry::Pose& T_i_j, Matrix6d& J_i, Matrix6d& J_j) {
  const Eigen::Matrix3d R_i = T_w_i.linear();
  const Eigen::Matrix3d R_j = T_w_j.linear();
  const Vector6d r = residual(T_w_i, T_w_j, T_i_j);
  const Eigen::Matrix3d Jr_inv = geometry::so3_right_jacobian_inv<double>(r.head<3>());
  J_i.setZero();
  J_j.setZero();
  // r_R = Log(R_Z^T R_i^T R_j): R_j Exp(phi_j) gives Jr^-1 phi_j; R_i Exp(phi_i) turns
  // R_i^T R_j into Exp(-phi_i) R_i^T R_j = R_i^T R_j Exp(-R_j^T R_i phi_i).
  J_i.topLeftCorner<3, 3>() = -Jr_inv * R_j.transpose() * R_i;
  J_j.topLeftCorner<3, 3>() = Jr_inv;
  // r_p = R_i^T (p_j - p_i) - p_Z: Exp(-phi_i) R_i^T d = R_i^T d + [R_i^T d]x phi_i.
  const Eigen::Vector3d d_i = R_i.transpose() * (T_w_j.translation() - T_w_i.translation());
  J_i.bottomLeftCorner<3, 3>() = geometry::hat<double>(d_i);
  J_i.bottomRightCorner<3, 3>() = -R_i.transpose();
  J_j.bottomRightCorner<3, 3>() = R_i.transpose();
}

geometry::Pose PoseGraph::retract(const geometry::Pose& T_w_i, const Vector6d& delta) {
  geometry::Pose T = geometry::Pose::Identity();
  T.linear() = geometry::normalize_rotation<double>(
      Eigen::Matrix3d(T_w_i.linear() * geometry::so3_exp<double>(delta.head<3>())));
  T.translation() = T_w_i.translation() + delta.tail<3>();
  return T;
}

double PoseGraph::cost() const {
  double c = 0.0;
  for (const PoseGraphEdge& e : edges_) {
    const Vector6d r = residual(pose(e.i), pose(e.j), e.T_i_j);
    c += r.dot(e.information * r);
  }
  return c;
}

PoseGraphResult PoseGraph::optimize(int max_iterations) {
  PoseGraphResult out;
  out.initial_cost = cost();
  out.final_cost = out.initial_cost;
  const int n = static_cast<int>(poses_.size());
  if (n < 2 || edges_.empty()) {
    out.converged = true;
    return out;
  }
  // Node 0 is fixed: the unknowns are nodes 1..n-1, 6 each.
  const int dim = 6 * (n - 1);
  double lambda = 1e-6;
  std::vector<Eigen::Triplet<double>> triplets;
  for (int it = 0; it < max_iterations; ++it) {
    triplets.clear();
    Eigen::VectorXd b = Eigen::VectorXd::Zero(dim);
    for (const PoseGraphEdge& e : edges_) {
      Matrix6d J[2];
      edge_jacobians(pose(e.i), pose(e.j), e.T_i_j, J[0], J[1]);
      const Vector6d r = residual(pose(e.i), pose(e.j), e.T_i_j);
      const int node[2] = {e.i, e.j};
      for (int a = 0; a < 2; ++a) {
        if (node[a] == 0) continue;
        const int ra = 6 * (node[a] - 1);
        b.segment<6>(ra) -= J[a].transpose() * e.information * r;
        for (int c = 0; c < 2; ++c) {
          if (node[c] == 0) continue;
          const int rc = 6 * (node[c] - 1);
          const Matrix6d block = J[a].transpose() * e.information * J[c];
          for (int u = 0; u < 6; ++u) {
            for (int v = 0; v < 6; ++v) triplets.emplace_back(ra + u, rc + v, block(u, v));
          }
        }
      }
    }
    Eigen::SparseMatrix<double> H(dim, dim);
    H.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::VectorXd diag = H.diagonal();
    const std::vector<geometry::Pose> before = poses_;
    const double cost_before = out.final_cost;
    bool accepted = false;
    Eigen::VectorXd delta;
    for (int attempt = 0; attempt < 10 && !accepted; ++attempt) {
      Eigen::SparseMatrix<double> A = H;
      for (int k = 0; k < dim; ++k) A.coeffRef(k, k) += lambda * std::max(diag[k], 1e-12);
      const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
      if (ldlt.info() != Eigen::Success) {
        lambda *= 10.0;
        continue;
      }
      delta = ldlt.solve(b);
      if (!delta.allFinite()) {
        lambda *= 10.0;
        continue;
      }
      for (int k = 1; k < n; ++k) {
        poses_[static_cast<std::size_t>(k)] =
            retract(before[static_cast<std::size_t>(k)], delta.segment<6>(6 * (k - 1)));
      }
      const double c = cost();
      if (c <= cost_before) {
        accepted = true;
        out.final_cost = c;
        lambda = std::max(lambda * 0.1, 1e-12);
      } else {
        poses_ = before;
        lambda *= 10.0;
      }
    }
    ++out.iterations;
    if (!accepted) break;
    if (delta.lpNorm<Eigen::Infinity>() < 1e-9 ||
        cost_before - out.final_cost <= 1e-12 * std::max(1.0, cost_before)) {
      out.converged = true;
      break;
    }
  }
  return out;
}

}  // namespace vigs::tracking
