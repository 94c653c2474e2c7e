// The user file of examples/counter_v2.iface for the C++ tests (replaces the src/node.cpp iface writes once).
//
// counter 2.0's behaviour in C++, as tests/runtime/data/counter_v2_node.py in Python: a work timer
// advances the count and publishes it (and its parity when publish_parity is set). One test hook:
// a reset waits 2.5 s inside its work transaction, so the tests can check that /diagnostics and
// ~/control are answered while a long callback blocks the main thread.
#include <chrono>
#include <thread>

#include "counter/base.hpp"

namespace counter
{

//! Counts ticks in its state, publishes each count and, if asked, its parity.
class Counter : public CounterBase
{
public:
  using CounterBase::CounterBase;

  void setup() override
  {
    create_work_timer(1.0 / params().rate_hz(), [this] {tick();}, "tick");
  }

  void handle_reset(const Reset::Request & request, Reset::Response & response) override
  {
    (void)request;
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    state.count = 0;
    response.done = true;
  }

private:
  void tick()
  {
    state.count += 1;
    Count count;
    count.value = state.count;
    publish_count(count);
    if (params().publish_parity()) {
      Parity parity;
      parity.even = state.count % 2 == 0;
      publish_parity(parity);
    }
  }
};

}  // namespace counter

COUNTER_COMPONENT(counter::Counter)
