// shadecut: reconstruct one image file into depth, normal and mesh files, without Blender.
#include <shadecut/support/errors.hpp>
#include <shadecut/estimate/estimate_light.hpp>
#include <shadecut/io/atomic_files.hpp>
#include <shadecut/io/image_io.hpp>
#include <shadecut/integrate/integrate.hpp>
#include <shadecut/pipeline/flip_surface.hpp>
#include <shadecut/pipeline/reconstruct.hpp>

#include <csignal>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>
#include <new>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

// Every default shown comes from ReconstructOptions, the one place defaults are held.
std::string usage() {
  const shadecut::ReconstructOptions defaults;
  auto choices = [](const std::vector<std::string>& names) {
    std::string text;
    for (std::size_t i = 0; i < names.size(); ++i) text += (i ? ", " : "") + names[i];
    return text;
  };
  auto estimator_for = [&defaults](shadecut::SceneKind scene) {
    shadecut::ReconstructOptions options = defaults;
    options.scene = scene;
    return shadecut::to_string(shadecut::light_method_used(options));
  };
  std::ostringstream text;
  text << R"(usage: shadecut IMAGE [--light X,Y,Z] [options]

Reconstructs a surface from one shaded image (shape from shading using graph cuts) and writes
depth.exr, depth.png, normals.exr, normals.png, mesh.ply and the albedo per pixel, albedo.exr and
albedo.png (in colour for a colour image), to the output folder.

Conventions (docs/conventions.md): x right, y up, z toward the viewer; the light points from the
surface toward the light, e.g. 1,0,1 = from the right-front. The image's alpha channel, if any, is
the mask.

options:
  --light X,Y,Z        light direction in the camera frame (Z > 0); without it the light (and,
                       unless --albedo is given, the albedo) is estimated from the image
  --light-method NAME  estimator used without --light: )"
       << choices(shadecut::light_method_names()) << "\n                       (default " << estimator_for(shadecut::SceneKind::Object)
       << " for an object, " << estimator_for(shadecut::SceneKind::Relief) << R"( for a relief)
  --scene NAME         )" << choices(shadecut::scene_kind_names()) << " (default " << shadecut::to_string(defaults.scene) << R"(): an object seen
                       whole, or a relief filling the frame (a wall, a coin) that sits flat, no ramp
  --no-cut-out         an object without alpha: reconstruct every pixel, not the object cut out of
                       its background (default: cut out when a plain background is found)
  --seamless           with --scene relief: depth and normals that tile (a seamless texture)
  --out DIR            output folder (default shadecut_out)
  --method NAME        )" << choices(shadecut::method_names()) << " (default " << shadecut::to_string(defaults.method) << R"()
  --albedo A           albedo (default: read from the image by --albedo-method)
  --albedo-method NAME )" << choices(shadecut::albedo_method_names()) << " (default " << shadecut::to_string(defaults.albedo_method) << R"(): one
                       albedo, or retinex: the paint separated from the shading, one per pixel
  --labels K           tilt labels (default )" << defaults.labels << R"()
  --data-weight L      data weight lambda of graphcut (default )" << defaults.data_weight << R"()
  --integrator NAME    )" << choices(shadecut::integrator_names()) << " (default " << shadecut::to_string(defaults.integrator) << R"()
  --color-space NAME   auto (default), linear or srgb: how the file's values relate to intensity
  --max-pixels N       refuse an image whose header declares more pixels (default )" << shadecut::kDefaultMaxPixels << R"()
  --tolerance T        stop when a cycle lowers the energy by at most T times it (default: the
                       method's own)
  --band B             coarse to fine: keep the labels within B steps of the half-resolution
                       solution's (default )" << defaults.coarse_to_fine_band << R"(); -1 = exact alpha-expansion over every label
  --band-radius R      coarse to fine: only pixels within R pixels of a jump of the half-resolution
                       labels keep the band (default )" << defaults.coarse_to_fine_radius << R"(); -1 = every pixel
  --contour-weight W   graph cuts, objects: pull of the outline toward outward normals (default )" << defaults.contour_weight << R"()
  --viscosity-weight W graphcut: pull of a second labelling toward the viscosity solution, kept if
                       it explains the image better (default )" << defaults.viscosity_weight << R"(); 0 with
                       --contour-weight 0 = the paper's energy alone
  --fit-shading        graphcut: after integration, fit the depth to the image: more accurate on
                       the training surfaces, about 0.7 s more at a megapixel (default )" << (defaults.fit_shading ? "on" : "off") << R"()
  --no-fit-shading     the integrated depth as it is, without that fit
  --fit-smoothness S   how smooth that fit's correction of the depth is (default )" << defaults.fit_smoothness << R"()
  --flip               write the surface inverted (depth z -> -z, normals (-nx, -ny, nz)): the
                       other answer when the light is near the viewer and the output says the
                       orientation is ambiguous
  --threads N          threads, 0 = all cores (default )" << defaults.threads << R"()
  --quiet              no progress
)";
  return text.str();
}

// Ctrl+C (or a termination request) asks the run to stop where it can end cleanly: the progress
// callback cancels the reconstruction, and the output files are written all or none.
// The signal's number once one came, else 0; a run it stops exits with 128 + that number, as the
// shell reports a process the signal ended.
volatile std::sig_atomic_t interrupted = 0;

void note_interruption(int signal_number) { interrupted = signal_number; }

// A run stopped by Ctrl+C; what it says is what was left as it was.
struct Interrupted : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void catch_interruptions() {
  struct sigaction action {};
  action.sa_handler = note_interruption;
  sigemptyset(&action.sa_mask);
  // A second Ctrl+C ends the process at once, for a user who will not wait for a clean stop.
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// Whether a progress line without its newline is on standard error: a message must start below it.
bool progress_line_open = false;

[[noreturn]] void stop(const std::string& message, int exit_code) {
  // Library errors already name their origin.
  const bool prefixed = message.rfind("shadecut:", 0) == 0;
  std::cerr << (progress_line_open ? "\n" : "") << (prefixed ? "" : "shadecut: ") << message << "\n";
  std::exit(exit_code);
}

[[noreturn]] void fail(const std::string& message) { stop(message + "\n(run 'shadecut --help' for usage)", 2); }

// The whole of `text` as a finite number; nothing for "1x", "", "nan" or "1e999".
std::optional<double> finite_number(const std::string& text) {
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  return std::nullopt;
}

Eigen::Vector3d parse_light(const std::string& text) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const std::optional<double> value = finite_number(item);
    if (!value) fail("--light takes three numbers X,Y,Z; got '" + text + "'");
    values.push_back(*value);
  }
  if (values.size() != 3) fail("--light takes three numbers X,Y,Z; got '" + text + "'");
  return {values[0], values[1], values[2]};
}

double parse_number(const std::string& flag, const std::string& text) {
  const std::optional<double> value = finite_number(text);
  if (!value) fail(flag + " takes a finite number; got '" + text + "'");
  return *value;
}

// The whole of `text` as a whole number in [low, high]; the message gives the range.
std::int64_t parse_whole_number(const std::string& flag, const std::string& text, std::int64_t low, std::int64_t high) {
  try {
    std::size_t used = 0;
    const long long value = std::stoll(text, &used);
    if (used == text.size() && value >= low && value <= high) return value;
  } catch (const std::exception&) {
  }
  fail(flag + " takes a whole number from " + std::to_string(low) + " to " + std::to_string(high) + "; got '" + text + "'");
}

int parse_integer(const std::string& flag, const std::string& text) {
  return int(parse_whole_number(flag, text, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()));
}

// Fails now, not after the reconstruction, when the output folder cannot be made or written; makes
// nothing, so that a failed run leaves nothing behind.
void check_output_folder(const std::filesystem::path& folder) {
  if (folder.empty()) fail("--out is empty: give a folder");
  std::filesystem::path existing = std::filesystem::absolute(folder);
  while (!std::filesystem::exists(existing) && existing.has_parent_path() && existing != existing.parent_path())
    existing = existing.parent_path();
  if (std::filesystem::exists(existing) && !std::filesystem::is_directory(existing))
    fail("--out: '" + existing.string() + "' is a file, not a folder");
  if (::access(existing.c_str(), W_OK | X_OK) != 0) fail("--out: cannot write into '" + existing.string() + "'");
}

const std::vector<std::string> kOutputNames{"depth.exr", "depth.png", "normals.exr", "normals.png",
                                           "mesh.ply", "albedo.exr", "albedo.png"};

std::string output_names() {
  std::string text;
  for (const std::string& name : kOutputNames) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// The folders create_directories(folder) would make, deepest first: what a failed run removes again.
std::vector<std::filesystem::path> missing_folders(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> missing;
  std::error_code status;
  for (std::filesystem::path path = std::filesystem::absolute(folder).lexically_normal();
       !path.empty() && !std::filesystem::exists(path, status) && path != path.parent_path(); path = path.parent_path())
    missing.push_back(path);
  return missing;
}

void remove_if_empty(const std::vector<std::filesystem::path>& folders) {
  std::error_code ignored;  // a folder someone else filled meanwhile stays
  for (const std::filesystem::path& folder : folders) std::filesystem::remove(folder, ignored);
}

// Writes the files of kOutputNames all or none: each under a temporary name, then all renamed, so
// that a full disk, a read-only file or Ctrl+C part-way leaves the folder's earlier results whole.
void write_outputs(const std::filesystem::path& out, const shadecut::Reconstruction& result, bool colour) {
  const std::string none_written = "wrote none of " + output_names() + " to " + out.string();
  shadecut::StagedFiles staged;
  try {
    std::filesystem::create_directories(out);
    std::vector<std::string> paths;
    for (const std::string& name : kOutputNames) paths.push_back(staged.stage((out / name).string()));
    auto save_staged = [&](std::size_t index, auto&& save) {
      if (interrupted) throw Interrupted("interrupted: " + none_written + "; the files there are unchanged");
      save(paths[index]);
    };
    save_staged(0, [&](const std::string& path) { shadecut::save_depth(path, result.depth, result.mask); });
    save_staged(1, [&](const std::string& path) { shadecut::save_depth(path, result.depth, result.mask); });
    save_staged(2, [&](const std::string& path) { shadecut::save_normals(path, result.normals, result.mask); });
    save_staged(3, [&](const std::string& path) { shadecut::save_normals(path, result.normals, result.mask); });
    save_staged(4, [&](const std::string& path) { shadecut::save_mesh(path, result.depth, result.mask); });
    for (std::size_t index : {5, 6}) {
      save_staged(index, [&](const std::string& path) {
        if (colour) shadecut::save_image(path, result.albedo_colour, &result.mask);
        else shadecut::save_image(path, result.albedo_map, &result.mask);
      });
    }
    if (interrupted) throw Interrupted("interrupted: " + none_written + "; the files there are unchanged");
  } catch (const Interrupted&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw shadecut::IoError(none_written + ": not enough memory; the files there are unchanged");
  } catch (const std::exception& error) {
    throw shadecut::IoError(none_written + ": " + error.what() + "; the files there are unchanged");
  }
  staged.commit();
}

}  // namespace

// "N times", the ratio of two residuals, for the orientation line.
std::string ratio_text(double inverted, double kept) {
  if (!(kept > 0.0)) return inverted > 0.0 ? "infinitely" : "as";
  std::ostringstream text;
  text.precision(3);
  text << inverted / kept << " times";
  return text.str();
}

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string image_path, out_dir = "shadecut_out", color_space = "auto";
  std::optional<Eigen::Vector3d> light;
  std::optional<double> albedo;
  std::int64_t max_pixels = shadecut::kDefaultMaxPixels;
  bool quiet = false, flip = false;
  shadecut::ReconstructOptions options;
  try {
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& arg = args[i];
      auto value = [&]() -> const std::string& {
        if (i + 1 >= args.size()) fail(arg + " needs a value");
        return args[++i];
      };
      if (arg == "-h" || arg == "--help") {
        std::cout << usage();
        return 0;
      } else if (arg == "--light") {
        light = parse_light(value());
      } else if (arg == "--light-method") {
        options.light_method = shadecut::parse_light_method(value());
      } else if (arg == "--scene") {
        options.scene = shadecut::parse_scene_kind(value());
      } else if (arg == "--out") {
        out_dir = value();
      } else if (arg == "--method") {
        options.method = shadecut::parse_method(value());
      } else if (arg == "--albedo") {
        albedo = parse_number(arg, value());
      } else if (arg == "--albedo-method") {
        options.albedo_method = shadecut::parse_albedo_method(value());
      } else if (arg == "--labels") {
        options.labels = parse_integer(arg, value());
      } else if (arg == "--data-weight") {
        options.data_weight = parse_number(arg, value());
      } else if (arg == "--integrator") {
        options.integrator = shadecut::parse_integrator(value());
      } else if (arg == "--max-pixels") {
        max_pixels = parse_whole_number(arg, value(), 1, std::numeric_limits<std::int64_t>::max());
      } else if (arg == "--color-space") {
        color_space = value();
      } else if (arg == "--tolerance") {
        options.tolerance = parse_number(arg, value());
      } else if (arg == "--band") {
        options.coarse_to_fine_band = parse_integer(arg, value());
      } else if (arg == "--band-radius") {
        options.coarse_to_fine_radius = parse_integer(arg, value());
      } else if (arg == "--threads") {
        options.threads = parse_integer(arg, value());
      } else if (arg == "--quiet") {
        quiet = true;
      } else if (arg == "--no-cut-out") {
        options.cut_out = false;
      } else if (arg == "--seamless") {
        options.seamless = true;
      } else if (arg == "--contour-weight") {
        options.contour_weight = parse_number(arg, value());
      } else if (arg == "--viscosity-weight") {
        options.viscosity_weight = parse_number(arg, value());
      } else if (arg == "--fit-shading" || arg == "--no-fit-shading") {
        options.fit_shading = arg == "--fit-shading";
      } else if (arg == "--flip") {
        flip = true;
      } else if (arg == "--fit-smoothness") {
        options.fit_smoothness = parse_number(arg, value());
      } else if (!arg.empty() && arg[0] == '-') {
        fail("unknown option " + arg);
      } else if (image_path.empty()) {
        image_path = arg;
      } else {
        fail("more than one image given: '" + image_path + "' and '" + arg + "'");
      }
    }
    if (image_path.empty()) fail("no image given");

    check_output_folder(out_dir);
    catch_interruptions();
    const shadecut::LoadedImage input = shadecut::load_image(image_path, shadecut::parse_color_space(color_space), max_pixels);
    // Reports even when quiet: the answer is what stops the reconstruction on Ctrl+C.
    options.progress = [quiet](double fraction, const std::string& stage) {
      if (!quiet) {
        std::fprintf(stderr, "\r%-12s %5.1f%%", stage.c_str(), 100.0 * fraction);
        progress_line_open = fraction < 1.0;
        if (!progress_line_open) std::fprintf(stderr, "\n");
      }
      return interrupted == 0;
    };
    const bool colour = input.colour.channel[0].size() > 0;
    // Without alpha no mask is given: reconstruct() then cuts an object out of its background.
    const shadecut::Mask* mask = input.has_alpha ? &input.mask : nullptr;
    shadecut::Reconstruction result =
        colour ? shadecut::reconstruct(input.colour, light, mask, albedo, options)
               : shadecut::reconstruct(input.intensity, light, mask, albedo, options);
    if (flip) shadecut::flip_surface(result.depth, result.normals, result.mask);

    const std::filesystem::path out(out_dir);
    const std::vector<std::filesystem::path> made = missing_folders(out);
    try {
      write_outputs(out, result, colour);
    } catch (...) {
      remove_if_empty(made);
      throw;
    }

    const Eigen::Vector3d& used = result.light;
    std::cout << "light " << used.x() << "," << used.y() << "," << used.z()
              << (result.stats.light_estimated ? " (estimated by " + shadecut::to_string(shadecut::light_method_used(options)) + ")" : "")
              << "\nmethod " << shadecut::to_string(options.method) << ", albedo " << result.albedo << ", "
              << result.stats.cycles << " cycles, " << result.stats.moves << " moves, "
              << result.stats.seconds.at("total") << " s\n"
              << "orientation " << (flip ? "flipped; " : "")
              << (result.stats.orientation_ambiguous
                      ? "ambiguous: its inversion explains the image about as well (the outline, or a relief's rule, chose); --flip gives it"
                      : "read from the image: its inversion renders " +
                            ratio_text(result.stats.inverted_residual, result.stats.orientation_residual) + " as far from it")
              << "\n";
    if (result.stats.cut_out == shadecut::CutOutOutcome::Found)
      std::cout << result.stats.cut_out_message << "\n";
    else if (result.stats.cut_out != shadecut::CutOutOutcome::NotTried)
      std::cout << "cut-out: " << result.stats.cut_out_message
                << "; so the whole image was reconstructed (give the image an alpha channel as its mask, or --scene relief "
                   "for a surface filling the frame)\n";
    std::cout << "wrote " << output_names() << " to " << out.string() << "\n";
    return 0;
  } catch (const Interrupted& e) {
    stop(e.what(), 128 + interrupted);
  } catch (const shadecut::Cancelled&) {
    stop("interrupted: nothing written", 128 + interrupted);
  } catch (const shadecut::InvalidArgument& e) {
    fail(e.what());
  } catch (const shadecut::IoError& e) {
    fail(e.what());
  } catch (const std::filesystem::filesystem_error& e) {
    fail(e.what());
  } catch (const std::bad_alloc&) {
    fail("not enough memory for this image; a smaller one, or a lower --max-pixels, fails early");
  }
}
