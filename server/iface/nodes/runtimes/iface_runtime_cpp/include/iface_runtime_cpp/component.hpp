// iface_runtime_cpp: the rclcpp_components factory of a component's node. Header
// only: the component library that registers the node (<PKG>_COMPONENT(Class) in its base.hpp) builds
// it, against its own rclcpp_components.
#ifndef IFACE_RUNTIME_CPP__COMPONENT_HPP_
#define IFACE_RUNTIME_CPP__COMPONENT_HPP_

#include <memory>

#include "iface_runtime_cpp/iface_runtime.hpp"
#include "rclcpp_components/node_factory.hpp"
#include "rclcpp_components/node_instance_wrapper.hpp"

namespace iface_runtime
{

//! rclcpp_components' factory but for the deletion. A container that unloads the node keeps spinning, and
//! rclcpp does not wait for a removed node's callbacks that have begun: the node is quiesced first
//! (ComponentNode::quiesce: none of its callbacks runs any more), then deleted.
template<class NodeT>
class ComponentFactory : public rclcpp_components::NodeFactory
{
public:
  rclcpp_components::NodeInstanceWrapper create_node_instance(const rclcpp::NodeOptions & options) override
  {
    auto node = std::make_shared<NodeT>(options);
    NodeT * raw = node.get();
    std::shared_ptr<void> instance(raw, [owner = std::move(node)](void *) mutable {
        owner->quiesce();
        owner.reset();
      });
    return rclcpp_components::NodeInstanceWrapper(
      instance, [raw](const std::shared_ptr<void> &) {return raw->get_node_base_interface();});
  }
};

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__COMPONENT_HPP_
