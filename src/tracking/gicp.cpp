#include "tracking/gicp.hpp"

#include "tracking/gicp_impl.hpp"

namespace vigs::tracking {

std::string_view to_string(GicpVerdict verdict) {
  switch (verdict) {
    case GicpVerdict::converged:
      return "converged";
    case GicpVerdict::not_converged:
      return "not_converged";
    case GicpVerdict::diverged:
      return "diverged";
    case GicpVerdict::degenerate:
      return "degenerate";
  }
  return "unknown";
}

Gicp::Gicp() : Gicp(Setting{}) {}

Gicp::Gicp(const Setting& setting, rt::WorkerTeam* team) : setting_(setting), team_(team) {
  if (team_ == nullptr) {
    own_team_.emplace(setting.num_threads, rt::ThreadSpec{.name = "tracker_w1"});
    team_ = &*own_team_;
  }
  partials_.resize(static_cast<std::size_t>(team_->size()));
}

template GicpResult Gicp::align<CloudTarget>(const CloudTarget&, const GaussianCloud&,
                                             const geometry::Pose&);

}  // namespace vigs::tracking
