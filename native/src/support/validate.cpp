#include <shadecut/support/validate.hpp>

#include <shadecut/support/errors.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdio>

namespace shadecut {

namespace {

// Eigen's allFinite() tests value by value (23 ms at 4 MP, called at every stage's entry); a float is
// finite unless its exponent bits are all ones, which a loop without branches tests 8 at a time.
bool all_finite(const ImageF& image) {
  constexpr std::uint32_t kExponent = 0x7f800000u;
  const float* values = image.data();
  std::uint32_t infinite = 0;
  for (Eigen::Index i = 0; i < image.size(); ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, values + i, sizeof bits);
    infinite |= std::uint32_t((bits & kExponent) == kExponent);
  }
  return infinite == 0;
}

}  // namespace

void check_image(const ImageF& image, const std::string& what) {
  if (image.rows() < 2 || image.cols() < 2)
    throw InvalidArgument("shadecut: the " + what + " is " + std::to_string(image.rows()) + " x " +
                          std::to_string(image.cols()) + " pixels; at least 2 x 2 are needed");
  if (!all_finite(image)) throw InvalidArgument("shadecut: the " + what + " has NaN or infinite pixels");
}

void check_mask(const Mask& mask, const ImageF& image) {
  if (mask.rows() != image.rows() || mask.cols() != image.cols())
    throw InvalidArgument("shadecut: the mask is " + std::to_string(mask.rows()) + " x " + std::to_string(mask.cols()) +
                          " but the image is " + std::to_string(image.rows()) + " x " + std::to_string(image.cols()));
  if (!mask.any()) throw InvalidArgument("shadecut: the mask selects no pixel");
}

void check_mask_fits(const Mask& mask, const NormalMap& normals) {
  if (mask.rows() != normals.rows || mask.cols() != normals.cols)
    throw InvalidArgument("shadecut: the mask is " + std::to_string(mask.rows()) + " x " + std::to_string(mask.cols()) +
                          " but the normal map is " + std::to_string(normals.rows) + " x " + std::to_string(normals.cols));
  for (Eigen::Index i = 0; i < normals.size(); ++i)
    if (mask.data()[i] && !normals.xyz.row(i).allFinite())
      throw InvalidArgument("shadecut: the normal map has NaN or infinite values inside the mask, at pixel (" +
                            std::to_string(i / normals.cols) + ", " + std::to_string(i % normals.cols) + ")");
}

void check_normals(const NormalMap& normals, int rows, int cols) {
  if (normals.rows != rows || normals.cols != cols || normals.xyz.rows() != normals.size())
    throw InvalidArgument("shadecut: the normal map is " + std::to_string(normals.rows) + " x " +
                          std::to_string(normals.cols) + " but " + std::to_string(rows) + " x " + std::to_string(cols) +
                          " was expected");
}

std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

std::string photograph_name(std::size_t index) { return "photograph " + std::to_string(index + 1); }

void check_same_size(const ImageF& photograph, std::size_t index, const ImageF& first) {
  if (photograph.rows() != first.rows() || photograph.cols() != first.cols())
    throw InvalidArgument("shadecut: " + photograph_name(index) + " is " + std::to_string(photograph.cols()) +
                          " x " + std::to_string(photograph.rows()) + " pixels but the first is " +
                          std::to_string(first.cols()) + " x " + std::to_string(first.rows()) +
                          "; several photographs must be of one view, all of one size");
}

void check_albedo(double albedo) {
  if (!(albedo > 0.0) || !std::isfinite(albedo))
    throw InvalidArgument("shadecut: the albedo must be finite and > 0; got " + number_text(albedo));
}

void check_iterations(int iterations) {
  if (iterations < 1) throw InvalidArgument("shadecut: iterations must be at least 1 (got " + std::to_string(iterations) + ")");
}

void check_iterative_input(const ImageF& image, const Mask& mask, double albedo, int iterations) {
  check_image(image);
  check_mask(mask, image);
  check_albedo(albedo);
  check_iterations(iterations);
}

}  // namespace shadecut
