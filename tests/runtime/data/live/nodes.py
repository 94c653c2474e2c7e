"""Hand-written rclpy nodes (not generated) for the live import and verify tests.

Run with ROS 2 sourced and robot_arm_msgs built (its action and service types):
``python3 nodes.py`` starts /live/talker, /live/listener and the lifecycle node /live/lifer in one
process, prints ``ready`` and spins until SIGTERM/SIGINT.
"""

import sys

import rclpy
from diagnostic_msgs.srv import AddDiagnostics
from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.action import ActionServer
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException, MultiThreadedExecutor
from rclpy.lifecycle import LifecycleNode
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, LivelinessPolicy, QoSProfile, ReliabilityPolicy
from rclpy.qos_overriding_options import QoSOverridingOptions
from robot_arm_msgs.action import FollowTrajectory
from robot_arm_msgs.srv import MoveToPose
from std_msgs.msg import Int32, String


class Talker(Node):
    """Non-default QoS both ways, a service, a client, an action server, parameters of every kind."""

    def __init__(self) -> None:
        super().__init__("talker", namespace="/live")
        chatter = QoSProfile(depth=5, reliability=ReliabilityPolicy.BEST_EFFORT,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL, deadline=Duration(seconds=2))
        self.chatter = self.create_publisher(String, "/chatter", chatter,
                                             qos_overriding_options=QoSOverridingOptions.with_default_policies())
        self.extra = self.create_publisher(Int32, "/extra", 10)
        numbers = QoSProfile(depth=10, liveliness=LivelinessPolicy.MANUAL_BY_TOPIC,
                             liveliness_lease_duration=Duration(seconds=3))
        self.create_subscription(Int32, "/numbers", lambda msg: None, numbers)
        self.create_service(AddDiagnostics, "~/add", lambda req, resp: resp)
        self.client = self.create_client(MoveToPose, "/arm/move_to_pose")
        self.action = ActionServer(self, FollowTrajectory, "/follow", lambda goal: FollowTrajectory.Result())
        self.declare_parameter("rate", 2.5, ParameterDescriptor(
            description="Loop rate.", additional_constraints="unit: Hz",
            floating_point_range=[FloatingPointRange(from_value=0.5, to_value=10.0, step=0.0)]))
        self.declare_parameter("count", 50, ParameterDescriptor(
            integer_range=[IntegerRange(from_value=0, to_value=100, step=1)]))
        self.declare_parameter("frame", "base", ParameterDescriptor(description="Frame of the readings.",
                                                                     read_only=True))
        self.declare_parameter("gains", [1.0, 2.0])
        self.declare_parameter("verbose", False)


class Listener(Node):
    """A reliable subscription to a best-effort topic: the QoS pair that cannot match."""

    def __init__(self) -> None:
        super().__init__("listener", namespace="/live")
        self.create_subscription(String, "/chatter", lambda msg: None, 10)
        self.create_subscription(Int32, "/numbers", lambda msg: None, 10)
        self.declare_parameter("threshold", 7)


class Lifer(LifecycleNode):
    """A lifecycle node with one lifecycle publisher."""

    def __init__(self) -> None:
        super().__init__("lifer", namespace="/live")
        self.status = self.create_lifecycle_publisher(String, "/live/status", 10)


def main() -> int:
    rclpy.init()
    nodes = [Talker(), Listener(), Lifer()]
    executor = MultiThreadedExecutor()
    for n in nodes:
        executor.add_node(n)
    # rclpy's own SIGINT/SIGTERM handlers shut the context down: spin then ends
    print("ready", flush=True)
    try:
        executor.spin()
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        executor.shutdown(timeout_sec=2)
        for n in nodes:
            n.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
