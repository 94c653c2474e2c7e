// JSON as Python's json module writes it (keys sorted, no spaces, UTF-8 kept): what the state document is
// written in, byte for byte as the Python runtime writes it, and read back.
#ifndef IFACE_RUNTIME_CPP__JSON_HPP_
#define IFACE_RUNTIME_CPP__JSON_HPP_

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace iface_runtime
{

//! A state document this component cannot take; what() says why.
class StateError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

// ---- JSON, as Python's json module writes it (keys sorted, no spaces, UTF-8 kept) ---------------

class Json
{
public:
  enum class Kind { Null, Bool, Number, String, Array, Object };
  using Array = std::vector<Json>;
  using Object = std::map<std::string, Json>;

  Json() = default;
  static Json boolean(bool value);
  static Json integer(int64_t value);
  static Json unsigned_integer(uint64_t value);
  //! A float: a number, or the string "nan", "inf" or "-inf" where JSON has none.
  static Json floating(double value);
  static Json string(std::string value);
  static Json array(Array items = {});
  static Json object(Object fields = {});
  //! A number as written in a JSON text.
  static Json raw_number(std::string text, bool integral, double value);
  //! Parse a JSON text; StateError when it is not JSON.
  static Json parse(const std::string & text);

  Kind kind() const {return kind_;}
  bool is_integer() const {return kind_ == Kind::Number && integral_;}
  bool as_bool() const {return bool_;}
  const std::string & text() const {return text_;}
  double as_double() const {return number_;}
  const Array & items() const {return items_;}
  Array & items() {return items_;}
  const Object & fields() const {return fields_;}
  Object & fields() {return fields_;}
  const Json * find(const std::string & key) const;

  //! Compact JSON, keys sorted.
  std::string dump() const;
  //! How Python shows the value in a message ({data!r}).
  std::string repr() const;

private:
  void write(std::string & out) const;
  Kind kind_ = Kind::Null;
  bool bool_ = false;
  bool integral_ = false;
  double number_ = 0.0;
  std::string text_;
  Array items_;
  Object fields_;
};

//! Python's repr() of a float (the shortest text that reads back the same double).
std::string py_float(double value);
//! Python's str() of a bool.
inline std::string py_bool(bool value) {return value ? "True" : "False";}

//! Characters (code points) of a UTF-8 text.
size_t utf8_length(const std::string & text);
//! UTF-8 from UTF-16 (wstring values) and back.
std::string utf8(const std::u16string & text);
std::u16string utf16(const std::string & text);

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__JSON_HPP_
