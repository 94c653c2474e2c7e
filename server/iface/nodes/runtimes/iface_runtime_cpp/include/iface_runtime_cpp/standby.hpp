// iface_runtime_cpp: a standby, the component manager's spare process for a fast restart (docs/system.md,
// "Standby"). A component's executable (run.hpp) and iface_container take --standby: ROS up with a hidden node of
// no endpoints, so that the process's DDS participant is up and discovered before it is needed, and the
// component's (or the container's) node made on SIGUSR1.
#ifndef IFACE_RUNTIME_CPP__STANDBY_HPP_
#define IFACE_RUNTIME_CPP__STANDBY_HPP_

#include <atomic>
#include <csignal>
#include <memory>

#include <sys/types.h>

#include "rclcpp/node.hpp"

namespace iface_runtime
{

//! SIGUSR1, the standby's order: blocked (call it before ROS starts its threads, which then leave it pending for
//! until_told), then a handler that does nothing, which tells the manager that the standby is ready (SigCgt) and
//! makes a second SIGUSR1 end nothing.
sigset_t standby_signal();

//! The hidden node a standby holds until it is told ("_iface_standby_<pid>"): no global ROS arguments (__node:=
//! and parameter files are the component's), no rosout, parameter or type description endpoints.
std::shared_ptr<rclcpp::Node> standby_node();

//! The process whose end ends a standby: the one IFACE_STANDBY_PARENT names (the manager sets it to its own pid, so
//! that one that ended before the standby looked is seen too), else the parent at this call.
pid_t standby_parent();

//! Wait for SIGUSR1: false when `stop` is set (a signal handler of the caller), ROS shuts down, or `parent` is no
//! longer this process's parent (it ended first).
bool until_told(const sigset_t & told, const std::atomic<bool> & stop, pid_t parent);

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__STANDBY_HPP_
