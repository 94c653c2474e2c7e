// The user file of examples/counter.iface for the C++ tests (replaces the src/node.cpp iface writes once).
//
// counter 1.0's behaviour in C++, as tests/runtime/data/counter_node.py in Python: a work timer
// advances the count and publishes it.
#include "counter/base.hpp"

namespace counter
{

//! Counts ticks in its state and publishes each count.
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
  }
};

}  // namespace counter

COUNTER_COMPONENT(counter::Counter)
