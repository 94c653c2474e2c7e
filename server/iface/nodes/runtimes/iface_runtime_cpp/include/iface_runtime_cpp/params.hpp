// Configuration parameters (P): their descriptors, and the values each one accepts (the Python runtime's
// reasons, word for word).
#ifndef IFACE_RUNTIME_CPP__PARAMS_HPP_
#define IFACE_RUNTIME_CPP__PARAMS_HPP_

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rcl_interfaces/msg/parameter_descriptor.hpp"
#include "rclcpp/parameter.hpp"
#include "rclcpp/parameter_value.hpp"

namespace iface_runtime
{

// ---- parameters -----------------------------------------------------------------------------------

//! A range end: as a double, as an integer, and as the interface wrote it (for messages).
struct Bound
{
  double number;
  int64_t whole;
  std::string text;
};

//! A configuration parameter of the interface and the values it accepts.
struct ParamSpec
{
  std::string name;
  std::string kind;  // bool, integer, double, string, and each with _array
  std::optional<rclcpp::ParameterValue> default_value;
  std::string description;
  std::string constraints;
  std::string unit;
  std::optional<Bound> low;
  std::optional<Bound> high;
  bool read_only = false;
  std::vector<std::pair<std::string, int64_t>> choices;
  std::optional<std::size_t> max_length;
  std::optional<std::size_t> size;
  std::string size_kind;

  //! Why the parameter is refused, or nothing.
  std::optional<std::string> problem(const rclcpp::Parameter & parameter) const;
  rcl_interfaces::msg::ParameterDescriptor descriptor() const;
  rclcpp::ParameterType type() const;
};

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__PARAMS_HPP_
