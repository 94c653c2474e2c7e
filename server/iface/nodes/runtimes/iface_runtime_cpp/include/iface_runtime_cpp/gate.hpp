// Work transactions and pausing: the gate every main callback of a component passes.
#ifndef IFACE_RUNTIME_CPP__GATE_HPP_
#define IFACE_RUNTIME_CPP__GATE_HPP_

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <stdexcept>
#include <string>
#include <utility>

namespace iface_runtime
{

// ---- work transactions ----------------------------------------------------------------------------

//! Work was refused: the component is paused.
class Paused : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

//! What Gate::hold did: ok (no transaction runs), held (release() it: false when the gate was paused), why not.
struct Hold
{
  bool ok = false;
  bool held = false;
  std::string message;
};

//! Work transactions and pausing: pause lets no new transaction in and waits for the running ones; hold (a
//! snapshot's moment) makes new work wait instead of refusing it.
class Gate
{
public:
  //! Start a transaction, after a hold if one is on; false while closed, and (counted as refused) while paused.
  bool enter();
  //! End a transaction.
  void leave();
  //! Refuse new work and wait (at most timeout s) for the work in progress to end.
  std::pair<bool, std::string> pause(double timeout);
  std::pair<bool, std::string> resume();
  //! Let new work wait, none refused, and wait (at most timeout s) for the work in progress to end.
  Hold hold(double timeout);
  //! End a hold (Hold::held): the work that waited goes on.
  void release();
  //! Let no new transaction in and wait (at most timeout s) for the ones in progress to end, before the members
  //! they use are destroyed (cleanup, shutdown, error); the gate stays closed either way.
  std::pair<bool, std::string> close(double timeout);
  //! Let transactions in again (configure made the members anew).
  void open();
  bool paused() const;
  uint64_t in_flight() const;
  uint64_t transactions() const;
  uint64_t refused() const;

private:
  mutable std::mutex mutex_;
  std::condition_variable cond_;
  uint64_t in_flight_ = 0;
  bool paused_ = false;
  bool closed_ = false;
  uint32_t holds_ = 0;
  uint64_t transactions_ = 0;
  uint64_t refused_ = 0;
};

//! Leaves the gate when it goes out of scope.
class Transaction
{
public:
  explicit Transaction(Gate & gate);
  ~Transaction();
  Transaction(const Transaction &) = delete;
  Transaction & operator=(const Transaction &) = delete;

private:
  Gate & gate_;
};

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__GATE_HPP_
