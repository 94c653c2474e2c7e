// Work transactions and pausing: a pause waits for the transaction in progress, or leaves the gate as it was.
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

}  // namespace

int main()
{
  a_pause_that_cannot_wait_long_enough_leaves_the_gate_open();
  a_pause_waits_for_the_transaction_in_progress();
  return check::done("gate");
}
