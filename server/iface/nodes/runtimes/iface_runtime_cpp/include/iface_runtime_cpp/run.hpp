// iface_runtime_cpp: how a component's executable starts its node. It names no
// rclcpp header, so src/main.cpp compiles in a moment (the node's machinery: iface_runtime.hpp).
#ifndef IFACE_RUNTIME_CPP__RUN_HPP_
#define IFACE_RUNTIME_CPP__RUN_HPP_

#include <functional>
#include <memory>
#include <string>

namespace rclcpp
{
class NodeOptions;
}  // namespace rclcpp

namespace iface_runtime
{

class ComponentNode;

//! Makes a component's node (its package's make_component).
using MakeNode = std::function<std::shared_ptr<ComponentNode>(const rclcpp::NodeOptions &)>;

//! Start a component: its installed parameter file, then the command line's ROS arguments.
int run(int argc, char ** argv, const std::string & package, const std::string & params_file, const MakeNode & make);

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__RUN_HPP_
