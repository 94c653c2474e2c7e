// Written once by iface from robot_arm.iface: this file is yours to edit. `iface-lsp generate`
// never overwrites it, not even with --force. When the interface changes,
// include/robot_arm/base.hpp is regenerated and this file stops compiling, saying why, until the
// handlers below match it: a missing handler is a pure virtual function, and a handler whose
// `override` overrides nothing handles a member the interface no longer has (`iface-lsp generate
// --check` reports both too).
//
// The behaviour of the robot_arm component: what it does with its members.
#include "robot_arm/base.hpp"

namespace robot_arm
{

//! robot_arm: keep `state` current (what ~/save_state saves and a replacement restores).
class RobotArm : public RobotArmBase
{
public:
  using RobotArmBase::RobotArmBase;

  //! Called on configure, once the members exist (e.g. create_work_timer(0.1, [this] {tick();})).
  void setup() override {}

  //! subscribes JointCommand on /arm/joint_command.
  void on_joint_command(const JointCommand & msg) override
  {
    (void)msg;
  }

  //! provides MoveToPose on /arm/move_to_pose.
  void handle_move_to_pose(
    const MoveToPose::Request & request,
    MoveToPose::Response & response
  ) override
  {
    (void)request;
    (void)response;
  }

  //! provides JointLimitsService.get_limits on /arm/joint_limits/get_limits.
  void handle_get_limits(
    const JointLimitsServiceGetLimits::Request & request,
    JointLimitsServiceGetLimits::Response & response
  ) override
  {
    (void)request;
    (void)response;
  }

  //! provides JointLimitsService.set_limits on /arm/joint_limits/set_limits.
  void handle_set_limits(
    const JointLimitsServiceSetLimits::Request & request,
    JointLimitsServiceSetLimits::Response & response
  ) override
  {
    (void)request;
    (void)response;
  }

  //! provides JointLimitsService.clear_fault on /arm/joint_limits/clear_fault.
  void handle_clear_fault(
    const JointLimitsServiceClearFault::Request & request,
    JointLimitsServiceClearFault::Response & response
  ) override
  {
    (void)request;
    (void)response;
  }

  //! provides FollowTrajectory on /arm/follow_trajectory: goal_handle->get_goal() is the goal.
  FollowTrajectory::Result::SharedPtr execute_follow_trajectory(
    const std::shared_ptr<rclcpp_action::ServerGoalHandle<FollowTrajectory>> & goal_handle) override
  {
    (void)goal_handle;
    return std::make_shared<FollowTrajectory::Result>();
  }

  //! diagnostics ArmDiagnostics on /arm/diagnostics.
  void handle_diagnostics(
    const ArmDiagnostics::Request & request,
    ArmDiagnostics::Response & response
  ) override
  {
    (void)request;
    (void)response;
  }
};

}  // namespace robot_arm

ROBOT_ARM_COMPONENT(robot_arm::RobotArm)
