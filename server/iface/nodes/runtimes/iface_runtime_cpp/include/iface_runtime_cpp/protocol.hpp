// The constants of the component protocol this library speaks (iface's iface.nodes.protocol), written
// here once for the C++ runtime; a test of iface ties each one to the protocol's definition.
#ifndef IFACE_RUNTIME_CPP__PROTOCOL_HPP_
#define IFACE_RUNTIME_CPP__PROTOCOL_HPP_

#include <cstdint>

namespace iface_runtime
{

//! The version tag of the state document.
inline constexpr const char * STATE_FORMAT = "iface-state/1";
//! The version of the protocol (iface_msgs) this library speaks.
inline constexpr const char * PROTOCOL_VERSION = "1";
//! Where every component publishes diagnostic_msgs/DiagnosticArray.
inline constexpr const char * DIAGNOSTICS_TOPIC = "/diagnostics";
//! How long PAUSE, SAVE and RESTORE wait for a work transaction to end when the request says 0.
inline constexpr double DEFAULT_TIMEOUT_SEC = 10.0;
//! PAUSE first lets the next tick of a work timer run when it is due within this many seconds (await_tick).
inline constexpr double ALIGN_SEC = 0.1;
//! ComponentControl commands.
inline constexpr uint8_t STATUS = 0, PAUSE = 1, RESUME = 2, SAVE = 3;

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__PROTOCOL_HPP_
