// shadecut: reconstruct one image file into depth, normal and mesh files, without Blender.
#include "cli_arguments.hpp"

#include <shadecut/io/atomic_files.hpp>
#include <shadecut/io/image_io.hpp>
#include <shadecut/pipeline/flip_surface.hpp>
#include <shadecut/pipeline/reconstruct.hpp>
#include <shadecut/support/errors.hpp>

#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

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
                                           "mesh.ply", "albedo.exr", "albedo.png", "residual.exr"};

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
    save_staged(7, [&](const std::string& path) { shadecut::save_image(path, result.residual, &result.mask); });
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

// An output named like the input (albedo.png read from the output folder) would replace the
// photograph itself: refused before anything is read or written.
void check_input_kept(const std::filesystem::path& image, const std::filesystem::path& out) {
  std::error_code unknown;
  const std::filesystem::path input = std::filesystem::weakly_canonical(image, unknown);
  if (unknown) return;  // load_image says what is wrong with the input
  for (const std::string& name : kOutputNames) {
    const std::filesystem::path output = std::filesystem::weakly_canonical(out / name, unknown);
    if (!unknown && output == input)
      fail("the output " + name + " would replace the input image '" + image.string() + "'; choose another --out");
  }
}

// The progress on standard error: one line rewritten on a terminal; in a log, a line per stage
// and per tenth of the call, not one line of carriage returns.
shadecut::ProgressCallback progress_reporter(bool quiet) {
  const bool terminal = ::isatty(STDERR_FILENO) == 1;
  return [quiet, terminal, last_stage = std::string(), last_tenth = -1](double fraction, const std::string& stage) mutable {
    if (quiet) return interrupted == 0;
    if (terminal) {
      std::fprintf(stderr, "\r%-12s %5.1f%%", stage.c_str(), 100.0 * fraction);
      progress_line_open = fraction < 1.0;
      if (!progress_line_open) std::fprintf(stderr, "\n");
    } else if (stage != last_stage || int(fraction * 10.0) != last_tenth) {
      std::fprintf(stderr, "%-12s %5.1f%%\n", stage.c_str(), 100.0 * fraction);
      last_stage = stage;
      last_tenth = int(fraction * 10.0);
    }
    // Reports even when quiet: the answer is what stops the reconstruction on Ctrl+C.
    return interrupted == 0;
  };
}

// "N times", the ratio of two residuals, for the orientation line.
std::string ratio_text(double inverted, double kept) {
  if (!(kept > 0.0)) return inverted > 0.0 ? "infinitely" : "as";
  std::ostringstream text;
  text.precision(3);
  text << inverted / kept << " times";
  return text.str();
}

// `value` to `decimals` places, a value that rounds to zero without a sign: what the summary prints, so
// that a light from the side named "top" reads 0,0.7071,0.7071, not 4.32978e-17,0.707107,0.707107.
double rounded(double value, int decimals) {
  const double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale + 0.0;
}

// A light's direction as the summary prints it, "0,0.7071,0.7071".
std::string light_text(const Eigen::Vector3d& light) {
  std::ostringstream text;
  for (int i = 0; i < 3; ++i) text << (i > 0 ? "," : "") << rounded(light[i], 4);
  return text.str();
}

// How the light was estimated, " (estimated by zheng_chellappa)", or "" when given; with several
// photographs, every light found.
std::string estimated_text(const shadecut::cli::Arguments& arguments, const shadecut::Reconstruction& result) {
  if (!result.stats.light_estimated) return "";
  if (result.stats.photographs == 1)
    return " (estimated by " + shadecut::to_string(shadecut::light_method_used(arguments.options)) + ")";
  std::ostringstream text;
  text << " (estimated from the photographs at " << arguments.options.light_slant << " degrees from the viewer, their turn "
       << "about it within " << rounded(result.stats.light_uncertainty, 1) << " degrees; the others ";
  for (std::size_t k = 1; k < result.lights.size(); ++k)
    text << (k > 1 ? "; " : "") << light_text(result.lights[k]);
  if (result.stats.lights_turned_by_outline)
    text << "; turned by half a circle from --first-light-tilt's side: the object's outline showed it inside out";
  text << ")";
  return text.str();
}

// How the pixels lit in exactly two photographs got their normals: with only two in all, the point of
// the circle the pair leaves nearest the photographs read alone; with more, the graph cut's choice
// between the pair's two normals.
std::string pair_text(const shadecut::ReconstructStats& stats) {
  if (stats.photographs == 2) return " taken on the circle the two leave, nearest the two read alone";
  return " chosen from two by the graph cut (" + std::to_string(stats.cycles) + " cycles)";
}

// Where one of four photographs missed the others' fit, the graph cut chose which to leave out.
std::string four_fits_text(const shadecut::ReconstructStats& stats) {
  if (stats.four_fit_pixels == 0) return "";
  return " (" + std::to_string(stats.four_fit_pixels) + " of them from three of four, the graph cut choosing which to leave out)";
}

// What was done, with the time it took. One photograph: the method, the albedo and the graph cut's
// work; several: how the pixels' normals came, by how many photographs were usable there.
std::string work_text(const shadecut::cli::Arguments& arguments, const shadecut::Reconstruction& result) {
  const shadecut::ReconstructStats& stats = result.stats;
  std::ostringstream text;
  if (stats.photographs == 1) {
    text << "method " << shadecut::to_string(arguments.options.method) << ", albedo " << rounded(result.albedo, 3) << ", "
         << stats.cycles << " cycles, " << stats.moves << " moves";
  } else {
    const std::int64_t fewer = stats.single_pixels + stats.dark_pixels;
    text << "photometric stereo of " << stats.photographs << " photographs, " << (arguments.albedo ? "albedo " : "median albedo ")
         << rounded(result.albedo, 3) << ": " << result.mask.count() - stats.pair_pixels - fewer << " pixels fitted from three or more"
         << four_fits_text(stats) << ", " << stats.pair_pixels << pair_text(stats) << ", " << fewer
         << " lit in fewer filled from their neighbours";
  }
  const double seconds = stats.seconds.at("total");
  text << ", " << rounded(seconds, seconds < 1.0 ? 3 : 2) << " s";
  return text.str();
}

// The orientation line. Several photographs fix it themselves: there is no inversion to weigh.
std::string orientation_text(const shadecut::cli::Arguments& arguments, const shadecut::ReconstructStats& stats) {
  if (stats.photographs > 1) return arguments.flip ? "orientation flipped\n" : "";
  return "orientation " + std::string(arguments.flip ? "flipped; " : "") +
         (stats.orientation_ambiguous
              ? "ambiguous: its inversion explains the image about as well (the outline, or a relief's rule, chose); --flip gives it"
              : "read from the image: its inversion renders " + ratio_text(stats.inverted_residual, stats.orientation_residual) +
                    " as far from it") +
         "\n";
}

void print_summary(const shadecut::cli::Arguments& arguments, const shadecut::Reconstruction& result) {
  const shadecut::ReconstructStats& stats = result.stats;
  std::cout << "light " << light_text(result.light) << estimated_text(arguments, result)
            << (stats.photographs > 1 ? " and " + std::to_string(stats.photographs - 1) + " more" : "") << "\n"
            << work_text(arguments, result) << "\n"
            << orientation_text(arguments, stats);
  if (!stats.albedo_message.empty()) std::cout << "albedo: " << stats.albedo_message << "\n";
  if (stats.cut_out == shadecut::CutOutOutcome::Found)
    std::cout << stats.cut_out_message << "\n";
  else if (stats.cut_out != shadecut::CutOutOutcome::NotTried)
    std::cout << "cut-out: " << stats.cut_out_message
              << "; so the whole image was reconstructed (give the image an alpha channel as its mask, or --scene relief "
                 "for a surface filling the frame)\n";
  std::cout << "wrote " << output_names() << " to " << arguments.out_dir << "\n";
}

// The photographs of the call, each with its light (none: estimated), read from their files.
std::vector<shadecut::Observation> read_photographs(const shadecut::cli::Arguments& arguments, bool& colour, bool& has_alpha,
                                                    shadecut::Mask& mask) {
  std::vector<shadecut::Observation> photographs;
  for (std::size_t k = 0; k < arguments.image_paths.size(); ++k) {
    shadecut::LoadedImage input =
        shadecut::load_image(arguments.image_paths[k], shadecut::parse_color_space(arguments.color_space), arguments.max_pixels);
    std::optional<Eigen::Vector3d> light;
    if (k < arguments.lights.size()) light = arguments.lights[k];
    colour = input.colour.channel[0].size() > 0;
    if (k == 0) {
      has_alpha = input.has_alpha;
      mask = input.mask;
    }
    photographs.push_back(colour ? shadecut::colour_observation(std::move(input.colour), light)
                                 : shadecut::grey_observation(std::move(input.intensity), light));
  }
  return photographs;
}

int run(const shadecut::cli::Arguments& arguments) {
  check_output_folder(arguments.out_dir);
  for (const std::string& image : arguments.image_paths) check_input_kept(image, arguments.out_dir);
  catch_interruptions();
  bool colour = false, has_alpha = false;
  shadecut::Mask alpha;
  const std::vector<shadecut::Observation> photographs = read_photographs(arguments, colour, has_alpha, alpha);
  shadecut::ReconstructOptions options = arguments.options;
  options.progress = progress_reporter(arguments.quiet);
  // Without alpha no mask is given: reconstruct() then cuts an object out of its background.
  shadecut::Reconstruction result = shadecut::reconstruct(photographs, has_alpha ? &alpha : nullptr, arguments.albedo, options);
  if (arguments.flip) shadecut::flip_surface(result.depth, result.normals, result.mask);
  const std::filesystem::path out(arguments.out_dir);
  const std::vector<std::filesystem::path> made = missing_folders(out);
  try {
    write_outputs(out, result, colour);
  } catch (...) {
    remove_if_empty(made);
    throw;
  }
  print_summary(arguments, result);
  if (!std::cout.flush()) stop("the files were written, but the summary could not be printed (standard output failed)", 2);
  return 0;
}

// A path the system refused, with the path and the system's reason.
std::string path_message(const std::filesystem::filesystem_error& error) {
  return "cannot use '" + error.path1().string() + "': " + error.code().message();
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const shadecut::cli::Arguments arguments = shadecut::cli::parse_arguments({argv + 1, argv + argc});
    if (arguments.help) {
      std::cout << shadecut::cli::usage();
      return std::cout.flush() ? 0 : 2;
    }
    return run(arguments);
  } catch (const shadecut::cli::UsageError& e) {
    fail(e.what());
  } catch (const Interrupted& e) {
    stop(e.what(), 128 + interrupted);
  } catch (const shadecut::Cancelled&) {
    stop("interrupted: nothing written", 128 + interrupted);
  } catch (const shadecut::InvalidArgument& e) {
    stop(e.what(), 2);
  } catch (const shadecut::IoError& e) {
    stop(e.what(), 2);
  } catch (const std::filesystem::filesystem_error& e) {
    stop(path_message(e), 2);
  } catch (const std::bad_alloc&) {
    stop("not enough memory for this image; a smaller one, or a lower --max-pixels, fails early", 2);
  }
}
