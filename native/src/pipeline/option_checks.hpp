// Internal: whether a call's options can run on its mask.
#pragma once

#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/support/types.hpp>

#include <cstdint>

namespace shadecut::detail {

/// Throws InvalidArgument for an option outside its range (check_option_ranges), a call whose memory
/// would not fit (estimated_peak_memory against available_memory()), or options that do not fit
/// the mask or each other.
void check_options(const ReconstructOptions& options, const Mask& mask);

/// The peak bytes a reconstruct() call with these options needs for an image of `pixels` pixels, from
/// the measured model in docs/benchmarks.md ("Memory").
std::uint64_t estimated_peak_memory(const ReconstructOptions& options, std::int64_t pixels);

}  // namespace shadecut::detail
