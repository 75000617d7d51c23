// ReconstructOptions made from the option table (pipeline/option_table.hpp): a new field of the table
// is a property here, a keyword of reconstruct() and a row of option_fields() without a line of this file.
#include "bind_options.hpp"

#include <shadecut/pipeline/reconstruct.hpp>

#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace py = pybind11;

namespace shadecut::python {

namespace {

template <class T>
struct is_optional : std::false_type {};
template <class T>
struct is_optional<std::optional<T>> : std::true_type {};

// Whether `value` is of T's kind: a flag takes True or False only (None or 2 would pass for one), a
// whole number an int but not a bool, a number an int or a float but not a bool.
template <class T>
bool is_kind(const py::handle& value) {
  const bool is_bool = py::isinstance<py::bool_>(value) ||
                       (py::hasattr(value, "dtype") && py::str(value.attr("dtype").attr("kind")).cast<std::string>() == "b");
  if constexpr (std::is_same_v<T, bool>) return is_bool;
  else if constexpr (std::is_integral_v<T>) return !is_bool && PyIndex_Check(value.ptr());
  else if constexpr (std::is_floating_point_v<T>) return !is_bool && (PyFloat_Check(value.ptr()) || PyIndex_Check(value.ptr()) ||
                                                                      (py::hasattr(value, "dtype") && PyNumber_Check(value.ptr())));
  else return true;  // enums: pybind11's cast decides
}

[[noreturn]] void refuse(const OptionField& field, const py::handle& value, const py::object& current) {
  throw py::type_error("shadecut: option '" + field.name + "' cannot be " + py::repr(value).cast<std::string>() + " (" +
                       py::type::of(value).attr("__name__").cast<std::string>() + "); it is now " +
                       py::repr(current).cast<std::string>());
}

// `value` as the field's type T; an enum also by its name.
template <class T>
T cast_option(const OptionField& field, const py::handle& value, const py::object& current) {
  if constexpr (std::is_enum_v<T>) {
    if (py::isinstance<py::str>(value)) {
      ReconstructOptions parsed;
      set_option_from_text(field, parsed, value.cast<std::string>());
      return std::visit(
          [&parsed](auto member) -> T {
            using Field = std::decay_t<decltype(parsed.*member)>;
            if constexpr (std::is_same_v<Field, T>) return parsed.*member;
            else if constexpr (std::is_same_v<Field, std::optional<T>>) return *(parsed.*member);
            else throw std::logic_error("shadecut: an option's type differs from its table entry");
          },
          field.member);
    }
  }
  if (!value.is_none() && is_kind<T>(value)) {
    try {
      return value.cast<T>();
    } catch (const py::cast_error&) {
    } catch (const py::reference_cast_error&) {
    }
  }
  refuse(field, value, current);
}

template <class T>
void bind_field(py::class_<ReconstructOptions>& options, const OptionField& field, OptionMember<T> member) {
  options.def_property(
      field.name.c_str(), [member](const ReconstructOptions& o) { return o.*member; },
      [member, &field](ReconstructOptions& o, const py::object& value) {
        if constexpr (is_optional<T>::value) {
          if (value.is_none()) o.*member = std::nullopt;
          else o.*member = cast_option<typename T::value_type>(field, value, py::cast(o.*member));
        } else {
          o.*member = cast_option<T>(field, value, py::cast(o.*member));
        }
      },
      field.help.c_str());
}

// A copy of `options` with the named fields set; an unknown name is a TypeError, as for a function.
ReconstructOptions replaced(const std::vector<std::string>& names, ReconstructOptions options, const py::kwargs& overrides) {
  // Cast by move: casting the caller's own object would find and change it.
  py::object copy = py::cast(std::move(options));
  for (const auto& [key, value] : overrides) {
    const std::string name = key.cast<std::string>();
    if (std::find(names.begin(), names.end(), name) == names.end())
      throw py::type_error("shadecut: unknown option '" + name + "'; the options are " +
                           py::str(", ").attr("join")(names).cast<std::string>());
    copy.attr(key) = value;
  }
  return copy.cast<ReconstructOptions>();
}

// One row of option_fields(): what the add-on, the docs and tests read of the table.
py::dict field_row(const OptionField& field, const py::object& defaults) {
  py::dict row;
  const OptionKind kind = option_kind(field);
  const bool number = kind == OptionKind::Whole || kind == OptionKind::Number;
  row["name"] = field.name;
  row["group"] = option_group_names().at(std::size_t(field.group));
  row["kind"] = kind == OptionKind::Flag ? "flag" : kind == OptionKind::Whole ? "whole" : number ? "number" : "name";
  row["default"] = defaults.attr(field.name.c_str());
  row["default_text"] = option_value_text(field, ReconstructOptions{});
  row["choices"] = py::tuple(py::cast(option_choices(field)));
  row["range"] = number ? py::cast(option_range_text(field)) : py::none();
  row["low"] = number && field.range.low > -std::numeric_limits<double>::max() ? py::cast(field.range.low) : py::none();
  row["high"] = number && field.range.high < std::numeric_limits<double>::max() ? py::cast(field.range.high) : py::none();
  row["low_open"] = field.range.low_open;
  row["high_open"] = field.range.high_open;
  row["help"] = field.help;
  row["flags"] = py::tuple(py::cast(field.flags));
  return row;
}

std::string options_repr(const std::vector<std::string>& names, const py::object& self) {
  // An option left None shows the value its method uses: `undefined_weight=None (graphcut: 0.5)`.
  const py::object per_method = py::cast(method_defaults(self.cast<const ReconstructOptions&>().method));
  const std::string method = self.attr("method").attr("name").cast<std::string>();
  std::string text = "ReconstructOptions(";
  for (std::size_t i = 0; i < names.size(); ++i) {
    const py::object value = self.attr(names[i].c_str());
    const bool is_enum = py::hasattr(value, "name") && py::hasattr(value, "value");
    text += std::string(i ? ", " : "") + names[i] + "=" +
            (is_enum ? "'" + value.attr("name").cast<std::string>() + "'" : py::repr(value).cast<std::string>());
    if (value.is_none() && py::hasattr(per_method, names[i].c_str()))
      text += " (" + method + ": " + py::repr(per_method.attr(names[i].c_str())).cast<std::string>() + ")";
  }
  return text + ")";
}

void bind_method_defaults(py::module_& m) {
  py::class_<MethodDefaults>(m, "MethodDefaults",
                             "The values a method uses for the options left None (tuned: docs/parameters.md); 0 = unused.")
      .def_readonly("min_curvature", &MethodDefaults::min_curvature)
      .def_readonly("undefined_weight", &MethodDefaults::undefined_weight)
      .def_readonly("tolerance", &MethodDefaults::tolerance)
      .def_readonly("iterations", &MethodDefaults::iterations)
      .def_readonly("smoothness", &MethodDefaults::smoothness)
      .def("__repr__", [](const MethodDefaults& d) {
        return "MethodDefaults(min_curvature=" + py::repr(py::float_(d.min_curvature)).cast<std::string>() +
               ", undefined_weight=" + py::repr(py::float_(d.undefined_weight)).cast<std::string>() +
               ", tolerance=" + py::repr(py::float_(d.tolerance)).cast<std::string>() +
               ", iterations=" + std::to_string(d.iterations) +
               ", smoothness=" + py::repr(py::float_(d.smoothness)).cast<std::string>() + ")";
      });
  m.def("method_defaults", [](const std::string& method) { return method_defaults(parse_method(method)); }, py::arg("method"),
        "The values `method` uses for the options left None (min_curvature, undefined_weight, tolerance, "
        "iterations, smoothness).");
}

}  // namespace

void bind_options(py::module_& m) {
  py::class_<ReconstructOptions> options(m, "ReconstructOptions",
                                         "Every setting of reconstruct() with its default (pipeline/option_table.hpp).");
  std::vector<std::string> names;
  for (const OptionField& field : option_fields()) {
    std::visit([&](auto member) { bind_field(options, field, member); }, field.member);
    names.push_back(field.name);
  }
  m.attr("OPTION_NAMES") = py::tuple(py::cast(names));
  m.attr("MIN_LABELS") = kMinLabels;
  m.attr("MAX_THREADS") = kMaxThreads;
  options.def(py::init([names](const py::kwargs& overrides) { return replaced(names, ReconstructOptions{}, overrides); }),
              "The defaults, with the given fields set (unknown names raise TypeError).");
  options.def(
      "replace", [names](const ReconstructOptions& self, const py::kwargs& overrides) { return replaced(names, self, overrides); },
      "A copy with the given fields set.");
  options.def("light_method_used", &light_method_used,
              "The light estimator reconstruct() uses when given no light: light_method, or by scene when None.");
  options.def("highlight_threshold_used", &highlight_threshold_used,
              "The highlight threshold reconstruct() uses: highlight_threshold, or by albedo_method when None.");
  options.def("__repr__", [names](const py::object& self) { return options_repr(names, self); });
  m.def(
      "option_fields",
      [] {
        const py::object defaults = py::cast(ReconstructOptions{});
        py::list rows;
        for (const OptionField& field : option_fields()) rows.append(field_row(field, defaults));
        return rows;
      },
      "Every option of the table: name, group, kind, default, choices, range, help, flags.");
  bind_method_defaults(m);
}

}  // namespace shadecut::python
