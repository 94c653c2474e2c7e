// Work transactions and pausing: a pause waits for the transaction in progress, or leaves the gate as it was; a
// hold (a snapshot) makes new work wait and refuses none.
#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "check.hpp"
#include "iface_runtime_cpp/gate.hpp"

using iface_runtime::Gate;

namespace
{

void a_pause_that_cannot_wait_long_enough_leaves_the_gate_open()
{
  Gate gate;
  CHECK(gate.enter());
  const auto [ok, message] = gate.pause(0.05);
  CHECK(!ok);
  CHECK_EQ(message, std::string("1 work transaction(s) still running after 0.05 s: not paused"));
  CHECK(!gate.paused());
  gate.leave();
  CHECK_EQ(gate.transactions(), uint64_t{1});
}

void a_pause_waits_for_the_transaction_in_progress()
{
  Gate gate;
  CHECK(gate.enter());
  std::thread worker([&gate] {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      gate.leave();
    });
  const auto start = std::chrono::steady_clock::now();
  const auto [ok, message] = gate.pause(5.0);
  const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  worker.join();
  CHECK(ok && gate.paused());
  CHECK(waited >= 0.09);
  CHECK_EQ(message, std::string("paused after 1 work transaction(s) in progress ended"));
  CHECK(!gate.enter());
  CHECK_EQ(gate.refused(), uint64_t{1});
  CHECK_THROWS(iface_runtime::Transaction(gate), iface_runtime::Paused, "the component is paused");
  CHECK(gate.pause(1.0) == std::make_pair(true, std::string("already paused")));
  CHECK(gate.resume() == std::make_pair(true, std::string("resumed")));
  CHECK(gate.resume() == std::make_pair(true, std::string("not paused")));
  {
    iface_runtime::Transaction t(gate);
    CHECK_EQ(gate.in_flight(), uint64_t{1});
  }
  CHECK_EQ(gate.in_flight(), uint64_t{0});
  CHECK(gate.pause(0.0) == std::make_pair(true, std::string("paused")));
}

void work_that_arrives_during_a_hold_waits_for_it_and_is_not_refused()
{
  Gate gate;
  const auto hold = gate.hold(1.0);
  CHECK(hold.ok && hold.held && !gate.paused());
  std::atomic<int> entered{-1};
  std::thread worker([&] {entered = gate.enter() ? 1 : 0;});
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  CHECK_EQ(entered.load(), -1);
  CHECK_EQ(gate.in_flight(), uint64_t{0});
  gate.release();
  worker.join();
  CHECK_EQ(entered.load(), 1);
  CHECK_EQ(gate.refused(), uint64_t{0});
  gate.leave();
}

void a_hold_waits_for_the_work_in_progress_or_leaves_the_gate_as_it_was()
{
  Gate gate;
  CHECK(gate.enter());
  auto hold = gate.hold(0.05);
  CHECK(!hold.ok && !hold.held);
  CHECK_EQ(hold.message, std::string("1 work transaction(s) still running after 0.05 s"));
  CHECK(gate.enter());  // not held
  gate.leave();
  std::thread worker([&gate] {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      gate.leave();
    });
  hold = gate.hold(5.0);
  worker.join();
  CHECK(hold.ok && hold.held);
  CHECK_EQ(gate.in_flight(), uint64_t{0});
  gate.release();
}

void a_pause_refuses_the_work_a_hold_made_wait_and_a_paused_gate_needs_no_hold()
{
  Gate gate;
  CHECK(gate.hold(1.0).held);
  std::atomic<int> entered{-1};
  std::thread worker([&] {entered = gate.enter() ? 1 : 0;});
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  CHECK(gate.pause(1.0).first);
  worker.join();
  CHECK_EQ(entered.load(), 0);
  CHECK_EQ(gate.refused(), uint64_t{1});
  gate.release();
  const auto again = gate.hold(1.0);
  CHECK(again.ok && !again.held && gate.paused());
  CHECK(!gate.enter());
}

void closing_waits_for_the_work_in_progress_and_lets_none_in_until_opened()
{
  Gate gate;
  CHECK(gate.enter());
  CHECK(gate.close(0.05) == std::make_pair(false, std::string("1 work transaction(s) still running after 0.05 s")));
  CHECK(!gate.enter());
  CHECK_EQ(gate.refused(), uint64_t{0});
  std::thread worker([&gate] {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      gate.leave();
    });
  const auto start = std::chrono::steady_clock::now();
  CHECK(gate.close(5.0) == std::make_pair(true, std::string("closed")));
  CHECK(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >= 0.09);
  worker.join();
  gate.open();
  CHECK(gate.hold(1.0).held);
  std::atomic<int> entered{-1};
  std::thread held([&] {entered = gate.enter() ? 1 : 0;});
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  CHECK(gate.close(1.0).first);  // turns the held work away
  held.join();
  CHECK_EQ(entered.load(), 0);
  gate.release();
  gate.open();
  CHECK(gate.enter());
  gate.leave();
}

}  // namespace

int main()
{
  a_pause_that_cannot_wait_long_enough_leaves_the_gate_open();
  a_pause_waits_for_the_transaction_in_progress();
  work_that_arrives_during_a_hold_waits_for_it_and_is_not_refused();
  a_hold_waits_for_the_work_in_progress_or_leaves_the_gate_as_it_was();
  a_pause_refuses_the_work_a_hold_made_wait_and_a_paused_gate_needs_no_hold();
  closing_waits_for_the_work_in_progress_and_lets_none_in_until_opened();
  return check::done("gate");
}
