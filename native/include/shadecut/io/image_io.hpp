// Image, depth, normal and mesh files through OpenImageIO (and plain text for meshes). Every save_*
// writes its file whole or not at all (write_atomically): a failed write leaves the file that was there.
#pragma once

#include <shadecut/support/intensity.hpp>
#include <shadecut/support/types.hpp>

#include <cstdint>
#include <string>

namespace shadecut {

/// How the stored values of a file relate to linear intensity.
enum class ColorSpace {
  Auto,    ///< Float formats are linear; integer formats are sRGB unless the file says it is linear.
  Linear,  ///< Stored values are linear (after scaling integers to [0, 1]).
  SRGB,    ///< Stored values are sRGB-encoded and are decoded to linear.
};

/// Parses "auto", "linear" or "srgb"; throws InvalidArgument otherwise.
ColorSpace parse_color_space(const std::string& name);

/// More channels than this is no photograph.
constexpr int kMaxChannels = 64;

/// An image file read as linear intensity.
struct LoadedImage {
  ImageF intensity;      ///< H x W linear intensity; integer formats scaled to [0, 1].
  ColourImage colour;    ///< H x W x 3 linear RGB of a colour file; empty (0 x 0 channels) for grey.
  Mask mask;             ///< H x W: alpha > 0.5 when the file has alpha, else all true.
  bool has_alpha = false;
  std::string color_space;  ///< what was assumed for the stored values: "linear" or "srgb".
};

/// Reads PNG (8/16-bit), TIFF, JPEG, EXR, ... Colour becomes Rec. 709 luminance of the linear channels,
/// and is kept as linear RGB beside it.
/// Channels: 1 = grey, 2 = grey + alpha, 3 = RGB, 4 = RGBA, unless the file names its alpha channel.
/// Alpha is read as stored (never premultiplied into the colour, never linearised). sRGB decoding uses
/// the exact piecewise curve. Auto treats an integer file as linear when its oiio:ColorSpace says
/// linear ("Linear", "scene_linear", "lin_srgb", ...) or its oiio:Gamma is 1 (a PNG gAMA of 1.0).
/// Non-finite values are returned as they are. Throws IoError (with the path and OIIO's message) when
/// the file is missing, unreadable or truncated, or not a regular file (a named pipe, a device: not
/// opened), and before allocating anything when its header declares more
/// than `max_pixels` pixels (a 1 KB file can claim 100000 x 100000) or more channels than
/// kMaxChannels.
LoadedImage load_image(const std::string& path, ColorSpace color_space = ColorSpace::Auto,
                       std::int64_t max_pixels = kDefaultMaxPixels);

/// Writes a linear single-channel image (channel Y, plus A = 0 / 1 when alpha is given): float for
/// .exr/.tif/.tiff (tagged linear), else 16-bit sRGB-encoded integers (tagged sRGB; PNG, or whatever
/// the extension names) with values clamped to [0, 1], so that load_image(path) returns the same
/// linear values (to 16-bit precision). Throws InvalidArgument for an empty image or an alpha of
/// another shape, IoError when the file cannot be written.
void save_image(const std::string& path, const ImageF& image, const Mask* alpha = nullptr);

/// The same for linear RGB (channels R, G, B): an albedo's colour, for example.
void save_image(const std::string& path, const ColourImage& image, const Mask* alpha = nullptr);

/// Writes depth: .exr/.tif/.tiff as float values (grey channel Y in pixel units, 0 outside the mask,
/// mask in alpha A: Blender and image viewers show it as a height image); other formats (PNG) as 16-bit grey scaled from the masked min..max to 0..65535 (a
/// picture, not data; 0 outside the mask and everywhere if the masked depth is flat).
void save_depth(const std::string& path, const ImageF& depth, const Mask& mask);

/// Writes normals: .exr/.tif/.tiff as float x, y, z in channels R, G, B; other formats (PNG) as 8-bit
/// RGB = (n + 1) / 2 * 255, the usual normal-map colours (y up, as in the camera frame). Pixels outside
/// the mask are black.
void save_normals(const std::string& path, const NormalMap& normals, const Mask& mask);

/// Writes the height field as a triangle mesh, .ply (binary little endian) or .obj (text): one vertex
/// per masked pixel sampled every `step` pixels (height_field_mesh) at (x, y, z) = (c, -r, depth) in
/// pixel units (camera frame), and two triangles for every 2 x 2 block of sampled masked pixels, wound
/// counter-clockwise as seen from the viewer (+z). Throws InvalidArgument for another extension or
/// step < 1, IoError when the file cannot be written.
void save_mesh(const std::string& path, const ImageF& depth, const Mask& mask, int step = 1);

}  // namespace shadecut
