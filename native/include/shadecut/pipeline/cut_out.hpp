// An object cut out of a plain background, for images without alpha: what reconstruct() does for
// scene = Object when no mask is given (ReconstructOptions::cut_out), and what the add-on and the
// command-line tool show as the mask used.
#pragma once

#include <shadecut/support/progress.hpp>
#include <shadecut/support/types.hpp>

#include <string>
#include <vector>

namespace shadecut {

/// How a cut-out ended. NotTried is only ever a ReconstructStats value (no cut-out was run).
enum class CutOutOutcome {
  NotTried,      ///< "not_tried": a mask was given, the scene is a relief, or cut_out is off
  Found,         ///< "found": an object stands apart from a plain background along most of its outline
  BusyBorder,    ///< "busy_border": the image's border is no plain background (a texture, or a surface
                 ///< filling the frame); no object can be told from it
  NoObject,      ///< "no_object": the border is plain but nothing large enough stands apart from it
  LowContrast,   ///< "low_contrast": a region was found, but too little of its outline differs from the
                 ///< background (a dark background meeting the object's attached shadow, say)
};

const std::vector<std::string>& cut_out_outcome_names();
std::string to_string(CutOutOutcome outcome);

/// The settings of cut_out(), with their defaults (the one place they are held). The models are those
/// of GrabCut (Rother, Kolmogorov & Blake 2004) with a plain background: docs/method.md, "Cutting out".
struct CutOutOptions {
  /// The long side, in pixels, of the shrunk image on which the models are learnt and the object
  /// labelled; the full image is then labelled only in a band along that outline.
  int working_size = 320;
  /// The width of the image's border read as background, as a share of the shorter side.
  double border = 0.04;
  /// The largest spread (robust standard deviation, display-encoded values in [0, 1]) of a plain
  /// background around its smooth fit; a busier border is a texture.
  double max_noise = 0.05;
  /// The least share of the border that must fit that plain background (the rest: the object
  /// standing on an edge, or leaving the frame).
  double min_border_share = 0.5;
  /// GrabCut's gamma: the cost, in nats, of cutting between two pixels of the same colour.
  double smoothness = 50.0;
  /// Rounds of GrabCut's alternation (models learnt from the labelling, labelling from the models).
  int iterations = 3;
  /// A part of the object smaller than this share of the image is dropped (noise, dust).
  double min_area = 0.001;
  /// The least share of the outline that must differ from the background (outline_contrast) for
  /// the object to count as found.
  double min_outline_contrast = 0.8;
};

struct CutOut {
  Mask mask;                       ///< H x W: the object (holes inside it filled); best guess when not found
  CutOutOutcome outcome = CutOutOutcome::NoObject;
  /// The share of the mask's outline that is a step edge against the background (unlike it by 3 of
  /// its standard deviations, and a sharper change across the outline than just inside it, not the
  /// ramp of a terminator or of a smooth surface): how clearly the object was told apart (0 with no mask).
  double outline_contrast = 0.0;
  double background_noise = 0.0;   ///< the border's robust spread about its fit (display-encoded units)
  double border_share = 0.0;       ///< the share of the border that fits a plain background
  std::string message;             ///< one sentence for the user: what was found, or why nothing was
};

/// Cuts the object out of an image of one object (or a few) on a plain background.
///
/// The background is a smooth (quadratic) field fitted robustly to the image's border, with its
/// noise; where the border does not fit one the image is said to have none (BusyBorder). The
/// object's colours are a histogram learnt from the pixels unlike the background; GrabCut's
/// contrast-sensitive smoothness joins them into regions, solved by ShadeCut's own max-flow.
///
/// @param[in] intensity H x W linear intensity, >= 0, finite, at least 2 x 2.
/// @param[in] colour    H x W x 3 linear RGB of the same image, or nullptr for a grey one.
/// @param[in] options   the settings.
/// @param[in] progress  told the share of the rounds done ("cut_out"); its callback returning false cancels.
/// @throws InvalidArgument for a bad image or options, Cancelled when the progress callback says so.
CutOut cut_out(const ImageF& intensity, const ColourImage* colour, const CutOutOptions& options = {},
               const Progress& progress = {});

}  // namespace shadecut
