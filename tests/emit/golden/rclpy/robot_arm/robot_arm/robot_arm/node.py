# Written once by iface from robot_arm.iface: this file is yours to edit. `iface-lsp generate` never
# overwrites it, not even with --force. When the interface changes, base.py is regenerated and the
# node refuses to start (as `iface-lsp generate --check` does) until the handlers below match it.
"""The behaviour of the robot_arm component: what it does with its members."""

from __future__ import annotations

from typing import Any

from robot_arm_msgs.action import FollowTrajectory
from robot_arm_msgs.msg import JointCommand
from robot_arm_msgs.srv import (
    ArmDiagnostics,
    JointLimitsServiceClearFault,
    JointLimitsServiceGetLimits,
    JointLimitsServiceSetLimits,
    MoveToPose,
)

from .base import RobotArmBase


class RobotArm(RobotArmBase):
    """robot_arm: keep self.state current (what ~/save_state saves and a replacement restores)."""

    def setup(self) -> None:
        """On configure, once the members exist: e.g. self.create_work_timer(0.1, self.tick)."""

    def on_joint_command(self, msg: JointCommand) -> None:
        """subscribes JointCommand on /arm/joint_command."""

    def handle_move_to_pose(
        self,
        request: MoveToPose.Request,
        response: MoveToPose.Response
    ) -> MoveToPose.Response:
        """provides MoveToPose on /arm/move_to_pose."""
        return response

    def handle_get_limits(
        self,
        request: JointLimitsServiceGetLimits.Request,
        response: JointLimitsServiceGetLimits.Response
    ) -> JointLimitsServiceGetLimits.Response:
        """provides JointLimitsService.get_limits on /arm/joint_limits/get_limits."""
        return response

    def handle_set_limits(
        self,
        request: JointLimitsServiceSetLimits.Request,
        response: JointLimitsServiceSetLimits.Response
    ) -> JointLimitsServiceSetLimits.Response:
        """provides JointLimitsService.set_limits on /arm/joint_limits/set_limits."""
        return response

    def handle_clear_fault(
        self,
        request: JointLimitsServiceClearFault.Request,
        response: JointLimitsServiceClearFault.Response
    ) -> JointLimitsServiceClearFault.Response:
        """provides JointLimitsService.clear_fault on /arm/joint_limits/clear_fault."""
        return response

    def execute_follow_trajectory(self, goal_handle: Any) -> FollowTrajectory.Result:
        """provides FollowTrajectory on /arm/follow_trajectory: goal_handle.request is the goal."""
        return FollowTrajectory.Result()

    def handle_diagnostics(
        self,
        request: ArmDiagnostics.Request,
        response: ArmDiagnostics.Response
    ) -> ArmDiagnostics.Response:
        """diagnostics ArmDiagnostics on /arm/diagnostics."""
        return response
