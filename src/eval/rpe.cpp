#include "eval/rpe.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "eval/ate.hpp"

namespace vigs::eval {

RpeResult compute_rpe(const Trajectory& gt, const Trajectory& est, const RpeOptions& opt) {
  if (!(opt.delta > 0.0)) throw std::invalid_argument("rpe: delta must be positive");
  if (opt.unit == DeltaUnit::kFrames && opt.delta != std::floor(opt.delta)) {
    throw std::invalid_argument("rpe: a delta in frames must be a whole number");
  }
  const auto pairs = associate_trajectories(gt, est, opt.max_dt_s, 0.0);
  RpeResult r;
  r.associated = pairs.size();
  std::vector<geometry::Pose> G, P;
  std::vector<double> t_s;
  for (const auto& m : pairs) {
    t_s.push_back(gt.poses[m.a].t_s);
    G.push_back(gt.poses[m.a].T_w_x);
    P.push_back(est.poses[m.b].T_w_x);
  }
  if (opt.align == Alignment::kSim3 && pairs.size() >= 3) {
    std::vector<Eigen::Vector3d> from, to;
    for (std::size_t i = 0; i < G.size(); ++i) {
      to.push_back(G[i].translation());
      from.push_back(P[i].translation());
    }
    r.scale = umeyama_align(from, to, Alignment::kSim3).s;
    for (auto& p : P) p.translation() *= r.scale;
  }
  // Cumulative ground-truth path length for deltas in metres.
  std::vector<double> path_m(G.size(), 0.0);
  for (std::size_t i = 1; i < G.size(); ++i) {
    path_m[i] = path_m[i - 1] + (G[i].translation() - G[i - 1].translation()).norm();
  }
  std::vector<double> et, er;
  std::size_t j = 0;
  for (std::size_t i = 0; i < G.size(); ++i) {
    if (opt.unit == DeltaUnit::kFrames) {
      j = i + static_cast<std::size_t>(opt.delta);
    } else if (opt.unit == DeltaUnit::kMetres) {
      if (j < i) j = i;
      while (j < G.size() && path_m[j] - path_m[i] < opt.delta) ++j;
    } else {
      if (j < i) j = i;
      while (j < G.size() && t_s[j] - t_s[i] < opt.delta) ++j;
    }
    if (j >= G.size()) break;
    const geometry::Pose dG = G[i].inverse() * G[j];
    const geometry::Pose dP = P[i].inverse() * P[j];
    const geometry::PoseError e = geometry::pose_error(dG, dP);
    et.push_back(e.translation_m);
    er.push_back(e.rotation_rad * 180.0 / M_PI);
  }
  if (et.empty()) {
    throw std::invalid_argument("rpe: no pose pair of " + est.source + " is one delta (" +
                                std::to_string(opt.delta) + ") apart");
  }
  r.pairs = et.size();
  r.translation_m = compute_stats(std::move(et));
  r.rotation_deg = compute_stats(std::move(er));
  return r;
}

io::Json rpe_to_json(const RpeResult& r, const RpeOptions& opt) {
  io::Json j;
  j["associated"] = r.associated;
  j["pairs"] = r.pairs;
  j["delta"] = opt.delta;
  j["delta_unit"] = opt.unit == DeltaUnit::kFrames   ? "frames"
                    : opt.unit == DeltaUnit::kMetres ? "m"
                                                     : "s";
  j["align"] = alignment_name(opt.align);
  j["scale"] = r.scale;
  add_stats_fields(j["translation_m"] = io::Json::object(), r.translation_m);
  add_stats_fields(j["rotation_deg"] = io::Json::object(), r.rotation_deg);
  return j;
}

std::string rpe_json(const RpeResult& r, const RpeOptions& opt) {
  return io::json_line(rpe_to_json(r, opt));
}

}  // namespace vigs::eval
