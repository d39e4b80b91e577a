#include "eval/ate.hpp"

#include <cstdio>
#include <stdexcept>

#include "eval/trajectory_file.hpp"

namespace vigs::eval {

std::vector<IndexPair> associate_trajectories(const Trajectory& gt, const Trajectory& est,
                                              double max_dt_s, double offset_s) {
  if (gt.format != est.format) {
    throw std::invalid_argument(gt.source + " is " + format_name(gt.format) + " but " + est.source +
                                " is " + format_name(est.format) +
                                ": KITTI files have no timestamps to associate with");
  }
  std::vector<double> ta, tb;
  ta.reserve(gt.poses.size());
  tb.reserve(est.poses.size());
  for (const auto& p : gt.poses) ta.push_back(p.t_s);
  for (const auto& p : est.poses) tb.push_back(p.t_s);
  return associate(ta, tb, max_dt_s, offset_s);
}

AteResult compute_ate(const Trajectory& gt, const Trajectory& est, const AteOptions& opt) {
  const auto pairs = associate_trajectories(gt, est, opt.max_dt_s, opt.offset_s);
  if (pairs.size() < 3) {
    throw std::invalid_argument("only " + std::to_string(pairs.size()) + " pose pairs of " +
                                gt.source + " and " + est.source + " lie within " +
                                std::to_string(opt.max_dt_s) + " s of each other (need >= 3)");
  }
  AteResult r;
  r.pairs = pairs.size();
  std::vector<Eigen::Vector3d> from, to;
  from.reserve(pairs.size());
  to.reserve(pairs.size());
  for (const auto& m : pairs) {
    to.push_back(gt.poses[m.a].T_w_x.translation());
    from.push_back(est.poses[m.b].T_w_x.translation());
    r.t_s.push_back(gt.poses[m.a].t_s);
  }
  r.alignment = umeyama_align(from, to, opt.align);
  r.error_m.reserve(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const Eigen::Vector3d aligned = r.alignment.apply(from[i]);
    r.error_m.push_back((to[i] - aligned).norm());
    r.p_est_m.push_back(aligned);
  }
  r.p_gt_m = std::move(to);
  r.stats = compute_stats(r.error_m);
  return r;
}

io::Json ate_to_json(const AteResult& r, const AteOptions& opt) {
  io::Json j;
  j["pairs"] = r.pairs;
  add_stats_fields(j, r.stats);
  j["align"] = alignment_name(opt.align);
  j["scale"] = r.alignment.s;
  j["max_dt_s"] = opt.max_dt_s;
  return j;
}

std::string ate_json(const AteResult& r, const AteOptions& opt) {
  return io::json_line(ate_to_json(r, opt));
}

}  // namespace vigs::eval
