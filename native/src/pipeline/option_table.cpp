#include <shadecut/pipeline/option_table.hpp>

#include <shadecut/graphcut/tilt_energy.hpp>
#include <shadecut/integrate/integrate.hpp>
#include <shadecut/support/errors.hpp>

#include <cmath>
#include <limits>
#include <iterator>
#include <sstream>
#include <type_traits>

namespace shadecut {

namespace {

using O = ReconstructOptions;
using G = OptionGroup;

constexpr double kUnbounded = std::numeric_limits<double>::max();

OptionRange at_least(double low) { return {low, kUnbounded, false, false}; }
OptionRange above(double low) { return {low, kUnbounded, true, false}; }
OptionRange between(double low, double high) { return {low, high, false, false}; }
OptionRange from_to_below(double low, double high) { return {low, high, false, true}; }
OptionRange above_up_to(double low, double high) { return {low, high, true, false}; }
OptionRange any_finite() { return {}; }

// The table, by stage, in the order of OptionGroup: the docs' and --help's order.
// The scene, the method and the graph cut.
std::vector<OptionField> scene_and_graph_cut_fields() {
  return {
      {"scene", G::Scene, &O::scene, {},
       "what the image shows: an object seen whole (its outline is the silhouette), or a relief filling the frame", {}},
      {"cut_out", G::Scene, &O::cut_out, {},
       "an object given without a mask: cut it out of a plain background first (else every pixel)", {}},
      {"method", G::Scene, &O::method, {}, "the reconstruction method (docs/method.md, docs/comparison_methods.md)", {}},
      {"light_method", G::Scene, &O::light_method, {},
       "the estimator used when no light is given; None = by scene (zheng_chellappa for an object, relief for a relief)", {}},
      {"labels", G::GraphCut, &O::labels, between(kMinLabels, kMaxLabels), "K, the tilt labels the graph cut chooses among", {}},
      {"data_weight", G::GraphCut, &O::data_weight, at_least(0.0),
       "lambda of the paper's eq. (15) (graphcut) for an object 128 pixels across, scaled to the object's size", {}},
      {"undefined_weight", G::GraphCut, &O::undefined_weight, at_least(0.0),
       "graph cuts: the pull toward tilt pi where the local tilt is undefined, scaled like data_weight; None = the method's default", {}},
      {"min_curvature", G::GraphCut, &O::min_curvature, at_least(0.0),
       "curvature (in units of the object) below which the local tilt is undefined; None = the method's default", {}},
      {"max_cycles", G::GraphCut, &O::max_cycles, at_least(0.0),
       "alpha-expansion cycles at most; it stops earlier when a cycle gains nothing", {}},
      {"coarse_to_fine_band", G::GraphCut, &O::coarse_to_fine_band, any_finite(),
       "coarse to fine: each pixel keeps the labels within this many steps of its half-resolution label; < 0 = one "
       "level, every label", {"--band"}},
      {"coarse_to_fine_radius", G::GraphCut, &O::coarse_to_fine_radius, any_finite(),
       "coarse to fine: only pixels within this many pixels of a jump of the half-resolution labels keep the band; "
       "< 0 = every pixel", {"--band-radius"}},
      {"refine", G::GraphCut, &O::refine, {}, "snap each label to the exact local candidate normal", {}},
      {"contour_weight", G::GraphCut, &O::contour_weight, at_least(0.0),
       "objects with occluding_contour: the pull of the outline's pixels toward normals pointing outward", {}},
      {"viscosity_weight", G::GraphCut, &O::viscosity_weight, at_least(0.0),
       "graphcut: the pull of a second coarsest labelling toward the viscosity solution, kept when its depth renders "
       "closer to the image; 0 = the paper's energy alone", {}},
  };
}

// The iterative methods and the paint.
std::vector<OptionField> iterative_and_paint_fields() {
  return {
      {"tolerance", G::Iterative, &O::tolerance, at_least(0.0),
       "graph cuts: stop when a cycle lowers the energy by at most this share; brooks_horn: when a sweep moves the normals by at most this; None = the method's default", {}},
      {"iterations", G::Iterative, &O::iterations, at_least(0.0),
       "brooks_horn and tsai_shah sweeps, upwind rounds, pentland solves; None = the method's default", {}},
      {"smoothness", G::Iterative, &O::smoothness, above(0.0),
       "brooks_horn's lambda for an object 128 pixels across, scaled with its area; pentland's weight of the slope across "
       "the light; None = the method's default", {}},
      {"albedo_method", G::Paint, &O::albedo_method, {},
       "how the albedo is read when none is given: one value (top_fit, brightest) or per pixel (retinex: paint told "
       "from shading)", {}},
      {"retinex_chroma_edge", G::Paint, &O::retinex_chroma_edge, at_least(0.0),
       "retinex: a change of chromaticity above this is a paint edge", {}},
      {"retinex_intensity_edge", G::Paint, &O::retinex_intensity_edge, any_finite(),
       "retinex: a sharp change of log brightness above this is a paint edge; <= 0 = off", {}},
      {"retinex_rim", G::Paint, &O::retinex_rim, at_least(0.0), "retinex, objects: pixels of the outline's rim left out", {}},
      {"retinex_highlight", G::Paint, &O::retinex_highlight, any_finite(),
       "retinex: pixels this much above the paint's brightness are highlights; <= 0 = none", {}},
      {"retinex_shadow", G::Paint, &O::retinex_shadow, from_to_below(0.0, 1.0),
       "retinex: pixels below this share of the albedo are shadow, not paint", {}},
      {"retinex_passes", G::Paint, &O::retinex_passes, between(1.0, 10.0),
       "retinex: how many times the paint is read, each pass after the first against the surface the pass before found", {}},
  };
}

// Shadows and highlights, integration, refinement and reliefs.
std::vector<OptionField> surface_fields() {
  return {
      {"fill_shadows", G::ShadowsAndHighlights, &O::fill_shadows, {},
       "fill the normals of attached shadows (and highlights) from their neighbours", {}},
      {"shadow_threshold", G::ShadowsAndHighlights, &O::shadow_threshold, from_to_below(0.0, 1.0),
       "a pixel at or below this share of the albedo is in shadow", {}},
      {"highlight_threshold", G::ShadowsAndHighlights, &O::highlight_threshold, any_finite(),
       "pixels brighter than this times the albedo are highlights, filled like shadows; <= 0 = never; None = by "
       "albedo_method (1 with retinex, never otherwise)", {}},
      {"occluding_contour", G::ShadowsAndHighlights, &O::occluding_contour, {},
       "objects: the mask's edge is an occluding contour (normals there point outward)", {}},
      {"integrator", G::Integration, &O::integrator, {}, "how the normals are integrated into depth", {}},
      {"max_slope", G::Integration, &O::max_slope, at_least(kMinMaxSlope), "the integrator clamps the depth's gradient to +- this (pixels per pixel)", {}},
      {"seamless", G::Integration, &O::seamless, {},
       "reliefs over the whole image (no mask): depth and normals that tile, for seamless textures; the integrator is then unused", {}},
      {"fit_shading", G::Refinement, &O::fit_shading, {},
       "graphcut: after integration, fit the depth to the image (integrable normals that render closer to it); not with seamless", {}},
      {"fit_smoothness", G::Refinement, &O::fit_smoothness, at_least(0.0), "fit_shading: how smooth its correction is", {}},
      {"fit_max_slant", G::Refinement, &O::fit_max_slant, above_up_to(0.0, 90.0),
       "fit_shading: pixels steeper than this many degrees are not fitted (their neighbours carry them); 90 = every pixel", {}},
      {"detail_size", G::Relief, &O::detail_size, any_finite(),
       "reliefs: forms larger than this many pixels are carrier and damped out; 0 = read from the image (pentland: "
       "keep every form); < 0 = keep every form", {}},
      {"detail_scale_factor", G::Relief, &O::detail_scale_factor, above(0.0),
       "reliefs with detail_size 0: the detail size in units of the relief's own scale", {}},
      {"paint_line_width", G::Relief, &O::paint_line_width, between(0.0, 1024.0),
       "reliefs: bright lines narrower than this many pixels are paint (mortar), not slope; < 2 = off", {}},
      {"paint_line_contrast", G::Relief, &O::paint_line_contrast, above(1.0),
       "reliefs: how much brighter than both its sides such a line is", {}},
  };
}

// Several photographs, and the runtime.
std::vector<OptionField> photograph_and_runtime_fields() {
  return {
      {"photometric_shadow_fraction", G::Photographs, &O::photometric_shadow_fraction, from_to_below(0.0, 1.0),
       "several photographs: one is in shadow at a pixel where it is darker than this share of the pixel's albedo", {}},
      {"photometric_outlier_tolerance", G::Photographs, &O::photometric_outlier_tolerance, above(0.0),
       "several photographs: with four or more lit, one that misses the others' fit by more than this share of the "
       "albedo (a highlight, a cast shadow) is left out", {}},
      {"candidate_smoothness", G::Photographs, &O::candidate_smoothness, above(0.0),
       "several photographs: the graph cut's weight on neighbours' normals agreeing where two photographs leave two "
       "normals", {}},
      {"light_slant", G::Photographs, &O::light_slant, between(kLeastHintSlant, kGreatestHintSlant),
       "several photographs without lights: the one slant, degrees from the viewer, their lights are estimated at (it "
       "scales the depth, as a side's does; the photographs fix the lights' directions around the viewer)", {}},
      {"first_light_tilt", G::Photographs, &O::first_light_tilt, any_finite(),
       "several photographs without lights: the image-plane direction, degrees (90 = from the top, 0 = from the "
       "right), the first photograph's light comes from, within 90 degrees; it tells a bump from a dent", {}},
      {"light_distance", G::Photographs, &O::light_distance, at_least(0.0),
       "several photographs with their lights given: how far the lamps stand from the frame's centre, in frame widths "
       "(each along its photograph's light); 0 = distant lights, as the sun's", {}},
      {"threads", G::Runtime, &O::threads, between(0.0, kMaxThreads), "threads; 0 = all cores", {}},
  };
}

std::vector<OptionField> make_fields() {
  std::vector<OptionField> fields;
  for (auto part : {&scene_and_graph_cut_fields, &iterative_and_paint_fields, &surface_fields, &photograph_and_runtime_fields}) {
    std::vector<OptionField> rows = part();
    fields.insert(fields.end(), std::make_move_iterator(rows.begin()), std::make_move_iterator(rows.end()));
  }
  return fields;
}

template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};

// The names of an enum type, the one table each enum has.
const std::vector<std::string>& names_of(SceneKind) { return scene_kind_names(); }
const std::vector<std::string>& names_of(Method) { return method_names(); }
const std::vector<std::string>& names_of(Integrator) { return integrator_names(); }
const std::vector<std::string>& names_of(AlbedoMethod) { return albedo_method_names(); }
const std::vector<std::string>& names_of(LightMethod) { return light_method_names(); }

// An enum's value by name, by its own parser (whose message names the enum as users know it).
void parse_named(const std::string& text, SceneKind& value) { value = parse_scene_kind(text); }
void parse_named(const std::string& text, Method& value) { value = parse_method(text); }
void parse_named(const std::string& text, Integrator& value) { value = parse_integrator(text); }
void parse_named(const std::string& text, AlbedoMethod& value) { value = parse_albedo_method(text); }
void parse_named(const std::string& text, LightMethod& value) { value = parse_light_method(text); }

template <class T>
std::string number_as_text(T value) {
  if constexpr (std::is_same_v<T, bool>) {
    return value ? "true" : "false";
  } else if constexpr (std::is_enum_v<T>) {
    return names_of(value).at(std::size_t(value));
  } else {
    std::ostringstream text;
    text << value;
    return text.str();
  }
}

template <class T>
std::string value_text(const T& value) {
  if constexpr (is_optional<T>::value) return value ? number_as_text(*value) : "None";
  else return number_as_text(value);
}

[[noreturn]] void refuse_text(const OptionField& field, const std::string& text, const std::string& takes) {
  throw InvalidArgument("shadecut: " + field.name + " takes " + takes + "; got '" + text + "'");
}

// The whole of `text` as T, or the field's message saying what it takes.
template <class T>
T parse_text(const OptionField& field, const std::string& text) {
  if constexpr (std::is_same_v<T, bool>) {
    if (text == "true" || text == "1" || text == "on") return true;
    if (text == "false" || text == "0" || text == "off") return false;
    refuse_text(field, text, "true or false");
  } else if constexpr (std::is_enum_v<T>) {
    T value{};
    parse_named(text, value);
    return value;
  } else {
    const bool whole = std::is_integral_v<T>;
    try {
      std::size_t used = 0;
      const double value = whole ? double(std::stoll(text, &used)) : std::stod(text, &used);
      if (used == text.size() && std::isfinite(value) &&
          (!whole || (value >= std::numeric_limits<T>::min() && value <= std::numeric_limits<T>::max())))
        return T(value);
    } catch (const std::exception&) {
    }
    refuse_text(field, text, whole ? "a whole number" : "a finite number");
  }
}

template <class T>
void check_range(const OptionField& field, const T& value) {
  if constexpr (is_optional<T>::value) {
    if (value) check_range(field, *value);
  } else if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
    if (!field.range.contains(double(value)))
      throw InvalidArgument("shadecut: " + field.name + " must be " + field.range.text(std::is_integral_v<T>) + "; got " +
                            number_as_text(value));
  }
}

std::string bound_text(double value, bool whole) {
  std::ostringstream text;
  if (whole) text << (long long)value;
  else text << value;
  return text.str();
}

}  // namespace

bool OptionRange::contains(double value) const {
  if (!std::isfinite(value)) return false;
  return (low_open ? value > low : value >= low) && (high_open ? value < high : value <= high);
}

std::string OptionRange::text(bool whole) const {
  const bool has_low = low > -kUnbounded, has_high = high < kUnbounded;
  const std::string finite = whole ? "" : "finite and ";
  if (has_low && has_high) {
    if (whole && !low_open && !high_open) return "in " + bound_text(low, true) + " .. " + bound_text(high, true);
    return "in " + std::string(low_open ? "(" : "[") + bound_text(low, whole) + ", " + bound_text(high, whole) +
           (high_open ? ")" : "]");
  }
  if (has_low) return finite + (low_open ? "> " : ">= ") + bound_text(low, whole);
  if (has_high) return finite + (high_open ? "< " : "<= ") + bound_text(high, whole);
  return whole ? "a whole number" : "finite";
}

const std::vector<std::string>& option_group_names() {
  static const std::vector<std::string> names{"scene and method", "graph cut",    "iterative methods",
                                              "paint",            "shadows and highlights", "integration",
                                              "refinement",       "reliefs",      "several photographs",
                                              "runtime"};
  return names;
}

const std::vector<OptionField>& option_fields() {
  static const std::vector<OptionField> fields = make_fields();
  return fields;
}

const OptionField* find_option(const std::string& name) {
  for (const OptionField& field : option_fields())
    if (field.name == name) return &field;
  return nullptr;
}

OptionKind option_kind(const OptionField& field) {
  return std::visit(
      [](auto member) {
        using Field = std::decay_t<decltype(ReconstructOptions{}.*member)>;
        using T = typename std::conditional_t<is_optional<Field>::value, Field, std::optional<Field>>::value_type;
        if constexpr (std::is_same_v<T, bool>) return OptionKind::Flag;
        else if constexpr (std::is_integral_v<T>) return OptionKind::Whole;
        else if constexpr (std::is_floating_point_v<T>) return OptionKind::Number;
        else return OptionKind::Name;
      },
      field.member);
}

std::string option_range_text(const OptionField& field) {
  const OptionKind kind = option_kind(field);
  if (kind == OptionKind::Whole || kind == OptionKind::Number) return field.range.text(kind == OptionKind::Whole);
  return "";
}

std::vector<std::string> option_choices(const OptionField& field) {
  return std::visit(
      [](auto member) -> std::vector<std::string> {
        using T = std::decay_t<decltype(ReconstructOptions{}.*member)>;
        if constexpr (is_optional<T>::value) {
          if constexpr (std::is_enum_v<typename T::value_type>) return names_of(typename T::value_type{});
          return {};
        } else if constexpr (std::is_enum_v<T>) {
          return names_of(T{});
        } else {
          return {};
        }
      },
      field.member);
}

std::string option_value_text(const OptionField& field, const ReconstructOptions& options) {
  return std::visit([&options](auto member) { return value_text(options.*member); }, field.member);
}

void set_option_from_text(const OptionField& field, ReconstructOptions& options, const std::string& text) {
  std::visit(
      [&](auto member) {
        using T = std::decay_t<decltype(options.*member)>;
        if constexpr (is_optional<T>::value) {
          if (text == "none" || text == "None") options.*member = std::nullopt;
          else options.*member = parse_text<typename T::value_type>(field, text);
        } else {
          options.*member = parse_text<T>(field, text);
        }
      },
      field.member);
}

void check_option_ranges(const ReconstructOptions& options) {
  for (const OptionField& field : option_fields())
    std::visit([&](auto member) { check_range(field, options.*member); }, field.member);
}

}  // namespace shadecut
