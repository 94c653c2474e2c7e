// The user file of tests/runtime/data/ticker.iface (and ticker_v1_1, ticker_v2) for the container tests and
// bench/container_bench.py: a work timer advances the count and publishes it, `burst` times per tick.
#include "ticker/base.hpp"

namespace ticker
{

//! Counts in its state and publishes each count.
class Ticker : public TickerBase
{
public:
  using TickerBase::TickerBase;

  void setup() override
  {
    create_work_timer(1.0 / params().rate_hz(), [this] {tick();}, "tick");
  }

private:
  void tick()
  {
    for (int32_t i = 0; i < params().burst(); ++i) {
      state.count += 1;
      Tick msg;
      msg.value = state.count;
      publish_tick(msg);
    }
  }
};

}  // namespace ticker

TICKER_COMPONENT(ticker::Ticker)
