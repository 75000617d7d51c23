#include "cli_arguments.hpp"

#include <shadecut/io/image_io.hpp>
#include <shadecut/pipeline/option_table.hpp>
#include <shadecut/support/errors.hpp>
#include <shadecut/support/light.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <sstream>
#include <utility>
#include <variant>

namespace shadecut::cli {

namespace {

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

// Three numbers X,Y,Z, or the side of the image the light comes from ("top").
Eigen::Vector3d parse_light(const std::string& text) {
  const std::vector<std::string>& sides = light_side_names();
  if (std::find(sides.begin(), sides.end(), text) != sides.end()) return light_from_side(text);
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    const std::optional<double> value = finite_number(item);
    if (!value) throw UsageError("--light takes three numbers X,Y,Z or a side such as top; got '" + text + "'");
    values.push_back(*value);
  }
  if (values.size() != 3) throw UsageError("--light takes three numbers X,Y,Z or a side such as top; got '" + text + "'");
  return {values[0], values[1], values[2]};
}

std::int64_t parse_max_pixels(const std::string& text) {
  try {
    std::size_t used = 0;
    const long long value = std::stoll(text, &used);
    if (used == text.size() && value >= 1) return value;
  } catch (const std::exception&) {
  }
  throw UsageError("--max-pixels takes a whole number from 1 to " + std::to_string(std::numeric_limits<std::int64_t>::max()) +
                   "; got '" + text + "'");
}

// "--coarse-to-fine-band" for coarse_to_fine_band.
std::string flag_of(const std::string& name) {
  std::string flag = "--" + name;
  for (char& c : flag)
    if (c == '_') c = '-';
  return flag;
}

bool is_flag_field(const OptionField& field) { return option_kind(field) == OptionKind::Flag; }

// The field a flag names and the value a flag alone gives (--seamless, --no-cut-out), if any.
const OptionField* field_of_flag(const std::string& flag, std::optional<bool>& flag_value) {
  for (const OptionField& field : option_fields()) {
    const std::string name = flag_of(field.name);
    if (is_flag_field(field) && (flag == name || flag == "--no-" + name.substr(2))) {
      flag_value = flag == name;
      return &field;
    }
    if (flag == name) return &field;
    for (const std::string& other : field.flags)
      if (flag == other) return &field;
  }
  return nullptr;
}

// One flag of the tool's own, with its value when it takes one; false when it is not one of them.
bool parse_own_flag(const std::string& flag, const std::function<std::string()>& value, Arguments& arguments) {
  if (flag == "-h" || flag == "--help") arguments.help = true;
  else if (flag == "--light") arguments.lights.push_back(parse_light(value()));
  else if (flag == "--out") arguments.out_dir = value();
  else if (flag == "--albedo") {
    const std::string text = value();
    arguments.albedo = finite_number(text);
    if (!arguments.albedo) throw UsageError("--albedo takes a finite number; got '" + text + "'");
  } else if (flag == "--color-space") arguments.color_space = value();
  else if (flag == "--max-pixels") arguments.max_pixels = parse_max_pixels(value());
  else if (flag == "--quiet") arguments.quiet = true;
  else if (flag == "--flip") arguments.flip = true;
  else return false;
  return true;
}

// `text` in lines of at most 100 columns, each starting with `indent`.
std::string wrapped(const std::string& text, const std::string& indent) {
  std::istringstream words(text);
  std::string word, line, lines;
  while (words >> word) {
    if (!line.empty() && indent.size() + line.size() + 1 + word.size() > 100) {
      lines += indent + line + "\n";
      line.clear();
    }
    line += (line.empty() ? "" : " ") + word;
  }
  return lines + (line.empty() ? "" : indent + line + "\n");
}

}  // namespace

Arguments parse_arguments(const std::vector<std::string>& args) {
  Arguments arguments;
  arguments.max_pixels = kDefaultMaxPixels;
  for (std::size_t i = 0; i < args.size(); ++i) {
    // --name=value is --name value.
    const std::size_t equals = args[i].rfind("--", 0) == 0 ? args[i].find('=') : std::string::npos;
    const std::string flag = args[i].substr(0, equals);
    std::optional<std::string> attached;
    if (equals != std::string::npos) attached = args[i].substr(equals + 1);
    const std::function<std::string()> value = [&]() -> std::string {
      if (attached) return *std::exchange(attached, std::nullopt);
      if (i + 1 >= args.size()) throw UsageError(flag + " needs a value");
      return args[++i];
    };
    std::optional<bool> flag_value;
    if (parse_own_flag(flag, value, arguments)) {
    } else if (const OptionField* field = field_of_flag(flag, flag_value)) {
      try {
        if (flag_value && !attached) set_option_from_text(*field, arguments.options, *flag_value ? "true" : "false");
        else set_option_from_text(*field, arguments.options, value());
      } catch (const InvalidArgument& error) {
        throw UsageError(std::string(error.what()) + " (" + flag + ")");
      }
    } else if (!flag.empty() && flag[0] == '-') {
      throw UsageError("unknown option " + flag);
    } else {
      arguments.image_paths.push_back(flag);
    }
    if (attached) throw UsageError(flag + " takes no value; got '" + args[i] + "'");
  }
  if (arguments.help) return arguments;
  if (arguments.image_paths.empty()) throw UsageError("no image given");
  if (arguments.image_paths.size() > 1 && !arguments.lights.empty() && arguments.lights.size() != arguments.image_paths.size())
    throw UsageError(std::to_string(arguments.image_paths.size()) + " photographs but " + std::to_string(arguments.lights.size()) +
                     " --light; give one --light per photograph, in their order, or none to have them estimated");
  if (arguments.image_paths.size() == 1 && arguments.lights.size() > 1)
    throw UsageError("one photograph but " + std::to_string(arguments.lights.size()) + " --light");
  return arguments;
}

// light_side_names() as --help lists them, wrapped under the flags' descriptions.
std::string side_names_text() {
  std::string text, line;
  for (const std::string& side : light_side_names()) {
    if (!line.empty() && line.size() + side.size() > 70) {
      text += line + ",\n                       ";
      line.clear();
    }
    line += (line.empty() ? "" : ", ") + side;
  }
  return text + line;
}

std::string usage() {
  std::ostringstream text;
  text << R"(usage: shadecut IMAGE [--light X,Y,Z] [options]
       shadecut IMAGE1 IMAGE2 ... [--light X,Y,Z --light X,Y,Z ...] [options]

Reconstructs a surface from one shaded image (shape from shading using graph cuts), or from several
photographs of one view each under its own light (photometric stereo, with the graph cut where two
photographs leave two normals; one --light per photograph, in their order, or none: four or more
photographs lit from around at one slant, --light-slant, give their lights), and writes
depth.exr, depth.png, normals.exr, normals.png, mesh.ply and the albedo per pixel, albedo.exr and
albedo.png (in colour for a colour image), to the output folder.

Conventions (docs/conventions.md): x right, y up, z toward the viewer; the light points from the
surface toward the light, e.g. 1,0,1 = from the right-front. The image's alpha channel, if any, is
the mask. A flag's value may follow it or be attached with '=' (--labels=24).

input and output:
  --light X,Y,Z        light direction in the camera frame (Z > 0); without it the light (and,
                       unless --albedo is given, the albedo) is estimated from the image; with
                       several photographs, once for each or never
  --light SIDE         a light from that side of the image at )" << kSideLightSlantDegrees << R"( degrees from the viewer (a light
                       nobody measured; its slant scales the depth), SIDE one of
                       )" << side_names_text() << R"(
  --albedo A           albedo (default: read from the image by --albedo-method)
  --out DIR            output folder (default shadecut_out)
  --color-space NAME   auto (default), linear or srgb: how the file's values relate to intensity
  --max-pixels N       refuse an image whose header declares more pixels (default )"
       << kDefaultMaxPixels << R"()
  --flip               write the surface inverted (depth z -> -z, normals (-nx, -ny, nz)): the
                       other answer when the output says the orientation is ambiguous
  --quiet              no progress
  -h, --help           this text
)";
  const ReconstructOptions defaults;
  for (std::size_t group = 0; group < option_group_names().size(); ++group) {
    text << "\n" << option_group_names()[group] << ":\n";
    for (const OptionField& field : option_fields()) {
      if (std::size_t(field.group) != group) continue;
      std::string spelled = flag_of(field.name);
      if (is_flag_field(field)) spelled += ", --no-" + spelled.substr(2);
      for (const std::string& other : field.flags) spelled += ", " + other;
      const std::vector<std::string> choices = option_choices(field);
      std::string takes;
      for (std::size_t i = 0; i < choices.size(); ++i) takes += (i ? ", " : "") + choices[i];
      const std::string range = option_range_text(field);
      const std::string placeholder = is_flag_field(field) ? "" : takes.empty() ? " N" : " NAME";
      text << "  " << flag_of(field.name) << placeholder << spelled.substr(flag_of(field.name).size()) << "\n"
           << wrapped(field.help + " [default " + option_value_text(field, defaults) + (takes.empty() ? "" : "; " + takes) +
                          (range.empty() || range == "finite" || range == "a whole number" ? "" : "; " + range) + "]",
                      "      ");
    }
  }
  return text.str();
}

}  // namespace shadecut::cli
