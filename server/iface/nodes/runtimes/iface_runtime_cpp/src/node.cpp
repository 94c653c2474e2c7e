// ComponentNode: see node.hpp.
#include "iface_runtime_cpp/node.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include "ament_index_cpp/get_package_share_directory.hpp"
#include "ament_index_cpp/get_resource.hpp"
#include "lifecycle_msgs/msg/state.hpp"
#include "rcl/error_handling.h"
#include "rcl/timer.h"
#include "rclcpp/create_timer.hpp"

#ifndef IFACE_RUNTIME_CPP_VERSION
#error "IFACE_RUNTIME_CPP_VERSION: CMakeLists.txt defines it from package.xml"
#endif

namespace iface_runtime
{

const char * runtime_version()
{
  return IFACE_RUNTIME_CPP_VERSION;
}

std::string installed_interface(
  const std::string & package, const std::string & version, const std::string & file_name)
{
  try {
    std::string content, prefix;
    const std::filesystem::path share =
      ament_index_cpp::get_resource("rclcpp_components", package + "@" + version, content, &prefix) ?
      std::filesystem::path(prefix) / "share" / package :
      std::filesystem::path(ament_index_cpp::get_package_share_directory(package));
    std::ifstream in(share / file_name, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return in ? text.str() : std::string();
  } catch (const std::exception &) {
    return "";  // not installed through ament
  }
}

// ---- QoS ----------------------------------------------------------------------------------------------

rclcpp::QoS qos(const std::map<std::string, std::string> & settings, const rclcpp::QoS & base)
{
  rclcpp::QoS profile = base;
  auto get = [&](const char * key) -> std::optional<std::string> {
      auto found = settings.find(key);
      return found == settings.end() ? std::nullopt : std::optional<std::string>(found->second);
    };
  if (auto h = get("history")) {
    if (*h == "keep_all") {
      profile.keep_all();
    } else if (*h == "keep_last") {
      profile.keep_last(profile.depth() ? profile.depth() : 10);
    } else {
      profile.history(rclcpp::HistoryPolicy::SystemDefault);
    }
  }
  if (auto d = get("depth")) {
    if (profile.history() != rclcpp::HistoryPolicy::KeepAll) {
      profile.keep_last(std::stoul(*d));
    }
  }
  if (auto r = get("reliability")) {
    profile.reliability(*r == "reliable" ? rclcpp::ReliabilityPolicy::Reliable :
      *r == "best_effort" ? rclcpp::ReliabilityPolicy::BestEffort : rclcpp::ReliabilityPolicy::SystemDefault);
  }
  if (auto d = get("durability")) {
    profile.durability(*d == "volatile" ? rclcpp::DurabilityPolicy::Volatile :
      *d == "transient_local" ? rclcpp::DurabilityPolicy::TransientLocal :
      rclcpp::DurabilityPolicy::SystemDefault);
  }
  if (auto l = get("liveliness")) {
    profile.liveliness(*l == "automatic" ? rclcpp::LivelinessPolicy::Automatic :
      *l == "manual_by_topic" ? rclcpp::LivelinessPolicy::ManualByTopic :
      rclcpp::LivelinessPolicy::SystemDefault);
  }
  auto duration = [](const std::string & seconds) {
      return rclcpp::Duration::from_nanoseconds(static_cast<int64_t>(std::llround(std::stod(seconds) * 1e9)));
    };
  if (auto d = get("deadline")) {
    profile.deadline(duration(*d));
  }
  if (auto d = get("lifespan")) {
    profile.lifespan(duration(*d));
  }
  if (auto d = get("liveliness_lease_duration")) {
    profile.liveliness_lease_duration(duration(*d));
  }
  return profile;
}

// ---- the node -------------------------------------------------------------------------------------

namespace
{

void declare_all(rclcpp_lifecycle::LifecycleNode & node, const std::vector<ParamSpec> & params)
{
  for (const auto & spec : params) {
    if (spec.default_value) {
      node.declare_parameter(spec.name, *spec.default_value, spec.descriptor());
    } else {
      node.declare_parameter(spec.name, spec.type(), spec.descriptor());
    }
  }
}

//! The component nodes of this process by their node's base interface (leaked: nodes may outlive static teardown).
std::mutex & registry_mutex()
{
  static auto * m = new std::mutex;
  return *m;
}
std::map<const rclcpp::node_interfaces::NodeBaseInterface *, ComponentNode *> & registry()
{
  static auto * r = new std::map<const rclcpp::node_interfaces::NodeBaseInterface *, ComponentNode *>;
  return *r;
}

}  // namespace

rclcpp::IntraProcessSetting intra_process(const rclcpp::QoS & profile)
{
  const bool allowed = profile.durability() == rclcpp::DurabilityPolicy::Volatile &&
    profile.history() == rclcpp::HistoryPolicy::KeepLast && profile.depth() > 0;
  return allowed ? rclcpp::IntraProcessSetting::NodeDefault : rclcpp::IntraProcessSetting::Disable;
}

rclcpp::IntraProcessSetting ComponentNode::intra_process_for(
  const std::string & what, const std::string & topic, const rclcpp::QoS & profile)
{
  const auto setting = intra_process(profile);
  if (get_node_options().use_intra_process_comms()) {
    std::lock_guard<std::mutex> lock(lock_);
    (setting == rclcpp::IntraProcessSetting::Disable ? over_dds_ : in_process_).push_back(what + " " + topic);
  }
  return setting;
}

std::shared_ptr<ComponentNode> ComponentNode::of(const rclcpp::node_interfaces::NodeBaseInterface * base)
{
  std::lock_guard<std::mutex> lock(registry_mutex());
  const auto found = registry().find(base);
  if (found == registry().end()) {
    return nullptr;
  }
  return std::static_pointer_cast<ComponentNode>(found->second->weak_from_this().lock());
}

ComponentNode::ComponentNode(Info info, std::vector<ParamSpec> params, const rclcpp::NodeOptions & options)
: rclcpp_lifecycle::LifecycleNode(info.node_name, options), info_(std::move(info)), params_(std::move(params))
{
  main_group = create_callback_group(rclcpp::CallbackGroupType::MutuallyExclusive);
  action_group = create_callback_group(rclcpp::CallbackGroupType::Reentrant);
  client_group = create_callback_group(rclcpp::CallbackGroupType::Reentrant);
  diagnostics_group = create_callback_group(rclcpp::CallbackGroupType::MutuallyExclusive);
  control_group = create_callback_group(rclcpp::CallbackGroupType::MutuallyExclusive);
  declare_all(*this, params_);
  on_set_ = add_on_set_parameters_callback(
    [this](const std::vector<rclcpp::Parameter> & changed) {return check_parameters(changed);});
  diagnostics_pub_ = rclcpp::create_publisher<diagnostic_msgs::msg::DiagnosticArray>(
    *this, DIAGNOSTICS_TOPIC, rclcpp::QoS(10));
  diagnostics_timer_ = create_wall_timer(
    std::chrono::duration<double>(1.0 / info_.diagnostics_rate), [this] {publish_diagnostics();},
    diagnostics_group);
  serve_protocol();
  std::lock_guard<std::mutex> lock(registry_mutex());
  registry()[get_node_base_interface().get()] = this;
}

void ComponentNode::serve_protocol()
{
  using iface_msgs::srv::ComponentControl;
  using iface_msgs::srv::Describe;
  using iface_msgs::srv::RestoreState;
  using iface_msgs::srv::SaveState;
  keep_service(
    create_service<SaveState>(
      "~/save_state",
      [this](const std::shared_ptr<SaveState::Request> request, std::shared_ptr<SaveState::Response> response) {
        const auto answer = answer_save(request->timeout_sec);
        response->success = answer.success;
        response->message = answer.message;
        response->state = answer.state;
        response->interface_hash = info_.interface_hash;
      }, rclcpp::ServicesQoS(), control_group));
  keep_service(
    create_service<RestoreState>(
      "~/restore_state",
      [this](const std::shared_ptr<RestoreState::Request> request, std::shared_ptr<RestoreState::Response> response) {
        const auto answer = answer_restore(request->state, request->timeout_sec);
        response->success = answer.success;
        response->message = answer.message;
        response->restored = answer.restored;
        response->kept = answer.kept;
        response->interface_hash = info_.interface_hash;
      }, rclcpp::ServicesQoS(), control_group));
  keep_service(
    create_service<ComponentControl>(
      "~/control",
      [this](const std::shared_ptr<ComponentControl::Request> request,
      std::shared_ptr<ComponentControl::Response> response) {
        const auto answer = answer_control(request->command, request->timeout_sec);
        response->success = answer.success;
        response->message = answer.message;
        response->paused = answer.paused;
        response->lifecycle_state = answer.lifecycle_state;
        response->in_flight = answer.in_flight;
        response->transactions = answer.transactions;
        response->component = info_.component;
        response->version = info_.version;
        response->interface_hash = info_.interface_hash;
        response->state = answer.state;
        response->protocol_version = PROTOCOL_VERSION;
        response->pid = static_cast<uint32_t>(::getpid());
        response->publisher_topics = answer.publisher_topics;
        response->publisher_matched = answer.publisher_matched;
      }, rclcpp::ServicesQoS(), control_group));
  keep_service(
    create_service<Describe>(
      "~/describe",
      [this](const std::shared_ptr<Describe::Request>, std::shared_ptr<Describe::Response> response) {
        response->node_name = get_fully_qualified_name();
        response->component = info_.component;
        response->version = info_.version;
        response->interface_hash = info_.interface_hash;
        response->runtime = "rclcpp";
        response->runtime_version = runtime_version();
        response->protocol_version = PROTOCOL_VERSION;
        response->interface_json = info_.interface_file.empty() ? info_.interface_json :
          installed_interface(info_.package, info_.version, info_.interface_file);
      }, rclcpp::ServicesQoS(), control_group));
}

ComponentNode::~ComponentNode()
{
  {
    std::lock_guard<std::mutex> lock(registry_mutex());
    registry().erase(get_node_base_interface().get());
  }
  join_goals();
}

void ComponentNode::quiesce(double timeout_sec)
{
  closing_ = true;
  std::vector<rclcpp::CallbackGroup::SharedPtr> groups;
  get_node_base_interface()->for_each_callback_group(
    [&groups](const rclcpp::CallbackGroup::SharedPtr & group) {groups.push_back(group);});
  for (const auto & group : groups) {
    group->collect_all_ptrs(
      [](const rclcpp::SubscriptionBase::SharedPtr &) {}, [](const rclcpp::ServiceBase::SharedPtr &) {},
      [](const rclcpp::ClientBase::SharedPtr &) {}, [](const rclcpp::TimerBase::SharedPtr & timer) {timer->cancel();},
      [](const rclcpp::Waitable::SharedPtr &) {});
  }
  // A mutually exclusive group cannot be taken from while one of its callbacks runs. An executor may still
  // take a callback it saw ready before the node was removed from it: the groups must stay free a while.
  const auto busy = [&] {
      return gate_.in_flight() > 0 || std::any_of(groups.begin(), groups.end(), [](const auto & group) {
               return group->type() == rclcpp::CallbackGroupType::MutuallyExclusive &&
               !group->can_be_taken_from().load();
             });
    };
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_sec);
  auto free_since = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() < deadline) {
    const auto now = std::chrono::steady_clock::now();
    if (busy()) {
      free_since = now;
    } else if (now - free_since >= std::chrono::milliseconds(100)) {
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  join_goals();
}

const MessageTypes & ComponentNode::message_types() const
{
  static const MessageTypes none;
  return none;
}

void ComponentNode::report_status(const std::string & level, const std::string & message)
{
  std::lock_guard<std::mutex> lock(lock_);
  if (level == "ok" && message.empty()) {
    status_.reset();
    return;
  }
  const uint8_t value = level == "warn" ? diagnostic_msgs::msg::DiagnosticStatus::WARN :
    level == "error" ? diagnostic_msgs::msg::DiagnosticStatus::ERROR :
    level == "stale" ? diagnostic_msgs::msg::DiagnosticStatus::STALE : diagnostic_msgs::msg::DiagnosticStatus::OK;
  status_ = std::make_pair(value, message);
}

namespace
{

//! Now on the system clock, in nanoseconds (the schedule of a state document is on this clock, as Python's
//! time.time_ns()).
int64_t wall_now_ns()
{
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
    std::chrono::system_clock::now().time_since_epoch()).count();
}

}  // namespace

rclcpp::TimerBase::SharedPtr ComponentNode::create_work_timer(
  double period_sec, std::function<void()> callback, const std::string & name)
{
  auto entry = std::make_shared<WorkTimer>();
  std::size_t taken = 0;
  for (const auto & other : work_timers_) {
    taken += other->name == name || other->name.rfind(name + "#", 0) == 0;
  }
  entry->name = taken == 0 ? name : name + "#" + std::to_string(taken);
  entry->period = period_sec;
  entry->callback = std::move(callback);
  std::weak_ptr<WorkTimer> weak = entry;
  entry->timer = create_wall_timer(
    std::chrono::duration<double>(period_sec), [this, weak] {
      if (auto t = weak.lock()) {
        tick(*t);
      }
    }, main_group);
  // Made now, stopped, so that continuing a schedule (continue_schedule, in a hand-over's critical section) only
  // sets its delay and starts it: a timer added then would wait for the executor to collect its entities again.
  entry->first = rclcpp::create_wall_timer(
    std::chrono::duration<double>(period_sec), [this, weak] {
      if (auto t = weak.lock()) {
        t->first->cancel();
        t->timer->reset();
        tick(*t);
      }
    }, main_group, get_node_base_interface().get(), get_node_timers_interface().get(), false);
  keep(entry->timer);
  keep(entry->first);
  keep(entry);
  work_timers_.push_back(entry);
  return entry->timer;
}

void ComponentNode::tick(WorkTimer & t)
{
  if (work(t.callback, "timer " + t.name)) {
    std::function<void(const std::string &)> then;
    {
      std::lock_guard<std::mutex> lock(tick_mutex_);
      t.last_ns = wall_now_ns();
      then.swap(after_tick_);
    }
    ticked_.notify_all();
    if (then) {
      then(t.name);
    }
  }
}

HandOverAnswer ComponentNode::hand_over_to(ComponentNode & next, double timeout_sec)
{
  const auto asked = std::chrono::steady_clock::now();
  HandOverAnswer refused;
  const auto next_state = next.get_current_state();
  if (&next == this) {
    refused.message = "OLD and NEW are one node";
  } else if (!active_) {
    refused.message = std::string("OLD ") + get_fully_qualified_name() + " is " + lifecycle_label() + ", not active";
  } else if (gate_.paused()) {
    refused.message = std::string("OLD ") + get_fully_qualified_name() + " is paused";
  } else if (next_state.id() != lifecycle_msgs::msg::State::PRIMARY_STATE_INACTIVE) {
    refused.message = std::string("NEW ") + next.get_fully_qualified_name() + " is " + next_state.label() +
      ", not inactive (configure it first)";
  }
  if (!refused.message.empty()) {
    return refused;
  }
  // The work timer due soonest: the switch follows its tick when that is due within ALIGN_SEC.
  double wait = std::numeric_limits<double>::infinity();
  double period = 0.0;
  for (const auto & entry : work_timers_) {
    for (const auto & timer : {entry->timer, entry->first}) {
      if (timer && !timer->is_canceled()) {
        const double left = std::max(0.0, std::chrono::duration<double>(timer->time_until_trigger()).count());
        if (left < wait) {
          wait = left;
          period = entry->period;
        }
      }
    }
  }
  auto done = std::make_shared<std::promise<HandOverAnswer>>();
  auto answer = done->get_future();
  std::function<void(const std::string &)> critical = [this, &next, timeout_sec, asked, done](const std::string & after) {
      done->set_value(switch_to(next, timeout_sec, asked, after));
    };
  if (wait <= std::min(ALIGN_SEC, timeout_sec)) {
    {
      std::lock_guard<std::mutex> lock(tick_mutex_);
      after_tick_ = critical;
    }
    const auto bound = std::chrono::duration<double>(wait + std::max(period, ALIGN_SEC) + 0.5);
    if (answer.wait_for(bound) != std::future_status::ready) {
      std::function<void(const std::string &)> mine;  // no tick came: take it back (unless a tick took it)
      {
        std::lock_guard<std::mutex> lock(tick_mutex_);
        mine.swap(after_tick_);
      }
      if (mine) {
        mine("");
      }
    }
    return answer.get();
  }
  critical("");
  return answer.get();
}

HandOverAnswer ComponentNode::switch_to(
  ComponentNode & next, double timeout_sec, std::chrono::steady_clock::time_point asked, const std::string & after)
{
  using Clock = std::chrono::steady_clock;
  const auto ms = [](Clock::duration d) {return std::chrono::duration<double, std::milli>(d).count();};
  HandOverAnswer answer;
  answer.after_tick = after;
  const auto start = Clock::now();
  answer.pause_ms = ms(start - asked);
  const auto [paused, why] = gate_.pause(timeout_sec);
  if (!paused) {
    answer.message = std::string("OLD did not pause: ") + why;
    return answer;
  }
  std::string step = "save OLD's state";
  Clock::time_point saved, restored_at;
  next.schedule_set_ns_ = 0;
  next.quiet_schedule_ = true;
  next.schedule_notes_.clear();
  const int64_t ticked_before = next.last_tick_ns();
  try {
    answer.state = save_state(timeout_sec);
    saved = Clock::now();
    step = "restore the state into NEW";
    const Restored restored = next.restore_state(answer.state, timeout_sec);
    restored_at = Clock::now();
    answer.restored = restored.restored;
    answer.kept = restored.kept;
    step = "activate NEW";
    if (next.activate().id() != lifecycle_msgs::msg::State::PRIMARY_STATE_ACTIVE) {
      throw std::runtime_error(std::string(next.get_fully_qualified_name()) + " did not become active");
    }
  } catch (const std::exception & e) {
    next.quiet_schedule_ = false;
    gate_.resume();
    answer.message = "could not " + step + ": " + e.what() + "; OLD goes on";
    RCLCPP_WARN(get_logger(), "hand-over to %s: %s", next.get_fully_qualified_name(), answer.message.c_str());
    return answer;
  }
  const auto active_at = Clock::now();
  answer.critical_ms = ms(active_at - start);
  const int64_t set_ns = next.schedule_set_ns_;
  char first[48] = "no schedule continued";
  if (set_ns != 0) {
    std::snprintf(first, sizeof first, "first tick set %.3f", ms(Clock::time_point(Clock::duration(set_ns)) - start));
  }
  char steps[160];
  std::snprintf(steps, sizeof steps, " (saved %.3f, restored %.3f, %s, active %.3f ms)", ms(saved - start),
    ms(restored_at - start), first, answer.critical_ms);
  next.quiet_schedule_ = false;
  if (set_ns != 0) {
    // OLD's deactivation and the log lines wait for NEW's first tick: on two cores they delayed it by milliseconds
    double period = 0.0;
    for (const auto & entry : next.work_timers_) {
      period = std::max(period, entry->period);
    }
    next.await_tick_after(ticked_before, std::min(1.0, 2 * period + 0.01));
  }
  for (const auto & line : next.schedule_notes_) {
    RCLCPP_INFO(next.get_logger(), "%s", line.c_str());
  }
  try {
    deactivate();
  } catch (const std::exception & e) {
    failed("deactivate after the hand-over", e.what());
  }
  gate_.resume();
  answer.success = true;
  char text[400];
  std::snprintf(text, sizeof text, "NEW %s active %.3f ms after OLD paused%s%s%s", next.get_fully_qualified_name(),
    answer.critical_ms, steps, after.empty() ? "" : ", right after a tick of ", after.c_str());
  answer.message = text;
  RCLCPP_INFO(get_logger(), "handed over: %s", text);
  return answer;
}

void ComponentNode::await_tick(double timeout_sec)
{
  if (!active_ || gate_.paused()) {
    return;
  }
  std::shared_ptr<WorkTimer> soonest;
  double wait = 0.0;
  for (const auto & entry : work_timers_) {
    if (!entry->timer || entry->timer->is_canceled()) {
      continue;
    }
    const double left = std::max(0.0, std::chrono::duration<double>(entry->timer->time_until_trigger()).count());
    if (soonest == nullptr || left < wait) {
      soonest = entry;
      wait = left;
    }
  }
  if (soonest == nullptr || wait > std::min(ALIGN_SEC, timeout_sec)) {
    return;
  }
  std::unique_lock<std::mutex> lock(tick_mutex_);
  const int64_t last = soonest->last_ns;
  ticked_.wait_for(lock, std::chrono::duration<double>(wait + std::min(soonest->period, ALIGN_SEC)),
    [&soonest, last] {return soonest->last_ns != last;});
}

int64_t ComponentNode::last_tick_ns()
{
  int64_t last = 0;
  for (const auto & entry : work_timers_) {
    last = std::max<int64_t>(last, entry->last_ns);
  }
  return last;
}

void ComponentNode::await_tick_after(int64_t since_ns, double timeout_sec)
{
  std::unique_lock<std::mutex> lock(tick_mutex_);
  ticked_.wait_for(lock, std::chrono::duration<double>(timeout_sec), [this, since_ns] {
      return last_tick_ns() > since_ns;
    });
}

void ComponentNode::continue_schedule()
{
  std::map<std::string, int64_t> schedule;
  {
    std::lock_guard<std::mutex> lock(lock_);
    schedule.swap(restored_schedule_);
  }
  const int64_t now = wall_now_ns();
  for (const auto & entry : work_timers_) {
    // The timer of the same name; with one timer on each side, that one.
    auto found = schedule.find(entry->name);
    if (found == schedule.end() && schedule.size() == 1 && work_timers_.size() == 1) {
      found = schedule.begin();
    }
    if (found == schedule.end()) {
      continue;
    }
    // The first tick one period after the last tick of the state's node, then every period from there.
    const double last = static_cast<double>(found->second) / 1e9;
    const double due = last + entry->period;
    entry->timer->cancel();
    const int64_t delay = std::max<int64_t>(
      1000, found->second + static_cast<int64_t>(std::llround(entry->period * 1e9)) - now);
    int64_t before = 0;
    if (rcl_timer_exchange_period(entry->first->get_timer_handle().get(), delay, &before) != RCL_RET_OK) {
      rcl_reset_error();
      entry->timer->reset();  // cannot set the delay: the next tick one period from now
      continue;
    }
    entry->first->reset();
    schedule_set_ns_ = std::chrono::steady_clock::now().time_since_epoch().count();
    char line[400];
    std::snprintf(line, sizeof line, "schedule: timer '%s' continues the restored state's '%s': last tick at %.6f, "
      "the first tick due at %.6f (period %.6f s, in %.6f s)", entry->name.c_str(), found->first.c_str(), last, due,
      entry->period, due - static_cast<double>(now) / 1e9);
    if (quiet_schedule_) {
      schedule_notes_.push_back(line);
    } else {
      RCLCPP_INFO(get_logger(), "%s", line);
    }
  }
}

void ComponentNode::failed(const std::string & what, const std::string & error)
{
  std::string line;
  {
    std::lock_guard<std::mutex> lock(lock_);
    ++errors_;
    error_seen_ = true;
    last_error_ = what + ": " + error;
    line = last_error_;
  }
  RCLCPP_ERROR(get_logger(), "%s", line.c_str());
}

bool ComponentNode::work(const std::function<void()> & body, const std::string & what)
{
  if (closing_) {
    return false;
  }
  if (!active_) {
    std::lock_guard<std::mutex> lock(lock_);
    ++dropped_inactive_;
    return false;
  }
  if (!gate_.enter()) {
    return false;
  }
  try {
    body();
  } catch (const std::exception & e) {
    failed(what, e.what());
  }
  gate_.leave();
  return true;
}

void ComponentNode::serve(
  const std::string & name, bool is_work, const std::function<void()> & body, const std::function<void()> & reset)
{
  if (closing_) {
    return;
  }
  if (is_work && !active_) {
    RCLCPP_WARN_THROTTLE(get_logger(), *get_clock(), 5000, "%s: called while %s: default response",
      name.c_str(), lifecycle_label().c_str());
    return;
  }
  if (is_work && !gate_.enter()) {
    RCLCPP_WARN_THROTTLE(get_logger(), *get_clock(), 5000, "%s: called while %s: default response",
      name.c_str(), gate_.paused() ? "paused" : "its members are destroyed");
    return;
  }
  try {
    body();
  } catch (const std::exception & e) {
    failed(name, e.what());
    reset();
  }
  if (is_work) {
    gate_.leave();
  }
}

void ComponentNode::destroy_members()
{
  join_goals();
  for (auto it = entities_.rbegin(); it != entities_.rend(); ++it) {
    it->reset();
  }
  entities_.clear();
  work_timers_.clear();
  {
    std::lock_guard<std::mutex> lock(lock_);
    publishers_.clear();
  }
  forget_members();
}

void ComponentNode::join_goals()
{
  std::vector<std::thread> goals;
  {
    std::lock_guard<std::mutex> lock(goals_mutex_);
    goals.swap(goals_);
  }
  for (auto & t : goals) {
    if (t.joinable()) {
      t.join();
    }
  }
}

std::string ComponentNode::lifecycle_label()
{
  return get_current_state().label();
}

ComponentNode::CallbackReturn ComponentNode::check_configure()
{
  std::vector<std::string> missing;
  for (const auto & spec : params_) {
    try {
      if (get_parameter(spec.name).get_type() == rclcpp::ParameterType::PARAMETER_NOT_SET) {
        missing.push_back(spec.name);
      }
    } catch (const std::exception &) {
      missing.push_back(spec.name);  // declared without a value (uninitialized)
    }
  }
  if (!missing.empty()) {
    std::string names;
    for (const auto & n : missing) {
      names += (names.empty() ? "" : ", ") + n;
    }
    RCLCPP_ERROR(get_logger(), "cannot configure: no value for %s (set it in the parameter file or with "
      "--ros-args -p NAME:=VALUE)", names.c_str());
    return CallbackReturn::FAILURE;
  }
  return CallbackReturn::SUCCESS;
}

ComponentNode::CallbackReturn ComponentNode::on_configure(const rclcpp_lifecycle::State & state)
{
  (void)state;
  if (check_configure() != CallbackReturn::SUCCESS) {
    return CallbackReturn::FAILURE;
  }
  {
    std::lock_guard<std::mutex> lock(lock_);
    in_process_.clear();
    over_dds_.clear();
  }
  gate_.open();
  try {
    create_members();
    setup();
  } catch (const std::exception & e) {
    failed("configure", e.what());
    destroy_members();
    return CallbackReturn::FAILURE;
  }
  if (get_node_options().use_intra_process_comms()) {
    const auto join = [](const std::vector<std::string> & items) {
        std::string out;
        for (const auto & item : items) {
          out += (out.empty() ? "" : ", ") + item;
        }
        return out.empty() ? std::string("none") : out;
      };
    std::lock_guard<std::mutex> lock(lock_);
    RCLCPP_INFO(get_logger(), "intra-process communication: %s; over DDS only (transient_local or keep_all): %s",
      join(in_process_).c_str(), join(over_dds_).c_str());
  }
  return CallbackReturn::SUCCESS;
}

ComponentNode::CallbackReturn ComponentNode::on_activate(const rclcpp_lifecycle::State & state)
{
  const auto result = LifecycleNode::on_activate(state);
  if (result != CallbackReturn::SUCCESS) {
    return result;
  }
  active_ = true;
  try {
    on_active();
  } catch (const std::exception & e) {
    active_ = false;
    failed("activate", e.what());
    return CallbackReturn::FAILURE;
  }
  // Last: on an executor of its own the first tick may come before this returns, and must find the node active.
  continue_schedule();
  return result;
}

ComponentNode::CallbackReturn ComponentNode::on_deactivate(const rclcpp_lifecycle::State & state)
{
  active_ = false;
  try {
    on_inactive();
  } catch (const std::exception & e) {
    failed("deactivate", e.what());
  }
  return LifecycleNode::on_deactivate(state);
}

ComponentNode::CallbackReturn ComponentNode::on_cleanup(const rclcpp_lifecycle::State & state)
{
  (void)state;
  end();
  return CallbackReturn::SUCCESS;
}

ComponentNode::CallbackReturn ComponentNode::on_shutdown(const rclcpp_lifecycle::State & state)
{
  (void)state;
  if (active_) {
    active_ = false;
    try {
      on_inactive();
    } catch (const std::exception & e) {
      failed("shutdown", e.what());
    }
  }
  end();
  finalized_ = true;
  return CallbackReturn::SUCCESS;
}

ComponentNode::CallbackReturn ComponentNode::on_error(const rclcpp_lifecycle::State & state)
{
  (void)state;
  active_ = false;
  end();
  return CallbackReturn::SUCCESS;
}

void ComponentNode::end()
{
  // no work transaction runs on a member being destroyed (a tick that a signal's shutdown overtook)
  const auto [closed, why] = gate_.close(kCloseTimeoutSec);
  if (!closed) {
    RCLCPP_WARN(get_logger(), "members destroyed while %s", why.c_str());
  }
  if (!entities_.empty()) {
    try {
      teardown();
    } catch (const std::exception & e) {
      failed("teardown", e.what());
    }
  }
  destroy_members();
}

rcl_interfaces::msg::SetParametersResult ComponentNode::check_parameters(
  const std::vector<rclcpp::Parameter> & changed)
{
  rcl_interfaces::msg::SetParametersResult result;
  result.successful = true;
  for (const auto & p : changed) {
    auto spec = std::find_if(params_.begin(), params_.end(), [&](const ParamSpec & s) {return s.name == p.get_name();});
    if (spec == params_.end() || p.get_type() == rclcpp::ParameterType::PARAMETER_NOT_SET) {
      continue;
    }
    if (auto problem = spec->problem(p)) {
      result.successful = false;
      result.reason = *problem;
      return result;
    }
  }
  return result;
}

// ---- Σ and control ----------------------------------------------------------------------------------

namespace
{

//! No transaction runs while it lives: new work waits (a paused gate refuses it anyway), none is refused, so that a
//! snapshot loses no message; std::runtime_error when the work in progress does not end in time.
class Quiet
{
public:
  Quiet(Gate & gate, double timeout)
  : gate_(gate), hold_(gate.hold(timeout))
  {
    if (!hold_.ok) {
      throw std::runtime_error(hold_.message);
    }
  }
  ~Quiet()
  {
    if (hold_.held) {
      gate_.release();
    }
  }
  Quiet(const Quiet &) = delete;
  Quiet & operator=(const Quiet &) = delete;

private:
  Gate & gate_;
  Hold hold_;
};

//! When each work timer of the node that saved ``document`` last ran (its "schedule": name -> ns).
std::map<std::string, int64_t> schedule_of(const std::string & document)
{
  std::map<std::string, int64_t> out;
  const Json doc = Json::parse(document);
  const Json * schedule = doc.kind() == Json::Kind::Object ? doc.find("schedule") : nullptr;
  if (schedule == nullptr || schedule->kind() != Json::Kind::Object) {
    return out;
  }
  for (const auto & [name, last] : schedule->fields()) {
    if (last.is_integer() && last.as_double() > 0) {
      try {
        out[name] = std::stoll(last.text());
      } catch (const std::exception &) {
        // not an int64: not a time this runtime writes
      }
    }
  }
  return out;
}

double effective(double timeout)
{
  return timeout > 0 ? timeout : DEFAULT_TIMEOUT_SEC;
}

}  // namespace

std::string ComponentNode::save_state(double timeout_sec)
{
  Quiet quiet(gate_, timeout_sec);
  Json::Object schedule;
  for (const auto & entry : work_timers_) {
    if (const int64_t last = entry->last_ns; last > 0) {
      schedule[entry->name] = Json::integer(last);
    }
  }
  return save_document(info_.component, info_.version, info_.interface_hash, info_.state_schema, message_types(),
           state_values(), schedule);
}

Restored ComponentNode::restore_state(const std::string & document, double timeout_sec)
{
  Restored report;
  {
    Quiet quiet(gate_, timeout_sec);
    auto [values, r] = read_document(document, info_.component, info_.interface_hash, info_.state_schema,
        message_types());
    set_state_values(values);
    report = r;
    auto schedule = schedule_of(document);
    std::lock_guard<std::mutex> lock(lock_);
    restored_schedule_ = std::move(schedule);
  }
  state_restored();
  return report;
}

SaveAnswer ComponentNode::answer_save(double timeout_sec)
{
  SaveAnswer answer;
  try {
    answer.state = save_state(effective(timeout_sec));
  } catch (const std::exception & e) {
    answer.message = std::string("not saved: ") + e.what();
    return answer;
  }
  answer.success = true;
  answer.message = "saved " + std::to_string(info_.state_schema.size()) + " state variable(s) of " +
    info_.component + " " + info_.version;
  return answer;
}

RestoreAnswer ComponentNode::answer_restore(const std::string & document, double timeout_sec)
{
  RestoreAnswer answer;
  try {
    const Restored report = restore_state(document, effective(timeout_sec));
    answer.success = true;
    answer.message = report.message;
    answer.restored = report.restored;
    answer.kept = report.kept;
    RCLCPP_INFO(get_logger(), "%s", report.message.c_str());
  } catch (const std::exception & e) {
    answer.message = std::string("refused: ") + e.what();
    RCLCPP_WARN(get_logger(), "restore refused: %s", e.what());
  }
  return answer;
}

ControlAnswer ComponentNode::answer_control(uint8_t command, double timeout_sec)
{
  const double timeout = effective(timeout_sec);
  ControlAnswer answer;
  bool ok = true;
  std::string message;
  if (command == PAUSE) {
    await_tick(timeout);
    std::tie(ok, message) = gate_.pause(timeout);
    if (ok) {  // the state at the pause, so that a hand-over needs no second round trip for it
      try {
        answer.state = save_state(timeout);
      } catch (const std::exception & e) {
        message = std::string("paused; the state could not be saved: ") + e.what();
      }
    }
  } else if (command == RESUME) {
    std::tie(ok, message) = gate_.resume();
  } else if (command == SAVE) {
    try {
      answer.state = save_state(timeout);
      message = "saved";
    } catch (const std::exception & e) {
      ok = false;
      message = std::string("not saved: ") + e.what();
    }
  } else if (command != STATUS) {
    ok = false;
    message = "unknown command " + std::to_string(command) + " (STATUS 0, PAUSE 1, RESUME 2, SAVE 3)";
  }
  const auto state = get_current_state();
  answer.success = ok;
  answer.paused = gate_.paused();
  answer.message = message.empty() ? state.label() + (answer.paused ? ", paused" : "") : message;
  answer.lifecycle_state = state.id();
  answer.in_flight = static_cast<uint32_t>(gate_.in_flight());
  answer.transactions = gate_.transactions();
  std::lock_guard<std::mutex> lock(lock_);
  for (const auto & weak : publishers_) {
    if (const auto pub = weak.lock()) {
      answer.publisher_topics.emplace_back(pub->get_topic_name());
      answer.publisher_matched.push_back(static_cast<uint32_t>(pub->get_subscription_count()));
    }
  }
  return answer;
}

// ---- Δ --------------------------------------------------------------------------------------------------

void ComponentNode::publish_diagnostics()
{
  if (closing_) {
    return;
  }
  using diagnostic_msgs::msg::DiagnosticStatus;
  const std::string label = lifecycle_label();
  uint8_t level = DiagnosticStatus::OK;
  std::string message = "active";
  uint64_t dropped = 0, errors = 0;
  {
    std::lock_guard<std::mutex> lock(lock_);
    dropped = dropped_inactive_;
    errors = errors_;
    const bool error_seen = error_seen_;
    error_seen_ = false;
    if (status_) {
      std::tie(level, message) = *status_;
    } else if (error_seen) {
      level = DiagnosticStatus::ERROR;
      message = last_error_;
    } else if (gate_.paused()) {
      level = DiagnosticStatus::WARN;
      message = "paused";
    } else if (label != "active") {
      level = DiagnosticStatus::WARN;
      message = label;
    }
  }
  std::vector<std::pair<std::string, std::string>> values = {
    {"lifecycle_state", label}, {"paused", py_bool(gate_.paused())},
    {"in_flight", std::to_string(gate_.in_flight())}, {"transactions", std::to_string(gate_.transactions())},
    {"refused_while_paused", std::to_string(gate_.refused())}, {"dropped_while_inactive", std::to_string(dropped)},
    {"errors", std::to_string(errors)}, {"component", info_.component}, {"version", info_.version},
    {"interface_hash", info_.interface_hash}};
  try {
    for (const auto & [name, value] : state_values()) {
      values.emplace_back("state." + name, value.dump().substr(0, 200));
    }
  } catch (const std::exception &) {
    // being changed right now
  }
  try {
    for (const auto & [key, value] : diagnostic_values()) {
      values.emplace_back(key, value);
    }
  } catch (const std::exception & e) {
    values.emplace_back("diagnostic_values", e.what());
  }
  DiagnosticStatus status;
  status.level = level;
  status.name = get_fully_qualified_name();
  status.hardware_id = info_.component;
  status.message = message.substr(0, 500);
  for (const auto & [key, value] : values) {
    diagnostic_msgs::msg::KeyValue kv;
    kv.key = key;
    kv.value = value;
    status.values.push_back(kv);
  }
  diagnostic_msgs::msg::DiagnosticArray array;
  array.header.stamp = now();
  array.status.push_back(status);
  diagnostics_pub_->publish(array);
}

}  // namespace iface_runtime
