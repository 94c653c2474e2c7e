// Written once by iface from every_member.iface: this file is yours to edit. `iface-lsp generate`
// never overwrites it, not even with --force. When the interface changes,
// include/every_member/base.hpp is regenerated and this file stops compiling, saying why, until the
// handlers below match it: a missing handler is a pure virtual function, and a handler whose
// `override` overrides nothing handles a member the interface no longer has (`iface-lsp generate
// --check` reports both too).
//
// The behaviour of the every_member component: what it does with its members.
#include "every_member/base.hpp"

namespace every_member
{

//! every_member: keep `state` current (what ~/save_state saves and a replacement restores).
class EveryMember : public EveryMemberBase
{
public:
  using EveryMemberBase::EveryMemberBase;

  //! Called on configure, once the members exist (e.g. create_work_timer(0.1, [this] {tick();})).
  void setup() override {}

  //! subscribes Command on /station/command.
  void on_command(const Command & msg) override
  {
    (void)msg;
  }

  //! subscribes Heartbeat on heartbeat.
  void on_heartbeat(const Heartbeat & msg) override
  {
    (void)msg;
  }

  //! provides Work on /station/work.
  void handle_work(const Work::Request & request, Work::Response & response) override
  {
    (void)request;
    (void)response;
  }

  //! provides Count on ~/count.
  void handle_count(const Count::Request & request, Count::Response & response) override
  {
    (void)request;
    (void)response;
  }

  //! provides Limits.get_limit on /station/limits/get_limit.
  void handle_get_limit(
    const LimitsGetLimit::Request & request,
    LimitsGetLimit::Response & response
  ) override
  {
    (void)request;
    (void)response;
  }

  //! provides Limits.reset on /station/limits/reset.
  void handle_reset(const LimitsReset::Request & request, LimitsReset::Response & response) override
  {
    (void)request;
    (void)response;
  }

  //! provides Travel on /station/travel: goal_handle->get_goal() is the goal.
  Travel::Result::SharedPtr execute_travel(
    const std::shared_ptr<rclcpp_action::ServerGoalHandle<Travel>> & goal_handle) override
  {
    (void)goal_handle;
    return std::make_shared<Travel::Result>();
  }

  //! diagnostics diagnostics on ~/diagnostics.
  void handle_diagnostics(
    const Diagnostics::Request & request,
    Diagnostics::Response & response
  ) override
  {
    (void)request;
    (void)response;
  }
};

}  // namespace every_member

EVERY_MEMBER_COMPONENT(every_member::EveryMember)
