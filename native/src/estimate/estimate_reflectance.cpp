#include <shadecut/estimate/estimate_reflectance.hpp>

#include <shadecut/estimate/estimate_albedo.hpp>
#include <shadecut/support/angular_error.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/validate.hpp>

#include "integrate/grid_poisson.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace shadecut {

namespace {

// How far (pixels) the shading's step is looked for on either side of an edge, and where its trend
// is read: far enough to clear an edge blurred over three pixels.
constexpr int kBridgeReach = 4;
constexpr int kTrendNear = 3, kTrendFar = 4;
// The share of the mask's pixels at which the relative reflectance is 1.
constexpr double kReferencePercentile = 0.9;
// The least-squares solve's precision (relative residual): log reflectance to about 1e-4.
constexpr double kSolveTolerance = 1e-5;

// The 3 x 3 box average, the border repeated outward.
ImageF box3(const ImageF& image) {
  const Eigen::Index rows = image.rows(), cols = image.cols();
  ImageF out(rows, cols);
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (Eigen::Index c = 0; c < cols; ++c) {
      double sum = 0.0;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc)
          sum += image(std::clamp<Eigen::Index>(r + dr, 0, rows - 1), std::clamp<Eigen::Index>(c + dc, 0, cols - 1));
      out(r, c) = float(sum / 9.0);
    }
  }
  return out;
}

// A field along one axis: value(r, c) read at (r, c + k) or (r + k, c), clamped to the image.
struct Along {
  const ImageF& field;
  bool across_rows;  // false: along a row (x), true: down a column (y)
  float at(Eigen::Index r, Eigen::Index c, int k) const {
    if (across_rows) return field(std::clamp<Eigen::Index>(r + k, 0, field.rows() - 1), c);
    return field(r, std::clamp<Eigen::Index>(c + k, 0, field.cols() - 1));
  }
};

// What the decomposition reads of the image, once.
struct Cues {
  ImageF log_intensity;          // of the image itself
  ImageF smooth_log;             // of the 3 x 3-smoothed image, for finding edges
  std::array<ImageF, 3> chroma;  // of the smoothed colour image; empty for grey
  Mask readable;                 // masked, neither shadow nor highlight
  Mask inner;                    // readable and at least `rim` pixels inside the mask
  ImageF log_shading;            // of a surface found before, where it can be read; NaN elsewhere; empty: none
};

Cues read_cues(const ImageF& intensity, const ColourImage* colour, const Mask& mask, const ReflectanceParams& params,
               const ImageF* shading) {
  Cues cues;
  if (shading) {
    const float dark = float(kReflectanceDarkShare) * mask.select(*shading, 0.0f).maxCoeff();
    cues.log_shading = (mask && *shading > dark).select(shading->max(1e-12f).log(), std::numeric_limits<float>::quiet_NaN());
  }
  const double albedo = estimate_albedo(intensity, mask);
  const double dark = params.shadow * albedo;
  const double bright = params.highlight > 0.0 ? params.highlight * albedo : INFINITY;
  cues.readable = mask && intensity > float(dark) && intensity <= float(bright);
  cues.log_intensity = intensity.max(1e-12f).log();
  cues.smooth_log = box3(intensity).max(1e-12f).log();
  if (colour) {
    std::array<ImageF, 3> smooth;
    for (int k = 0; k < 3; ++k) smooth[std::size_t(k)] = box3(colour->channel[std::size_t(k)]);
    const ImageF sum = (smooth[0] + smooth[1] + smooth[2]).max(1e-12f);
    for (int k = 0; k < 3; ++k) cues.chroma[std::size_t(k)] = smooth[std::size_t(k)] / sum;
  }
  // No edge is read on the rim: the masked pixels within `rim` 4-steps of an unmasked one or of the
  // image's border.
  cues.inner = cues.readable && erode_mask(mask, params.rim);
  return cues;
}

// Whether the pair (p, p + 1 along the axis) is a paint edge.
bool is_edge(const Cues& cues, const ReflectanceParams& params, Eigen::Index r, Eigen::Index c, bool across_rows) {
  const Along log{cues.smooth_log, across_rows};
  auto step = [&](int k) { return log.at(r, c, k + 1) - log.at(r, c, k); };
  if (params.intensity_edge > 0.0) {
    float trend[4] = {step(-kTrendFar), step(-kTrendNear), step(kTrendNear), step(kTrendFar)};
    std::sort(trend, trend + 4);
    const double expected = 0.5 * (double(trend[1]) + double(trend[2]));
    if (std::abs(double(log.at(r, c, 2) - log.at(r, c, -1)) - 3.0 * expected) > params.intensity_edge) return true;
  }
  if (!cues.chroma[0].size()) return false;
  double squared = 0.0;
  for (const ImageF& chroma : cues.chroma) {
    const Along along{chroma, across_rows};
    const double d = along.at(r, c, 2) - along.at(r, c, -1);
    squared += d * d;
  }
  return std::sqrt(squared) > params.chroma_edge;
}

// The log-reflectance steps along one axis: at a paint edge between two readable pixels, the image's
// step less the shading's: the step of the surface found before where it can be read, else the mean
// of the nearest non-edge image steps before and after the edge; 0 elsewhere.
std::vector<double> reflectance_steps(const Cues& cues, const ReflectanceParams& params, bool across_rows, int& edges) {
  const Eigen::Index rows = cues.readable.rows(), cols = cues.readable.cols();
  const Eigen::Index lines = across_rows ? cols : rows, length = across_rows ? rows : cols;
  std::vector<double> steps(std::size_t(rows * cols), 0.0);
  std::vector<double> image_step(static_cast<std::size_t>(length));
  std::vector<char> edge(static_cast<std::size_t>(length)), usable(static_cast<std::size_t>(length));
  for (Eigen::Index line = 0; line < lines; ++line) {
    auto pixel = [&](Eigen::Index i) { return across_rows ? std::pair{i, line} : std::pair{line, i}; };
    for (Eigen::Index i = 0; i + 1 < length; ++i) {
      const auto [r, c] = pixel(i);
      const auto [r1, c1] = pixel(i + 1);
      usable[std::size_t(i)] = cues.readable(r, c) && cues.readable(r1, c1);
      image_step[std::size_t(i)] = double(cues.log_intensity(r1, c1)) - double(cues.log_intensity(r, c));
      edge[std::size_t(i)] = usable[std::size_t(i)] && cues.inner(r, c) && cues.inner(r1, c1) &&
                             is_edge(cues, params, r, c, across_rows);
    }
    for (Eigen::Index i = 0; i + 1 < length; ++i) {
      if (!edge[std::size_t(i)]) continue;
      const auto [r, c] = pixel(i);
      if (cues.log_shading.size()) {
        const auto [r1, c1] = pixel(i + 1);
        const double surface = double(cues.log_shading(r1, c1)) - double(cues.log_shading(r, c));
        if (std::isfinite(surface)) {
          steps[std::size_t(r * cols + c)] = image_step[std::size_t(i)] - surface;
          ++edges;
          continue;
        }
      }
      double shading = 0.0;
      int found = 0;
      for (int side : {-1, 1}) {
        for (int k = 1; k <= kBridgeReach; ++k) {
          const Eigen::Index j = i + side * k;
          if (j < 0 || j + 1 >= length) break;
          if (edge[std::size_t(j)] || !usable[std::size_t(j)]) continue;
          shading += image_step[std::size_t(j)];
          ++found;
          break;
        }
      }
      steps[std::size_t(r * cols + c)] = image_step[std::size_t(i)] - (found ? shading / found : 0.0);
      ++edges;
    }
  }
  return steps;
}

}  // namespace

Reflectance estimate_reflectance(const ImageF& intensity, const ColourImage* colour, const Mask& mask,
                                 const ReflectanceParams& params, const Progress& progress, const ImageF* shading) {
  check_image(intensity);
  check_mask(mask, intensity);
  if (colour) {
    for (const ImageF& channel : colour->channel) {
      if (channel.rows() != intensity.rows() || channel.cols() != intensity.cols())
        throw InvalidArgument("shadecut: the colour image is not the intensity's shape");
      if (!channel.isFinite().all() || channel.minCoeff() < 0.0f)
        throw InvalidArgument("shadecut: the colour image must be finite and >= 0");
    }
  }
  if (!(params.chroma_edge >= 0.0) || !std::isfinite(params.chroma_edge) || !std::isfinite(params.intensity_edge) ||
      !std::isfinite(params.highlight) || params.rim < 0 || !(params.shadow >= 0.0 && params.shadow < 1.0))
    throw InvalidArgument("shadecut: the reflectance settings must be finite, chroma_edge and rim >= 0, shadow in [0, 1)");
  progress.report(0.0, "albedo");
  if (shading) {
    check_image(*shading, "shading");
    if (shading->rows() != intensity.rows() || shading->cols() != intensity.cols())
      throw InvalidArgument("shadecut: the shading is not the intensity's shape");
  }
  const Cues cues = read_cues(intensity, colour, mask, params, shading);
  Reflectance result;
  detail::EdgeRises rises;
  rises.right = reflectance_steps(cues, params, false, result.edge_pairs);
  rises.down = reflectance_steps(cues, params, true, result.edge_pairs);
  progress.report(0.3, "albedo");
  const std::vector<double> log_reflectance =
      detail::solve_grid_poisson(mask, rises, kSolveTolerance, progress.range(0.3, 1.0));
  // Each component's constant is free: fix it so that its own 90th percentile is 1.
  std::vector<double> values;
  for (Eigen::Index i = 0; i < mask.size(); ++i)
    if (mask.data()[i]) values.push_back(log_reflectance[std::size_t(i)]);
  result.relative = ImageF::Ones(intensity.rows(), intensity.cols());
  if (values.empty()) return result;
  auto at = values.begin() + std::ptrdiff_t(kReferencePercentile * double(values.size() - 1));
  std::nth_element(values.begin(), at, values.end());
  for (Eigen::Index i = 0; i < mask.size(); ++i)
    if (mask.data()[i]) result.relative.data()[i] = float(std::exp(log_reflectance[std::size_t(i)] - *at));
  progress.report(1.0, "albedo");
  return result;
}

ColourImage reflectance_colour(const ImageF& intensity, const ColourImage& colour, const Mask& mask,
                               const ImageF& grey_albedo) {
  const Eigen::Index rows = intensity.rows(), cols = intensity.cols();
  const double dark = kReflectanceDarkShare * (mask.select(intensity, 0.0f).maxCoeff());
  // The chromaticity relative to the luminance, read where the pixel is bright enough, then spread
  // outward one ring at a time into the pixels where it cannot be read (shadows).
  std::array<ImageF, 3> tint;
  for (ImageF& t : tint) t = ImageF::Zero(rows, cols);
  Mask known = mask && intensity > float(dark);
  for (Eigen::Index i = 0; i < mask.size(); ++i)
    if (known.data()[i])
      for (int k = 0; k < 3; ++k) tint[std::size_t(k)].data()[i] = colour.channel[std::size_t(k)].data()[i] / intensity.data()[i];
  for (bool spreading = true; spreading;) {
    spreading = false;
    Mask grown = known;
    for (Eigen::Index r = 0; r < rows; ++r) {
      for (Eigen::Index c = 0; c < cols; ++c) {
        if (!mask(r, c) || known(r, c)) continue;
        std::array<double, 3> sum{};
        int count = 0;
        for (auto [dr, dc] : {std::pair{-1, 0}, {1, 0}, {0, -1}, {0, 1}}) {
          const Eigen::Index rr = r + dr, cc = c + dc;
          if (rr < 0 || cc < 0 || rr >= rows || cc >= cols || !known(rr, cc)) continue;
          for (int k = 0; k < 3; ++k) sum[std::size_t(k)] += tint[std::size_t(k)](rr, cc);
          ++count;
        }
        if (!count) continue;
        for (int k = 0; k < 3; ++k) tint[std::size_t(k)](r, c) = float(sum[std::size_t(k)] / count);
        grown(r, c) = true;
        spreading = true;
      }
    }
    known = grown;
  }
  ColourImage result;
  for (int k = 0; k < 3; ++k)
    result.channel[std::size_t(k)] = mask.select(tint[std::size_t(k)] * grey_albedo, 0.0f);
  return result;
}

}  // namespace shadecut
