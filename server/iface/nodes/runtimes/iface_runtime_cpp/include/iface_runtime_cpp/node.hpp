// ComponentNode: the lifecycle node every generated base class derives from (Σ, Δ, control, the protocol
// services of iface_msgs), and the QoS of its members.
#ifndef IFACE_RUNTIME_CPP__NODE_HPP_
#define IFACE_RUNTIME_CPP__NODE_HPP_

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "diagnostic_msgs/msg/diagnostic_array.hpp"
#include "iface_msgs/srv/component_control.hpp"
#include "iface_msgs/srv/describe.hpp"
#include "iface_msgs/srv/restore_state.hpp"
#include "iface_msgs/srv/save_state.hpp"
#include "iface_runtime_cpp/gate.hpp"
#include "iface_runtime_cpp/json.hpp"
#include "iface_runtime_cpp/params.hpp"
#include "iface_runtime_cpp/protocol.hpp"
#include "iface_runtime_cpp/run.hpp"
#include "iface_runtime_cpp/state.hpp"
#include "rcl_interfaces/msg/set_parameters_result.hpp"
#include "rclcpp/rclcpp.hpp"
#include "rclcpp_action/rclcpp_action.hpp"
#include "rclcpp_lifecycle/lifecycle_node.hpp"
#include "rclcpp_lifecycle/lifecycle_publisher.hpp"

namespace iface_runtime
{

//! This library's version (the one in its package.xml).
const char * runtime_version();

//! A QoS profile from the interface's qos.* settings (durations in seconds), on top of base.
rclcpp::QoS qos(const std::map<std::string, std::string> & settings, const rclcpp::QoS & base = rclcpp::QoS(10));

// ---- the node -------------------------------------------------------------------------------------

//! What the generated base class says about its component.
struct Info
{
  std::string component;
  std::string version;
  std::string interface_hash;
  std::string source;
  std::string node_name;
  std::string package;
  double diagnostics_rate = 1.0;
  std::size_t executor_threads = 4;
  Schema state_schema;
  //! The json target's file of the interface, installed as share/<package>/<interface_file>: what ~/describe
  //! answers.
  std::string interface_file;
  //! The interface as JSON, as base classes generated before runtime 1.3 carry it (answered when they
  //! install no file).
  std::string interface_json;
};

//! The text of share/<package>/<file_name> of the install that holds <package> <version>: the prefix that
//! registered the component as <package>@<version> (two versions of one component loaded into one container each
//! find their own), else the one the ament index finds for <package>; empty when it is not there.
std::string installed_interface(
  const std::string & package, const std::string & version, const std::string & file_name);

//! Answers of the component protocol, filled into the interface package's service responses.
struct SaveAnswer
{
  bool success = false;
  std::string message;
  std::string state;
};
struct RestoreAnswer
{
  bool success = false;
  std::string message;
  std::vector<std::string> restored;
  std::vector<std::string> kept;
};
struct ControlAnswer
{
  bool success = false;
  std::string message;
  bool paused = false;
  uint8_t lifecycle_state = 0;
  uint32_t in_flight = 0;
  uint64_t transactions = 0;
  std::string state;
  //! Each publisher's topic and how many subscriptions it has matched (a hand-over waits for NEW's).
  std::vector<std::string> publisher_topics;
  std::vector<uint32_t> publisher_matched;
};

//! What a hand-over inside a process did (ComponentNode::hand_over_to; a container's ~/handover answers it).
struct HandOverAnswer
{
  bool success = false;
  std::string message;
  //! OLD's state document at the pause (what NEW restored).
  std::string state;
  std::vector<std::string> restored;
  std::vector<std::string> kept;
  //! From the request to OLD paused (its next tick and its work in progress), and from OLD paused to NEW active.
  double pause_ms = 0.0;
  double critical_ms = 0.0;
  //! The work timer of OLD whose tick the switch followed ("" when none was due within ALIGN_SEC).
  std::string after_tick;
};

//! Whether intra-process communication may carry a topic of this QoS: volatile durability, keep_last history,
//! a depth. A publisher or subscription whose QoS does not allow it asks for none, whatever its node says.
rclcpp::IntraProcessSetting intra_process(const rclcpp::QoS & profile);

//! A managed node built from an interface; subclassed by the generated base class.
class ComponentNode : public rclcpp_lifecycle::LifecycleNode
{
public:
  using CallbackReturn = rclcpp_lifecycle::node_interfaces::LifecycleNodeInterface::CallbackReturn;

  ComponentNode(Info info, std::vector<ParamSpec> params, const rclcpp::NodeOptions & options);
  ~ComponentNode() override;

  //! Make the node safe to delete while an executor may still run its callbacks (a component unloaded
  //! from a container: the container's executor keeps running, and rclcpp does not wait for a removed
  //! node's callbacks): no callback of it starts any more, the running ones end (at most timeout_sec
  //! s), its goals' threads join. The component factory (COMPONENT(Class) in base.hpp) calls it.
  void quiesce(double timeout_sec = 5.0);

  //! The component node of this process whose node is base; nullptr when there is none (a node that is not an
  //! iface component, or one being deleted). One iface_runtime_cpp per process: every component registers here.
  static std::shared_ptr<ComponentNode> of(const rclcpp::node_interfaces::NodeBaseInterface * base);

  //! Hand over from this node (OLD, active) to next (NEW, configured) in this process, without a service call:
  //! right after the next tick of a work timer of OLD when one is due within ALIGN_SEC (on the tick's thread,
  //! once its work transaction has ended), else at once between transactions: OLD pauses, its state document
  //! is restored into NEW, NEW is activated (its work timers continue OLD's schedule), OLD is deactivated and
  //! its gate opened again, once NEW's first tick has come (or its bound passed: two of its periods, at most 1 s),
  //! so that nothing of OLD's runs beside that tick. On a failure OLD is left as it was: active, not paused.
  HandOverAnswer hand_over_to(ComponentNode & next, double timeout_sec);

  // ---- what the user may call or override
  //! Called on configure, once the members exist: create work timers here. Throw to fail.
  virtual void setup() {}
  //! Called on cleanup and shutdown, before the members are destroyed.
  virtual void teardown() {}
  //! Called when the node has become active.
  virtual void on_active() {}
  //! Called when the node stops being active.
  virtual void on_inactive() {}
  //! Called after a state document was restored into the state.
  virtual void state_restored() {}
  //! More key/values for /diagnostics (called from the diagnostics thread).
  virtual std::map<std::string, std::string> diagnostic_values() {return {};}
  //! Set the level ("ok", "warn", "error") and message /diagnostics shows; ("ok", "") clears it.
  void report_status(const std::string & level, const std::string & message);
  //! A timer whose calls are work transactions, run only while active; destroyed on cleanup. After a
  //! hand-over it continues the schedule of the node it replaced: its first call comes one period after
  //! that node's last call of the timer of the same name (Python names a timer after its callback).
  rclcpp::TimerBase::SharedPtr create_work_timer(
    double period_sec, std::function<void()> callback, const std::string & name = "timer");
  //! Work transactions in user code (a thread of its own): Transaction t(gate()) throws Paused while paused.
  Gate & gate() {return gate_;}
  bool is_active() const {return active_;}
  //! Threads of the executor of each reentrant group (action and client groups): none waits for another.
  std::size_t executor_threads() const {return info_.executor_threads;}
  //! True once the node has shut down.
  bool finalized() const {return finalized_;}
  const Info & info() const {return info_;}

  // ---- Σ and control, as the protocol services answer them
  //! The state document, taken between work transactions (std::runtime_error when none ends in time).
  std::string save_state(double timeout_sec = DEFAULT_TIMEOUT_SEC);
  //! Restore a state document between work transactions (StateError when refused).
  Restored restore_state(const std::string & document, double timeout_sec = DEFAULT_TIMEOUT_SEC);
  SaveAnswer answer_save(double timeout_sec);
  RestoreAnswer answer_restore(const std::string & document, double timeout_sec);
  ControlAnswer answer_control(uint8_t command, double timeout_sec);

  rclcpp::CallbackGroup::SharedPtr main_group;
  rclcpp::CallbackGroup::SharedPtr action_group;
  rclcpp::CallbackGroup::SharedPtr client_group;
  rclcpp::CallbackGroup::SharedPtr diagnostics_group;
  rclcpp::CallbackGroup::SharedPtr control_group;

protected:
  // ---- generated code fills these
  //! Publishers, subscriptions, services, clients and actions (on configure).
  virtual void create_members() {}
  //! Reset the generated fields that hold members.
  virtual void forget_members() {}
  //! The state as JSON values, one per variable.
  virtual Json::Object state_values() const {return {};}
  //! Decode values into a copy of the state and put it in place (all or nothing; StateError).
  virtual void set_state_values(const Json::Object &) {}
  virtual const MessageTypes & message_types() const;

  // ---- entities, for the generated code
  void keep(std::shared_ptr<void> entity) {entities_.push_back(std::move(entity));}
  void failed(const std::string & what, const std::string & error);

  template<class MsgT>
  std::shared_ptr<rclcpp_lifecycle::LifecyclePublisher<MsgT>> make_publisher(
    const std::string & name, const std::map<std::string, std::string> & settings)
  {
    const auto profile = qos(settings);
    rclcpp::PublisherOptions options;
    options.use_intra_process_comm = intra_process_for("publisher", name, profile);
    auto pub = this->create_publisher<MsgT>(name, profile, options);
    keep(pub);
    {
      std::lock_guard<std::mutex> lock(lock_);
      publishers_.push_back(pub);
    }
    return pub;
  }

  template<class MsgT>
  void make_subscription(
    const std::string & name, std::function<void(const MsgT &)> handler, const std::string & what,
    const std::map<std::string, std::string> & settings)
  {
    const auto profile = qos(settings);
    rclcpp::SubscriptionOptions options;
    options.callback_group = main_group;
    options.use_intra_process_comm = intra_process_for("subscription", name, profile);
    auto sub = this->create_subscription<MsgT>(
      name, profile,
      [this, handler, what](const MsgT & msg) {work([&] {handler(msg);}, what);}, options);
    keep(sub);
  }

  template<class SrvT>
  void make_server(
    const std::string & name,
    std::function<void(const typename SrvT::Request &, typename SrvT::Response &)> handler,
    const std::map<std::string, std::string> & settings, bool is_work)
  {
    auto callback = [this, handler, name, is_work](
      const std::shared_ptr<typename SrvT::Request> request, std::shared_ptr<typename SrvT::Response> response) {
        serve(name, is_work, [&] {handler(*request, *response);}, [&] {*response = typename SrvT::Response();});
      };
    auto srv = this->create_service<SrvT>(
      name, callback, qos(settings, rclcpp::ServicesQoS()), is_work ? main_group : diagnostics_group);
    if (is_work) {
      keep(srv);
    } else {
      services_.push_back(srv);
    }
  }

  template<class SrvT>
  std::shared_ptr<rclcpp::Client<SrvT>> make_client(
    const std::string & name, const std::map<std::string, std::string> & settings)
  {
    auto client = this->create_client<SrvT>(name, qos(settings, rclcpp::ServicesQoS()), client_group);
    keep(client);
    return client;
  }

  template<class SrvT>
  typename SrvT::Response::SharedPtr call(
    const std::shared_ptr<rclcpp::Client<SrvT>> & client, typename SrvT::Request::SharedPtr request,
    double timeout_sec)
  {
    if (!client) {
      throw std::runtime_error("the node is not configured: clients exist from configure to cleanup");
    }
    const auto timeout = std::chrono::duration<double>(timeout_sec);
    if (!client->wait_for_service(timeout)) {
      throw std::runtime_error(std::string(client->get_service_name()) + " is not available after " +
              py_float(timeout_sec) + " s");
    }
    auto pending = client->async_send_request(request);
    if (pending.future.wait_for(timeout) != std::future_status::ready) {
      client->remove_pending_request(pending.request_id);
      throw std::runtime_error(std::string("no answer from ") + client->get_service_name() + " within " +
              py_float(timeout_sec) + " s");
    }
    return pending.future.get();
  }

  template<class ActionT>
  void make_action_server(
    const std::string & name,
    std::function<typename ActionT::Result::SharedPtr(
      const std::shared_ptr<rclcpp_action::ServerGoalHandle<ActionT>> &)> execute,
    std::function<bool(const typename ActionT::Goal &)> accept,
    std::function<bool(const std::shared_ptr<rclcpp_action::ServerGoalHandle<ActionT>> &)> cancel,
    const std::map<std::string, std::string> & settings)
  {
    using Handle = rclcpp_action::ServerGoalHandle<ActionT>;
    rcl_action_server_options_t options = rcl_action_server_get_default_options();
    if (!settings.empty()) {
      const auto services = qos(settings, rclcpp::ServicesQoS()).get_rmw_qos_profile();
      options.goal_service_qos = services;
      options.result_service_qos = services;
      options.cancel_service_qos = services;
      options.feedback_topic_qos = qos(settings).get_rmw_qos_profile();
    }
    auto server = rclcpp_action::create_server<ActionT>(
      this, name,
      [this, accept](const rclcpp_action::GoalUUID &, std::shared_ptr<const typename ActionT::Goal> goal) {
        if (!active_ || gate_.paused()) {
          return rclcpp_action::GoalResponse::REJECT;
        }
        return accept(*goal) ? rclcpp_action::GoalResponse::ACCEPT_AND_EXECUTE :
        rclcpp_action::GoalResponse::REJECT;
      },
      [cancel](const std::shared_ptr<Handle> handle) {
        return cancel(handle) ? rclcpp_action::CancelResponse::ACCEPT : rclcpp_action::CancelResponse::REJECT;
      },
      [this, execute, name](const std::shared_ptr<Handle> handle) {
        std::lock_guard<std::mutex> lock(goals_mutex_);
        goals_.emplace_back([this, execute, name, handle] {run_goal<ActionT>(handle, execute, name);});
      },
      options, action_group);
    keep(server);
  }

  template<class ActionT>
  std::shared_ptr<rclcpp_action::Client<ActionT>> make_action_client(
    const std::string & name, const std::map<std::string, std::string> & settings)
  {
    rcl_action_client_options_t options = rcl_action_client_get_default_options();
    if (!settings.empty()) {
      const auto services = qos(settings, rclcpp::ServicesQoS()).get_rmw_qos_profile();
      options.goal_service_qos = services;
      options.result_service_qos = services;
      options.cancel_service_qos = services;
      options.feedback_topic_qos = qos(settings).get_rmw_qos_profile();
    }
    auto client = rclcpp_action::create_client<ActionT>(this, name, client_group, options);
    keep(client);
    return client;
  }

  template<class ActionT>
  typename rclcpp_action::ClientGoalHandle<ActionT>::WrappedResult send_goal(
    const std::shared_ptr<rclcpp_action::Client<ActionT>> & client, const typename ActionT::Goal & goal,
    typename rclcpp_action::Client<ActionT>::SendGoalOptions options, double timeout_sec)
  {
    if (!client) {
      throw std::runtime_error("the node is not configured: action clients exist from configure to cleanup");
    }
    const auto timeout = std::chrono::duration<double>(timeout_sec);
    if (!client->wait_for_action_server(timeout)) {
      throw std::runtime_error("the action server is not available after " + py_float(timeout_sec) + " s");
    }
    auto sent = client->async_send_goal(goal, options);
    if (sent.wait_for(timeout) != std::future_status::ready) {
      throw std::runtime_error("no answer from the goal within " + py_float(timeout_sec) + " s");
    }
    auto handle = sent.get();
    if (!handle) {
      throw std::runtime_error("the goal was rejected");
    }
    auto result = client->async_get_result(handle);
    if (result.wait_for(timeout) != std::future_status::ready) {
      throw std::runtime_error("no answer from the result within " + py_float(timeout_sec) + " s");
    }
    return result.get();
  }

  template<class MsgT>
  void publish(const std::shared_ptr<rclcpp_lifecycle::LifecyclePublisher<MsgT>> & publisher, const MsgT & msg)
  {
    if (!publisher) {
      throw std::runtime_error("the node is not configured: publishers exist from configure to cleanup");
    }
    publisher->publish(msg);
  }

  // ---- lifecycle
  CallbackReturn on_configure(const rclcpp_lifecycle::State & state) override;
  CallbackReturn on_activate(const rclcpp_lifecycle::State & state) override;
  CallbackReturn on_deactivate(const rclcpp_lifecycle::State & state) override;
  CallbackReturn on_cleanup(const rclcpp_lifecycle::State & state) override;
  CallbackReturn on_shutdown(const rclcpp_lifecycle::State & state) override;
  CallbackReturn on_error(const rclcpp_lifecycle::State & state) override;

  //! The current value of a parameter.
  rclcpp::Parameter parameter(const std::string & name) const {return this->get_parameter(name);}
  //! The intra-process setting of a publisher or subscription of this QoS (intra_process), noted for the log of
  //! configure when the node uses intra-process communication.
  rclcpp::IntraProcessSetting intra_process_for(
    const std::string & what, const std::string & topic, const rclcpp::QoS & profile);
  //! Keep a Δ service (served from construction to the end).
  void keep_service(rclcpp::ServiceBase::SharedPtr service) {services_.push_back(std::move(service));}

private:
  //! A work timer: its period, its callback, the timer, and the one-shot (stopped until then) that continues a
  //! restored schedule.
  struct WorkTimer
  {
    std::string name;
    double period = 0.0;
    std::atomic<int64_t> last_ns{0};
    std::function<void()> callback;
    rclcpp::TimerBase::SharedPtr timer;
    rclcpp::TimerBase::SharedPtr first;
  };
  //! One tick of a work timer, as a work transaction; notes the time it ran; then runs what waits for a tick.
  void tick(WorkTimer & t);
  //! The critical section of hand_over_to.
  HandOverAnswer switch_to(
    ComponentNode & next, double timeout_sec, std::chrono::steady_clock::time_point asked, const std::string & after);
  //! Before a pause: wait for the next tick of the work timer due soonest, when it is due within ALIGN_SEC, so
  //! that a hand-over's silence on its topic holds the critical section only, not also part of a period.
  void await_tick(double timeout_sec);
  //! On activate after a restore: each work timer's first tick one period after the last tick of the node
  //! that saved the state (its document's "schedule"), not one period after this activation. Its log line
  //! waits in schedule_notes_ while quiet_schedule_ is set (a hand-over logs it after NEW's first tick).
  void continue_schedule();
  //! The latest tick of any work timer (wall clock, ns; 0: none yet).
  int64_t last_tick_ns();
  //! Wait until a work timer ticks after since_ns, at most timeout_sec.
  void await_tick_after(int64_t since_ns, double timeout_sec);
  //! Run body as a work transaction; false when it did not run (inactive or paused).
  bool work(const std::function<void()> & body, const std::string & what);
  void serve(
    const std::string & name, bool is_work, const std::function<void()> & body,
    const std::function<void()> & reset);
  template<class ActionT>
  void run_goal(
    const std::shared_ptr<rclcpp_action::ServerGoalHandle<ActionT>> & handle,
    const std::function<typename ActionT::Result::SharedPtr(
      const std::shared_ptr<rclcpp_action::ServerGoalHandle<ActionT>> &)> & execute,
    const std::string & name)
  {
    if (!gate_.enter()) {
      handle->abort(std::make_shared<typename ActionT::Result>());
      return;
    }
    try {
      auto result = execute(handle);
      if (!result) {
        result = std::make_shared<typename ActionT::Result>();
      }
      if (handle->is_active()) {
        if (handle->is_canceling()) {
          handle->canceled(result);
        } else {
          handle->succeed(result);
        }
      }
    } catch (const std::exception & e) {
      failed(name, e.what());
      if (handle->is_active()) {
        handle->abort(std::make_shared<typename ActionT::Result>());
      }
    }
    gate_.leave();
  }
  void serve_protocol();
  void end();
  void destroy_members();
  void join_goals();
  std::string lifecycle_label();
  void publish_diagnostics();
  CallbackReturn check_configure();
  rcl_interfaces::msg::SetParametersResult check_parameters(const std::vector<rclcpp::Parameter> & params);

  Info info_;
  std::vector<ParamSpec> params_;
  Gate gate_;
  //! How long cleanup, shutdown and error wait for the work in progress before destroying the members.
  static constexpr double kCloseTimeoutSec = 5.0;
  std::atomic<bool> active_{false};
  std::atomic<bool> finalized_{false};
  //! Set by quiesce(): the node is about to be deleted, its callbacks return at once.
  std::atomic<bool> closing_{false};
  std::vector<std::shared_ptr<void>> entities_;
  std::vector<std::shared_ptr<WorkTimer>> work_timers_;
  //! The publishers of the members, for the matched counts of ~/control (guarded by lock_).
  std::vector<std::weak_ptr<rclcpp::PublisherBase>> publishers_;
  std::mutex tick_mutex_;
  std::condition_variable ticked_;
  //! Run once by the next tick of any work timer, on its thread, after its work transaction (a hand-over).
  std::function<void(const std::string &)> after_tick_;
  //! With intra-process communication: the members that use it, and those whose QoS keeps them on DDS.
  std::vector<std::string> in_process_;
  std::vector<std::string> over_dds_;
  //! The restored document's schedule, until the next activation continues from it.
  std::map<std::string, int64_t> restored_schedule_;
  //! When continue_schedule last started a first tick (steady clock; 0: never): a hand-over's report.
  std::atomic<int64_t> schedule_set_ns_{0};
  bool quiet_schedule_ = false;
  std::vector<std::string> schedule_notes_;
  std::vector<rclcpp::ServiceBase::SharedPtr> services_;
  std::mutex goals_mutex_;
  std::vector<std::thread> goals_;
  std::mutex lock_;
  uint64_t dropped_inactive_ = 0;
  uint64_t errors_ = 0;
  std::string last_error_;
  bool error_seen_ = false;
  std::optional<std::pair<uint8_t, std::string>> status_;
  rclcpp::Publisher<diagnostic_msgs::msg::DiagnosticArray>::SharedPtr diagnostics_pub_;
  rclcpp::TimerBase::SharedPtr diagnostics_timer_;
  rclcpp::node_interfaces::OnSetParametersCallbackHandle::SharedPtr on_set_;
};

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__NODE_HPP_
