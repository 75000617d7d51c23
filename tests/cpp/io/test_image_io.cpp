#include <shadecut/support/errors.hpp>
#include <shadecut/io/atomic_files.hpp>
#include <shadecut/io/image_io.hpp>

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using shadecut::ColorSpace;
using shadecut::ImageF;
using shadecut::InvalidArgument;
using shadecut::IoError;
using shadecut::LoadedImage;
using shadecut::Mask;
using shadecut::NormalMap;

// Written out here rather than taken from the library, so that a wrong curve there cannot agree with
// itself.
double srgb_eotf(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}

double luminance(double red, double green, double blue) { return 0.2126 * red + 0.7152 * green + 0.0722 * blue; }

template <typename Pixel>
void write_with_oiio(const std::string& path, int rows, int cols, int channels, OIIO::TypeDesc type,
                     const std::vector<Pixel>& pixels, const char* color_space = nullptr) {
  OIIO::ImageSpec spec(cols, rows, channels, type);
  if (color_space != nullptr) spec.attribute("oiio:ColorSpace", color_space);
  auto output = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(output) << OIIO::geterror();
  ASSERT_TRUE(output->open(path, spec)) << output->geterror();
  ASSERT_TRUE(output->write_image(type, pixels.data())) << output->geterror();
  ASSERT_TRUE(output->close()) << output->geterror();
}

struct RawImage {
  OIIO::ImageSpec spec;
  std::vector<float> pixels;  // interleaved, as stored in the file, scaled to [0, 1] for integers
};

RawImage read_with_oiio(const std::string& path) {
  RawImage raw;
  auto input = OIIO::ImageInput::open(path);
  if (!input) {
    ADD_FAILURE() << OIIO::geterror();
    return raw;
  }
  raw.spec = input->spec();
  raw.pixels.resize(std::size_t(raw.spec.width) * raw.spec.height * raw.spec.nchannels);
  EXPECT_TRUE(input->read_image(0, 0, 0, raw.spec.nchannels, OIIO::TypeDesc::FLOAT, raw.pixels.data()));
  return raw;
}

std::string read_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

struct Mesh {
  std::vector<std::array<float, 3>> vertices;
  std::vector<std::array<int, 3>> triangles;  // 0-based
};

std::uint32_t little_endian_u32(const std::string& bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = (value << 8) | std::uint8_t(bytes.at(at + std::size_t(i)));
  return value;
}

Mesh parse_binary_ply(const std::string& bytes) {
  const std::string end_of_header = "end_header\n";
  const std::size_t header_size = bytes.find(end_of_header) + end_of_header.size();
  std::istringstream header(bytes.substr(0, header_size));
  std::string line;
  std::getline(header, line);
  EXPECT_EQ(line, "ply");
  std::getline(header, line);
  EXPECT_EQ(line, "format binary_little_endian 1.0");
  std::size_t vertex_count = 0;
  std::size_t face_count = 0;
  std::vector<std::string> properties;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string keyword, kind;
    std::size_t count = 0;
    words >> keyword;
    if (keyword == "element") {
      words >> kind >> count;
      (kind == "vertex" ? vertex_count : face_count) = count;
    } else if (keyword == "property") {
      properties.push_back(line);
    }
  }
  EXPECT_EQ(properties, (std::vector<std::string>{"property float x", "property float y", "property float z",
                                                  "property list uchar int vertex_indices"}));
  EXPECT_EQ(bytes.size(), header_size + vertex_count * 12 + face_count * 13);

  Mesh mesh;
  std::size_t at = header_size;
  for (std::size_t v = 0; v < vertex_count; ++v) {
    std::array<float, 3> xyz{};
    for (float& coordinate : xyz) {
      const std::uint32_t bits = little_endian_u32(bytes, at);
      std::memcpy(&coordinate, &bits, sizeof coordinate);
      at += 4;
    }
    mesh.vertices.push_back(xyz);
  }
  for (std::size_t f = 0; f < face_count; ++f) {
    EXPECT_EQ(bytes.at(at), 3);
    ++at;
    std::array<int, 3> corners{};
    for (int& corner : corners) {
      corner = std::int32_t(little_endian_u32(bytes, at));
      at += 4;
    }
    mesh.triangles.push_back(corners);
  }
  return mesh;
}

Mesh parse_obj(const std::string& text) {
  Mesh mesh;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "v") {
      std::array<float, 3> xyz{};
      words >> xyz[0] >> xyz[1] >> xyz[2];
      mesh.vertices.push_back(xyz);
    } else if (keyword == "f") {
      std::array<int, 3> corners{};
      words >> corners[0] >> corners[1] >> corners[2];
      for (int& corner : corners) --corner;
      mesh.triangles.push_back(corners);
    }
  }
  return mesh;
}

// z component of the triangle's (unnormalised) normal for counter-clockwise winding.
double winding_normal_z(const Mesh& mesh, const std::array<int, 3>& triangle) {
  const auto& a = mesh.vertices.at(triangle[0]);
  const auto& b = mesh.vertices.at(triangle[1]);
  const auto& c = mesh.vertices.at(triangle[2]);
  return double(b[0] - a[0]) * (c[1] - a[1]) - double(b[1] - a[1]) * (c[0] - a[0]);
}

class ImageIO : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    directory_ = fs::temp_directory_path() /
                 ("shadecut_" + std::string(test->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(directory_);
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  std::string path(const std::string& name) const { return (directory_ / name).string(); }

 private:
  fs::path directory_;
};

TEST_F(ImageIO, ParsesColorSpaceNames) {
  EXPECT_EQ(shadecut::parse_color_space("auto"), ColorSpace::Auto);
  EXPECT_EQ(shadecut::parse_color_space("linear"), ColorSpace::Linear);
  EXPECT_EQ(shadecut::parse_color_space("srgb"), ColorSpace::SRGB);
  EXPECT_THROW(shadecut::parse_color_space("sRGB2"), InvalidArgument);
}

TEST_F(ImageIO, RefusesAHeaderAboveThePixelLimitBeforeReading) {
  const std::string file = path("sixteen.png");
  write_with_oiio(file, 4, 4, 1, OIIO::TypeDesc::UINT8, std::vector<std::uint8_t>(16, 128));
  EXPECT_EQ(shadecut::load_image(file, ColorSpace::Auto, 16).intensity.size(), 16);
  try {
    shadecut::load_image(file, ColorSpace::Auto, 15);
    FAIL() << "a 4 x 4 image passed a limit of 15 pixels";
  } catch (const IoError& error) {
    EXPECT_NE(std::string(error.what()).find("declares 4 x 4 pixels, above the limit of 15"), std::string::npos)
        << error.what();
  }
}

TEST_F(ImageIO, EightBitPngIsDecodedWithTheExactSrgbCurve) {
  // Every byte value once, 16 x 16.
  std::vector<std::uint8_t> bytes(256);
  for (int i = 0; i < 256; ++i) bytes[i] = std::uint8_t(i);
  const std::string file = path("ramp8.png");
  write_with_oiio(file, 16, 16, 1, OIIO::TypeDesc::UINT8, bytes);

  const LoadedImage loaded = shadecut::load_image(file);
  EXPECT_EQ(loaded.color_space, "srgb");
  EXPECT_FALSE(loaded.has_alpha);
  ASSERT_EQ(loaded.intensity.rows(), 16);
  ASSERT_EQ(loaded.intensity.cols(), 16);
  EXPECT_TRUE(loaded.mask.all());
  for (int i = 0; i < 256; ++i) {
    EXPECT_NEAR(loaded.intensity(i / 16, i % 16), srgb_eotf(i / 255.0), 1e-6) << "byte " << i;
  }

  const LoadedImage as_linear = shadecut::load_image(file, ColorSpace::Linear);
  EXPECT_EQ(as_linear.color_space, "linear");
  EXPECT_NEAR(as_linear.intensity(8, 0), 128 / 255.0, 1e-6);
}

TEST_F(ImageIO, PngTaggedLinearIsNotDecoded) {
  const std::vector<std::uint16_t> words{0, 1000, 30000, 65535};
  const std::string file = path("linear16.png");
  write_with_oiio(file, 2, 2, 1, OIIO::TypeDesc::UINT16, words, "Linear");

  const LoadedImage loaded = shadecut::load_image(file);
  EXPECT_EQ(loaded.color_space, "linear");
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(loaded.intensity(i / 2, i % 2), words[i] / 65535.0, 1e-6);

  const LoadedImage forced = shadecut::load_image(file, ColorSpace::SRGB);
  EXPECT_EQ(forced.color_space, "srgb");
  EXPECT_NEAR(forced.intensity(1, 0), srgb_eotf(30000 / 65535.0), 1e-6);
}

TEST_F(ImageIO, SixteenBitPngRoundTripsLinearValues) {
  constexpr int kRows = 7, kCols = 40;
  ImageF image(kRows, kCols);
  Mask alpha(kRows, kCols);
  for (int r = 0; r < kRows; ++r) {
    for (int c = 0; c < kCols; ++c) {
      // Dense in the dark end, where sRGB's linear segment and the curve meet, and up to exactly 1.
      const double t = double(r * kCols + c) / (kRows * kCols - 1);
      image(r, c) = float(t * t * t);
      alpha(r, c) = (r + c) % 3 != 0;
    }
  }
  const std::string file = path("round_trip.png");
  shadecut::save_image(file, image, &alpha);

  const LoadedImage loaded = shadecut::load_image(file);
  EXPECT_EQ(loaded.color_space, "srgb");
  EXPECT_TRUE(loaded.has_alpha);
  EXPECT_TRUE((loaded.mask == alpha).all());
  EXPECT_LE((loaded.intensity - image).abs().maxCoeff(), 2e-5f);

  const RawImage raw = read_with_oiio(file);
  EXPECT_EQ(raw.spec.format, OIIO::TypeDesc::UINT16);
  EXPECT_EQ(raw.spec.get_string_attribute("oiio:ColorSpace"), "sRGB");

  // Out of range values are clamped, not wrapped.
  ImageF out_of_range(1, 2);
  out_of_range << -0.5f, 1.5f;
  shadecut::save_image(path("clamped.png"), out_of_range);
  const LoadedImage clamped = shadecut::load_image(path("clamped.png"));
  EXPECT_FALSE(clamped.has_alpha);
  EXPECT_EQ(clamped.intensity(0, 0), 0.0f);
  EXPECT_EQ(clamped.intensity(0, 1), 1.0f);
}

TEST_F(ImageIO, FloatFilesRoundTripExactly) {
  ImageF image(3, 4);
  image << 0.0f, 0.25f, 1.0f, 7.5f, -0.125f, 1e-6f, 0.333f, 2.0f, 0.5f, 0.75f, 100.0f, 0.01f;
  Mask alpha = Mask::Constant(3, 4, true);
  alpha(1, 2) = false;
  for (const char* name : {"image.exr", "image.tif", "image.TIFF"}) {
    shadecut::save_image(path(name), image, &alpha);
    const LoadedImage loaded = shadecut::load_image(path(name));
    EXPECT_EQ(loaded.color_space, "linear") << name;
    EXPECT_TRUE(loaded.has_alpha) << name;
    EXPECT_TRUE((loaded.mask == alpha).all()) << name;
    EXPECT_TRUE((loaded.intensity == image).all()) << name;
  }
}

TEST_F(ImageIO, ExrWithAlphaGivesLuminanceAndMask) {
  // RGBA, linear, including values above 1 and alphas either side of 0.5.
  const std::vector<float> pixels{0.2f, 0.4f, 0.6f, 1.0f,  3.0f, 0.5f, 0.1f, 0.75f,
                                  0.9f, 0.1f, 0.0f, 0.25f, 0.0f, 0.0f, 1.0f, 0.0f};
  const std::string file = path("rgba.exr");
  write_with_oiio(file, 2, 2, 4, OIIO::TypeDesc::FLOAT, pixels);

  const LoadedImage loaded = shadecut::load_image(file);
  EXPECT_EQ(loaded.color_space, "linear");
  EXPECT_TRUE(loaded.has_alpha);
  for (int i = 0; i < 4; ++i) {
    const float* p = &pixels[4 * i];
    EXPECT_NEAR(loaded.intensity(i / 2, i % 2), luminance(p[0], p[1], p[2]), 1e-6) << "pixel " << i;
    EXPECT_EQ(loaded.mask(i / 2, i % 2), p[3] > 0.5f) << "pixel " << i;
  }
}

TEST_F(ImageIO, ColourPngGivesLuminanceOfLinearChannels) {
  const std::vector<std::uint8_t> rgb{255, 0, 0, 0, 255, 0, 0, 0, 255, 200, 100, 50, 10, 20, 30, 128, 128, 128};
  const std::string file = path("rgb.png");
  write_with_oiio(file, 2, 3, 3, OIIO::TypeDesc::UINT8, rgb);

  const LoadedImage loaded = shadecut::load_image(file);
  EXPECT_EQ(loaded.color_space, "srgb");
  EXPECT_FALSE(loaded.has_alpha);
  EXPECT_TRUE(loaded.mask.all());
  for (int i = 0; i < 6; ++i) {
    const double expected =
        luminance(srgb_eotf(rgb[3 * i] / 255.0), srgb_eotf(rgb[3 * i + 1] / 255.0), srgb_eotf(rgb[3 * i + 2] / 255.0));
    EXPECT_NEAR(loaded.intensity(i / 3, i % 3), expected, 1e-6) << "pixel " << i;
  }
}

TEST_F(ImageIO, UnreadableOrUnwritableFilesRaiseIoError) {
  const std::string missing = path("does_not_exist.png");
  try {
    shadecut::load_image(missing);
    ADD_FAILURE() << "no exception";
  } catch (const IoError& error) {
    EXPECT_NE(std::string(error.what()).find(missing), std::string::npos) << error.what();
  }

  std::ofstream(path("not_really.png")) << "this is not a PNG file";
  EXPECT_THROW(shadecut::load_image(path("not_really.png")), IoError);

  const std::string unwritable = path("no_such_folder") + "/out";
  const ImageF image = ImageF::Constant(2, 2, 0.5f);
  const Mask mask = Mask::Constant(2, 2, true);
  for (const std::string& file : {unwritable + ".png", unwritable + ".exr"}) {
    try {
      shadecut::save_image(file, image);
      ADD_FAILURE() << "no exception for " << file;
    } catch (const IoError& error) {
      EXPECT_NE(std::string(error.what()).find(file), std::string::npos) << error.what();
    }
  }
  EXPECT_THROW(shadecut::save_depth(unwritable + ".exr", image, mask), IoError);
  EXPECT_THROW(shadecut::save_mesh(unwritable + ".ply", image, mask), IoError);
  EXPECT_THROW(shadecut::save_mesh(unwritable + ".obj", image, mask), IoError);
}

TEST_F(ImageIO, RejectsBadShapes) {
  const ImageF image = ImageF::Constant(2, 3, 0.5f);
  const Mask wrong = Mask::Constant(3, 2, true);
  EXPECT_THROW(shadecut::save_image(path("a.png"), image, &wrong), InvalidArgument);
  EXPECT_THROW(shadecut::save_image(path("a.png"), ImageF()), InvalidArgument);
  EXPECT_THROW(shadecut::save_depth(path("a.exr"), image, wrong), InvalidArgument);
  EXPECT_THROW(shadecut::save_normals(path("a.exr"), NormalMap(2, 3), wrong), InvalidArgument);
  EXPECT_THROW(shadecut::save_mesh(path("a.ply"), image, wrong), InvalidArgument);
  EXPECT_THROW(shadecut::save_mesh(path("a.stl"), image, Mask::Constant(2, 3, true)), InvalidArgument);
}

TEST_F(ImageIO, DepthRoundTripsThroughExr) {
  ImageF depth(3, 4);
  depth << 1.5f, 2.0f, 90.0f, 1.75f, 3.25f, 4.0f, 5.0f, 6.0f, 7.0f, 8.0f, 10.0f, -12.5f;
  Mask mask = Mask::Constant(3, 4, true);
  mask(0, 2) = false;
  mask(2, 3) = false;
  shadecut::save_depth(path("depth.exr"), depth, mask);

  const LoadedImage loaded = shadecut::load_image(path("depth.exr"));
  EXPECT_TRUE(loaded.has_alpha);
  EXPECT_TRUE((loaded.mask == mask).all());
  EXPECT_TRUE((loaded.intensity == mask.select(depth, 0.0f)).all());

  // As a picture: masked min..max stretched over 16 bits.
  shadecut::save_depth(path("depth.png"), depth, mask);
  const RawImage picture = read_with_oiio(path("depth.png"));
  ASSERT_EQ(picture.spec.nchannels, 1);
  EXPECT_EQ(picture.spec.format, OIIO::TypeDesc::UINT16);
  EXPECT_EQ(picture.pixels[0 * 4 + 0], 0.0f);  // the masked minimum, 1.5
  EXPECT_EQ(picture.pixels[2 * 4 + 2], 1.0f);  // the masked maximum, 10
  EXPECT_NEAR(picture.pixels[1 * 4 + 2], (5.0 - 1.5) / (10.0 - 1.5), 0.5 / 65535);
  EXPECT_EQ(picture.pixels[0 * 4 + 2], 0.0f);  // outside the mask
}

TEST_F(ImageIO, NormalsRoundTripThroughExrAndAsColours) {
  NormalMap normals(2, 2);
  normals.xyz << 0.0f, 0.0f, 1.0f, 0.6f, 0.0f, 0.8f, 0.0f, -0.6f, 0.8f, 0.48f, 0.6f, 0.64f;
  Mask mask = Mask::Constant(2, 2, true);
  mask(1, 1) = false;

  shadecut::save_normals(path("normals.exr"), normals, mask);
  const RawImage exr = read_with_oiio(path("normals.exr"));
  ASSERT_EQ(exr.spec.nchannels, 3);
  EXPECT_EQ(exr.spec.format, OIIO::TypeDesc::FLOAT);
  for (int i = 0; i < 4; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(exr.pixels[3 * i + axis], mask.data()[i] ? normals.xyz(i, axis) : 0.0f) << i << ", " << axis;
    }
  }

  shadecut::save_normals(path("normals.png"), normals, mask);
  const RawImage png = read_with_oiio(path("normals.png"));
  ASSERT_EQ(png.spec.nchannels, 3);
  EXPECT_EQ(png.spec.format, OIIO::TypeDesc::UINT8);
  for (int i = 0; i < 4; ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      const double expected = mask.data()[i] ? std::round((normals.xyz(i, axis) + 1.0) / 2.0 * 255.0) / 255.0 : 0.0;
      EXPECT_NEAR(png.pixels[3 * i + axis], expected, 1e-6) << i << ", " << axis;
    }
  }
}

TEST_F(ImageIO, MeshesHaveOneVertexPerPixelAndFaceTheViewer) {
  ImageF depth(3, 3);
  depth << 0.0f, 1.0f, 2.0f, 0.5f, 1.5f, 2.5f, 1.0f, 2.0f, 3.25f;
  const Mask mask = Mask::Constant(3, 3, true);
  shadecut::save_mesh(path("mesh.ply"), depth, mask);
  shadecut::save_mesh(path("mesh.obj"), depth, mask);

  for (const Mesh& mesh : {parse_binary_ply(read_file(path("mesh.ply"))), parse_obj(read_file(path("mesh.obj")))}) {
    ASSERT_EQ(mesh.vertices.size(), 9u);
    ASSERT_EQ(mesh.triangles.size(), 8u);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        const auto& vertex = mesh.vertices[std::size_t(r) * 3 + c];
        EXPECT_EQ(vertex[0], float(c));
        EXPECT_EQ(vertex[1], float(-r));
        EXPECT_EQ(vertex[2], depth(r, c));
      }
    }
    for (const auto& triangle : mesh.triangles) EXPECT_GT(winding_normal_z(mesh, triangle), 0.0);
  }

  // Without its centre a 3 x 3 mask has no complete 2 x 2 block: vertices but no triangles.
  Mask ring = mask;
  ring(1, 1) = false;
  shadecut::save_mesh(path("ring.ply"), depth, ring);
  const Mesh ring_mesh = parse_binary_ply(read_file(path("ring.ply")));
  EXPECT_EQ(ring_mesh.vertices.size(), 8u);
  EXPECT_TRUE(ring_mesh.triangles.empty());

  // Every second pixel: the corners, still at their pixels' positions and depths, joined by 2 triangles.
  shadecut::save_mesh(path("coarse.ply"), depth, mask, 2);
  const Mesh coarse = parse_binary_ply(read_file(path("coarse.ply")));
  ASSERT_EQ(coarse.vertices.size(), 4u);
  EXPECT_EQ(coarse.triangles.size(), 2u);
  EXPECT_EQ(coarse.vertices[3][0], 2.0f);
  EXPECT_EQ(coarse.vertices[3][1], -2.0f);
  EXPECT_EQ(coarse.vertices[3][2], depth(2, 2));
  EXPECT_THROW(shadecut::save_mesh(path("none.ply"), depth, mask, 0), InvalidArgument);
}

std::string contents(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

// The files of a set appear together at commit(), or not at all; what stood at their names stays
// until then, and no temporary file outlives the set.
TEST_F(ImageIO, StagedFilesReplaceTheOldOnesTogetherOrNotAtAll) {
  std::ofstream(path("a.txt")) << "old a";
  {
    shadecut::StagedFiles staged;
    const std::string a = staged.stage(path("a.txt")), b = staged.stage(path("b.ply"));
    EXPECT_EQ(fs::path(b).extension(), ".ply");  // writers that choose the format by it still find it
    EXPECT_EQ(fs::path(b).parent_path(), fs::path(path("b.ply")).parent_path());
    std::ofstream(a) << "new a";
    std::ofstream(b) << "new b";
  }  // dropped without commit(): a failure part-way
  EXPECT_EQ(contents(path("a.txt")), "old a");
  EXPECT_EQ(std::distance(fs::directory_iterator(path("")), fs::directory_iterator()), 1);

  shadecut::StagedFiles staged;
  std::ofstream(staged.stage(path("a.txt"))) << "new a";
  std::ofstream(staged.stage(path("b.ply"))) << "new b";
  staged.commit();
  EXPECT_EQ(contents(path("a.txt")), "new a");
  EXPECT_EQ(contents(path("b.ply")), "new b");
  EXPECT_EQ(std::distance(fs::directory_iterator(path("")), fs::directory_iterator()), 2);

  fs::create_directory(path("folder.exr"));
  EXPECT_THROW(staged.stage(path("folder.exr")), IoError);  // a rename cannot replace a folder
  EXPECT_THROW(shadecut::write_atomically(path("a.txt"), [](const std::string&) { throw IoError("disk full"); }),
               IoError);
  EXPECT_EQ(contents(path("a.txt")), "new a");
}

}  // namespace
