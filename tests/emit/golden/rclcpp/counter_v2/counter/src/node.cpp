// Written once by iface from counter_v2.iface: this file is yours to edit. `iface-lsp generate`
// never overwrites it, not even with --force. When the interface changes, include/counter/base.hpp
// is regenerated and this file stops compiling, saying why, until the handlers below match it: a
// missing handler is a pure virtual function, and a handler whose `override` overrides nothing
// handles a member the interface no longer has (`iface-lsp generate --check` reports both too).
//
// The behaviour of the counter component: what it does with its members.
#include "counter/base.hpp"

namespace counter
{

//! counter: keep `state` current (what ~/save_state saves and a replacement restores).
class Counter : public CounterBase
{
public:
  using CounterBase::CounterBase;

  //! Called on configure, once the members exist (e.g. create_work_timer(0.1, [this] {tick();})).
  void setup() override {}

  //! provides Reset on /counter/reset.
  void handle_reset(const Reset::Request & request, Reset::Response & response) override
  {
    (void)request;
    (void)response;
  }
};

}  // namespace counter

COUNTER_COMPONENT(counter::Counter)
