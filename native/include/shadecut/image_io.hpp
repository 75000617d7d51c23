// Image, depth, normal and mesh files through OpenImageIO (and plain text for meshes).
#pragma once

#include <shadecut/types.hpp>

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

/// An image file read as linear intensity.
struct LoadedImage {
  ImageF intensity;      ///< H x W linear intensity; integer formats scaled to [0, 1].
  Mask mask;             ///< H x W: alpha > 0.5 when the file has alpha, else all true.
  bool has_alpha = false;
  std::string color_space;  ///< what was assumed for the stored values: "linear" or "srgb".
};

/// Reads PNG (8/16-bit), TIFF, JPEG, EXR, ... Colour becomes Rec. 709 luminance of the linear channels.
/// Throws IoError when the file is missing or unreadable.
LoadedImage load_image(const std::string& path, ColorSpace color_space = ColorSpace::Auto);

/// Writes a linear single-channel image: float for .exr/.tif, else 16-bit sRGB-encoded PNG, so that
/// load_image(path) returns the same linear values (to 16-bit precision).
void save_image(const std::string& path, const ImageF& image, const Mask* alpha = nullptr);

/// Writes depth: .exr/.tif as float values (pixel units, 0 outside the mask, mask in alpha); other
/// formats (PNG) as 16-bit grey scaled from the masked min..max to 0..65535 (a picture, not data).
void save_depth(const std::string& path, const ImageF& depth, const Mask& mask);

/// Writes normals: .exr/.tif as float x, y, z; other formats (PNG) as 8-bit RGB = (n + 1) / 2 * 255,
/// the usual normal-map colours (y up, as in the camera frame). Pixels outside the mask are black.
void save_normals(const std::string& path, const NormalMap& normals, const Mask& mask);

/// Writes the height field as a triangle mesh, .ply (binary little endian) or .obj (text): one vertex
/// per masked pixel at (x, y, z) = (c, -r, depth) in pixel units (camera frame), and two triangles for
/// every 2 x 2 block of masked pixels. Throws InvalidArgument for another extension.
void save_mesh(const std::string& path, const ImageF& depth, const Mask& mask);

}  // namespace shadecut
