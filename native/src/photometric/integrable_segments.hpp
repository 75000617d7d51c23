// Internal to choose_candidates: the segments of two candidates switched to the more integrable
// choice (CandidateCutParams::integrable_segments). Not part of the public API.
#pragma once

#include <shadecut/photometric/choose_candidates.hpp>

#include <vector>

namespace shadecut::detail {

struct SegmentCount {
  int segments = 0;
  int switched = 0;
};

/// Switches, in `choice` (one candidate index per pixel, -1 where none), every segment whose other
/// candidates have less curl; two passes over the segments.
SegmentCount switch_to_integrable(const NormalCandidates& candidates, std::vector<int>& choice);

}  // namespace shadecut::detail
