// Internal to reconstruct(): an object small in a large frame is reconstructed in a window around
// its mask, and the result put back in the frame.
#pragma once

#include <shadecut/pipeline/observation.hpp>
#include <shadecut/pipeline/reconstruction.hpp>
#include <shadecut/support/types.hpp>

#include "support/mask_bounds.hpp"

#include <algorithm>
#include <optional>
#include <vector>

namespace shadecut::detail {

/// The window a reconstruction of `mask` works in, when it is at most half the frame: the mask's
/// bounding box grown by a margin (the local steps read a few pixels around each masked one) and
/// set on a 64-pixel grid of the frame (coarse to fine halves the object up to six times; on that
/// grid its blocks are the frame's). std::nullopt when the window would not save half the frame.
std::optional<Box> object_window(const Mask& mask);

/// The photographs and the mask within `window`.
std::vector<Observation> crop_observations(const std::vector<Observation>& observations, const Box& window);
Mask crop_mask(const Mask& mask, const Box& window);

/// `result`, reconstructed within `window`, put back in a frame of `rows` x `cols`: every map
/// outside the window is what it is outside the mask (zero; the mask false).
Reconstruction put_back(Reconstruction result, const Box& window, int rows, int cols);

/// solve(observations, mask) within the object's window when there is one (object_window) and
/// every photograph has the mask's shape (else the solve's own checks name what is wrong), put back
/// in the frame: an object's memory and time follow its size, not its frame's.
template <typename Solve>
Reconstruction solve_in_object_window(const std::vector<Observation>& observations, const Mask& mask, Solve&& solve) {
  const bool same_shape = std::all_of(observations.begin(), observations.end(), [&](const Observation& photograph) {
    return photograph.image.rows() == mask.rows() && photograph.image.cols() == mask.cols() &&
           (!photograph.has_colour() || (photograph.colour.rows() == mask.rows() && photograph.colour.cols() == mask.cols()));
  });
  const std::optional<Box> window = same_shape ? object_window(mask) : std::nullopt;
  if (!window) return solve(observations, mask);
  return put_back(solve(crop_observations(observations, *window), crop_mask(mask, *window)), *window, int(mask.rows()),
                  int(mask.cols()));
}

}  // namespace shadecut::detail
