// The state document: see state.hpp.
#include "iface_runtime_cpp/state.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "iface_runtime_cpp/protocol.hpp"

namespace iface_runtime
{

// ---- types ------------------------------------------------------------------------------------------

namespace
{

const std::map<std::string, int> & bits()
{
  static const std::map<std::string, int> table = {
    {"byte", 8}, {"char", 8}, {"uint8", 8}, {"int8", 8}, {"uint16", 16}, {"int16", 16}, {"uint32", 32},
    {"int32", 32}, {"uint64", 64}, {"int64", 64}};
  return table;
}

bool is_signed(const std::string & base)
{
  return base == "int8" || base == "int16" || base == "int32" || base == "int64";
}

int float_exact(const std::string & base)
{
  return base == "float32" ? 24 : base == "float64" ? 53 : 0;
}

constexpr double FLOAT32_MAX = 3.4028234663852886e38;

}  // namespace

bool is_integer_type(const std::string & base)
{
  return bits().count(base) > 0;
}

Type Type::parse(const std::string & text)
{
  // NAME(/NAME)?(<=N)?([(<=)?N?])?, scanned by hand (std::regex took ~3 ms the first time, in a hand-over)
  std::string s = text;
  s.erase(0, s.find_first_not_of(" \t\n"));
  s.erase(s.find_last_not_of(" \t\n") + 1);
  std::size_t i = 0;
  const auto letter = [&s](std::size_t at) {
      return at < s.size() && ((s[at] >= 'A' && s[at] <= 'Z') || (s[at] >= 'a' && s[at] <= 'z'));
    };
  const auto digit = [&s](std::size_t at) {return at < s.size() && s[at] >= '0' && s[at] <= '9';};
  const auto name = [&] {
      if (!letter(i)) {
        return false;
      }
      while (letter(i) || digit(i) || (i < s.size() && s[i] == '_')) {
        ++i;
      }
      return true;
    };
  const auto number = [&] {
      const std::size_t from = i;
      while (digit(i)) {
        ++i;
      }
      return s.substr(from, i - from);
    };
  bool ok = name();
  if (ok && i < s.size() && s[i] == '/') {
    ++i;
    ok = name();
  }
  Type t;
  t.base = s.substr(0, i);
  if (ok && s.compare(i, 2, "<=") == 0) {
    i += 2;
    const std::string bound = number();
    ok = !bound.empty();
    if (ok) {
      t.bound = std::stoull(bound);
    }
  }
  if (ok && i < s.size() && s[i] == '[') {
    ++i;
    const bool bounded = s.compare(i, 2, "<=") == 0;
    i += bounded ? 2 : 0;
    const std::string size = number();
    ok = i < s.size() && s[i] == ']';
    ++i;
    t.array = bounded ? "bounded" : (size.empty() ? "unbounded" : "fixed");
    if (!size.empty()) {
      t.size = std::stoull(size);
    }
  }
  if (!ok || i != s.size()) {
    throw StateError("'" + text + "' is not a type");
  }
  return t;
}

std::string Type::str() const
{
  std::string core = base + (bound ? "<=" + std::to_string(*bound) : "");
  if (array == "fixed") {
    return core + "[" + std::to_string(size.value_or(0)) + "]";
  }
  if (array == "bounded") {
    return core + "[<=" + std::to_string(size.value_or(0)) + "]";
  }
  if (array == "unbounded") {
    return core + "[]";
  }
  return core;
}

bool widens(const std::string & old, const std::string & new_)
{
  if (old == new_) {
    return true;
  }
  const auto & b = bits();
  if (b.count(old) && b.count(new_)) {
    const int old_bits = b.at(old), new_bits = b.at(new_);
    if (is_signed(old) == is_signed(new_)) {
      return new_bits >= old_bits;
    }
    return is_signed(new_) && new_bits > old_bits;
  }
  if (b.count(old) && float_exact(new_)) {
    return b.at(old) - (is_signed(old) ? 1 : 0) <= float_exact(new_);
  }
  return old == "float32" && new_ == "float64";
}

bool assignable(const Type & old, const Type & new_)
{
  if (old == new_) {
    return true;
  }
  if (!old.array.empty() || !new_.array.empty() || old.is_message() || new_.is_message()) {
    return false;
  }
  if ((old.base == "string" || old.base == "wstring") && new_.base == old.base) {
    return !new_.bound || (old.bound && *new_.bound >= *old.bound);
  }
  if (old.bound || new_.bound) {
    return false;
  }
  return widens(old.base, new_.base);
}

std::pair<std::string, std::string> integer_range_text(const std::string & base)
{
  const int n = bits().at(base);
  if (is_signed(base)) {
    const int64_t high = n == 64 ? std::numeric_limits<int64_t>::max() : (int64_t{1} << (n - 1)) - 1;
    return {std::to_string(-high - 1), std::to_string(high)};
  }
  const uint64_t high = n == 64 ? std::numeric_limits<uint64_t>::max() : (uint64_t{1} << n) - 1;
  return {"0", std::to_string(high)};
}

// ---- values -----------------------------------------------------------------------------------------

bool decode_bool(const Json & data, const std::string & where)
{
  if (data.kind() != Json::Kind::Bool) {
    throw StateError(where + ": expected true or false, not " + data.repr());
  }
  return data.as_bool();
}

namespace
{

void check_integer(const Json & data, const Type & t, const std::string & where)
{
  if (!data.is_integer()) {
    throw StateError(where + ": expected an integer for " + t.str() + ", not " + data.repr());
  }
}

[[noreturn]] void does_not_fit(const Json & data, const Type & t, const std::string & where)
{
  const auto [low, high] = integer_range_text(t.base);
  throw StateError(where + ": " + data.text() + " does not fit " + t.str() + " (" + low + ".." + high + ")");
}

}  // namespace

int64_t decode_signed(const Json & data, const Type & t, const std::string & where)
{
  check_integer(data, t, where);
  int64_t value = 0;
  const auto & s = data.text();
  if (std::from_chars(s.data(), s.data() + s.size(), value).ec != std::errc()) {
    does_not_fit(data, t, where);
  }
  const int n = bits().at(t.base);
  if (is_signed(t.base)) {
    if (n < 64 && (value < -(int64_t{1} << (n - 1)) || value > (int64_t{1} << (n - 1)) - 1)) {
      does_not_fit(data, t, where);
    }
  } else if (value < 0 || (n < 64 && value > (int64_t{1} << n) - 1)) {
    does_not_fit(data, t, where);
  }
  return value;
}

uint64_t decode_unsigned(const Json & data, const Type & t, const std::string & where)
{
  check_integer(data, t, where);
  uint64_t value = 0;
  const auto & s = data.text();
  if (s.empty() || s[0] == '-' || std::from_chars(s.data(), s.data() + s.size(), value).ec != std::errc()) {
    does_not_fit(data, t, where);
  }
  const int n = bits().at(t.base);
  if (n < 64 && value > (uint64_t{1} << n) - 1) {
    does_not_fit(data, t, where);
  }
  return value;
}

double decode_float(const Json & data, const Type & t, const std::string & where)
{
  if (data.kind() == Json::Kind::String) {
    if (data.text() == "nan") {
      return std::numeric_limits<double>::quiet_NaN();
    }
    if (data.text() == "inf" || data.text() == "-inf") {
      return data.text() == "inf" ? HUGE_VAL : -HUGE_VAL;
    }
  }
  if (data.kind() != Json::Kind::Number) {
    throw StateError(where + ": expected a number for " + t.str() + ", not " + data.repr());
  }
  const double number = data.is_integer() ? std::strtod(data.text().c_str(), nullptr) : data.as_double();
  if (t.base == "float32" && std::abs(number) > FLOAT32_MAX) {
    throw StateError(where + ": " + data.text() + " does not fit float32");
  }
  return number;
}

std::string decode_string(const Json & data, const Type & t, const std::string & where)
{
  if (data.kind() != Json::Kind::String) {
    throw StateError(where + ": expected a string for " + t.str() + ", not " + data.repr());
  }
  const size_t length = utf8_length(data.text());
  if (t.bound && length > *t.bound) {
    throw StateError(where + ": " + std::to_string(length) + " characters do not fit " + t.str());
  }
  return data.text();
}

void check_sequence(const Json & data, const Type & t, const std::string & where)
{
  if (data.kind() != Json::Kind::Array) {
    throw StateError(where + ": expected a list for " + t.str());
  }
  const auto n = data.items().size();
  if (t.array == "fixed" && n != t.size.value_or(0)) {
    throw StateError(where + ": " + t.str() + " holds exactly " + std::to_string(t.size.value_or(0)) +
            " elements, not " + std::to_string(n));
  }
  if (t.array == "bounded" && t.size && n > *t.size) {
    throw StateError(where + ": " + t.str() + " holds at most " + std::to_string(*t.size) + " elements, not " +
            std::to_string(n));
  }
}

void check_message(
  const Json & data, const Type & t, const std::string & where, const std::vector<std::string> & fields)
{
  if (data.kind() != Json::Kind::Object) {
    throw StateError(where + ": expected an object for " + t.base);
  }
  for (const auto & [key, value] : data.fields()) {
    (void)value;
    if (std::find(fields.begin(), fields.end(), key) == fields.end()) {
      throw StateError(where + ": " + t.base + " has no field " + key);
    }
  }
}

// ---- the state document ---------------------------------------------------------------------------

namespace
{

MessageTypes used_types(const Schema & schema, const MessageTypes & known)
{
  MessageTypes out;
  std::vector<std::string> todo;
  for (const auto & [name, type] : schema) {
    (void)name;
    todo.push_back(Type::parse(type).base);
  }
  while (!todo.empty()) {
    const std::string base = todo.back();
    todo.pop_back();
    if (base.find('/') == std::string::npos || out.count(base) || !known.count(base)) {
      continue;
    }
    out[base] = known.at(base);
    for (const auto & [field, type] : out[base]) {
      (void)field;
      todo.push_back(Type::parse(type).base);
    }
  }
  return out;
}

std::string join(const std::vector<std::string> & items, const std::string & sep)
{
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    out += (i ? sep : "") + items[i];
  }
  return out;
}

}  // namespace

std::string save_document(
  const std::string & component, const std::string & version, const std::string & interface_hash,
  const Schema & schema, const MessageTypes & types, const Json::Object & values, const Json::Object & schedule)
{
  Json::Object schema_json, types_json;
  for (const auto & [name, type] : schema) {
    schema_json[name] = Json::string(type);
  }
  for (const auto & [base, fields] : used_types(schema, types)) {
    Json::Object f;
    for (const auto & [field, type] : fields) {
      f[field] = Json::string(type);
    }
    types_json[base] = Json::object(std::move(f));
  }
  Json::Object doc;
  doc["format"] = Json::string(STATE_FORMAT);
  doc["component"] = Json::string(component);
  doc["version"] = Json::string(version);
  doc["interface_hash"] = Json::string(interface_hash);
  doc["protocol_version"] = Json::string(PROTOCOL_VERSION);
  doc["schedule"] = Json::object(schedule);
  doc["schema"] = Json::object(std::move(schema_json));
  doc["types"] = Json::object(std::move(types_json));
  doc["values"] = Json::object(values);
  return Json::object(std::move(doc)).dump();
}

std::pair<Json::Object, Restored> read_document(
  const std::string & text, const std::string & component, const std::string & interface_hash,
  const Schema & schema, const MessageTypes & types)
{
  const Json doc = Json::parse(text);
  const Json * format = doc.kind() == Json::Kind::Object ? doc.find("format") : nullptr;
  if (format == nullptr || format->kind() != Json::Kind::String || format->text() != STATE_FORMAT) {
    const std::string found = format == nullptr ? "None" : format->repr();
    throw StateError("the state document's format is " + found + ", not '" + STATE_FORMAT + "'");
  }
  const Json * their_schema = doc.find("schema");
  const Json * values = doc.find("values");
  const Json * their_types = doc.find("types");
  const Json no_types = Json::object();
  if (their_types == nullptr) {
    their_types = &no_types;
  }
  if (their_schema == nullptr || their_schema->kind() != Json::Kind::Object || values == nullptr ||
    values->kind() != Json::Kind::Object || their_types->kind() != Json::Kind::Object)
  {
    throw StateError("the state document has no schema, types or values object");
  }
  const Json * their_component = doc.find("component");
  const Json * their_version = doc.find("version");
  std::string origin = (their_component && their_component->kind() == Json::Kind::String ?
    their_component->text() : std::string("?")) + " " +
    (their_version && their_version->kind() == Json::Kind::String ? their_version->text() : std::string());
  origin.erase(origin.find_last_not_of(' ') + 1);
  std::vector<std::string> problems;
  for (const auto & [name, type] : their_schema->fields()) {
    const Type theirs = Type::parse(type.kind() == Json::Kind::String ? type.text() : type.dump());
    if (!schema.count(name)) {
      problems.push_back("state '" + name + "' of " + origin + " has no place in " + component +
        ": its value would be lost");
      continue;
    }
    const Type mine = Type::parse(schema.at(name));
    if (!assignable(theirs, mine)) {
      problems.push_back("state '" + name + "' is " + theirs.str() + " in " + origin + " but " + mine.str() +
        " in " + component);
    }
  }
  const MessageTypes mine_types = used_types(schema, types);
  for (const auto & [base, fields] : their_types->fields()) {
    auto mine = mine_types.find(base);
    if (mine == mine_types.end()) {
      continue;
    }
    std::map<std::string, std::string> theirs;
    if (fields.kind() == Json::Kind::Object) {
      for (const auto & [field, type] : fields.fields()) {
        theirs[field] = type.kind() == Json::Kind::String ? type.text() : type.dump();
      }
    }
    if (theirs != mine->second) {
      problems.push_back("message " + base + " has other fields in " + origin + " than in " + component);
    }
  }
  if (!problems.empty()) {
    throw StateError(join(problems, "; "));
  }
  Json::Object decoded;
  Restored report;
  for (const auto & [name, type] : their_schema->fields()) {
    (void)type;
    const Json * value = values->find(name);
    if (value == nullptr) {
      throw StateError("the state document has no value for '" + name + "'");
    }
    decoded[name] = *value;
    report.restored.push_back(name);
  }
  for (const auto & [name, type] : schema) {
    (void)type;
    if (!their_schema->find(name)) {
      report.kept.push_back(name);
    }
  }
  const Json * hash = doc.find("interface_hash");
  const std::string their_hash = hash && hash->kind() == Json::Kind::String ? hash->text() : "?";
  report.same_interface = hash != nullptr && their_hash == interface_hash;
  const std::string how = report.same_interface ? "the same interface" : "interface " + their_hash;
  report.message = "restored " + std::to_string(decoded.size()) + " variable(s) saved by " + origin + " (" + how + ")";
  if (!report.kept.empty()) {
    report.message += "; kept " + join(report.kept, ", ");
  }
  return {decoded, report};
}

}  // namespace iface_runtime
