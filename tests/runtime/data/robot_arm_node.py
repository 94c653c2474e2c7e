# The user module of robot_arm for the end-to-end tests: it replaces the node.py that iface writes
# once, as a developer would, and must survive regeneration.
"""robot_arm's behaviour for the tests: follows commands, counts them in its state, moves slowly."""

from __future__ import annotations

import time
from typing import Any

from robot_arm_msgs.action import FollowTrajectory
from robot_arm_msgs.msg import JointCommand, JointState
from robot_arm_msgs.srv import (
    ArmDiagnostics,
    JointLimitsServiceClearFault,
    JointLimitsServiceGetLimits,
    JointLimitsServiceSetLimits,
    MoveToPose,
)

from .base import RobotArmBase


class RobotArm(RobotArmBase):
    """Each JointCommand advances state.trajectory_index; JointState is published at a fixed rate."""

    NOT_HANDLERS = ("on_tick",)

    def setup(self) -> None:
        self.create_work_timer(1.0 / min(self.params.rate_hz, 20.0), self.on_tick)

    def on_tick(self) -> None:
        msg = JointState(timestamp=self.get_clock().now().nanoseconds // 1000, velocity=list(self.state.setpoint),
                         mode=self.state.mode)
        msg.position = [float(self.state.trajectory_index)] * 6
        self.publish_joint_state(msg)

    def on_joint_command(self, msg: JointCommand) -> None:
        self.state.trajectory_index += 1
        self.state.setpoint = list(msg.velocity) if msg.enable else [0.0] * 6
        self.state.mode = JointState.ARM_MODE_MOVING if msg.enable else JointState.ARM_MODE_IDLE

    def handle_move_to_pose(self, request: MoveToPose.Request, response: MoveToPose.Response) -> MoveToPose.Response:
        time.sleep(3.0 * request.speed_scale)  # a slow move: one long work transaction
        response.success = bool(request.target.frame_id)
        response.message = f"moved in {request.target.frame_id} at {request.speed_scale:.2f}"
        return response

    def handle_get_limits(self, request: JointLimitsServiceGetLimits.Request,
                          response: JointLimitsServiceGetLimits.Response) -> Any:
        response.result.joint_name = f"joint{request.joint}"
        response.result.max_velocity = self.params.max_speed
        return response

    def handle_set_limits(self, request: JointLimitsServiceSetLimits.Request,
                          response: JointLimitsServiceSetLimits.Response) -> Any:
        response.result = request.limits.lower < request.limits.upper
        return response

    def handle_clear_fault(self, request: JointLimitsServiceClearFault.Request,
                           response: JointLimitsServiceClearFault.Response) -> Any:
        self.state.mode = JointState.ARM_MODE_IDLE
        return response

    def execute_follow_trajectory(self, goal_handle: Any) -> FollowTrajectory.Result:
        points = goal_handle.request.points
        for i, _ in enumerate(points):
            if goal_handle.is_cancel_requested:
                return FollowTrajectory.Result(success=False)
            self.state.trajectory_index += 1
            goal_handle.publish_feedback(FollowTrajectory.Feedback(current_point=i,
                                                                   progress=100.0 * (i + 1) / len(points)))
            time.sleep(0.02)
        return FollowTrajectory.Result(success=True, reason=FollowTrajectory.Result.STOP_REASON_NONE)

    def handle_diagnostics(self, request: ArmDiagnostics.Request, response: ArmDiagnostics.Response) -> Any:
        response.summary = f"{'active' if self.active else 'inactive'}, level {request.level}"
        response.error_count = 0
        return response
