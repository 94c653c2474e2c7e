// A node's callback groups on executors and threads of their own: see group_executors.hpp.
#include "iface_runtime_cpp/group_executors.hpp"

#include <pthread.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <utility>

#include "rclcpp/executors.hpp"
#include "rclcpp/utilities.hpp"

namespace iface_runtime
{

GroupExecutors::GroupExecutors(
  rclcpp::node_interfaces::NodeBaseInterface::SharedPtr node, std::size_t reentrant_threads)
: node_(std::move(node))
{
  const std::size_t threads = std::max<std::size_t>(2, reentrant_threads);
  node_->for_each_callback_group([this, threads](const rclcpp::CallbackGroup::SharedPtr & group) {
      if (!group->automatically_add_to_executor_with_node()) {
        return;  // a group its node adds to an executor of its own
      }
      if (group->type() == rclcpp::CallbackGroupType::Reentrant) {
        executors_.push_back(
          std::make_shared<rclcpp::executors::MultiThreadedExecutor>(rclcpp::ExecutorOptions(), threads));
      } else {
        executors_.push_back(std::make_shared<rclcpp::executors::SingleThreadedExecutor>());
      }
      executors_.back()->add_callback_group(group, node_);
    });
  executors_.push_back(std::make_shared<rclcpp::executors::SingleThreadedExecutor>());
  executors_.back()->add_node(node_);
  const std::string name = std::string(node_->get_name()).substr(0, 15);  // a thread name's limit
  for (const auto & executor : executors_) {
    threads_.emplace_back([executor, name] {
        pthread_setname_np(pthread_self(), name.c_str());
        executor->spin();
      });
  }
}

GroupExecutors::~GroupExecutors()
{
  stop();
}

void GroupExecutors::stop()
{
  const auto context = node_->get_context();
  for (std::size_t i = 0; i < executors_.size() && i < threads_.size(); ++i) {
    while (threads_[i].joinable() && !executors_[i]->is_spinning() && rclcpp::ok(context)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    executors_[i]->cancel();
  }
  for (auto & thread : threads_) {
    if (thread.joinable()) {
      thread.join();
    }
  }
  threads_.clear();
}

}  // namespace iface_runtime
