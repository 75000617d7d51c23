#include "photometric/integrable_segments.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace shadecut::detail {
namespace {

// Cells with a normal steeper than this n_z (73 degrees from the viewer) are left out: there the
// gradient's differences between pixels are the discretization's, not the surface's curl.
constexpr float kSteepest = 0.3f;
constexpr int kPasses = 2;
// A segment is switched only when that divides its curl by this much or more: the real photographs'
// noise and non-Lambertian shading leave both choices curled about as much, and then the cut's
// choice (smoothness, anchors, the outline) stands.
constexpr double kClearGain = 2.0;

class CurlField {
 public:
  CurlField(const NormalCandidates& candidates, const std::vector<int>& choice)
      : candidates_(candidates), choice_(choice), rows_(int(candidates.count.rows())), cols_(int(candidates.count.cols())) {}

  // Squared curl dgx/dy - dgy/dx of the 2 x 2 cell whose top-left pixel is (r, c); 0 unless all four
  // pixels have a chosen normal no steeper than kSteepest. Row r lies above row r + 1 (y up).
  double cell(int r, int c) const {
    if (r < 0 || c < 0 || r + 1 >= rows_ || c + 1 >= cols_) return 0.0;
    const int p = r * cols_ + c;
    const int corners[4] = {p, p + 1, p + cols_, p + cols_ + 1};
    Eigen::Vector2f g[4];
    for (int i = 0; i < 4; ++i) {
      const int k = choice_[std::size_t(corners[i])];
      if (k < 0) return 0.0;
      const Eigen::Vector3f n = candidates_.normals[std::size_t(k)].xyz.row(corners[i]);
      if (n.z() < kSteepest) return 0.0;
      g[i] = Eigen::Vector2f(-n.x() / n.z(), -n.y() / n.z());
    }
    const double dgx_dy = 0.5 * double(g[0].x() + g[1].x() - g[2].x() - g[3].x());
    const double dgy_dx = 0.5 * double(g[1].y() + g[3].y() - g[0].y() - g[2].y());
    return (dgx_dy - dgy_dx) * (dgx_dy - dgy_dx);
  }

 private:
  const NormalCandidates& candidates_;
  const std::vector<int>& choice_;
  int rows_, cols_;
};

// Segments: 4-connected pixels with two candidates that differ by kCoincidentDegrees or more.
std::vector<std::vector<int>> two_candidate_segments(const NormalCandidates& candidates) {
  const int rows = int(candidates.count.rows()), cols = int(candidates.count.cols());
  const float apart = float(std::cos(kCoincidentDegrees * M_PI / 180.0));
  std::vector<std::uint8_t> open(std::size_t(rows) * std::size_t(cols), 0);
  for (int p = 0; p < rows * cols; ++p)
    open[std::size_t(p)] = candidates.count.data()[p] == 2 &&
                           candidates.normals[0].xyz.row(p).dot(candidates.normals[1].xyz.row(p)) < apart;
  std::vector<std::vector<int>> segments;
  for (int seed = 0; seed < rows * cols; ++seed) {
    if (!open[std::size_t(seed)]) continue;
    std::vector<int> segment{seed};
    open[std::size_t(seed)] = 0;
    for (std::size_t i = 0; i < segment.size(); ++i) {
      const int p = segment[i], r = p / cols, c = p % cols;
      const int next[4] = {r > 0 ? p - cols : -1, r + 1 < rows ? p + cols : -1, c > 0 ? p - 1 : -1, c + 1 < cols ? p + 1 : -1};
      for (const int q : next)
        if (q >= 0 && open[std::size_t(q)]) {
          open[std::size_t(q)] = 0;
          segment.push_back(q);
        }
    }
    segments.push_back(std::move(segment));
  }
  return segments;
}

}  // namespace

SegmentCount switch_to_integrable(const NormalCandidates& candidates, std::vector<int>& choice) {
  const int cols = int(candidates.count.cols());
  const std::vector<std::vector<int>> segments = two_candidate_segments(candidates);
  const CurlField curl(candidates, choice);
  std::vector<int> stamp(choice.size(), -1), cells;
  std::vector<std::uint8_t> switched(segments.size(), 0);
  for (int pass = 0; pass < kPasses; ++pass) {
    for (std::size_t s = 0; s < segments.size(); ++s) {
      // The cells that touch the segment: those whose top-left pixel is the pixel or its up/left neighbours.
      cells.clear();
      const int mark = int(pass * segments.size() + s);
      for (const int p : segments[s])
        for (const int cell : {p, p - 1, p - cols, p - cols - 1})
          if (cell >= 0 && stamp[std::size_t(cell)] != mark) {
            stamp[std::size_t(cell)] = mark;
            cells.push_back(cell);
          }
      auto total = [&] {
        double sum = 0.0;
        for (const int cell : cells) sum += curl.cell(cell / cols, cell % cols);
        return sum;
      };
      const double before = total();
      for (const int p : segments[s]) choice[std::size_t(p)] = 1 - choice[std::size_t(p)];
      if (kClearGain * total() < before) {
        switched[s] ^= 1;
      } else {
        for (const int p : segments[s]) choice[std::size_t(p)] = 1 - choice[std::size_t(p)];
      }
    }
  }
  SegmentCount count;
  count.segments = int(segments.size());
  count.switched = int(std::count(switched.begin(), switched.end(), std::uint8_t(1)));
  return count;
}

}  // namespace shadecut::detail
