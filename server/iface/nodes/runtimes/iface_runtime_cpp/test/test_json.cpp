// JSON as Python's json module writes it: dump, parse, Python's float and string forms, UTF-8 and UTF-16.
#include <cmath>
#include <string>

#include "check.hpp"
#include "iface_runtime_cpp/json.hpp"

using iface_runtime::Json;
using iface_runtime::StateError;

namespace
{

void dump_is_pythons()
{
  // json.dumps(doc, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
  Json::Object inner;
  inner["z"] = Json();
  inner["y"] = Json::boolean(true);
  Json::Object doc;
  doc["b"] = Json::array({Json::integer(1), Json::string("\xc3\xbc\"\\x\xe2\x98\x83\n\t\x01")});
  doc["a"] = Json::object(inner);
  CHECK_EQ(Json::object(doc).dump(), std::string("{\"a\":{\"y\":true,\"z\":null},"
    "\"b\":[1,\"\xc3\xbc\\\"\\\\x\xe2\x98\x83\\n\\t\\u0001\"]}"));
  CHECK_EQ(Json::unsigned_integer(18446744073709551615ULL).dump(), std::string("18446744073709551615"));
  CHECK_EQ(Json::integer(-9223372036854775807LL - 1).dump(), std::string("-9223372036854775808"));
  CHECK_EQ(Json::floating(std::nan("")).dump(), std::string("\"nan\""));
  CHECK_EQ(Json::floating(-HUGE_VAL).dump(), std::string("\"-inf\""));
  CHECK_EQ(Json::array().dump(), std::string("[]"));
  CHECK_EQ(Json::object().dump(), std::string("{}"));
}

void floats_are_pythons_repr()
{
  const std::pair<double, const char *> cases[] = {
    {0.1, "0.1"}, {1e-07, "1e-07"}, {1e16, "1e+16"}, {1e22, "1e+22"}, {-0.0, "-0.0"}, {123.456, "123.456"},
    {1.0 / 3.0, "0.3333333333333333"}, {5e-324, "5e-324"}, {1.7976931348623157e308, "1.7976931348623157e+308"},
    {100.0, "100.0"}, {1e15, "1000000000000000.0"}, {0.0001, "0.0001"}, {0.00001, "1e-05"},
    {3.4028234663852886e38, "3.4028234663852886e+38"}};
  for (const auto & [value, text] : cases) {
    CHECK_EQ(iface_runtime::py_float(value), std::string(text));
    CHECK_EQ(Json::floating(value).dump(), std::string(text));
  }
  CHECK_EQ(iface_runtime::py_bool(true), std::string("True"));
}

void parse_reads_back_what_dump_writes()
{
  const std::string text = "{\"a\":[1,-2.5e3,\"x\",true,false,null],\"b\":{\"c\":18446744073709551615}}";
  const Json doc = Json::parse(text);
  CHECK_EQ(doc.dump(), text);
  CHECK(doc.find("a")->items()[0].is_integer());
  CHECK(!doc.find("a")->items()[1].is_integer());
  CHECK_EQ(doc.find("a")->items()[1].as_double(), -2500.0);
  CHECK(doc.find("missing") == nullptr);
  // spaces, escapes and a surrogate pair (😀), as Python writes with ensure_ascii=True
  const Json spaced = Json::parse(" { \"k\" : [ \"\\u00fc\\ud83d\\ude00\\/\" ] } ");
  CHECK_EQ(spaced.find("k")->items()[0].text(), std::string("\xc3\xbc\xf0\x9f\x98\x80/"));
  const Json nan = Json::parse("NaN");  // held: text() is a reference into it
  CHECK_EQ(nan.text(), std::string("nan"));  // a float JSON cannot hold, as the document writes it
}

void what_is_not_json_is_refused_with_pythons_reason()
{
  CHECK_THROWS(Json::parse("{\"a\":1,}"), StateError, "Expecting property name enclosed in double quotes");
  CHECK_THROWS(Json::parse("[1 2]"), StateError, "Expecting ',' delimiter");
  CHECK_THROWS(Json::parse(""), StateError, "the state is not JSON: Expecting value");
  for (const char * number : {"0", "-0", "7", "-12", "3.25", "-0.5", "1e3", "2E-7", "6.5e+2", "123456789012345678901"}) {
    const Json parsed = Json::parse(number);
    CHECK_EQ(parsed.text(), std::string(number));
  }
  CHECK(Json::parse("[0, -3]").items()[1].is_integer() && !Json::parse("[1e2]").items()[0].is_integer());
  CHECK_EQ(Json::parse("[-2.5e1]").items()[0].as_double(), -25.0);
  for (const char * bad : {"-", "01", "1.", ".5", "1e", "1e+", "-x", "+1"}) {
    CHECK_THROWS(Json::parse(bad), StateError, "");
  }
  CHECK_THROWS(Json::parse("\"abc"), StateError, "Unterminated string");
  CHECK_THROWS(Json::parse("\"\\q\""), StateError, "Invalid \\escape");
  CHECK_THROWS(Json::parse("1 2"), StateError, "Extra data");
  CHECK_THROWS(Json::parse(std::string(300, '[') + std::string(300, ']')), StateError, "nesting too deep");
}

void repr_is_pythons()
{
  CHECK_EQ(Json::string("it's").repr(), std::string("'it\\'s'"));
  CHECK_EQ(Json().repr(), std::string("None"));
  CHECK_EQ(Json::boolean(false).repr(), std::string("False"));
  CHECK_EQ(Json::integer(7).repr(), std::string("7"));
}

void text_in_utf8_and_utf16()
{
  const std::string text = "a\xc3\xbc\xe2\x98\x83\xf0\x9f\x98\x80";  // aü☃😀
  CHECK_EQ(iface_runtime::utf8_length(text), std::size_t{4});
  const std::u16string wide = iface_runtime::utf16(text);
  CHECK_EQ(wide.size(), std::size_t{5});  // 😀 is a surrogate pair
  CHECK(iface_runtime::utf8(wide) == text);
}

}  // namespace

int main()
{
  dump_is_pythons();
  floats_are_pythons_repr();
  parse_reads_back_what_dump_writes();
  what_is_not_json_is_refused_with_pythons_reason();
  repr_is_pythons();
  text_in_utf8_and_utf16();
  return check::done("json");
}
