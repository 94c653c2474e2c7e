// A standby: see standby.hpp.
#include "iface_runtime_cpp/standby.hpp"

#include <pthread.h>
#include <unistd.h>

#include <cstdlib>
#include <ctime>
#include <string>

#include "rclcpp/rclcpp.hpp"

namespace iface_runtime
{

namespace
{

void on_told(int)
{
}

}  // namespace

sigset_t standby_signal()
{
  sigset_t told;
  sigemptyset(&told);
  sigaddset(&told, SIGUSR1);
  pthread_sigmask(SIG_BLOCK, &told, nullptr);
  std::signal(SIGUSR1, on_told);
  return told;
}

std::shared_ptr<rclcpp::Node> standby_node()
{
  return std::make_shared<rclcpp::Node>("_iface_standby_" + std::to_string(getpid()), rclcpp::NodeOptions()
    .use_global_arguments(false).enable_rosout(false).start_parameter_services(false)
    .start_parameter_event_publisher(false)
    .parameter_overrides({rclcpp::Parameter("start_type_description_service", false)}));
}

pid_t standby_parent()
{
  const char * given = std::getenv("IFACE_STANDBY_PARENT");
  if (given != nullptr && *given != '\0') {
    char * end = nullptr;
    const long pid = std::strtol(given, &end, 10);
    if (*end == '\0' && pid > 0) {
      return static_cast<pid_t>(pid);
    }
  }
  return getppid();
}

bool until_told(const sigset_t & told, const std::atomic<bool> & stop, pid_t parent)
{
  const timespec look{0, 200 * 1000 * 1000};
  while (sigtimedwait(&told, nullptr, &look) < 0) {
    if (stop || !rclcpp::ok() || getppid() != parent) {
      return false;
    }
  }
  return true;
}

}  // namespace iface_runtime
