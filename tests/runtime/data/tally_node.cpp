// The user file of tests/runtime/data/tally.iface for the container tests and bench/container_bench.py: counts the
// ticks it receives and the counts it missed between two.
#include "tally/base.hpp"

namespace tally
{

//! Keeps the tally of /tick in its state.
class Tally : public TallyBase
{
public:
  using TallyBase::TallyBase;

  void on_tick(const Tick & msg) override
  {
    state.received += 1;
    if (state.last != 0 && msg.value != state.last + 1) {
      RCLCPP_WARN(get_logger(), "tick %ld after %ld", static_cast<long>(msg.value), static_cast<long>(state.last));
    }
    if (state.last != 0 && msg.value > state.last + 1) {
      state.missed += msg.value - state.last - 1;
    }
    state.last = msg.value;
  }
};

}  // namespace tally

TALLY_COMPONENT(tally::Tally)
