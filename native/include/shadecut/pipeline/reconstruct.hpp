// The whole pipeline: shaded photographs in, normals and depth out.
#pragma once

#include <shadecut/pipeline/observation.hpp>
#include <shadecut/pipeline/option_table.hpp>
#include <shadecut/pipeline/reconstruct_options.hpp>
#include <shadecut/pipeline/reconstruction.hpp>
#include <shadecut/pipeline/stage_params.hpp>
#include <shadecut/support/types.hpp>

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace shadecut {

/// Reconstructs normals and depth from photographs of one view.
///
/// @param[in] observations the photographs, each with its light (observation.hpp); all H x W, all grey
///                         or all colour. One photograph is read as the paper reads it (its light
///                         given or estimated); several of one view under different given lights by
///                         photometric stereo, with the graph cut where two photographs leave two
///                         normals (docs/method.md, "Several photographs").
/// @param[in] mask    H x W pixels to reconstruct, or nullptr for all (an object without one is cut
///                    out of its background first: ReconstructOptions::cut_out).
/// @param[in] albedo  > 0, or std::nullopt: the light estimator's albedo when the light is estimated,
///                    estimate_albedo with options.albedo_method otherwise.
/// @param[in] options method and parameters (option_table.hpp).
/// Throws InvalidArgument for bad input and Cancelled when options.progress returns false.
Reconstruction reconstruct(const std::vector<Observation>& observations, const Mask* mask, std::optional<double> albedo,
                           const ReconstructOptions& options);

/// One grey photograph: H x W linear intensity (>= 2 x 2, finite); light as Observation::light.
Reconstruction reconstruct(const ImageF& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                           std::optional<double> albedo, const ReconstructOptions& options);

/// One colour photograph (H x W x 3 linear RGB under one white light): the shape from its luminance;
/// with retinex the chromaticity tells paint from shading, and albedo_colour is filled.
Reconstruction reconstruct(const ColourImage& image, const std::optional<Eigen::Vector3d>& light, const Mask* mask,
                           std::optional<double> albedo, const ReconstructOptions& options);

}  // namespace shadecut
