#include <shadecut/support/errors.hpp>
#include <shadecut/integrate/height_field_mesh.hpp>
#include <shadecut/io/atomic_files.hpp>
#include <shadecut/io/image_io.hpp>
#include <shadecut/support/intensity.hpp>

#include "support/enum_names.hpp"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <system_error>
#include <utility>

#include <unistd.h>
#include <vector>

namespace shadecut {

namespace {

std::string lowercase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  return text;
}

std::string extension_of(const std::string& path) {
  return lowercase(std::filesystem::path(path).extension().string());
}

bool stores_floats(const std::string& path) {
  const std::string extension = extension_of(path);
  return extension == ".exr" || extension == ".tif" || extension == ".tiff";
}

// Clamps to [0, 1] and scales to the integer range; NaN becomes 0 rather than undefined behaviour.
template <typename Integer>
Integer to_unsigned_normalized(double value) {
  constexpr double kMax = double(std::numeric_limits<Integer>::max());
  if (!(value > 0.0)) return 0;
  if (value >= 1.0) return Integer(kMax);
  return Integer(std::lround(value * kMax));
}

bool is_float_type(OIIO::TypeDesc type) {
  return type.basetype == OIIO::TypeDesc::FLOAT || type.basetype == OIIO::TypeDesc::HALF ||
         type.basetype == OIIO::TypeDesc::DOUBLE;
}

// OIIO reports a PNG gAMA of 1.0 as "Linear" with oiio:Gamma 1; other readers and writers spell linear
// "linear", "scene_linear", "lin_srgb", "lin_rec709", ...
bool file_says_linear(const OIIO::ImageSpec& spec) {
  const std::string name = lowercase(spec.get_string_attribute("oiio:ColorSpace"));
  if (name.find("linear") != std::string::npos || name.rfind("lin_", 0) == 0) return true;
  return spec.get_float_attribute("oiio:Gamma", 0.0f) == 1.0f;
}

bool decode_as_srgb(ColorSpace requested, const OIIO::ImageSpec& spec) {
  switch (requested) {
    case ColorSpace::Linear:
      return false;
    case ColorSpace::SRGB:
      return true;
    case ColorSpace::Auto:
      break;
  }
  return !is_float_type(spec.format) && !file_says_linear(spec);
}

// A NUL would cut the name short where the operating system reads it: another file than the one named.
void require_path(const char* function, const std::string& path) {
  if (path.find('\0') != std::string::npos) throw InvalidArgument(std::string(function) + ": the path contains a NUL character");
  if (path.empty()) throw InvalidArgument(std::string(function) + ": the path is empty");
}

void require_image(const char* function, Eigen::Index rows, Eigen::Index cols) {
  if (rows <= 0 || cols <= 0) throw InvalidArgument(std::string(function) + ": the image is empty");
}

void require_mask_shape(const char* function, const Mask& mask, Eigen::Index rows, Eigen::Index cols) {
  if (mask.rows() != rows || mask.cols() != cols) {
    throw InvalidArgument(std::string(function) + ": the mask is " + std::to_string(mask.rows()) + " x " +
                          std::to_string(mask.cols()) + " but the image is " + std::to_string(rows) + " x " +
                          std::to_string(cols));
  }
}

// Writes `size` bytes to `path` whole or not at all (write_atomically), every write checked: a full
// disk or a file size limit is an IoError naming `path` after `failure` ("cannot write"), never a
// short file.
void write_bytes(const std::string& path, const void* data, std::size_t size, const std::string& failure) {
  write_atomically(path, [&](const std::string& temporary) {
    std::ofstream file(temporary, std::ios::binary);
    if (!file) throw IoError(failure + " \"" + path + "\": " + std::strerror(errno));
    file.write(static_cast<const char*>(data), std::streamsize(size));
    file.close();
    if (!file) throw IoError(failure + " \"" + path + "\": " + std::strerror(errno));
  });
}

// Writes interleaved pixels whose layout and file type `spec` describes; `pixel_type` is the type of
// `pixels` in memory. The file is encoded in memory and then written by write_bytes: OpenImageIO's PNG
// writer, for one, reports success when the disk fills part-way, and its fragment would replace the
// file that was there.
void write_pixels(const std::string& path, const OIIO::ImageSpec& spec, OIIO::TypeDesc pixel_type,
                  const void* pixels) {
  auto output = OIIO::ImageOutput::create(path);
  if (!output) throw IoError("cannot write \"" + path + "\": " + OIIO::geterror());
  auto encode = [&](const std::string& target) {
    if (!output->open(target, spec) || !output->write_image(pixel_type, pixels) || !output->close())
      throw IoError("cannot write \"" + path + "\": " + output->geterror());
  };
  if (!output->supports("ioproxy")) {  // a format that can only write files: at least never half a file
    write_atomically(path, encode);
    return;
  }
  std::vector<unsigned char> encoded;
  OIIO::Filesystem::IOVecOutput memory(encoded);
  output->set_ioproxy(&memory);
  encode(path);
  write_bytes(path, encoded.data(), encoded.size(), "cannot write");
}

OIIO::ImageSpec make_spec(Eigen::Index rows, Eigen::Index cols, OIIO::TypeDesc type,
                          std::vector<std::string> channel_names, bool last_is_alpha) {
  OIIO::ImageSpec spec(int(cols), int(rows), int(channel_names.size()), type);
  spec.channelnames = std::move(channel_names);
  spec.alpha_channel = last_is_alpha ? spec.nchannels - 1 : -1;
  if (last_is_alpha) {
    // Alpha is a mask and the values are not premultiplied by it. Saying so keeps OIIO from dividing
    // them by alpha when writing PNG and makes TIFF mark the alpha as unassociated.
    spec.attribute("oiio:UnassociatedAlpha", 1);
  }
  return spec;
}

// The words of shadecut.file_kinds, which the add-on uses where Blender reads the file.
std::string special_file_kind(const std::filesystem::file_status& kind) {
  if (std::filesystem::is_fifo(kind)) return "a named pipe (FIFO)";
  if (std::filesystem::is_character_file(kind)) return "a character device";
  if (std::filesystem::is_block_file(kind)) return "a block device";
  if (std::filesystem::is_socket(kind)) return "a socket";
  return "not a regular file";
}

void append_u32_le(std::string& bytes, std::uint32_t value) {
  for (int shift = 0; shift < 32; shift += 8) bytes.push_back(char((value >> shift) & 0xffu));
}

void append_f32_le(std::string& bytes, float value) {
  std::uint32_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  append_u32_le(bytes, bits);
}

struct Triangle {
  std::int32_t a, b, c;
};

// The pixels (rows x cols x channels, row-major) as viewers show a file of EXIF `orientation` (1-8):
// its stored rows turned and mirrored upright (6: turned 90 degrees clockwise, 8: counter-clockwise,
// 3: 180 degrees, 2 and 4 mirrored, 5 and 7 mirrored across a diagonal). rows and cols become the
// upright image's.
void turn_upright(std::vector<float>& pixels, int& rows, int& cols, int channels, int orientation) {
  if (orientation < 2 || orientation > 8) return;
  const bool swaps = orientation >= 5;
  const int out_rows = swaps ? cols : rows, out_cols = swaps ? rows : cols;
  std::vector<float> upright(pixels.size());
  for (int r = 0; r < out_rows; ++r)
    for (int c = 0; c < out_cols; ++c) {
      int sr = r, sc = c;  // the stored pixel shown at (r, c)
      switch (orientation) {
        case 2: sc = cols - 1 - c; break;
        case 3: sr = rows - 1 - r; sc = cols - 1 - c; break;
        case 4: sr = rows - 1 - r; break;
        case 5: sr = c; sc = r; break;
        case 6: sr = rows - 1 - c; sc = r; break;
        case 7: sr = rows - 1 - c; sc = cols - 1 - r; break;
        case 8: sr = c; sc = cols - 1 - r; break;
      }
      std::copy_n(&pixels[(std::size_t(sr) * std::size_t(cols) + std::size_t(sc)) * std::size_t(channels)],
                  channels, &upright[(std::size_t(r) * std::size_t(out_cols) + std::size_t(c)) * std::size_t(channels)]);
    }
  pixels.swap(upright);
  rows = out_rows;
  cols = out_cols;
}

// The alpha channel the file declares (or names A), else none: a second channel that is not declared
// alpha (TIFF R, G; EXR foo, bar) is not a mask.
int declared_alpha(const OIIO::ImageSpec& spec) {
  if (spec.nchannels > 1 && spec.alpha_channel >= 0 && spec.alpha_channel < spec.nchannels) return spec.alpha_channel;
  for (int channel = 0; channel < spec.nchannels; ++channel) {
    const std::string name = lowercase(spec.channel_name(channel));
    if (spec.nchannels > 1 && (name == "a" || name == "alpha")) return channel;
  }
  return -1;
}

// Whether the file's channels say what they hold: one channel, or some of them named as colour or
// grey (R, G, B, Y, or a layer's .R ...). Channels of other names (depth, foo) are no photograph.
bool names_colour_or_grey(const OIIO::ImageSpec& spec) {
  if (spec.nchannels == 1) return true;
  for (int channel = 0; channel < spec.nchannels; ++channel) {
    std::string name = lowercase(spec.channel_name(channel));
    if (const std::size_t dot = name.rfind('.'); dot != std::string::npos) name = name.substr(dot + 1);
    if (name == "r" || name == "g" || name == "b" || name == "y" || name == "red" || name == "green" || name == "blue")
      return true;
  }
  return false;
}

}  // namespace

ColorSpace parse_color_space(const std::string& name) {
  static const std::vector<std::string> names{"auto", "linear", "srgb"};
  return parse_enum<ColorSpace>(names, name, "colour space");
}

LoadedImage load_image(const std::string& path, ColorSpace color_space, std::int64_t max_pixels) {
  OIIO::ImageSpec config;
  // Alpha is only a mask here: the intensities must come back as stored, not premultiplied by it.
  config.attribute("oiio:UnassociatedAlpha", 1);
  require_path("load_image", path);
  std::error_code status;
  const std::filesystem::file_status kind = std::filesystem::status(path, status);
  if (std::filesystem::is_directory(kind)) throw IoError("cannot read image \"" + path + "\": it is a folder");
  // The system's own reason (a loop of symbolic links, a name too long, a folder not searchable), not
  // "no such file" for every path it could not look at.
  if (status && status != std::errc::no_such_file_or_directory)
    throw IoError("cannot read image \"" + path + "\": " + status.message());
  if (!std::filesystem::exists(kind)) throw IoError("cannot read image \"" + path + "\": there is no such file");
  // A named pipe blocks a reader until something writes to it and a device such as /dev/zero feeds
  // it bytes without end: neither is an image, and both are refused without being opened.
  if (!std::filesystem::is_regular_file(kind))
    throw IoError("cannot read image \"" + path + "\": it is " + special_file_kind(kind) + ", not a regular file");
  if (::access(path.c_str(), R_OK) != 0)
    throw IoError("cannot read image \"" + path + "\": " + std::generic_category().message(errno));
  if (std::filesystem::file_size(path, status) == 0 && !status)
    throw IoError("cannot read image \"" + path + "\": the file is empty (0 bytes)");
  auto input = OIIO::ImageInput::open(path, &config);
  if (!input) throw IoError("cannot read image \"" + path + "\": " + OIIO::geterror());
  const OIIO::ImageSpec spec = input->spec();
  if (spec.depth > 1) throw IoError("cannot read image \"" + path + "\": volume images are not supported");

  const int channels = spec.nchannels;
  if (channels < 1 || channels > kMaxChannels)
    throw IoError("cannot read image \"" + path + "\": it declares " + std::to_string(channels) + " channels");
  const std::int64_t declared = std::int64_t(spec.width) * std::int64_t(spec.height);
  if (spec.width < 1 || spec.height < 1 || declared > max_pixels)
    throw IoError("cannot read image \"" + path + "\": its header declares " + std::to_string(spec.width) + " x " +
                  std::to_string(spec.height) + " pixels, above the limit of " + std::to_string(max_pixels) +
                  " (max_pixels)");
  const std::size_t pixel_count = std::size_t(declared);
  std::vector<float> pixels(pixel_count * std::size_t(channels));
  // A truncated JPEG or strip TIFF reads "successfully" with grey or black rows: the decoder's
  // complaint is only left pending on the reader (or, from some plugins, globally).
  OIIO::geterror();  // what opening left (formats tried and refused) is not this read's complaint
  const bool read = input->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, pixels.data());
  if (!read || input->has_error() || OIIO::has_error()) {
    std::string reason = input->geterror();
    const std::string global = OIIO::geterror();
    if (reason.empty()) reason = global.empty() ? "the file is damaged or truncated" : global;
    throw IoError("cannot read image \"" + path + "\": " + reason);
  }

  // Which one is meant is unknown: the first would be read without a word.
  if (input->seek_subimage(1, 0))
    throw IoError("cannot read image \"" + path + "\": it holds several images (the pages of a TIFF, the frames of a "
                  "GIF); save the one to read as a file of its own");
  if (!names_colour_or_grey(spec))
    throw IoError("cannot read image \"" + path + "\": none of its channels is named as colour or grey (R, G, B or Y)");
  const int alpha = declared_alpha(spec);
  const bool srgb = decode_as_srgb(color_space, spec);
  int rows = spec.height, cols = spec.width;
  turn_upright(pixels, rows, cols, channels, spec.get_int_attribute("Orientation", 1));
  Intensity decoded = intensity_from_pixels(pixels.data(), rows, cols, channels, alpha, srgb);

  LoadedImage loaded;
  loaded.intensity = std::move(decoded.intensity);
  loaded.colour = std::move(decoded.colour);
  loaded.mask = std::move(decoded.mask);
  loaded.has_alpha = alpha >= 0;
  loaded.color_space = srgb ? "srgb" : "linear";
  return loaded;
}

namespace {

// Linear planes of one shape (Y, or R G B) and an optional alpha: floats tagged linear for
// .exr/.tif, else 16-bit sRGB-encoded integers, clamped to [0, 1].
void save_planes(const std::string& path, const std::vector<const ImageF*>& planes, std::vector<std::string> names,
                 const Mask* alpha) {
  const ImageF& first = *planes.front();
  require_path("save_image", path);
  require_image("save_image", first.rows(), first.cols());
  if (alpha != nullptr) require_mask_shape("save_image", *alpha, first.rows(), first.cols());
  const std::size_t pixel_count = std::size_t(first.size());
  const std::size_t planes_count = planes.size();
  const int channels = int(planes_count) + (alpha != nullptr ? 1 : 0);
  if (alpha != nullptr) names.emplace_back("A");

  if (stores_floats(path)) {
    OIIO::ImageSpec spec = make_spec(first.rows(), first.cols(), OIIO::TypeDesc::FLOAT, names, alpha != nullptr);
    spec.attribute("oiio:ColorSpace", "Linear");
    std::vector<float> pixels(pixel_count * channels);
    for (std::size_t i = 0; i < pixel_count; ++i) {
      for (std::size_t k = 0; k < planes_count; ++k) pixels[i * channels + k] = planes[k]->data()[i];
      if (alpha != nullptr) pixels[i * channels + planes_count] = alpha->data()[i] ? 1.0f : 0.0f;
    }
    write_pixels(path, spec, OIIO::TypeDesc::FLOAT, pixels.data());
    return;
  }

  OIIO::ImageSpec spec = make_spec(first.rows(), first.cols(), OIIO::TypeDesc::UINT16, names, alpha != nullptr);
  spec.attribute("oiio:ColorSpace", "sRGB");
  std::vector<std::uint16_t> pixels(pixel_count * channels);
  for (std::size_t i = 0; i < pixel_count; ++i) {
    // Encoding maps [0, 1] onto itself and is monotonic, so clamping after it clamps the linear value.
    for (std::size_t k = 0; k < planes_count; ++k)
      pixels[i * channels + k] = to_unsigned_normalized<std::uint16_t>(linear_to_srgb(planes[k]->data()[i]));
    if (alpha != nullptr) pixels[i * channels + planes_count] = alpha->data()[i] ? 0xffff : 0;
  }
  write_pixels(path, spec, OIIO::TypeDesc::UINT16, pixels.data());
}

}  // namespace

void save_image(const std::string& path, const ImageF& image, const Mask* alpha) {
  save_planes(path, {&image}, {"Y"}, alpha);
}

void save_image(const std::string& path, const ColourImage& image, const Mask* alpha) {
  for (const ImageF& channel : image.channel)
    if (channel.rows() != image.rows() || channel.cols() != image.cols())
      throw InvalidArgument("save_image: the colour image's channels differ in shape");
  save_planes(path, {&image.channel[0], &image.channel[1], &image.channel[2]}, {"R", "G", "B"}, alpha);
}

void save_depth(const std::string& path, const ImageF& depth, const Mask& mask) {
  require_path("save_depth", path);
  require_image("save_depth", depth.rows(), depth.cols());
  require_mask_shape("save_depth", mask, depth.rows(), depth.cols());
  if (!mask.select(depth, 0.0f).allFinite()) throw InvalidArgument("save_depth: the depth is NaN or infinite inside the mask");
  const std::size_t pixel_count = std::size_t(depth.size());

  // Y (grey) rather than Z: Blender reads a Y + A file as a grey image of the heights, and a Z + A
  // one as black; OIIO and other readers take Y as the grey channel too.
  if (stores_floats(path)) {
    const OIIO::ImageSpec spec = make_spec(depth.rows(), depth.cols(), OIIO::TypeDesc::FLOAT, {"Y", "A"}, true);
    std::vector<float> pixels(pixel_count * 2);
    for (std::size_t i = 0; i < pixel_count; ++i) {
      const bool inside = mask.data()[i];
      pixels[2 * i] = inside ? depth.data()[i] : 0.0f;
      pixels[2 * i + 1] = inside ? 1.0f : 0.0f;
    }
    write_pixels(path, spec, OIIO::TypeDesc::FLOAT, pixels.data());
    return;
  }

  float low = std::numeric_limits<float>::infinity();
  float high = -std::numeric_limits<float>::infinity();
  for (std::size_t i = 0; i < pixel_count; ++i) {
    if (!mask.data()[i]) continue;
    low = std::min(low, depth.data()[i]);
    high = std::max(high, depth.data()[i]);
  }
  const double span = double(high) - double(low);
  std::vector<std::uint16_t> pixels(pixel_count, 0);
  if (span > 0.0) {
    for (std::size_t i = 0; i < pixel_count; ++i) {
      if (mask.data()[i]) pixels[i] = to_unsigned_normalized<std::uint16_t>((double(depth.data()[i]) - low) / span);
    }
  }
  const OIIO::ImageSpec spec = make_spec(depth.rows(), depth.cols(), OIIO::TypeDesc::UINT16, {"Y"}, false);
  write_pixels(path, spec, OIIO::TypeDesc::UINT16, pixels.data());
}

void save_normals(const std::string& path, const NormalMap& normals, const Mask& mask) {
  require_path("save_normals", path);
  require_image("save_normals", normals.rows, normals.cols);
  if (normals.xyz.rows() != normals.size()) {
    throw InvalidArgument("save_normals: the normal map holds " + std::to_string(normals.xyz.rows()) +
                          " vectors for " + std::to_string(normals.rows) + " x " + std::to_string(normals.cols) +
                          " pixels");
  }
  require_mask_shape("save_normals", mask, normals.rows, normals.cols);
  const std::size_t pixel_count = std::size_t(normals.size());

  // R, G, B rather than X, Y, Z: viewers then show the usual normal-map colours, and OIIO would
  // take a channel named Z for depth.
  if (stores_floats(path)) {
    const OIIO::ImageSpec spec = make_spec(normals.rows, normals.cols, OIIO::TypeDesc::FLOAT, {"R", "G", "B"}, false);
    std::vector<float> pixels(pixel_count * 3, 0.0f);
    for (std::size_t i = 0; i < pixel_count; ++i) {
      if (!mask.data()[i]) continue;
      for (int axis = 0; axis < 3; ++axis) pixels[3 * i + axis] = normals.xyz(Eigen::Index(i), axis);
    }
    write_pixels(path, spec, OIIO::TypeDesc::FLOAT, pixels.data());
    return;
  }

  const OIIO::ImageSpec spec = make_spec(normals.rows, normals.cols, OIIO::TypeDesc::UINT8, {"R", "G", "B"}, false);
  std::vector<std::uint8_t> pixels(pixel_count * 3, 0);
  for (std::size_t i = 0; i < pixel_count; ++i) {
    if (!mask.data()[i]) continue;
    for (int axis = 0; axis < 3; ++axis) {
      pixels[3 * i + axis] = to_unsigned_normalized<std::uint8_t>((normals.xyz(Eigen::Index(i), axis) + 1.0) / 2.0);
    }
  }
  write_pixels(path, spec, OIIO::TypeDesc::UINT8, pixels.data());
}

void save_mesh(const std::string& path, const ImageF& depth, const Mask& mask, int step) {
  const std::string extension = extension_of(path);
  if (extension != ".ply" && extension != ".obj") {
    throw InvalidArgument("save_mesh: \"" + path + "\" must end in .ply or .obj");
  }
  require_path("save_mesh", path);
  require_image("save_mesh", depth.rows(), depth.cols());
  require_mask_shape("save_mesh", mask, depth.rows(), depth.cols());
  const HeightFieldMesh mesh = height_field_mesh(depth, mask, step);
  // Each quad (top-left a, bottom-left d, bottom-right e, top-right b) becomes the triangles a d b
  // and b d e, which keep its counter-clockwise turn as seen from +z.
  std::vector<Triangle> triangles;
  triangles.reserve(std::size_t(mesh.quads.rows()) * 2);
  for (Eigen::Index q = 0; q < mesh.quads.rows(); ++q) {
    const auto quad = mesh.quads.row(q);
    triangles.push_back({quad(0), quad(1), quad(3)});
    triangles.push_back({quad(3), quad(1), quad(2)});
  }
  const Eigen::Index vertex_count = mesh.vertices.rows();

  std::string bytes;
  if (extension == ".ply") {
    bytes = "ply\nformat binary_little_endian 1.0\n"
            "comment ShadeCut height field; camera frame: x right, y up, z toward the viewer, pixel units\n"
            "element vertex " + std::to_string(vertex_count) +
            "\nproperty float x\nproperty float y\nproperty float z\n"
            "element face " + std::to_string(triangles.size()) +
            "\nproperty list uchar int vertex_indices\nend_header\n";
    bytes.reserve(bytes.size() + std::size_t(vertex_count) * 12 + triangles.size() * 13);
    for (Eigen::Index v = 0; v < vertex_count; ++v)
      for (int axis = 0; axis < 3; ++axis) append_f32_le(bytes, mesh.vertices(v, axis));
    for (const Triangle& triangle : triangles) {
      bytes.push_back(char(3));
      append_u32_le(bytes, std::uint32_t(triangle.a));
      append_u32_le(bytes, std::uint32_t(triangle.b));
      append_u32_le(bytes, std::uint32_t(triangle.c));
    }
  } else {
    bytes = "# ShadeCut height field; camera frame: x right, y up, z toward the viewer, pixel units\n";
    char line[96];
    for (Eigen::Index v = 0; v < vertex_count; ++v) {
      // %.9g prints every float exactly enough to read back the same value.
      bytes.append(line, std::size_t(std::snprintf(line, sizeof line, "v %d %d %.9g\n", int(mesh.vertices(v, 0)),
                                                   int(mesh.vertices(v, 1)), double(mesh.vertices(v, 2)))));
    }
    for (const Triangle& triangle : triangles) {
      bytes.append(line, std::size_t(std::snprintf(line, sizeof line, "f %d %d %d\n", triangle.a + 1, triangle.b + 1,
                                                   triangle.c + 1)));
    }
  }
  write_bytes(path, bytes.data(), bytes.size(), "cannot write mesh");
}

}  // namespace shadecut
