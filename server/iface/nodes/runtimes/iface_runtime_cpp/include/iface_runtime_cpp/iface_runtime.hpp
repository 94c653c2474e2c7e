// iface_runtime_cpp: the node machinery every component iface generates for
// rclcpp links (one shared library): the state document, parameter checks, work transactions, the
// lifecycle, Δ and Σ, and the protocol services of iface_msgs (~/save_state, ~/restore_state,
// ~/control, ~/describe). The same rules as iface_runtime_py (docs/runtime.md): a state saved by
// either node restores into the other.
//
// Callback groups, and why:
// - main_group (mutually exclusive): subscriptions, services, work timers; each call is a work
//   transaction, the user's main code runs one callback at a time;
// - action_group (reentrant): action servers' goal and cancel requests (each goal then runs in
//   a thread of its own, one work transaction);
// - client_group (reentrant): service and action clients, so a handler can wait for an answer;
// - diagnostics_group: the /diagnostics timer and the Δ services;
// - control_group: ~/control, ~/save_state, ~/restore_state.
// Each group runs on an executor and a thread of its own (group_executors.hpp; a reentrant group on several),
// so diagnostics and control are answered while the work runs.
//
// The parts, each its own header: protocol.hpp (the protocol's constants), json.hpp, state.hpp (the
// state document), params.hpp, gate.hpp (work transactions), node.hpp (ComponentNode),
// group_executors.hpp (its groups' threads), run.hpp (what an executable's main calls), component.hpp
// (a container's factory). A generated component includes this one.
#ifndef IFACE_RUNTIME_CPP__IFACE_RUNTIME_HPP_
#define IFACE_RUNTIME_CPP__IFACE_RUNTIME_HPP_

#include "iface_runtime_cpp/gate.hpp"
#include "iface_runtime_cpp/json.hpp"
#include "iface_runtime_cpp/node.hpp"
#include "iface_runtime_cpp/params.hpp"
#include "iface_runtime_cpp/protocol.hpp"
#include "iface_runtime_cpp/run.hpp"
#include "iface_runtime_cpp/state.hpp"

#endif  // IFACE_RUNTIME_CPP__IFACE_RUNTIME_HPP_
