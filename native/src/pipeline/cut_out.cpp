// cut_out(): GrabCut with a plain background. The background is a quadratic field per channel fitted
// robustly to the border (so a gradient or vignetting is still plain), the object a colour histogram;
// both learnt on a shrunk image, the labelling then finished at full resolution along the outline.
#include <shadecut/graphcut/grid_graph.hpp>
#include <shadecut/graphcut/maxflow.hpp>
#include <shadecut/pipeline/cut_out.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/mask_components.hpp>
#include <shadecut/support/validate.hpp>

#include "support/enum_names.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace shadecut {

namespace {

constexpr double kNoiseFloor = 0.01;    // encoded units: renders have no noise, 8-bit files 1/255 and more
constexpr double kOutlier = 3.0;        // standard deviations from the background: unlike it
constexpr double kUniformShare = 0.01;  // of each model's density spread over the whole colour cube
constexpr float kHard = 1e6f;           // a terminal capacity no cut pays

// Display-encoded channels (values mostly in [0, 1], unclipped so that a bright graded background stays
// smooth; gamma 1/2.2 of the linear image over its 99.5th
// percentile): colour differences there are about as visible in the shadows as in the light, so
// one noise level serves a whole background.
struct Planes {
  int rows = 0, cols = 0;
  std::vector<ImageF> channel;
};

// The channels over the intensity's 99.5th percentile: linear (gamma 1), or display-encoded (1 / 2.2).
Planes normalized(const ImageF& intensity, const ColourImage* colour, float gamma) {
  std::vector<float> values(intensity.data(), intensity.data() + intensity.size());
  const std::size_t at = std::min(values.size() - 1, std::size_t(0.995 * double(values.size())));
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(at), values.end());
  const float scale = values[at] > 0.0f ? values[at] : 1.0f;
  Planes planes{int(intensity.rows()), int(intensity.cols()), {}};
  auto encoded = [scale, gamma](const ImageF& linear) { return (linear / scale).pow(1.0f / gamma).eval(); };
  if (colour)
    for (const ImageF& channel : colour->channel) planes.channel.push_back(encoded(channel));
  else
    planes.channel.push_back(encoded(intensity));
  return planes;
}

// Block means over factor x factor blocks (partial blocks at the right and bottom edges included).
Planes shrink(const Planes& full, int factor) {
  if (factor == 1) return full;
  Planes small{(full.rows + factor - 1) / factor, (full.cols + factor - 1) / factor, {}};
  for (const ImageF& channel : full.channel) {
    ImageF sum = ImageF::Zero(small.rows, small.cols), count = ImageF::Zero(small.rows, small.cols);
    for (int r = 0; r < full.rows; ++r)
      for (int c = 0; c < full.cols; ++c) {
        sum(r / factor, c / factor) += channel(r, c);
        count(r / factor, c / factor) += 1.0f;
      }
    small.channel.push_back(sum / count);
  }
  return small;
}

// The six quadratic terms at a pixel, in coordinates that run over [-1, 1] across the image whatever
// its resolution, so that a fit on the shrunk image holds at full size.
Eigen::Matrix<double, 6, 1> terms(int r, int c, int rows, int cols) {
  const double x = cols > 1 ? 2.0 * c / (cols - 1) - 1.0 : 0.0, y = rows > 1 ? 2.0 * r / (rows - 1) - 1.0 : 0.0;
  return (Eigen::Matrix<double, 6, 1>() << 1.0, x, y, x * x, x * y, y * y).finished();
}

struct Background {
  std::vector<Eigen::Matrix<double, 6, 1>> fit;  // per channel
  std::vector<double> sigma;                     // per channel, >= kNoiseFloor
  double inlier_share = 0.0;                     // of the pixels it was fitted to

  double mean(std::size_t channel, int r, int c, int rows, int cols) const { return fit[channel].dot(terms(r, c, rows, cols)); }
};

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
  return values[values.size() / 2];
}

// A robust fit to the pixels `at` (indices into the planes): from the channels' medians, then
// quadratics fitted to the pixels within kOutlier standard deviations of the last fit.
Background fit_background(const Planes& p, const std::vector<int>& at) {
  const std::size_t channels = p.channel.size();
  Background bg{std::vector<Eigen::Matrix<double, 6, 1>>(channels, Eigen::Matrix<double, 6, 1>::Zero()),
                std::vector<double>(channels, kNoiseFloor), 0.0};
  std::vector<std::uint8_t> inlier(at.size(), 1);
  for (int round = 0; round < 4; ++round) {
    for (std::size_t ch = 0; ch < channels; ++ch) {
      if (round == 0) {
        std::vector<double> values;
        for (const int i : at) values.push_back(p.channel[ch].data()[i]);
        bg.fit[ch](0) = median(values);
      } else {
        Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
        Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
        for (std::size_t k = 0; k < at.size(); ++k) {
          if (!inlier[k]) continue;
          const Eigen::Matrix<double, 6, 1> t = terms(at[k] / p.cols, at[k] % p.cols, p.rows, p.cols);
          normal += t * t.transpose();
          rhs += t * double(p.channel[ch].data()[at[k]]);
        }
        // A little ridge keeps the fit defined when the inliers lie on a line (a border one pixel wide).
        bg.fit[ch] = (normal + 1e-6 * double(at.size()) * Eigen::Matrix<double, 6, 6>::Identity()).ldlt().solve(rhs);
      }
      std::vector<double> deviations;
      for (std::size_t k = 0; k < at.size(); ++k)
        if (round == 0 || inlier[k])
          deviations.push_back(std::abs(p.channel[ch].data()[at[k]] - bg.mean(ch, at[k] / p.cols, at[k] % p.cols, p.rows, p.cols)));
      bg.sigma[ch] = std::max(kNoiseFloor, 1.4826 * median(deviations));
    }
    std::size_t kept = 0;
    for (std::size_t k = 0; k < at.size(); ++k) {
      bool near = true;
      for (std::size_t ch = 0; ch < channels; ++ch)
        near = near && std::abs(p.channel[ch].data()[at[k]] - bg.mean(ch, at[k] / p.cols, at[k] % p.cols, p.rows, p.cols)) <=
                           kOutlier * bg.sigma[ch];
      inlier[k] = near;
      kept += near;
    }
    bg.inlier_share = at.empty() ? 0.0 : double(kept) / double(at.size());
  }
  return bg;
}

// The largest distance, in background standard deviations over the channels, of each pixel from
// the background.
ImageF deviation(const Planes& p, const Background& bg) {
  ImageF d = ImageF::Zero(p.rows, p.cols);
  for (int r = 0; r < p.rows; ++r)
    for (int c = 0; c < p.cols; ++c)
      for (std::size_t ch = 0; ch < p.channel.size(); ++ch)
        d(r, c) = std::max(d(r, c), float(std::abs(p.channel[ch](r, c) - bg.mean(ch, r, c, p.rows, p.cols)) / bg.sigma[ch]));
  return d;
}

// The object's colours: a histogram over the encoded colour cube (64 bins grey, 16^3 colour),
// blurred by one bin, as a density.
struct Histogram {
  int bins = 0;
  std::size_t channels = 0;
  std::vector<double> density;

  std::size_t bin(const Planes& p, int i) const {
    std::size_t index = 0;
    for (std::size_t ch = 0; ch < channels; ++ch)
      index = index * std::size_t(bins) + std::size_t(std::clamp(int(p.channel[ch].data()[i] * float(bins)), 0, bins - 1));
    return index;
  }
};

Histogram learn_object(const Planes& p, const Mask& object) {
  Histogram h{p.channel.size() == 1 ? 64 : 16, p.channel.size(), {}};
  std::size_t cells = 1;
  for (std::size_t ch = 0; ch < h.channels; ++ch) cells *= std::size_t(h.bins);
  std::vector<double> counts(cells, 0.0);
  double total = 0.0;
  for (int i = 0; i < int(object.size()); ++i)
    if (object.data()[i]) counts[h.bin(p, i)] += 1.0, total += 1.0;
  // [1 2 1] / 4 along each axis of the cube.
  for (std::size_t axis = 0, stride = 1; axis < h.channels; ++axis, stride *= std::size_t(h.bins)) {
    std::vector<double> blurred(cells, 0.0);
    for (std::size_t k = 0; k < cells; ++k) {
      const std::size_t along = (k / stride) % std::size_t(h.bins);
      blurred[k] += 0.5 * counts[k];
      blurred[along > 0 ? k - stride : k] += 0.25 * counts[k];
      blurred[along + 1 < std::size_t(h.bins) ? k + stride : k] += 0.25 * counts[k];
    }
    counts.swap(blurred);
  }
  h.density.assign(cells, 0.0);
  for (std::size_t k = 0; k < cells; ++k) h.density[k] = total > 0.0 ? counts[k] / total * double(cells) : 0.0;
  return h;
}

// -log of each model's density (with a uniform share) at pixel i (row r, column c).
double object_cost(const Planes& p, const Histogram& h, int i) {
  return -std::log((1.0 - kUniformShare) * h.density[h.bin(p, i)] + kUniformShare);
}

double background_cost(const Planes& p, const Background& bg, int r, int c) {
  double log_density = 0.0;
  for (std::size_t ch = 0; ch < p.channel.size(); ++ch) {
    const double z = (p.channel[ch](r, c) - bg.mean(ch, r, c, p.rows, p.cols)) / bg.sigma[ch];
    log_density += -0.5 * z * z - std::log(bg.sigma[ch] * std::sqrt(2.0 * M_PI));
  }
  return -std::log((1.0 - kUniformShare) * std::exp(log_density) + kUniformShare);
}

// GrabCut's pairwise weight gamma exp(-beta |dz|^2), beta = 1 / (2 <|dz|^2>) over the image.
double colour_step(const Planes& p, int i, int j) {
  double sum = 0.0;
  for (const ImageF& channel : p.channel) sum += double(channel.data()[i] - channel.data()[j]) * (channel.data()[i] - channel.data()[j]);
  return sum;
}

double contrast_beta(const Planes& p) {
  double sum = 0.0;
  std::size_t pairs = 0;
  for (int r = 0; r < p.rows; ++r)
    for (int c = 0; c < p.cols; ++c) {
      const int i = r * p.cols + c;
      if (c + 1 < p.cols) sum += colour_step(p, i, i + 1), ++pairs;
      if (r + 1 < p.rows) sum += colour_step(p, i, i + p.cols), ++pairs;
    }
  return sum > 0.0 ? double(pairs) / (2.0 * sum) : 0.0;
}

// One labelling: the object (sink side) against the background (source side). `fixed` (may be
// null) holds -1 for free pixels, 0 / 1 for pixels held on the background / the object.
Mask label(const Planes& p, const Background& bg, const Histogram& object, double smoothness, const std::vector<int8_t>* fixed,
           MaxFlowSolver& solver) {
  GridGraph graph;
  graph.reset(p.rows, p.cols);
  const double beta = contrast_beta(p);
  for (int r = 0; r < p.rows; ++r)
    for (int c = 0; c < p.cols; ++c) {
      const int i = r * p.cols + c;
      const int held = fixed ? (*fixed)[std::size_t(i)] : -1;
      if (held >= 0) {
        (held ? graph.sink_cap : graph.source_cap)[std::size_t(i)] = kHard;
      } else {
        const double on_object = object_cost(p, object, i), on_background = background_cost(p, bg, r, c);
        const double least = std::min(on_object, on_background);
        graph.source_cap[std::size_t(i)] = float(on_object - least);      // paid on the object's side
        graph.sink_cap[std::size_t(i)] = float(on_background - least);    // paid on the background's
      }
      auto weight = [&](int j) {
        const bool both_held = held >= 0 && fixed && (*fixed)[std::size_t(j)] >= 0;
        return both_held ? 0.0f : float(smoothness * std::exp(-beta * colour_step(p, i, j)));
      };
      if (c + 1 < p.cols) graph.right_cap[std::size_t(i)] = graph.right_rev_cap[std::size_t(i)] = weight(i + 1);
      if (r + 1 < p.rows) graph.down_cap[std::size_t(i)] = graph.down_rev_cap[std::size_t(i)] = weight(i + p.cols);
    }
  std::vector<std::uint8_t> sink_side;
  solver.solve(graph, sink_side);
  Mask mask(p.rows, p.cols);
  for (int i = 0; i < int(mask.size()); ++i) mask.data()[i] = sink_side[std::size_t(i)] != 0;
  return mask;
}

// The background's pixels that reach the image's border (4-connected): the others are holes of
// the object (a highlight as bright as the background) and join it.
Mask fill_holes(const Mask& object) {
  const MaskComponents background = mask_components(!object);
  const Eigen::Index rows = object.rows(), cols = object.cols();
  std::vector<std::uint8_t> reaches_border(std::size_t(background.count), 0);
  auto mark = [&](Eigen::Index r, Eigen::Index c) {
    if (background.labels(r, c) >= 0) reaches_border[std::size_t(background.labels(r, c))] = 1;
  };
  for (Eigen::Index r = 0; r < rows; ++r) mark(r, 0), mark(r, cols - 1);
  for (Eigen::Index c = 0; c < cols; ++c) mark(0, c), mark(rows - 1, c);
  Mask filled = object;
  for (Eigen::Index i = 0; i < filled.size(); ++i) {
    const std::int32_t part = background.labels.data()[i];
    if (part >= 0 && !reaches_border[std::size_t(part)]) filled.data()[i] = true;
  }
  return filled;
}

// The object without its 4-connected parts smaller than min_pixels.
Mask drop_small_parts(const Mask& object, double min_pixels) {
  const MaskComponents parts = mask_components(object);
  std::vector<std::int64_t> size(std::size_t(parts.count), 0);
  for (Eigen::Index i = 0; i < parts.labels.size(); ++i)
    if (parts.labels.data()[i] >= 0) ++size[std::size_t(parts.labels.data()[i])];
  Mask kept = Mask::Constant(object.rows(), object.cols(), false);
  for (Eigen::Index i = 0; i < kept.size(); ++i) {
    const std::int32_t part = parts.labels.data()[i];
    kept.data()[i] = part >= 0 && double(size[std::size_t(part)]) >= min_pixels;
  }
  return kept;
}

// The share of the object's outline that is a step edge: an outline pixel p (in the object, its
// 4-neighbour q outside along direction d) counts when it is unlike the background (kOutlier) and
// the linear colour changes more from q to 3 pixels inside than over the next 3 pixels inward, by
// kStepRatio. A silhouette is a step (on black, a sphere's limb under a frontal light gives 2.4; on
// a brighter background far more); a terminator or a smooth surface seen through a gap of the fit
// is a ramp (1). Pixels with no 6 object pixels inward along d are not judged.
constexpr double kStepRatio = 1.5;

double outline_contrast(const Mask& object, const ImageF& deviation_map, const Planes& linear) {
  const int rows = int(object.rows()), cols = int(object.cols());
  auto distance = [&](int r0, int c0, int r1, int c1) {
    double sum = 0.0;
    for (const ImageF& channel : linear.channel) sum += double(channel(r0, c0) - channel(r1, c1)) * (channel(r0, c0) - channel(r1, c1));
    return std::sqrt(sum);
  };
  auto inside = [&](int r, int c) { return r >= 0 && c >= 0 && r < rows && c < cols && object(r, c); };
  std::size_t judged = 0, seen = 0;
  const int directions[4][2] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (!object(r, c)) continue;
      for (const auto& d : directions) {
        const int qr = r + d[0], qc = c + d[1];
        if (qr < 0 || qc < 0 || qr >= rows || qc >= cols || object(qr, qc)) continue;
        if (!inside(qr - 6 * d[0], qc - 6 * d[1]) || !inside(qr - 3 * d[0], qc - 3 * d[1])) continue;
        ++judged;
        const double across = distance(qr, qc, qr - 3 * d[0], qc - 3 * d[1]);
        const double within = distance(qr - 3 * d[0], qc - 3 * d[1], qr - 6 * d[0], qc - 6 * d[1]);
        seen += deviation_map(r, c) >= kOutlier && across > kStepRatio * within;
        break;  // one direction per pixel: each outline pixel counts once
      }
    }
  return judged ? double(seen) / double(judged) : 0.0;
}

void check_cut_out_options(const CutOutOptions& o) {
  auto bad = [](const std::string& what) { throw InvalidArgument("shadecut: cut-out option " + what); };
  if (o.working_size < 16) bad("working_size must be >= 16; got " + std::to_string(o.working_size));
  if (!(o.border > 0.0 && o.border < 0.5)) bad("border must lie in (0, 0.5); got " + number_text(o.border));
  if (!(o.max_noise > 0.0) || !std::isfinite(o.max_noise)) bad("max_noise must be finite and > 0; got " + number_text(o.max_noise));
  if (!(o.min_border_share >= 0.0 && o.min_border_share <= 1.0)) bad("min_border_share must lie in [0, 1]; got " + number_text(o.min_border_share));
  if (!(o.smoothness >= 0.0) || !std::isfinite(o.smoothness)) bad("smoothness must be finite and >= 0; got " + number_text(o.smoothness));
  if (o.iterations < 1) bad("iterations must be >= 1; got " + std::to_string(o.iterations));
  if (!(o.min_area >= 0.0 && o.min_area < 1.0)) bad("min_area must lie in [0, 1); got " + number_text(o.min_area));
  if (!(o.min_outline_contrast >= 0.0 && o.min_outline_contrast <= 1.0))
    bad("min_outline_contrast must lie in [0, 1]; got " + number_text(o.min_outline_contrast));
}

std::string percent(double share) { return std::to_string(int(std::lround(100.0 * share))) + "%"; }

// The object on the shrunk image: pixels unlike the background, joined into regions by GrabCut's
// rounds (the background fitted again to what they leave), small parts dropped. `bg` ends as the
// last round's background.
Mask segment(const Planes& small, const CutOutOptions& options, const Progress& progress, MaxFlowSolver& solver,
             Background& bg) {
  Mask object = deviation(small, bg) >= float(kOutlier);
  const double min_pixels = options.min_area * double(small.rows) * double(small.cols);
  for (int round = 0; round < options.iterations && object.count() >= std::max(1.0, min_pixels); ++round) {
    progress.report(double(round) / options.iterations, "cut_out");
    std::vector<int> background_pixels;
    for (int i = 0; i < int(object.size()); ++i)
      if (!object.data()[i]) background_pixels.push_back(i);
    if (round > 0 && !background_pixels.empty()) bg = fit_background(small, background_pixels);
    object = fill_holes(label(small, bg, learn_object(small, object), options.smoothness, nullptr, solver));
  }
  return drop_small_parts(object, std::max(1.0, min_pixels));
}

// At full resolution (factor times the shrunk object's size), the pixels whose 3 x 3 neighbourhood of
// shrunk pixels agrees keep its label (1 object, 0 background); the others (-1) are labelled again.
std::vector<int8_t> agreed_labels(const Mask& object, int factor, int rows, int cols) {
  std::vector<int8_t> fixed(std::size_t(rows) * std::size_t(cols), -1);
  if (factor == 1) return fixed;
  const int small_rows = int(object.rows()), small_cols = int(object.cols());
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int sr = r / factor, sc = c / factor;
      const bool label_here = object(sr, sc);
      bool uniform = true;
      for (int dr = -1; dr <= 1 && uniform; ++dr)
        for (int dc = -1; dc <= 1 && uniform; ++dc) {
          const int nr = std::clamp(sr + dr, 0, small_rows - 1), nc = std::clamp(sc + dc, 0, small_cols - 1);
          uniform = object(nr, nc) == label_here;
        }
      if (uniform) fixed[std::size_t(r) * std::size_t(cols) + std::size_t(c)] = label_here ? 1 : 0;
    }
  return fixed;
}

}  // namespace

const std::vector<std::string>& cut_out_outcome_names() {
  static const std::vector<std::string> names{"not_tried", "found", "busy_border", "no_object", "low_contrast"};
  return names;
}

std::string to_string(CutOutOutcome outcome) { return cut_out_outcome_names().at(std::size_t(outcome)); }

CutOut cut_out(const ImageF& intensity, const ColourImage* colour, const CutOutOptions& options, const Progress& progress) {
  check_image(intensity);
  check_cut_out_options(options);
  if (colour && (colour->rows() != intensity.rows() || colour->cols() != intensity.cols()))
    throw InvalidArgument("shadecut: the colour image and its intensity differ in shape");
  const Planes full = normalized(intensity, colour, 2.2f);
  const int factor = std::max(1, (std::max(full.rows, full.cols) + options.working_size - 1) / options.working_size);
  const Planes small = shrink(full, factor);

  CutOut result;
  result.mask = Mask::Constant(full.rows, full.cols, false);
  const int border = std::max(1, int(std::lround(options.border * std::min(small.rows, small.cols))));
  std::vector<int> ring;
  for (int r = 0; r < small.rows; ++r)
    for (int c = 0; c < small.cols; ++c)
      if (r < border || c < border || r >= small.rows - border || c >= small.cols - border) ring.push_back(r * small.cols + c);
  Background bg = fit_background(small, ring);
  result.background_noise = *std::max_element(bg.sigma.begin(), bg.sigma.end());
  result.border_share = bg.inlier_share;
  if (result.background_noise > options.max_noise || result.border_share < options.min_border_share) {
    result.outcome = CutOutOutcome::BusyBorder;
    result.message = "no plain background: " +
                     (result.border_share < options.min_border_share
                          ? "only " + percent(result.border_share) + " of the image's border fits one"
                          : "the image's border varies " + std::to_string(int(std::lround(100.0 * result.background_noise))) +
                                "% about its smooth fit") +
                     " (a texture, or a surface filling the frame); give a mask, or take it for a relief";
    return result;
  }

  const auto solver = make_maxflow_solver();
  Mask object = segment(small, options, progress, *solver, bg);
  // Judged on the shrunk image, where a photograph's edge blurred over a few pixels is a step again.
  result.outline_contrast = outline_contrast(object, deviation(small, bg), shrink(normalized(intensity, colour, 1.0f), factor));
  if (object.count() == 0) {
    result.outcome = CutOutOutcome::NoObject;
    result.message = "nothing stands apart from the plain background";
    return result;
  }

  // Full resolution: pixels whose 3 x 3 neighbourhood of shrunk pixels agrees keep its label; the
  // band along the outline is labelled again with the same models.
  const Histogram model = learn_object(small, object);
  const std::vector<int8_t> fixed = agreed_labels(object, factor, full.rows, full.cols);
  Mask fine = label(full, bg, model, options.smoothness, &fixed, *solver);
  fine = drop_small_parts(fill_holes(fine), std::max(1.0, options.min_area * double(full.rows) * double(full.cols)));
  result.mask = fine;
  if (fine.count() == 0) {
    result.outcome = CutOutOutcome::NoObject;
    result.message = "nothing stands apart from the plain background";
  } else if (result.outline_contrast < options.min_outline_contrast) {
    result.outcome = CutOutOutcome::LowContrast;
    result.message = "an object was found, but only " + percent(result.outline_contrast) +
                     " of its outline is an edge against the background (a shadow meeting a dark background, or a surface filling the frame); give a mask";
  } else {
    result.outcome = CutOutOutcome::Found;
    result.message = "cut out: " + percent(double(fine.count()) / double(fine.size())) + " of the image, " +
                     percent(result.outline_contrast) + " of its outline a clear edge";
  }
  return result;
}

}  // namespace shadecut
