#include <shadecut/photometric/choose_candidates.hpp>

#include "photometric/integrable_segments.hpp"

#include <shadecut/graphcut/maxflow.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

namespace shadecut {
namespace {

void check_candidates(const NormalCandidates& candidates, const CandidateCutParams& params) {
  if (!(params.smoothness > 0.0) || !std::isfinite(params.smoothness))
    throw InvalidArgument("shadecut: the smoothness weight must be > 0, got " + number_text(params.smoothness));
  check_iterations(params.max_cycles);
  const int rows = int(candidates.count.rows()), cols = int(candidates.count.cols());
  const int n = int(candidates.normals.size());
  if (rows < 1 || cols < 1 || n < 1) throw InvalidArgument("shadecut: no candidates given");
  if (!candidates.data_cost.empty() && int(candidates.data_cost.size()) != n)
    throw InvalidArgument("shadecut: " + std::to_string(candidates.data_cost.size()) + " data cost maps for " +
                          std::to_string(n) + " candidate maps; give none or one per candidate");
  for (int k = 0; k < n; ++k) {
    check_normals(candidates.normals[std::size_t(k)], rows, cols);
    if (!candidates.data_cost.empty()) {
      const ImageF& cost = candidates.data_cost[std::size_t(k)];
      if (cost.rows() != rows || cost.cols() != cols)
        throw InvalidArgument("shadecut: data cost map " + std::to_string(k) + " does not have the counts' size");
      if (!cost.isFinite().all() || (cost < 0.0f).any())
        throw InvalidArgument("shadecut: data cost map " + std::to_string(k) + " holds a negative or non-finite cost");
    }
  }
  for (int p = 0; p < rows * cols; ++p) {
    const int count = candidates.count.data()[p];
    if (count < 0 || count > n)
      throw InvalidArgument("shadecut: a pixel has " + std::to_string(count) + " candidates; 0 to " +
                            std::to_string(n) + " are possible");
    for (int k = 0; k < count; ++k)
      if (!candidates.normals[std::size_t(k)].xyz.row(p).allFinite())
        throw InvalidArgument("shadecut: candidate " + std::to_string(k) + " holds a NaN or infinite normal");
  }
}

// The energy's terms, read from the candidates.
class CandidateEnergy {
 public:
  CandidateEnergy(const NormalCandidates& candidates, double smoothness)
      : candidates_(candidates),
        smoothness_(float(smoothness)),
        rows_(int(candidates.count.rows())),
        cols_(int(candidates.count.cols())) {}

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  int count(int p) const { return candidates_.count.data()[p]; }
  float data(int p, int k) const {
    return candidates_.data_cost.empty() ? 0.0f : candidates_.data_cost[std::size_t(k)].data()[p];
  }
  float pair(int p, int kp, int q, int kq) const {
    return smoothness_ * (candidates_.normals[std::size_t(kp)].xyz.row(p) -
                          candidates_.normals[std::size_t(kq)].xyz.row(q)).norm();
  }

  double total(const std::vector<int>& choice) const {
    double sum = 0.0;
    for (int p = 0; p < rows_ * cols_; ++p) {
      if (count(p) == 0) continue;
      const int r = p / cols_, c = p % cols_;
      sum += data(p, choice[std::size_t(p)]);
      if (c + 1 < cols_ && count(p + 1) > 0) sum += pair(p, choice[std::size_t(p)], p + 1, choice[std::size_t(p) + 1]);
      if (r + 1 < rows_ && count(p + cols_) > 0)
        sum += pair(p, choice[std::size_t(p)], p + cols_, choice[std::size_t(p + cols_)]);
    }
    return sum;
  }

  // Every pixel at its cheapest candidate (the first on ties); -1 where it has none.
  std::vector<int> cheapest() const {
    std::vector<int> choice(std::size_t(rows_) * std::size_t(cols_), -1);
    for (int p = 0; p < rows_ * cols_; ++p) {
      if (count(p) == 0) continue;
      int best = 0;
      for (int k = 1; k < count(p); ++k)
        if (data(p, k) < data(p, best)) best = k;
      choice[std::size_t(p)] = best;
    }
    return choice;
  }

 private:
  const NormalCandidates& candidates_;
  float smoothness_;
  int rows_, cols_;
};

// Kolmogorov & Zabih's graph of the move to candidate `alpha` (x_p = 1: p switches, the sink side).
class FusionMove {
 public:
  FusionMove(const CandidateEnergy& energy, const std::vector<int>& choice, int alpha)
      : energy_(energy), choice_(choice), alpha_(alpha) {}

  bool variable(int p) const { return energy_.count(p) > alpha_ && choice_[std::size_t(p)] != alpha_; }

  // Builds `graph` (sized already); false when no pixel can switch.
  bool build(GridGraph& graph) const {
    const int rows = energy_.rows(), cols = energy_.cols();
    std::vector<double> unary(std::size_t(rows) * std::size_t(cols), 0.0);
    bool any = false;
    for (int p = 0; p < rows * cols; ++p) {
      if (!variable(p)) continue;
      any = true;
      unary[std::size_t(p)] += double(energy_.data(p, alpha_)) - energy_.data(p, choice_[std::size_t(p)]);
    }
    if (!any) return false;
    for (int p = 0; p < rows * cols; ++p) {
      const int r = p / cols, c = p % cols;
      if (c + 1 < cols) add_pair(p, p + 1, unary, graph.right_cap[std::size_t(p)]);
      if (r + 1 < rows) add_pair(p, p + cols, unary, graph.down_cap[std::size_t(p)]);
    }
    for (int p = 0; p < rows * cols; ++p) {
      const double u = unary[std::size_t(p)];
      graph.source_cap[std::size_t(p)] = u > 0.0 ? float(u) : 0.0f;
      graph.sink_cap[std::size_t(p)] = u < 0.0 ? float(-u) : 0.0f;
    }
    return true;
  }

 private:
  // The pair (p, q): A = E(keep, keep), B = E(keep, switch), C = E(switch, keep), D = E(switch, switch)
  // as A + (C - A) x_p + (D - C) x_q + (B + C - A - D) (1 - x_p) x_q, the last an arc p -> q. Where
  // B + C < A + D (not submodular) D is lowered to B + C - A: the move's graph then overestimates
  // nothing but that pair's double switch.
  void add_pair(int p, int q, std::vector<double>& unary, float& arc) const {
    arc = 0.0f;
    if (energy_.count(p) == 0 || energy_.count(q) == 0) return;
    const bool vp = variable(p), vq = variable(q);
    if (!vp && !vq) return;
    const int kp = choice_[std::size_t(p)], kq = choice_[std::size_t(q)];
    const double a = energy_.pair(p, kp, q, kq);
    if (vp && !vq) {
      unary[std::size_t(p)] += energy_.pair(p, alpha_, q, kq) - a;
    } else if (!vp && vq) {
      unary[std::size_t(q)] += energy_.pair(p, kp, q, alpha_) - a;
    } else {
      const double b = energy_.pair(p, kp, q, alpha_), c = energy_.pair(p, alpha_, q, kq);
      const double d = std::min(double(energy_.pair(p, alpha_, q, alpha_)), b + c - a);
      unary[std::size_t(p)] += c - a;
      unary[std::size_t(q)] += d - c;
      arc = float(b + c - a - d);
    }
  }

  const CandidateEnergy& energy_;
  const std::vector<int>& choice_;
  int alpha_;
};

CandidateCutResult chosen_normals(const NormalCandidates& candidates, const std::vector<int>& choice) {
  const int rows = int(candidates.count.rows()), cols = int(candidates.count.cols());
  CandidateCutResult result;
  result.normals = NormalMap(rows, cols);
  result.choice = CountImage::Constant(rows, cols, -1);
  for (int p = 0; p < rows * cols; ++p) {
    const int k = choice[std::size_t(p)];
    if (k < 0) continue;
    result.choice.data()[p] = k;
    result.normals.xyz.row(p) = candidates.normals[std::size_t(k)].xyz.row(p);
  }
  return result;
}

// Where no pixel has a choice, each keeps its one candidate, taken over without a copy; the energy,
// which no move could change, is not summed over the grid (CandidateCutResult::initial_energy).
CandidateCutResult fixed_candidates(NormalCandidates candidates) {
  CandidateCutResult result;
  result.normals = std::move(candidates.normals.front());
  result.choice = std::move(candidates.count);
  result.choice -= 1;
  for (Eigen::Index p = 0; p < result.choice.size(); ++p)
    if (result.choice.data()[p] < 0) result.normals.xyz.row(p).setZero();
  return result;
}

bool any_choice(const CountImage& count) {
  return std::any_of(count.data(), count.data() + count.size(), [](std::int32_t n) { return n > 1; });
}

}  // namespace

CandidateCutResult choose_candidates(NormalCandidates candidates, const CandidateCutParams& params,
                                     const Progress& progress) {
  check_candidates(candidates, params);
  if (!any_choice(candidates.count)) return fixed_candidates(std::move(candidates));
  const CandidateEnergy energy(candidates, params.smoothness);
  const int labels = int(candidates.normals.size());
  std::vector<int> choice = energy.cheapest();
  const double initial = energy.total(choice);
  double current = initial;
  std::unique_ptr<MaxFlowSolver> solver = make_maxflow_solver();
  GridGraph graph;
  std::vector<std::uint8_t> sink_side;
  int cycles = 0, accepted = 0;
  for (bool improved = true; improved && cycles < params.max_cycles;) {
    improved = false;
    for (int alpha = 0; alpha < labels; ++alpha) {
      graph.reset(energy.rows(), energy.cols());
      const FusionMove move(energy, choice, alpha);
      if (move.build(graph)) {
        solver->solve(graph, sink_side);
        std::vector<int> proposal = choice;
        for (std::size_t p = 0; p < proposal.size(); ++p)
          if (sink_side[p] && move.variable(int(p))) proposal[p] = alpha;
        const double proposed = energy.total(proposal);
        if (proposed < current - 1e-9 * std::max(1.0, std::abs(current))) {
          choice.swap(proposal);
          current = proposed;
          improved = true;
          ++accepted;
        }
      }
      progress.report(double(cycles * labels + alpha + 1) / double(params.max_cycles * labels), "candidate cut");
    }
    ++cycles;
  }
  detail::SegmentCount segments;
  if (params.integrable_segments) segments = detail::switch_to_integrable(candidates, choice);
  CandidateCutResult result = chosen_normals(candidates, choice);
  result.segments = segments.segments;
  result.switched_segments = segments.switched;
  result.initial_energy = initial;
  result.energy = current;
  result.cycles = cycles;
  result.accepted_moves = accepted;
  return result;
}

NormalCandidates photometric_candidates(PhotometricStereoResult result) {
  const int rows = result.normals.rows, cols = result.normals.cols;
  NormalCandidates candidates;
  // Moved, not copied (each map is 12 bytes a pixel): candidate 0 is the fit where three or more
  // photographs are usable, candidate 1 is read only where two are, and there it is second_candidate.
  candidates.normals.push_back(std::move(result.normals));
  candidates.normals.push_back(std::move(result.second_candidate));
  candidates.count = (result.usable >= 3).cast<std::int32_t>();
  const std::int32_t* usable = result.usable.data();
  if (std::find(usable, usable + result.usable.size(), 2) == usable + result.usable.size())
    return candidates;  // nothing to choose: no costs to weigh
  candidates.data_cost.assign(2, ImageF::Zero(rows, cols));
  for (int p = 0; p < rows * cols; ++p) {
    if (result.usable.data()[p] == 2) {
      candidates.count.data()[p] = 2;
      candidates.normals[0].xyz.row(p) = result.first_candidate.xyz.row(p);
      const float conflict[2] = {result.first_shadow_conflict.data()[p], result.second_shadow_conflict.data()[p]};
      for (int k = 0; k < 2; ++k)
        candidates.data_cost[std::size_t(k)].data()[p] =
            std::max(0.0f, -candidates.normals[std::size_t(k)].xyz(p, 2)) + conflict[k];
    }
  }
  return candidates;
}

}  // namespace shadecut
