// JSON as Python's json module writes it: see json.hpp.
#include "iface_runtime_cpp/json.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <system_error>
#include <utility>

namespace iface_runtime
{

Json Json::boolean(bool value)
{
  Json j;
  j.kind_ = Kind::Bool;
  j.bool_ = value;
  return j;
}

Json Json::integer(int64_t value)
{
  Json j;
  j.kind_ = Kind::Number;
  j.integral_ = true;
  j.number_ = static_cast<double>(value);
  j.text_ = std::to_string(value);
  return j;
}

Json Json::unsigned_integer(uint64_t value)
{
  Json j;
  j.kind_ = Kind::Number;
  j.integral_ = true;
  j.number_ = static_cast<double>(value);
  j.text_ = std::to_string(value);
  return j;
}

Json Json::floating(double value)
{
  if (std::isnan(value)) {
    return string("nan");
  }
  if (std::isinf(value)) {
    return string(value > 0 ? "inf" : "-inf");
  }
  Json j;
  j.kind_ = Kind::Number;
  j.number_ = value;
  j.text_ = py_float(value);
  return j;
}

Json Json::string(std::string value)
{
  Json j;
  j.kind_ = Kind::String;
  j.text_ = std::move(value);
  return j;
}

Json Json::array(Array items)
{
  Json j;
  j.kind_ = Kind::Array;
  j.items_ = std::move(items);
  return j;
}

Json Json::object(Object fields)
{
  Json j;
  j.kind_ = Kind::Object;
  j.fields_ = std::move(fields);
  return j;
}

const Json * Json::find(const std::string & key) const
{
  auto found = fields_.find(key);
  return found == fields_.end() ? nullptr : &found->second;
}

namespace
{

void write_string(std::string & out, const std::string & text)
{
  out += '"';
  for (unsigned char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  out += '"';
}

void append_utf8(std::string & out, uint32_t cp)
{
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

class Parser
{
public:
  explicit Parser(const std::string & text)
  : text_(text) {}

  Json document()
  {
    Json value = parse_value(0);
    skip();
    if (pos_ != text_.size()) {
      fail("Extra data");
    }
    return value;
  }

private:
  [[noreturn]] void fail(const std::string & what)
  {
    throw StateError("the state is not JSON: " + what + " at character " + std::to_string(pos_));
  }

  void skip()
  {
    while (pos_ < text_.size() && (text_[pos_] == ' ' || text_[pos_] == '\n' || text_[pos_] == '\r' ||
      text_[pos_] == '\t'))
    {
      ++pos_;
    }
  }

  bool literal(const char * word)
  {
    const std::string w(word);
    if (text_.compare(pos_, w.size(), w) == 0) {
      pos_ += w.size();
      return true;
    }
    return false;
  }

  Json parse_value(int depth)
  {
    if (depth > 200) {
      fail("nesting too deep");
    }
    skip();
    if (pos_ >= text_.size()) {
      fail("Expecting value");
    }
    const char c = text_[pos_];
    if (c == '{') {
      ++pos_;
      Json::Object fields;
      skip();
      if (pos_ < text_.size() && text_[pos_] == '}') {
        ++pos_;
        return Json::object(std::move(fields));
      }
      while (true) {
        skip();
        if (pos_ >= text_.size() || text_[pos_] != '"') {
          fail("Expecting property name enclosed in double quotes");
        }
        std::string key = parse_string();
        skip();
        if (pos_ >= text_.size() || text_[pos_] != ':') {
          fail("Expecting ':' delimiter");
        }
        ++pos_;
        fields[key] = parse_value(depth + 1);
        skip();
        if (pos_ < text_.size() && text_[pos_] == ',') {
          ++pos_;
          continue;
        }
        if (pos_ < text_.size() && text_[pos_] == '}') {
          ++pos_;
          return Json::object(std::move(fields));
        }
        fail("Expecting ',' delimiter");
      }
    }
    if (c == '[') {
      ++pos_;
      Json::Array items;
      skip();
      if (pos_ < text_.size() && text_[pos_] == ']') {
        ++pos_;
        return Json::array(std::move(items));
      }
      while (true) {
        items.push_back(parse_value(depth + 1));
        skip();
        if (pos_ < text_.size() && text_[pos_] == ',') {
          ++pos_;
          continue;
        }
        if (pos_ < text_.size() && text_[pos_] == ']') {
          ++pos_;
          return Json::array(std::move(items));
        }
        fail("Expecting ',' delimiter");
      }
    }
    if (c == '"') {
      return Json::string(parse_string());
    }
    if (literal("true")) {
      return Json::boolean(true);
    }
    if (literal("false")) {
      return Json::boolean(false);
    }
    if (literal("null")) {
      return Json();
    }
    if (literal("NaN")) {
      return Json::floating(std::nan(""));
    }
    if (literal("Infinity")) {
      return Json::floating(HUGE_VAL);
    }
    if (literal("-Infinity")) {
      return Json::floating(-HUGE_VAL);
    }
    return parse_number();
  }

  //! A JSON number (-?(0|[1-9][0-9]*)(.[0-9]+)?([eE][-+]?[0-9]+)?), scanned by hand: std::regex took ~3 ms the
  //! first time a process used it, inside a hand-over's critical section (docs/system.md).
  Json parse_number()
  {
    const std::size_t start = pos_;
    const auto digit = [this](std::size_t at) {return at < text_.size() && text_[at] >= '0' && text_[at] <= '9';};
    const auto digits = [this, &digit] {
        const std::size_t from = pos_;
        while (digit(pos_)) {
          ++pos_;
        }
        return pos_ - from;
      };
    if (pos_ < text_.size() && text_[pos_] == '-') {
      ++pos_;
    }
    if (pos_ < text_.size() && text_[pos_] == '0') {
      ++pos_;
    } else if (digits() == 0) {
      pos_ = start;
      fail("Expecting value");
    }
    bool integral = true;
    if (pos_ < text_.size() && text_[pos_] == '.' && digit(pos_ + 1)) {
      ++pos_;
      digits();
      integral = false;
    }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      const std::size_t mark = pos_++;
      if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) {
        ++pos_;
      }
      if (digits() == 0) {
        pos_ = mark;  // not an exponent: the number ends before it
      } else {
        integral = false;
      }
    }
    const std::string text = text_.substr(start, pos_ - start);
    return Json::raw_number(text, integral, std::strtod(text.c_str(), nullptr));
  }

  std::string parse_string()
  {
    ++pos_;  // the opening quote
    std::string out;
    while (true) {
      if (pos_ >= text_.size()) {
        fail("Unterminated string");
      }
      const unsigned char c = static_cast<unsigned char>(text_[pos_++]);
      if (c == '"') {
        return out;
      }
      if (c < 0x20) {
        fail("Invalid control character");
      }
      if (c != '\\') {
        out += static_cast<char>(c);
        continue;
      }
      if (pos_ >= text_.size()) {
        fail("Unterminated string");
      }
      const char e = text_[pos_++];
      switch (e) {
        case '"': out += '"'; break;
        case '\\': out += '\\'; break;
        case '/': out += '/'; break;
        case 'b': out += '\b'; break;
        case 'f': out += '\f'; break;
        case 'n': out += '\n'; break;
        case 'r': out += '\r'; break;
        case 't': out += '\t'; break;
        case 'u': {
            uint32_t cp = hex4();
            if (cp >= 0xD800 && cp < 0xDC00 && text_.compare(pos_, 2, "\\u") == 0) {
              pos_ += 2;
              const uint32_t low = hex4();
              if (low >= 0xDC00 && low < 0xE000) {
                cp = 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
              } else {
                append_utf8(out, cp);
                cp = low;
              }
            }
            append_utf8(out, cp);
            break;
          }
        default:
          fail("Invalid \\escape");
      }
    }
  }

  uint32_t hex4()
  {
    if (pos_ + 4 > text_.size()) {
      fail("Invalid \\uXXXX escape");
    }
    uint32_t value = 0;
    const auto r = std::from_chars(text_.data() + pos_, text_.data() + pos_ + 4, value, 16);
    if (r.ec != std::errc() || r.ptr != text_.data() + pos_ + 4) {
      fail("Invalid \\uXXXX escape");
    }
    pos_ += 4;
    return value;
  }

  const std::string & text_;
  std::size_t pos_ = 0;
};

}  // namespace

Json Json::raw_number(std::string text, bool integral, double value)
{
  Json j;
  j.kind_ = Kind::Number;
  j.integral_ = integral;
  j.number_ = value;
  j.text_ = std::move(text);
  return j;
}

Json Json::parse(const std::string & text)
{
  return Parser(text).document();
}

void Json::write(std::string & out) const
{
  switch (kind_) {
    case Kind::Null: out += "null"; break;
    case Kind::Bool: out += bool_ ? "true" : "false"; break;
    case Kind::Number: out += text_; break;
    case Kind::String: write_string(out, text_); break;
    case Kind::Array: {
        out += '[';
        bool first = true;
        for (const auto & item : items_) {
          if (!first) {
            out += ',';
          }
          first = false;
          item.write(out);
        }
        out += ']';
        break;
      }
    case Kind::Object: {
        out += '{';
        bool first = true;
        for (const auto & [key, value] : fields_) {
          if (!first) {
            out += ',';
          }
          first = false;
          write_string(out, key);
          out += ':';
          value.write(out);
        }
        out += '}';
        break;
      }
  }
}

std::string Json::dump() const
{
  std::string out;
  write(out);
  return out;
}

std::string Json::repr() const
{
  switch (kind_) {
    case Kind::Null: return "None";
    case Kind::Bool: return py_bool(bool_);
    case Kind::String: {
        std::string out = "'";
        for (char c : text_) {
          if (c == '\'' || c == '\\') {
            out += '\\';
          }
          out += c;
        }
        return out + "'";
      }
    default: return dump();
  }
}

std::string py_float(double value)
{
  if (std::isnan(value)) {
    return "nan";
  }
  if (std::isinf(value)) {
    return value > 0 ? "inf" : "-inf";
  }
  if (value == 0.0) {
    return std::signbit(value) ? "-0.0" : "0.0";
  }
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::scientific);
  const std::string s(buf, r.ptr);
  const auto e = s.find('e');
  std::string mantissa = s.substr(0, e);
  const int exponent = std::stoi(s.substr(e + 1));
  const bool negative = mantissa[0] == '-';
  std::string digits;
  for (char c : mantissa) {
    if (c >= '0' && c <= '9') {
      digits += c;
    }
  }
  std::string out;
  if (exponent >= -4 && exponent < 16) {
    if (exponent >= 0) {
      const auto whole = static_cast<std::size_t>(exponent + 1);
      if (digits.size() <= whole) {
        out = digits + std::string(whole - digits.size(), '0') + ".0";
      } else {
        out = digits.substr(0, whole) + "." + digits.substr(whole);
      }
    } else {
      out = "0." + std::string(static_cast<std::size_t>(-exponent - 1), '0') + digits;
    }
  } else {
    out = digits.substr(0, 1);
    if (digits.size() > 1) {
      out += "." + digits.substr(1);
    }
    char exp[16];
    std::snprintf(exp, sizeof exp, "e%c%02d", exponent < 0 ? '-' : '+', std::abs(exponent));
    out += exp;
  }
  return (negative ? "-" : "") + out;
}

size_t utf8_length(const std::string & text)
{
  return static_cast<size_t>(std::count_if(text.begin(), text.end(), [](char c) {
           return (static_cast<unsigned char>(c) & 0xC0) != 0x80;
         }));
}

std::string utf8(const std::u16string & text)
{
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    uint32_t cp = text[i];
    if (cp >= 0xD800 && cp < 0xDC00 && i + 1 < text.size()) {
      cp = 0x10000 + ((cp - 0xD800) << 10) + (text[++i] - 0xDC00);
    }
    append_utf8(out, cp);
  }
  return out;
}

std::u16string utf16(const std::string & text)
{
  std::u16string out;
  for (std::size_t i = 0; i < text.size(); ) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    uint32_t cp = c;
    int extra = c >= 0xF0 ? 3 : c >= 0xE0 ? 2 : c >= 0xC0 ? 1 : 0;
    cp = extra == 3 ? c & 0x07 : extra == 2 ? c & 0x0F : extra == 1 ? c & 0x1F : c;
    for (int k = 1; k <= extra && i + k < text.size(); ++k) {
      cp = (cp << 6) | (static_cast<unsigned char>(text[i + k]) & 0x3F);
    }
    i += 1 + extra;
    if (cp >= 0x10000) {
      cp -= 0x10000;
      out += static_cast<char16_t>(0xD800 + (cp >> 10));
      out += static_cast<char16_t>(0xDC00 + (cp & 0x3FF));
    } else {
      out += static_cast<char16_t>(cp);
    }
  }
  return out;
}

}  // namespace iface_runtime
