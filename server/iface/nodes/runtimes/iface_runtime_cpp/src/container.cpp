// iface_container: a component container (rclcpp_components' ComponentManager) that runs each callback group of
// each node it loads on an executor and threads of its own, and that also
// - hands over between two iface components it holds, in the process (~/handover, iface_msgs/srv/HandOver:
//   ComponentNode::hand_over_to, no DDS round trip in the critical section);
// - loads a package by the absolute path of its ament index entry, <prefix>/share/ament_index/resource_index/
//   rclcpp_components/<package>, so that the library loaded is that prefix's (the one whose signature was checked);
// - takes more extra arguments in LoadNode: "params_files" (parameter files, read as --params-file), "configure",
//   "state" (a state document restored after configure) and "activate": a component brought up in one request.
// docs/runtime.md, "The hand-over inside a container".
#include <algorithm>
#include <atomic>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "iface_msgs/srv/hand_over.hpp"
#include "iface_runtime_cpp/group_executors.hpp"
#include "iface_runtime_cpp/iface_runtime.hpp"
#include "iface_runtime_cpp/standby.hpp"
#include "lifecycle_msgs/msg/state.hpp"
#include "rclcpp/rclcpp.hpp"
#include "rclcpp_components/component_manager.hpp"

namespace iface_runtime
{

namespace
{

//! Threads of the container's own executor (its services: load, unload, list, hand-over) when the parameter
//! executor_threads gives none; the nodes it loads run on threads of their own (add_node_to_executor).
constexpr int64_t DEFAULT_THREADS = 2;
constexpr const char * INDEX = "/share/ament_index/resource_index/";

std::vector<std::string> split(const std::string & text, char separator)
{
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, separator)) {
    if (!part.empty()) {
      out.push_back(part);
    }
  }
  return out;
}

//! What a LoadNode request asks beyond rclcpp_components' own extra arguments.
struct BringUp
{
  std::vector<std::string> params_files;
  bool configure = false;
  bool activate = false;
  std::string state;
  //! The extra arguments rclcpp_components takes itself.
  std::vector<rcl_interfaces::msg::Parameter> rest;
};

BringUp bring_up_of(const composition_interfaces::srv::LoadNode::Request & request)
{
  using rclcpp_components::ComponentManagerException;
  BringUp out;
  for (const auto & argument : request.extra_arguments) {
    const auto p = rclcpp::Parameter::from_parameter_msg(argument);
    const auto & name = p.get_name();
    const auto type = p.get_type();
    if (name == "params_files") {
      if (type != rclcpp::ParameterType::PARAMETER_STRING_ARRAY) {
        throw ComponentManagerException("extra argument 'params_files' must be a string array");
      }
      out.params_files = p.as_string_array();
    } else if (name == "configure" || name == "activate") {
      if (type != rclcpp::ParameterType::PARAMETER_BOOL) {
        throw ComponentManagerException("extra argument '" + name + "' must be a boolean");
      }
      (name == "configure" ? out.configure : out.activate) = p.as_bool();
    } else if (name == "state") {
      if (type != rclcpp::ParameterType::PARAMETER_STRING) {
        throw ComponentManagerException("extra argument 'state' must be a string (a state document)");
      }
      out.state = p.as_string();
    } else {
      out.rest.push_back(argument);
    }
  }
  return out;
}

}  // namespace

//! The container: ComponentManager's services, the hand-over inside it, and the bring-up of what it loads.
class Container : public rclcpp_components::ComponentManager
{
public:
  explicit Container(const rclcpp::NodeOptions & options)
  : ComponentManager(std::weak_ptr<rclcpp::Executor>(), "iface_container", options)
  {
    using iface_msgs::srv::HandOver;
    hand_over_ = create_service<HandOver>(
      "~/handover",
      [this](const std::shared_ptr<HandOver::Request> request, std::shared_ptr<HandOver::Response> response) {
        on_hand_over(*request, *response);
      });
  }

  ~Container() override
  {
    executors_.clear();  // stops them
    // ComponentManager's destructor would remove each node from the container's executor, which has none of them
    node_wrappers_.clear();
  }

  //! A package by name (the ament index of this process), or by the absolute path of its index entry: the
  //! entry's lines with their libraries in the entry's prefix.
  std::vector<ComponentResource> get_component_resources(
    const std::string & package_name, const std::string & resource_index) const override
  {
    if (package_name.empty() || package_name.front() != '/') {
      return ComponentManager::get_component_resources(package_name, resource_index);
    }
    const auto mark = package_name.find(INDEX);
    if (mark == std::string::npos) {
      throw rclcpp_components::ComponentManagerException(
              package_name + " is no ament index entry (<prefix>" + INDEX + resource_index + "/<package>)");
    }
    std::ifstream file(package_name);
    if (!file) {
      throw rclcpp_components::ComponentManagerException("cannot read " + package_name);
    }
    std::stringstream content;
    content << file.rdbuf();
    const std::string prefix = package_name.substr(0, mark);
    std::vector<ComponentResource> resources;
    for (const auto & line : split(content.str(), '\n')) {
      const auto parts = split(line, ';');
      if (parts.size() != 2) {
        throw rclcpp_components::ComponentManagerException("invalid entry '" + line + "' in " + package_name);
      }
      resources.push_back({parts[0], parts[1].front() == '/' ? parts[1] : prefix + "/" + parts[1]});
    }
    return resources;
  }

protected:
  //! Each callback group of a loaded node on an executor and threads of its own (GroupExecutors): one
  //! multi-threaded executor for the whole container ticked a 1 kHz timer ~570 times a second.
  void add_node_to_executor(uint64_t node_id) override
  {
    const auto base = node_wrappers_[node_id].get_node_base_interface();
    const auto component = ComponentNode::of(base.get());
    executors_[node_id] = std::make_unique<GroupExecutors>(base, component ? component->executor_threads() : 2);
  }

  void remove_node_from_executor(uint64_t node_id) override
  {
    executors_.erase(node_id);  // stops them
  }

  rclcpp::NodeOptions create_node_options(const std::shared_ptr<LoadNode::Request> request) override
  {
    const BringUp asked = bring_up_of(*request);
    auto plain = std::make_shared<LoadNode::Request>(*request);
    plain->extra_arguments = asked.rest;
    auto options = ComponentManager::create_node_options(plain);
    // --ros-args first, then the parameter files, then the remappings ComponentManager wrote
    const auto arguments = options.arguments();
    std::vector<std::string> with_files(arguments.begin(), arguments.begin() + (arguments.empty() ? 0 : 1));
    for (const auto & file : asked.params_files) {
      with_files.push_back("--params-file");
      with_files.push_back(file);
    }
    with_files.insert(with_files.end(), arguments.begin() + (arguments.empty() ? 0 : 1), arguments.end());
    options.arguments(with_files);
    return options;
  }

  void on_load_node(
    const std::shared_ptr<rmw_request_id_t> header, const std::shared_ptr<LoadNode::Request> request,
    std::shared_ptr<LoadNode::Response> response) override
  {
    ComponentManager::on_load_node(header, request, response);
    if (!response->success) {
      return;
    }
    RCLCPP_INFO(get_logger(), "loaded %s from %s as %s (id %lu)", request->plugin_name.c_str(),
      request->package_name.c_str(), response->full_node_name.c_str(),
      static_cast<unsigned long>(response->unique_id));
    const BringUp asked = bring_up_of(*request);
    if (!asked.configure && !asked.activate && asked.state.empty()) {
      return;
    }
    const std::string problem = bring_up(response->unique_id, asked);
    if (problem.empty()) {
      return;
    }
    RCLCPP_ERROR(get_logger(), "%s %s: unloaded", response->full_node_name.c_str(), problem.c_str());
    remove_node_from_executor(response->unique_id);
    node_wrappers_.erase(response->unique_id);
    response->success = false;
    response->error_message = response->full_node_name + " " + problem;
    response->unique_id = 0;
  }

private:
  //! Configure a node just loaded, restore a state document into it, activate it, as asked: why it did not go, or
  //! "".
  std::string bring_up(uint64_t id, const BringUp & asked)
  {
    const auto node = ComponentNode::of(node_wrappers_[id].get_node_base_interface().get());
    if (!node) {
      return "is no iface component: its container cannot configure, restore or activate it";
    }
    if (node->configure().id() != lifecycle_msgs::msg::State::PRIMARY_STATE_INACTIVE) {
      return "did not configure";
    }
    if (!asked.state.empty()) {
      try {
        const Restored restored = node->restore_state(asked.state, DEFAULT_TIMEOUT_SEC);
        RCLCPP_INFO(get_logger(), "%s: %s", node->get_fully_qualified_name(), restored.message.c_str());
      } catch (const std::exception & e) {
        return std::string("refused the state: ") + e.what();
      }
    }
    if (asked.activate && node->activate().id() != lifecycle_msgs::msg::State::PRIMARY_STATE_ACTIVE) {
      return "did not activate";
    }
    return "";
  }

  //! The iface component this container holds under the fully qualified node name, or nullptr.
  std::shared_ptr<ComponentNode> find(const std::string & name)
  {
    for (auto & entry : node_wrappers_) {
      const auto base = entry.second.get_node_base_interface();
      if (base->get_fully_qualified_name() == name) {
        return ComponentNode::of(base.get());
      }
    }
    return nullptr;
  }

  void on_hand_over(const iface_msgs::srv::HandOver::Request & request, iface_msgs::srv::HandOver::Response & response)
  {
    const auto old_node = find(request.old_node);
    const auto new_node = find(request.new_node);
    if (!old_node || !new_node) {
      response.message = "this container holds no iface component " + (old_node ? request.new_node : request.old_node);
      RCLCPP_WARN(get_logger(), "hand-over refused: %s", response.message.c_str());
      return;
    }
    const double timeout = request.timeout_sec > 0 ? request.timeout_sec : DEFAULT_TIMEOUT_SEC;
    const HandOverAnswer answer = old_node->hand_over_to(*new_node, timeout);
    response.success = answer.success;
    response.message = answer.message;
    response.state = answer.state;
    response.restored = answer.restored;
    response.kept = answer.kept;
    response.pause_ms = answer.pause_ms;
    response.critical_ms = answer.critical_ms;
    response.after_tick = answer.after_tick;
  }

  rclcpp::Service<iface_msgs::srv::HandOver>::SharedPtr hand_over_;
  std::map<uint64_t, std::unique_ptr<GroupExecutors>> executors_;
};

}  // namespace iface_runtime

namespace
{
//! rclcpp's own signal handlers end a standby container (rclcpp::ok()): nothing else stops it.
const std::atomic<bool> g_never{false};
}  // namespace

int main(int argc, char ** argv)
{
  // --standby (the manager's spare container, docs/system.md "Standby"): ROS up, the container's node made on
  // SIGUSR1
  const auto own = rclcpp::remove_ros_arguments(argc, argv);
  const bool standby = std::find(own.begin() + 1, own.end(), "--standby") != own.end();
  const pid_t parent = iface_runtime::standby_parent();
  sigset_t told{};
  if (standby) {
    told = iface_runtime::standby_signal();  // before ROS starts its threads
  }
  rclcpp::init(argc, argv);
  std::shared_ptr<rclcpp::Node> spare;
  if (standby) {
    spare = iface_runtime::standby_node();
    if (!iface_runtime::until_told(told, g_never, parent)) {
      spare.reset();
      rclcpp::shutdown();
      return 0;
    }
  }
  auto node = std::make_shared<iface_runtime::Container>(rclcpp::NodeOptions());
  spare.reset();  // after the container's node: the participant stays up between the two
  rcl_interfaces::msg::ParameterDescriptor threads;
  threads.description = "threads of the executor of the container's own services (each loaded node's callback "
    "groups run on threads of their own)";
  threads.read_only = true;
  const int64_t count = std::max<int64_t>(
    2, node->declare_parameter("executor_threads", iface_runtime::DEFAULT_THREADS, threads));
  auto executor = std::make_shared<rclcpp::executors::MultiThreadedExecutor>(
    rclcpp::ExecutorOptions(), static_cast<size_t>(count));
  node->set_executor(executor);
  executor->add_node(node);
  executor->spin();
  executor->remove_node(node);
  node.reset();  // unloads every component (each quiesced first: ComponentFactory)
  rclcpp::shutdown();
  return 0;
}
