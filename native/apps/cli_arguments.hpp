// The command line's arguments: the tool's own (the image, the light, the output) and every option of
// the option table as a flag, parsed and explained from that one table.
#pragma once

#include <shadecut/pipeline/reconstruct_options.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace shadecut::cli {

/// A command line that cannot run as written; its message says why (exit code 2, with a pointer to --help).
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Arguments {
  /// One photograph, or several of one view under different lights (each with its --light, in order).
  std::vector<std::string> image_paths;
  std::string out_dir = "shadecut_out";
  std::string color_space = "auto";
  std::vector<Eigen::Vector3d> lights;  ///< --light, once per photograph; none = estimated (one photograph)
  std::optional<double> albedo;
  std::int64_t max_pixels = 0;  ///< 0 until parsed: then the library's kDefaultMaxPixels or --max-pixels
  bool quiet = false;
  bool flip = false;
  bool help = false;
  ReconstructOptions options;
};

/// The arguments after the program's name; throws UsageError (and InvalidArgument for a bad option value).
Arguments parse_arguments(const std::vector<std::string>& args);

/// --help: the tool's flags, then every option of the table by stage, with its default and range.
std::string usage();

}  // namespace shadecut::cli
