// A tiny check helper for the runtime's unit tests (no test framework needed): each CHECK that fails prints
// where and what, and the program exits 1 when any did (ctest reads the exit status).
#ifndef IFACE_RUNTIME_CPP__TEST__CHECK_HPP_
#define IFACE_RUNTIME_CPP__TEST__CHECK_HPP_

#include <iostream>
#include <sstream>
#include <string>

namespace check
{

inline int & failures()
{
  static int count = 0;
  return count;
}

inline void fail(const char * file, int line, const std::string & what)
{
  ++failures();
  std::cerr << file << ":" << line << ": FAILED: " << what << "\n";
}

//! The exit status of a test program: 0 when every check passed.
inline int done(const char * name)
{
  std::cout << name << ": " << (failures() ? std::to_string(failures()) + " check(s) failed" : "ok") << "\n";
  return failures() ? 1 : 0;
}

}  // namespace check

#define CHECK(cond) \
  do { \
    if (!(cond)) {::check::fail(__FILE__, __LINE__, #cond);} \
  } while (0)

#define CHECK_EQ(actual, expected) \
  do { \
    const auto & check_a_ = (actual); \
    const auto & check_e_ = (expected); \
    if (!(check_a_ == check_e_)) { \
      std::ostringstream check_s_; \
      check_s_ << #actual << " is [" << check_a_ << "], expected [" << check_e_ << "]"; \
      ::check::fail(__FILE__, __LINE__, check_s_.str()); \
    } \
  } while (0)

//! expr throws an exception of type Error whose what() contains text.
#define CHECK_THROWS(expr, Error, text) \
  do { \
    try { \
      (void)(expr); \
      ::check::fail(__FILE__, __LINE__, std::string(#expr) + " did not throw"); \
    } catch (const Error & check_e_) { \
      if (std::string(check_e_.what()).find(text) == std::string::npos) { \
        ::check::fail(__FILE__, __LINE__, std::string(#expr) + " threw [" + check_e_.what() + "], expected [" + \
          (text) + "]"); \
      } \
    } \
  } while (0)

#endif  // IFACE_RUNTIME_CPP__TEST__CHECK_HPP_
