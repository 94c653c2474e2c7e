"""A hand-written rclpy node, /intruder, on three names of /live/talker's file with other types (issue 33).

Run with ROS 2 sourced and live_probe_msgs built: ``python3 intruder.py`` starts /intruder, which publishes
std_msgs/Int32 on /chatter (talker.iface: std_msgs/String), serves diagnostic_msgs/SelfTest on
/arm/move_to_pose (talker.iface calls robot_arm_msgs/MoveToPose there) and is an action client of /follow
with live_probe_msgs/Seek (talker.iface provides robot_arm_msgs/FollowTrajectory); prints ``ready`` and spins
until SIGTERM/SIGINT.
"""

import sys

import rclpy
from diagnostic_msgs.srv import SelfTest
from live_probe_msgs.action import Seek
from rclpy.action import ActionClient
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from std_msgs.msg import Int32


def main() -> int:
    rclpy.init()
    node = Node("intruder")
    node.create_publisher(Int32, "/chatter", 10)
    node.create_service(SelfTest, "/arm/move_to_pose", lambda req, resp: resp)
    client = ActionClient(node, Seek, "/follow")
    print("ready", flush=True)
    try:
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        client.destroy()
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
