// The option table: every field of ReconstructOptions described once (name, stage, type, default,
// allowed range, one line of help). The checks (check_option_ranges), the Python binding, the command
// line's flags and --help, the add-on's defaults and docs/python_api.md's table are made from it.
#pragma once

#include <shadecut/pipeline/reconstruct_options.hpp>

#include <limits>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace shadecut {

/// The stage an option belongs to, in the order the docs list them.
enum class OptionGroup {
  Scene,
  GraphCut,
  Iterative,
  Paint,
  ShadowsAndHighlights,
  Integration,
  Refinement,
  Relief,
  Photographs,
  Runtime
};

/// Every group's title ("graph cut"), in the order of the enum.
const std::vector<std::string>& option_group_names();

template <class T>
using OptionMember = T ReconstructOptions::*;

/// Where a field lives in ReconstructOptions, with its type.
using OptionMemberPointer =
    std::variant<OptionMember<bool>, OptionMember<int>, OptionMember<double>, OptionMember<std::optional<int>>,
                 OptionMember<std::optional<double>>, OptionMember<SceneKind>, OptionMember<Method>,
                 OptionMember<Integrator>, OptionMember<AlbedoMethod>, OptionMember<std::optional<LightMethod>>>;

/// The values a number may take: [low, high], either end open; numbers are always finite.
struct OptionRange {
  double low = -std::numeric_limits<double>::max();
  double high = std::numeric_limits<double>::max();
  bool low_open = false;
  bool high_open = false;

  bool contains(double value) const;
  /// "at least 4", "in [0, 1)", "in 0 .. 256", "> 1", "finite": the words of an error message.
  std::string text(bool whole) const;
};

struct OptionField {
  std::string name;         ///< the Python keyword; the command line's flag is --name with dashes
  OptionGroup group;
  OptionMemberPointer member;
  OptionRange range;        ///< numbers only
  std::string help;         ///< one line; for an optional field, says what None means
  std::vector<std::string> flags;  ///< the command line's other spellings of the flag ("--band"); may be empty
};

/// What kind of value a field holds (an optional one holds it or None).
enum class OptionKind { Flag, Whole, Number, Name };
OptionKind option_kind(const OptionField& field);

/// The field's range in words ("in 4 .. 360", ">= 0"), or "" for a flag or a name.
std::string option_range_text(const OptionField& field);

/// Every option, grouped by stage in the order of OptionGroup.
const std::vector<OptionField>& option_fields();

/// The field named `name`, or nullptr.
const OptionField* find_option(const std::string& name);

/// The names an enum field may take (empty for other fields).
std::vector<std::string> option_choices(const OptionField& field);

/// The field's value in `options` as text: "36", "0.2", "graphcut", "true", "None".
std::string option_value_text(const OptionField& field, const ReconstructOptions& options);

/// Sets the field from text as the command line gives it ("36", "0.2", "graphcut", "true"/"false",
/// "none" for an optional); throws InvalidArgument naming the field, the text and what it takes.
void set_option_from_text(const OptionField& field, ReconstructOptions& options, const std::string& text);

/// Throws InvalidArgument for the first number outside its field's range, with the range.
void check_option_ranges(const ReconstructOptions& options);

}  // namespace shadecut
