#include "graphcut/maxflow_warm_start.hpp"

namespace shadecut::maxflow_internal {

KeptFlows::KeptFlows(const TiltEnergy& energy)
    : energy_(energy),
      right_(std::size_t(energy.slot_count()), 0.0f),
      down_(std::size_t(energy.slot_count()), 0.0f),
      states_(std::size_t(energy.labels())),
      seen_(std::size_t(energy.rows()) * std::size_t(energy.cols()), -1) {}

void KeptFlows::start_from(int label) {
  state().started = true;
  if (label < 0 || !states_[std::size_t(label)].started) return;
  for (int p = 0; p < energy_.rows() * energy_.cols(); ++p) {
    const std::int64_t from = energy_.slot(p, label), to = energy_.slot(p, alpha_);
    if (from < 0 || to < 0) continue;
    right_[std::size_t(to)] = right_[std::size_t(from)];
    down_[std::size_t(to)] = down_[std::size_t(from)];
  }
}

void KeptFlows::keep(const GridGraph& graph) {
  for (int p = 0; p < graph.size(); ++p) {
    set_right(p, graph.right_rev_cap[std::size_t(p)]);
    set_down(p, graph.down_rev_cap[std::size_t(p)]);
  }
}

void KeptFlows::changed_since_cut(std::vector<int>& nodes) {
  ++seen_round_;
  nodes.clear();
  for (std::size_t k = state().log_position; k < log_.size(); ++k) {
    const int p = log_[k];
    if (seen_[std::size_t(p)] != seen_round_) seen_[std::size_t(p)] = seen_round_, nodes.push_back(p);
  }
}

}  // namespace shadecut::maxflow_internal
