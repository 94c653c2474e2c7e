// Parameter checks: the values each parameter accepts, refused with the Python runtime's reasons, and the
// descriptor a parameter is declared with.
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "check.hpp"
#include "iface_runtime_cpp/params.hpp"

using iface_runtime::Bound;
using iface_runtime::ParamSpec;

namespace
{

std::string problem(const ParamSpec & spec, const rclcpp::ParameterValue & value)
{
  return spec.problem(rclcpp::Parameter(spec.name, value)).value_or("");
}

ParamSpec spec(const std::string & name, const std::string & kind)
{
  ParamSpec p;
  p.name = name;
  p.kind = kind;
  return p;
}

void ranges_with_their_unit()
{
  ParamSpec gain = spec("gain", "double");
  gain.low = Bound{0.0, 0, "0.0"};
  gain.high = Bound{10.0, 10, "10.0"};
  gain.unit = "1/s";
  CHECK_EQ(problem(gain, rclcpp::ParameterValue(5.0)), std::string());
  CHECK_EQ(problem(gain, rclcpp::ParameterValue(11.0)), std::string("gain=11.0 1/s is above the maximum 10.0 1/s"));
  CHECK_EQ(problem(gain, rclcpp::ParameterValue(-0.5)), std::string("gain=-0.5 1/s is below the minimum 0.0 1/s"));
  ParamSpec retries = spec("retries", "integer");
  retries.low = Bound{0.0, 0, "0"};
  retries.high = Bound{10.0, 10, "10"};
  CHECK_EQ(problem(retries, rclcpp::ParameterValue(int64_t{11})), std::string("retries=11 is above the maximum 10"));
  CHECK_EQ(problem(retries, rclcpp::ParameterValue(int64_t{10})), std::string());
}

void choices_lengths_and_sizes()
{
  ParamSpec mode = spec("mode", "integer");
  mode.choices = {{"IDLE", 0}, {"RUN", 1}};
  CHECK_EQ(problem(mode, rclcpp::ParameterValue(int64_t{1})), std::string());
  CHECK_EQ(problem(mode, rclcpp::ParameterValue(int64_t{3})), std::string("mode=3 is not one of IDLE (0), RUN (1)"));
  ParamSpec label = spec("label", "string");
  label.max_length = 3;
  CHECK_EQ(problem(label, rclcpp::ParameterValue(std::string("abcd"))),
    std::string("label is 4 characters long; at most 3 are allowed"));
  CHECK_EQ(problem(label, rclcpp::ParameterValue(std::string("\xc3\xbc\xc3\xbc\xc3\xbc"))), std::string());
  ParamSpec fixed = spec("v", "double_array");
  fixed.size = 2;
  fixed.size_kind = "fixed";
  fixed.low = Bound{0.0, 0, "0.0"};
  CHECK_EQ(problem(fixed, rclcpp::ParameterValue(std::vector<double>{1.0})),
    std::string("v must have exactly 2 elements, not 1"));
  CHECK_EQ(problem(fixed, rclcpp::ParameterValue(std::vector<double>{1.0, -1.0})),
    std::string("v[1]=-1.0 is below the minimum 0.0"));
  ParamSpec bounded = spec("ids", "integer_array");
  bounded.size = 2;
  bounded.size_kind = "bounded";
  CHECK_EQ(problem(bounded, rclcpp::ParameterValue(std::vector<int64_t>{1, 2})), std::string());
  CHECK_EQ(problem(bounded, rclcpp::ParameterValue(std::vector<int64_t>{1, 2, 3})),
    std::string("ids may have at most 2 elements, not 3"));
}

void descriptors()
{
  ParamSpec retries = spec("retries", "integer");
  retries.low = Bound{0.0, 0, "0"};
  retries.description = "how often";
  retries.read_only = true;
  const auto d = retries.descriptor();
  CHECK_EQ(d.description, std::string("how often"));
  CHECK(d.read_only);
  CHECK_EQ(d.integer_range.size(), std::size_t{1});
  CHECK_EQ(d.integer_range[0].from_value, int64_t{0});
  CHECK_EQ(d.integer_range[0].to_value, std::numeric_limits<int64_t>::max());
  CHECK(retries.type() == rclcpp::ParameterType::PARAMETER_INTEGER);
  ParamSpec gain = spec("gain", "double");
  gain.low = Bound{0.0, 0, "0.0"};
  CHECK(gain.descriptor().floating_point_range.empty());  // a double range needs both ends
  gain.high = Bound{2.5, 2, "2.5"};
  CHECK_EQ(gain.descriptor().floating_point_range.size(), std::size_t{1});
}

}  // namespace

int main()
{
  ranges_with_their_unit();
  choices_lengths_and_sizes();
  descriptors();
  return check::done("params");
}
