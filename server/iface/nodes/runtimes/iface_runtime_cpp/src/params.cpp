// Configuration parameters: see params.hpp.
#include "iface_runtime_cpp/params.hpp"

#include <algorithm>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "iface_runtime_cpp/json.hpp"

namespace iface_runtime
{

// ---- parameters -----------------------------------------------------------------------------------

rclcpp::ParameterType ParamSpec::type() const
{
  static const std::map<std::string, rclcpp::ParameterType> types = {
    {"bool", rclcpp::ParameterType::PARAMETER_BOOL},
    {"integer", rclcpp::ParameterType::PARAMETER_INTEGER},
    {"double", rclcpp::ParameterType::PARAMETER_DOUBLE},
    {"string", rclcpp::ParameterType::PARAMETER_STRING},
    {"bool_array", rclcpp::ParameterType::PARAMETER_BOOL_ARRAY},
    {"integer_array", rclcpp::ParameterType::PARAMETER_INTEGER_ARRAY},
    {"double_array", rclcpp::ParameterType::PARAMETER_DOUBLE_ARRAY},
    {"string_array", rclcpp::ParameterType::PARAMETER_STRING_ARRAY}};
  return types.at(kind);
}

rcl_interfaces::msg::ParameterDescriptor ParamSpec::descriptor() const
{
  rcl_interfaces::msg::ParameterDescriptor d;
  d.name = name;
  d.type = static_cast<uint8_t>(type());
  d.description = description;
  d.additional_constraints = constraints;
  d.read_only = read_only;
  if (kind == "integer" && choices.empty() && (low || high)) {
    rcl_interfaces::msg::IntegerRange range;
    range.from_value = low ? low->whole : std::numeric_limits<int64_t>::min();
    range.to_value = high ? high->whole : std::numeric_limits<int64_t>::max();
    range.step = 0;
    d.integer_range.push_back(range);
  } else if (kind == "double" && low && high) {
    rcl_interfaces::msg::FloatingPointRange range;
    range.from_value = low->number;
    range.to_value = high->number;
    range.step = 0.0;
    d.floating_point_range.push_back(range);
  }
  return d;
}

namespace
{

struct Scalar
{
  enum class Kind { Bool, Integer, Double, String } kind;
  bool b = false;
  int64_t i = 0;
  double d = 0.0;
  std::string s;

  std::string text() const
  {
    switch (kind) {
      case Kind::Bool: return py_bool(b);
      case Kind::Integer: return std::to_string(i);
      case Kind::Double: return py_float(d);
      default: return s;
    }
  }
};

std::optional<std::string> scalar_problem(const ParamSpec & spec, const Scalar & value, const std::string & what)
{
  const std::string unit = spec.unit.empty() ? "" : " " + spec.unit;
  if (!spec.choices.empty()) {
    const bool number = value.kind == Scalar::Kind::Integer || value.kind == Scalar::Kind::Double ||
      value.kind == Scalar::Kind::Bool;
    const double v = value.kind == Scalar::Kind::Integer ? static_cast<double>(value.i) :
      value.kind == Scalar::Kind::Double ? value.d : value.b ? 1.0 : 0.0;
    const bool known = number && std::any_of(spec.choices.begin(), spec.choices.end(), [&](const auto & c) {
          return static_cast<double>(c.second) == v;
        });
    if (!known) {
      std::string names;
      for (const auto & [n, c] : spec.choices) {
        names += (names.empty() ? "" : ", ") + n + " (" + std::to_string(c) + ")";
      }
      return what + "=" + value.text() + " is not one of " + names;
    }
  }
  if (value.kind == Scalar::Kind::Integer) {
    if (spec.low && static_cast<double>(value.i) < spec.low->number && value.i < spec.low->whole) {
      return what + "=" + value.text() + unit + " is below the minimum " + spec.low->text + unit;
    }
    if (spec.high && static_cast<double>(value.i) > spec.high->number && value.i > spec.high->whole) {
      return what + "=" + value.text() + unit + " is above the maximum " + spec.high->text + unit;
    }
  }
  if (value.kind == Scalar::Kind::Double) {
    if (spec.low && value.d < spec.low->number) {
      return what + "=" + value.text() + unit + " is below the minimum " + spec.low->text + unit;
    }
    if (spec.high && value.d > spec.high->number) {
      return what + "=" + value.text() + unit + " is above the maximum " + spec.high->text + unit;
    }
  }
  if (value.kind == Scalar::Kind::String && spec.max_length) {
    const size_t length = utf8_length(value.s);
    if (length > *spec.max_length) {
      return what + " is " + std::to_string(length) + " characters long; at most " +
             std::to_string(*spec.max_length) + " are allowed";
    }
  }
  return std::nullopt;
}

std::vector<Scalar> scalars(const rclcpp::Parameter & p)
{
  std::vector<Scalar> out;
  switch (p.get_type()) {
    case rclcpp::ParameterType::PARAMETER_BOOL_ARRAY:
      for (bool b : p.as_bool_array()) {
        out.push_back(Scalar{Scalar::Kind::Bool, b, 0, 0.0, ""});
      }
      break;
    case rclcpp::ParameterType::PARAMETER_INTEGER_ARRAY:
      for (int64_t i : p.as_integer_array()) {
        out.push_back(Scalar{Scalar::Kind::Integer, false, i, 0.0, ""});
      }
      break;
    case rclcpp::ParameterType::PARAMETER_DOUBLE_ARRAY:
      for (double d : p.as_double_array()) {
        out.push_back(Scalar{Scalar::Kind::Double, false, 0, d, ""});
      }
      break;
    case rclcpp::ParameterType::PARAMETER_STRING_ARRAY:
      for (const auto & s : p.as_string_array()) {
        out.push_back(Scalar{Scalar::Kind::String, false, 0, 0.0, s});
      }
      break;
    case rclcpp::ParameterType::PARAMETER_BYTE_ARRAY:
      for (auto b : p.as_byte_array()) {
        out.push_back(Scalar{Scalar::Kind::Integer, false, b, 0.0, ""});
      }
      break;
    default:
      break;
  }
  return out;
}

}  // namespace

std::optional<std::string> ParamSpec::problem(const rclcpp::Parameter & p) const
{
  if (kind.size() > 6 && kind.compare(kind.size() - 6, 6, "_array") == 0) {
    const auto items = scalars(p);
    if (size_kind == "fixed" && items.size() != size.value_or(0)) {
      return name + " must have exactly " + std::to_string(size.value_or(0)) + " elements, not " +
             std::to_string(items.size());
    }
    if (size_kind == "bounded" && size && items.size() > *size) {
      return name + " may have at most " + std::to_string(*size) + " elements, not " + std::to_string(items.size());
    }
    for (std::size_t i = 0; i < items.size(); ++i) {
      auto found = scalar_problem(*this, items[i], name + "[" + std::to_string(i) + "]");
      if (found) {
        return found;
      }
    }
    return std::nullopt;
  }
  switch (p.get_type()) {
    case rclcpp::ParameterType::PARAMETER_BOOL:
      return scalar_problem(*this, Scalar{Scalar::Kind::Bool, p.as_bool(), 0, 0.0, ""}, name);
    case rclcpp::ParameterType::PARAMETER_INTEGER:
      return scalar_problem(*this, Scalar{Scalar::Kind::Integer, false, p.as_int(), 0.0, ""}, name);
    case rclcpp::ParameterType::PARAMETER_DOUBLE:
      return scalar_problem(*this, Scalar{Scalar::Kind::Double, false, 0, p.as_double(), ""}, name);
    case rclcpp::ParameterType::PARAMETER_STRING:
      return scalar_problem(*this, Scalar{Scalar::Kind::String, false, 0, 0.0, p.as_string()}, name);
    default:
      return std::nullopt;
  }
}

}  // namespace iface_runtime
