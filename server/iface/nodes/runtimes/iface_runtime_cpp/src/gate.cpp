// Work transactions and pausing: see gate.hpp.
#include "iface_runtime_cpp/gate.hpp"

#include <chrono>
#include <cstdio>
#include <string>

namespace iface_runtime
{

// ---- work transactions ----------------------------------------------------------------------------

bool Gate::enter()
{
  std::unique_lock<std::mutex> lock(mutex_);
  cond_.wait(lock, [this] {return holds_ == 0 || paused_ || closed_;});
  if (closed_) {
    return false;
  }
  if (paused_) {
    ++refused_;
    return false;
  }
  ++in_flight_;
  return true;
}

void Gate::leave()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    --in_flight_;
    ++transactions_;
  }
  cond_.notify_all();
}

std::pair<bool, std::string> Gate::pause(double timeout)
{
  std::unique_lock<std::mutex> lock(mutex_);
  if (paused_) {
    return {true, "already paused"};
  }
  paused_ = true;
  cond_.notify_all();  // work waiting on a hold is refused now
  const uint64_t busy = in_flight_;
  if (!cond_.wait_for(lock, std::chrono::duration<double>(timeout), [this] {return in_flight_ == 0;})) {
    paused_ = false;
    char g[64];
    std::snprintf(g, sizeof g, "%g", timeout);
    return {false, std::to_string(in_flight_) + " work transaction(s) still running after " + g + " s: not paused"};
  }
  if (busy) {
    return {true, "paused after " + std::to_string(busy) + " work transaction(s) in progress ended"};
  }
  return {true, "paused"};
}

std::pair<bool, std::string> Gate::resume()
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!paused_) {
    return {true, "not paused"};
  }
  paused_ = false;
  return {true, "resumed"};
}

std::pair<bool, std::string> Gate::close(double timeout)
{
  std::unique_lock<std::mutex> lock(mutex_);
  closed_ = true;
  cond_.notify_all();  // work waiting on a hold is turned away now
  if (!cond_.wait_for(lock, std::chrono::duration<double>(timeout), [this] {return in_flight_ == 0;})) {
    char g[64];
    std::snprintf(g, sizeof g, "%g", timeout);
    return {false, std::to_string(in_flight_) + " work transaction(s) still running after " + g + " s"};
  }
  return {true, "closed"};
}

void Gate::open()
{
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = false;
}

Hold Gate::hold(double timeout)
{
  std::unique_lock<std::mutex> lock(mutex_);
  if (paused_) {
    return {true, false, "paused"};
  }
  ++holds_;
  const uint64_t busy = in_flight_;
  if (!cond_.wait_for(lock, std::chrono::duration<double>(timeout), [this] {return in_flight_ == 0;})) {
    --holds_;
    lock.unlock();
    cond_.notify_all();
    char g[64];
    std::snprintf(g, sizeof g, "%g", timeout);
    return {false, false, std::to_string(busy) + " work transaction(s) still running after " + g + " s"};
  }
  return {true, true, "held"};
}

void Gate::release()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (holds_ > 0) {
      --holds_;
    }
  }
  cond_.notify_all();
}

bool Gate::paused() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return paused_;
}

uint64_t Gate::in_flight() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return in_flight_;
}

uint64_t Gate::transactions() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return transactions_;
}

uint64_t Gate::refused() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return refused_;
}

Transaction::Transaction(Gate & gate)
: gate_(gate)
{
  if (!gate_.enter()) {
    throw Paused("the component is paused");
  }
}

Transaction::~Transaction()
{
  gate_.leave();
}

}  // namespace iface_runtime
