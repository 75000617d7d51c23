#include <shadecut/photometric/choose_candidates.hpp>

#include "photometric/integrable_segments.hpp"

#include <shadecut/graphcut/maxflow.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <utility>

namespace shadecut {
namespace {

// Whether candidate map k is finite wherever a pixel has more than k candidates (the others never
// read it). Branch-free over the frame: x * 0 is 0 for a finite x and NaN otherwise.
bool read_candidates_are_finite(const NormalMap& map, const CountImage& count, int k) {
  const float* xyz = map.xyz.data();
  const std::int32_t* counts = count.data();
  bool finite = true;
  for (Eigen::Index p = 0; p < count.size(); ++p)
    finite &= (counts[p] <= k) | (xyz[3 * p] * 0.0f + xyz[3 * p + 1] * 0.0f + xyz[3 * p + 2] * 0.0f == 0.0f);
  return finite;
}

// Branch-free: a NaN fails both comparisons.
bool costs_are_finite_and_not_negative(const ImageF& cost) {
  bool fine = true;
  for (Eigen::Index i = 0; i < cost.size(); ++i)
    fine &= (cost.data()[i] >= 0.0f) & (cost.data()[i] <= std::numeric_limits<float>::max());
  return fine;
}

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
      if (!costs_are_finite_and_not_negative(cost))
        throw InvalidArgument("shadecut: data cost map " + std::to_string(k) + " holds a negative or non-finite cost");
    }
  }
  const int fewest = candidates.count.minCoeff(), most = candidates.count.maxCoeff();
  if (fewest < 0 || most > n)
    throw InvalidArgument("shadecut: a pixel has " + std::to_string(fewest < 0 ? fewest : most) + " candidates; 0 to " +
                          std::to_string(n) + " are possible");
  for (int k = 0; k < n; ++k)
    if (!read_candidates_are_finite(candidates.normals[std::size_t(k)], candidates.count, k))
      throw InvalidArgument("shadecut: candidate " + std::to_string(k) + " holds a NaN or infinite normal");
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

// The 4-connected regions of pixels with a choice (count > 1): region[p] its index, -1 where the
// pixel has none. Regions meet only through fixed pixels, so each can be cut on its own.
std::vector<int> choice_regions(const CountImage& count, int& regions) {
  const int rows = int(count.rows()), cols = int(count.cols());
  std::vector<int> region(std::size_t(rows) * std::size_t(cols), -1), stack;
  regions = 0;
  for (int seed = 0; seed < rows * cols; ++seed) {
    if (count.data()[seed] < 2 || region[std::size_t(seed)] >= 0) continue;
    region[std::size_t(seed)] = regions;
    stack.push_back(seed);
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      const int r = p / cols, c = p % cols;
      for (const int q : {c > 0 ? p - 1 : -1, c + 1 < cols ? p + 1 : -1, r > 0 ? p - cols : -1,
                          r + 1 < rows ? p + cols : -1})
        if (q >= 0 && count.data()[q] > 1 && region[std::size_t(q)] < 0) {
          region[std::size_t(q)] = regions;
          stack.push_back(q);
        }
    }
    ++regions;
  }
  return region;
}

struct Box {
  int row = 0, col = 0, rows = 0, cols = 0;
};

// Each region's bounding box grown by the fixed pixels around it, and its pixel count.
std::vector<Box> region_boxes(const std::vector<int>& region, int regions, int rows, int cols,
                              std::vector<std::int64_t>& pixels) {
  std::vector<int> top(std::size_t(regions), rows), left(std::size_t(regions), cols), bottom(std::size_t(regions), -1),
      right(std::size_t(regions), -1);
  pixels.assign(std::size_t(regions), 0);
  for (int p = 0; p < rows * cols; ++p) {
    const int id = region[std::size_t(p)];
    if (id < 0) continue;
    const int r = p / cols, c = p % cols;
    top[std::size_t(id)] = std::min(top[std::size_t(id)], r);
    bottom[std::size_t(id)] = std::max(bottom[std::size_t(id)], r);
    left[std::size_t(id)] = std::min(left[std::size_t(id)], c);
    right[std::size_t(id)] = std::max(right[std::size_t(id)], c);
    ++pixels[std::size_t(id)];
  }
  std::vector<Box> boxes(static_cast<std::size_t>(regions));
  for (std::size_t id = 0; id < boxes.size(); ++id) {
    const int r0 = std::max(0, top[id] - 1), c0 = std::max(0, left[id] - 1);
    boxes[id] = {r0, c0, std::min(rows, bottom[id] + 2) - r0, std::min(cols, right[id] + 2) - c0};
  }
  return boxes;
}

// The candidates inside `box`: the pixels of region `id` and the fixed pixels; other regions' pixels,
// never next to this one's, take no part.
NormalCandidates crop(const NormalCandidates& all, const std::vector<int>& region, int id, const Box& box) {
  const int cols = int(all.count.cols());
  NormalCandidates part;
  part.count = all.count.block(box.row, box.col, box.rows, box.cols);
  for (const NormalMap& map : all.normals) {
    NormalMap cropped(box.rows, box.cols);
    for (int r = 0; r < box.rows; ++r)
      cropped.xyz.middleRows(Eigen::Index(r) * box.cols, box.cols) =
          map.xyz.middleRows(Eigen::Index(box.row + r) * cols + box.col, box.cols);
    part.normals.push_back(std::move(cropped));
  }
  for (const ImageF& cost : all.data_cost) part.data_cost.push_back(cost.block(box.row, box.col, box.rows, box.cols));
  for (int r = 0; r < box.rows; ++r)
    for (int c = 0; c < box.cols; ++c)
      if (part.count(r, c) > 1 && region[std::size_t(box.row + r) * std::size_t(cols) + std::size_t(box.col + c)] != id)
        part.count(r, c) = 0;
  return part;
}

struct MoveCount {
  int cycles = 0, accepted = 0;
};

// Fusion moves over every candidate index until a cycle keeps none or after max_cycles; `choice`
// starts at the energy's cheapest. Progress runs from `done` to `done + share`.
MoveCount run_moves(const CandidateEnergy& energy, std::vector<int>& choice, const CandidateCutParams& params,
                    MaxFlowSolver& solver, int labels, const Progress& progress, double done, double share) {
  double current = energy.total(choice);
  GridGraph graph;
  std::vector<std::uint8_t> sink_side;
  MoveCount count;
  for (bool improved = true; improved && count.cycles < params.max_cycles;) {
    improved = false;
    for (int alpha = 0; alpha < labels; ++alpha) {
      graph.reset(energy.rows(), energy.cols());
      const FusionMove move(energy, choice, alpha);
      if (move.build(graph)) {
        solver.solve(graph, sink_side);
        std::vector<int> proposal = choice;
        for (std::size_t p = 0; p < proposal.size(); ++p)
          if (sink_side[p] && move.variable(int(p))) proposal[p] = alpha;
        const double proposed = energy.total(proposal);
        if (proposed < current - 1e-9 * std::max(1.0, std::abs(current))) {
          choice.swap(proposal);
          current = proposed;
          improved = true;
          ++count.accepted;
        }
      }
      progress.report(done + share * double(count.cycles * labels + alpha + 1) / double(params.max_cycles * labels),
                      "candidate cut");
    }
    ++count.cycles;
  }
  return count;
}

}  // namespace

CandidateCutResult choose_candidates(NormalCandidates candidates, const CandidateCutParams& params,
                                     const Progress& progress) {
  check_candidates(candidates, params);
  if (!any_choice(candidates.count)) return fixed_candidates(std::move(candidates));
  const CandidateEnergy energy(candidates, params.smoothness);
  const int rows = energy.rows(), cols = energy.cols();
  std::vector<int> choice = energy.cheapest();
  const double initial = energy.total(choice);
  int regions = 0;
  const std::vector<int> region = choice_regions(candidates.count, regions);
  std::vector<std::int64_t> pixels;
  const std::vector<Box> boxes = region_boxes(region, regions, rows, cols, pixels);
  const double all_pixels = double(std::accumulate(pixels.begin(), pixels.end(), std::int64_t(0)));
  std::unique_ptr<MaxFlowSolver> solver = make_maxflow_solver();
  int cycles = 0, accepted = 0;
  double done = 0.0;
  // Each region on its own box: the moves' graphs then span the pixels with a choice, not the frame.
  for (int id = 0; id < regions; ++id) {
    const Box& box = boxes[std::size_t(id)];
    const NormalCandidates part = crop(candidates, region, id, box);
    const CandidateEnergy part_energy(part, params.smoothness);
    std::vector<int> part_choice = part_energy.cheapest();
    const double share = double(pixels[std::size_t(id)]) / all_pixels;
    const MoveCount count = run_moves(part_energy, part_choice, params, *solver, int(candidates.normals.size()),
                                      progress, done, share);
    done += share;
    cycles = std::max(cycles, count.cycles);
    accepted += count.accepted;
    for (int r = 0; r < box.rows; ++r)
      for (int c = 0; c < box.cols; ++c) {
        const std::size_t p = std::size_t(box.row + r) * std::size_t(cols) + std::size_t(box.col + c);
        if (region[p] == id) choice[p] = part_choice[std::size_t(r) * std::size_t(box.cols) + std::size_t(c)];
      }
  }
  const double final_energy = energy.total(choice);
  detail::SegmentCount segments;
  if (params.integrable_segments) segments = detail::switch_to_integrable(candidates, choice);
  CandidateCutResult result = chosen_normals(candidates, choice);
  result.segments = segments.segments;
  result.switched_segments = segments.switched;
  result.initial_energy = initial;
  result.energy = final_energy;
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
  const bool pairs = std::find(usable, usable + result.usable.size(), 2) != usable + result.usable.size();
  const bool four = !result.four_fits.empty();
  if (!pairs && !four) return candidates;  // nothing to choose: no costs to weigh
  candidates.data_cost.assign(four ? 4 : 2, ImageF::Zero(rows, cols));
  if (four) candidates.normals.resize(4, NormalMap(rows, cols));
  // A candidate that faces away from the viewer costs -n_z, its distance to the nearest visible normal.
  const auto away = [&](std::size_t k, int p) { return std::max(0.0f, -candidates.normals[k].xyz(p, 2)); };
  for (int p = 0; p < rows * cols; ++p) {
    if (result.usable.data()[p] != 2) continue;
    candidates.count.data()[p] = 2;
    candidates.normals[0].xyz.row(p) = result.first_candidate.xyz.row(p);
    const float conflict[2] = {result.first_shadow_conflict.data()[p], result.second_shadow_conflict.data()[p]};
    for (std::size_t k = 0; k < 2; ++k) candidates.data_cost[k].data()[p] = away(k, p) + conflict[k];
  }
  // Candidate i leaves out the i-th of the four: the same photograph for every pixel of a region whose
  // four are the same, so a move switches such a region's choice at once.
  for (const FourFits& fits : result.four_fits) {
    const int p = fits.pixel;
    candidates.count.data()[p] = 4;
    const float cheapest = *std::min_element(fits.cost.begin(), fits.cost.end());
    for (std::size_t i = 0; i < 4; ++i) {
      candidates.normals[i].xyz.row(p) = fits.normals[i].transpose();
      candidates.data_cost[i].data()[p] = away(i, p) + fits.cost[i] - cheapest;
    }
  }
  return candidates;
}

}  // namespace shadecut
