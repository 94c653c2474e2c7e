// Starting a component's executable: see run.hpp.
#include "iface_runtime_cpp/run.hpp"

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <thread>
#include <vector>


#include "ament_index_cpp/get_package_share_directory.hpp"
#include "iface_runtime_cpp/group_executors.hpp"
#include "iface_runtime_cpp/node.hpp"
#include "iface_runtime_cpp/standby.hpp"
#include "rclcpp/rclcpp.hpp"

namespace iface_runtime
{

// ---- starting a component -------------------------------------------------------------------------------

namespace
{

std::atomic<bool> g_stop{false};

void on_signal(int)
{
  g_stop = true;
}

}  // namespace

int run(int argc, char ** argv, const std::string & package, const std::string & params_file, const MakeNode & make)
{
  const std::vector<std::string> own = rclcpp::remove_ros_arguments(argc, argv);
  const std::string usage = "usage: " + package +
    " [-h] [--activate] [--no-default-params] [--standby] [--ros-args ...]";
  bool activate = false, no_default = false, standby = false;
  for (std::size_t i = 1; i < own.size(); ++i) {
    if (own[i] == "--activate") {
      activate = true;
    } else if (own[i] == "--no-default-params") {
      no_default = true;
    } else if (own[i] == "--standby") {
      standby = true;
    } else if (own[i] == "-h" || own[i] == "--help") {
      std::cout << usage << "\n\nStart the " << package << " lifecycle node (ROS arguments after --ros-args).\n\n"
                << "  --activate           configure and activate at start\n"
                << "  --no-default-params  do not load the installed config/" << params_file << "\n"
                << "  --standby            a spare for a fast restart: start ROS and wait; make the node on\n"
                << "                       SIGUSR1, end when the process that started it ends first (the\n"
                << "                       component manager's standby)\n";
      return 0;
    } else {
      std::cerr << usage << "\n" << package << ": error: unrecognized arguments: " << own[i] << "\n";
      return 2;
    }
  }
  std::string params;
  if (!no_default) {
    try {
      const auto path = std::filesystem::path(ament_index_cpp::get_package_share_directory(package)) / "config" /
        params_file;
      if (std::filesystem::is_regular_file(path)) {
        params = path.string();
      }
    } catch (const std::exception &) {
      // not installed through ament
    }
  }
  std::vector<std::string> ros_argv = {argv[0]};
  if (!params.empty()) {
    ros_argv.insert(ros_argv.end(), {"--ros-args", "--params-file", params, "--"});
  }
  for (int i = 1; i < argc; ++i) {
    ros_argv.emplace_back(argv[i]);
  }
  std::vector<const char *> c_argv;
  for (const auto & a : ros_argv) {
    c_argv.push_back(a.c_str());
  }
  // SIGINT and SIGTERM end the node through its lifecycle (shutdown, teardown) while the context is
  // still valid, then rclcpp; rclcpp's own handlers would invalidate the context first.
  const pid_t parent = standby_parent();
  sigset_t told{};
  if (standby) {
    told = standby_signal();  // before ROS starts its threads
  }
  rclcpp::init(static_cast<int>(c_argv.size()), c_argv.data(), rclcpp::InitOptions(),
    rclcpp::SignalHandlerOptions::None);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  int code = 0;
  {
    std::shared_ptr<rclcpp::Node> spare;
    if (standby) {
      spare = standby_node();
      if (!until_told(told, g_stop, parent)) {
        spare.reset();
        rclcpp::shutdown();
        return 0;
      }
    }
    std::shared_ptr<ComponentNode> node;
    try {
      node = make(rclcpp::NodeOptions());
      spare.reset();  // after the component's node: the participant stays up between the two
    } catch (const std::exception & e) {
      std::cerr << package << ": cannot start the component: " << e.what() << "\n";
      rclcpp::shutdown();
      return 2;
    }
    RCLCPP_INFO(node->get_logger(), "%s", params.empty() ? "parameter file: none installed" :
      ("parameter file: " + params).c_str());
    GroupExecutors executors(node->get_node_base_interface(), node->executor_threads());
    if (activate) {
      node->configure();
      node->activate();
    }
    while (rclcpp::ok() && !node->finalized() && !g_stop) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    if (node->finalized()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let the answer to the shutdown go out
    } else if (rclcpp::ok()) {
      node->shutdown();  // stopped by a signal: leave through the lifecycle (teardown runs)
    }
    executors.stop();
  }
  rclcpp::shutdown();
  return code;
}

}  // namespace iface_runtime
