// The state document: its types and the widening rule, values to and from JSON (overloads the generated
// code adds for its messages, found by ADL), save and read. The same rules as iface_runtime_py's state.
#ifndef IFACE_RUNTIME_CPP__STATE_HPP_
#define IFACE_RUNTIME_CPP__STATE_HPP_

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "iface_runtime_cpp/json.hpp"
#include "rosidl_runtime_cpp/bounded_vector.hpp"

namespace iface_runtime
{

// ---- types of the state document -----------------------------------------------------------------

//! A type of the state document: .msg spelling, message types as package/Name.
struct Type
{
  std::string base;
  std::optional<uint64_t> bound;
  std::string array;  // "", "fixed", "bounded", "unbounded"
  std::optional<uint64_t> size;

  static Type parse(const std::string & text);
  Type element() const {return Type{base, bound, "", std::nullopt};}
  bool is_message() const {return base.find('/') != std::string::npos;}
  std::string str() const;
  bool operator==(const Type & other) const
  {
    return base == other.base && bound == other.bound && array == other.array && size == other.size;
  }
};

//! True when every value of primitive old is a value of primitive new_.
bool widens(const std::string & old, const std::string & new_);
//! True when a value saved as old can be held by new_ (the same type, or a wider primitive).
bool assignable(const Type & old, const Type & new_);
bool is_integer_type(const std::string & base);
std::pair<std::string, std::string> integer_range_text(const std::string & base);

// ---- values: encode and decode, overloads found by the generated code for messages (ADL) --------

template<class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
Json iface_to_json(T value)
{
  if constexpr (std::is_same_v<T, bool>) {
    return Json::boolean(value);
  } else if constexpr (std::is_floating_point_v<T>) {
    return Json::floating(static_cast<double>(value));
  } else if constexpr (std::is_signed_v<T>) {
    return Json::integer(static_cast<int64_t>(value));
  } else {
    return Json::unsigned_integer(static_cast<uint64_t>(value));
  }
}
inline Json iface_to_json(const std::string & value) {return Json::string(value);}
inline Json iface_to_json(const std::u16string & value) {return Json::string(utf8(value));}

bool decode_bool(const Json & data, const std::string & where);
int64_t decode_signed(const Json & data, const Type & t, const std::string & where);
uint64_t decode_unsigned(const Json & data, const Type & t, const std::string & where);
double decode_float(const Json & data, const Type & t, const std::string & where);
std::string decode_string(const Json & data, const Type & t, const std::string & where);
void check_sequence(const Json & data, const Type & t, const std::string & where);
//! A message object: an object whose keys are all fields of the message.
void check_message(const Json & data, const Type & t, const std::string & where,
  const std::vector<std::string> & fields);

template<class T, std::enable_if_t<std::is_arithmetic_v<T>, int> = 0>
void iface_from_json(const Json & data, const Type & t, const std::string & where, T & out)
{
  if constexpr (std::is_same_v<T, bool>) {
    out = decode_bool(data, where);
  } else if constexpr (std::is_floating_point_v<T>) {
    out = static_cast<T>(decode_float(data, t, where));
  } else if constexpr (std::is_signed_v<T>) {
    out = static_cast<T>(decode_signed(data, t, where));
  } else {
    out = static_cast<T>(decode_unsigned(data, t, where));
  }
}
inline void iface_from_json(const Json & data, const Type & t, const std::string & where, std::string & out)
{
  out = decode_string(data, t, where);
}
inline void iface_from_json(const Json & data, const Type & t, const std::string & where, std::u16string & out)
{
  out = utf16(decode_string(data, t, where));
}

template<class Sequence>
Json sequence_to_json(const Sequence & values)
{
  Json::Array items;
  for (const auto & value : values) {
    items.push_back(iface_to_json(value));
  }
  return Json::array(std::move(items));
}
template<class T, class A>
Json iface_to_json(const std::vector<T, A> & values) {return sequence_to_json(values);}
template<class T, std::size_t N>
Json iface_to_json(const std::array<T, N> & values) {return sequence_to_json(values);}
template<class T, std::size_t N, class A>
Json iface_to_json(const rosidl_runtime_cpp::BoundedVector<T, N, A> & values) {return sequence_to_json(values);}

template<class Sequence>
void sequence_from_json(const Json & data, const Type & t, const std::string & where, Sequence & out)
{
  check_sequence(data, t, where);
  Sequence values;
  const Type element = t.element();
  for (std::size_t i = 0; i < data.items().size(); ++i) {
    typename Sequence::value_type value{};
    iface_from_json(data.items()[i], element, where + "[" + std::to_string(i) + "]", value);
    values.push_back(value);
  }
  out = std::move(values);
}
template<class T, class A>
void iface_from_json(const Json & data, const Type & t, const std::string & where, std::vector<T, A> & out)
{
  sequence_from_json(data, t, where, out);
}
template<class T, std::size_t N, class A>
void iface_from_json(
  const Json & data, const Type & t, const std::string & where, rosidl_runtime_cpp::BoundedVector<T, N, A> & out)
{
  sequence_from_json(data, t, where, out);
}
template<class T, std::size_t N>
void iface_from_json(const Json & data, const Type & t, const std::string & where, std::array<T, N> & out)
{
  check_sequence(data, t, where);
  std::array<T, N> values{};
  const Type element = t.element();
  for (std::size_t i = 0; i < N; ++i) {
    iface_from_json(data.items()[i], element, where + "[" + std::to_string(i) + "]", values[i]);
  }
  out = values;
}

// ---- the state document ---------------------------------------------------------------------------

//! {state variable: type} and {message type: {field: type}}.
using Schema = std::map<std::string, std::string>;
using MessageTypes = std::map<std::string, std::map<std::string, std::string>>;

//! What a restore did: variables set from the document, variables that kept their value.
struct Restored
{
  std::vector<std::string> restored;
  std::vector<std::string> kept;
  bool same_interface = false;
  std::string message;
};

//! The state document of values (keys sorted, no spaces) with the component's identity.
std::string save_document(
  const std::string & component, const std::string & version, const std::string & interface_hash,
  const Schema & schema, const MessageTypes & types, const Json::Object & values, const Json::Object & schedule = {});
//! Check a document against this component; its values and what restoring it does, or StateError.
std::pair<Json::Object, Restored> read_document(
  const std::string & text, const std::string & component, const std::string & interface_hash,
  const Schema & schema, const MessageTypes & types);

}  // namespace iface_runtime

#endif  // IFACE_RUNTIME_CPP__STATE_HPP_
