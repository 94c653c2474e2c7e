// iface_runtime_cpp: a node's callback groups, each on an executor and threads of its own. Used by a component's
// executable (run.cpp) and by iface_container for each node it loads.
#ifndef IFACE_RUNTIME_CPP__GROUP_EXECUTORS_HPP_
#define IFACE_RUNTIME_CPP__GROUP_EXECUTORS_HPP_

#include <cstddef>
#include <memory>
#include <thread>
#include <vector>

#include "rclcpp/executor.hpp"
#include "rclcpp/node_interfaces/node_base_interface.hpp"

namespace iface_runtime
{

//! Each callback group of a node on an executor of its own, spun by threads of its own named as the node (what
//! `top -H` shows): a single-threaded executor for a mutually exclusive group, a multi-threaded one of
//! ``reentrant_threads`` threads for a reentrant group, and one more single-threaded executor for the groups the
//! node makes later. rclcpp's multi-threaded executor collects every entity it holds again after each callback of
//! a mutually exclusive group and wakes its threads for each event: a 1 kHz timer cost it 0.44 CPU seconds a
//! second, a single-threaded executor 0.13 (docs/system.md, "Each callback group on a thread of its own").
class GroupExecutors
{
public:
  GroupExecutors(rclcpp::node_interfaces::NodeBaseInterface::SharedPtr node, std::size_t reentrant_threads);
  ~GroupExecutors();
  GroupExecutors(const GroupExecutors &) = delete;
  GroupExecutors & operator=(const GroupExecutors &) = delete;

  //! Cancel each executor once it spins (a cancel before its spin started would be lost) and wait for its thread.
  void stop();

private:
  rclcpp::node_interfaces::NodeBaseInterface::SharedPtr node_;
  std::vector<std::shared_ptr<rclcpp::Executor>> executors_;
  std::vector<std::thread> threads_;
};

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__GROUP_EXECUTORS_HPP_
