// The state document: types, the widening rule (test/widening.txt, the table iface's tests hold compat and
// the Python runtime to), values decoded or refused with the Python runtime's reasons, save and read.
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "check.hpp"
#include "iface_runtime_cpp/state.hpp"

using iface_runtime::Json;
using iface_runtime::StateError;
using iface_runtime::Type;

namespace
{

void types_parse_and_print()
{
  for (const char * text : {"int32", "string<=8", "float64[3]", "p/Point[<=4]", "byte[]", "wstring<=2[]"}) {
    CHECK_EQ(Type::parse(text).str(), std::string(text));
  }
  const Type t = Type::parse(" p/Point[<=4] ");
  CHECK_EQ(t.base, std::string("p/Point"));
  CHECK_EQ(t.array, std::string("bounded"));
  CHECK(t.is_message() && *t.size == 4);
  CHECK(!Type::parse("float64[3]").element().is_message());
  CHECK_THROWS(Type::parse("9lives"), StateError, "'9lives' is not a type");
  for (const char * bad : {"", "a/", "a/9", "a<=", "a<=x", "a[", "a[3", "a[x]", "a[3]b", "a b", "a<=3<=4", "-a"}) {
    CHECK_THROWS(Type::parse(bad), StateError, "'" + std::string(bad) + "' is not a type");
  }
  const Type u = Type::parse("string<=12[<=]");
  CHECK(u.base == "string" && *u.bound == 12 && u.array == "bounded" && !u.size);
  CHECK(Type::parse("x_1/Y_2[]").array == "unbounded" && Type::parse("uint8[16]").size == 16u);
}

//! Every cell of test/widening.txt: widens(row, column) is 'x'.
void widening_is_the_shared_table(const std::string & folder)
{
  std::ifstream in(folder + "/widening.txt");
  CHECK(in.good());
  std::string line;
  std::vector<std::string> columns;
  int cells = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') {
      continue;
    }
    std::istringstream words(line);
    if (columns.empty()) {
      for (std::string name; words >> name; ) {
        columns.push_back(name);
      }
      continue;
    }
    std::string row, mark;
    words >> row;
    for (const auto & column : columns) {
      words >> mark;
      if (iface_runtime::widens(row, column) != (mark == "x")) {
        check::fail(__FILE__, __LINE__, "widens(" + row + ", " + column + ") is not the table's " + mark);
      }
      ++cells;
    }
  }
  CHECK_EQ(cells, 15 * 15);
}

void strings_widen_by_their_bound()
{
  CHECK(iface_runtime::assignable(Type::parse("string<=4"), Type::parse("string<=8")));
  CHECK(iface_runtime::assignable(Type::parse("string<=4"), Type::parse("string")));
  CHECK(!iface_runtime::assignable(Type::parse("string"), Type::parse("string<=8")));
  CHECK(!iface_runtime::assignable(Type::parse("uint8[3]"), Type::parse("uint16[3]")));
  CHECK(iface_runtime::assignable(Type::parse("p/Point"), Type::parse("p/Point")));
}

void values_that_do_not_fit_are_refused()
{
  const Type u32 = Type::parse("uint32");
  CHECK_EQ(iface_runtime::decode_unsigned(Json::parse("4294967295"), u32, "count"), uint64_t{4294967295u});
  CHECK_THROWS(iface_runtime::decode_unsigned(Json::parse("-1"), u32, "count"), StateError,
    "count: -1 does not fit uint32 (0..4294967295)");
  CHECK_THROWS(iface_runtime::decode_signed(Json::parse("128"), Type::parse("int8"), "x"), StateError,
    "x: 128 does not fit int8 (-128..127)");
  CHECK_THROWS(iface_runtime::decode_signed(Json::parse("1.5"), Type::parse("int64"), "x"), StateError,
    "x: expected an integer for int64, not 1.5");
  CHECK_THROWS(iface_runtime::decode_bool(Json::parse("1"), "flag"), StateError, "flag: expected true or false, not 1");
  CHECK_THROWS(iface_runtime::decode_float(Json::parse("1e39"), Type::parse("float32"), "g"), StateError,
    "g: 1e39 does not fit float32");
  CHECK(std::isnan(iface_runtime::decode_float(Json::parse("\"nan\""), Type::parse("float32"), "g")));
  CHECK_THROWS(iface_runtime::decode_string(Json::parse("\"123456789\""), Type::parse("string<=8"), "label"),
    StateError, "label: 9 characters do not fit string<=8");
  CHECK_EQ(iface_runtime::decode_string(Json::parse("\"\xc3\xbc\xc3\xbc\""), Type::parse("string<=2"), "l"),
    std::string("\xc3\xbc\xc3\xbc"));
  CHECK_THROWS(iface_runtime::check_sequence(Json::parse("[1,2,3,4]"), Type::parse("uint8[<=3]"), "path"),
    StateError, "path: uint8[<=3] holds at most 3 elements, not 4");
  CHECK_THROWS(iface_runtime::check_sequence(Json::parse("[1]"), Type::parse("uint8[2]"), "v"), StateError,
    "v: uint8[2] holds exactly 2 elements, not 1");
  CHECK_THROWS(iface_runtime::check_message(Json::parse("{\"x\":1,\"z\":2}"), Type::parse("p/Point"), "where",
    {"x", "name"}), StateError, "where: p/Point has no field z");
}

void values_convert_both_ways()
{
  std::vector<uint8_t> bytes;
  iface_runtime::iface_from_json(Json::parse("[1,2,255]"), Type::parse("byte[]"), "raw", bytes);
  CHECK_EQ(iface_runtime::iface_to_json(bytes).dump(), std::string("[1,2,255]"));
  std::array<double, 2> pair{};
  iface_runtime::iface_from_json(Json::parse("[0.5,\"-inf\"]"), Type::parse("float64[2]"), "p", pair);
  CHECK_EQ(iface_runtime::iface_to_json(pair).dump(), std::string("[0.5,\"-inf\"]"));
  std::u16string wide;
  iface_runtime::iface_from_json(Json::parse("\"\xe2\x98\x83\""), Type::parse("wstring"), "w", wide);
  CHECK_EQ(iface_runtime::iface_to_json(wide).dump(), std::string("\"\xe2\x98\x83\""));
}

const iface_runtime::Schema SCHEMA = {{"count", "uint32"}, {"label", "string<=8"}, {"gain", "float32"}};

std::string saved()
{
  Json::Object values;
  values["count"] = Json::unsigned_integer(7);
  values["label"] = Json::string("abc");
  values["gain"] = Json::floating(0.5);
  Json::Object schedule;
  schedule["tick"] = Json::integer(1700000000000000000);
  return iface_runtime::save_document("c", "1.0.0", "sha256:a", SCHEMA, {}, values, schedule);
}

void the_document_is_the_python_runtimes()
{
  CHECK_EQ(saved(), std::string("{\"component\":\"c\",\"format\":\"iface-state/1\",\"interface_hash\":\"sha256:a\","
    "\"protocol_version\":\"1\",\"schedule\":{\"tick\":1700000000000000000},\"schema\":{\"count\":\"uint32\","
    "\"gain\":\"float32\",\"label\":\"string<=8\"},\"types\":{},\"values\":{\"count\":7,\"gain\":0.5,"
    "\"label\":\"abc\"},\"version\":\"1.0.0\"}"));
  auto [values, report] = iface_runtime::read_document(saved(), "c", "sha256:a", SCHEMA, {});
  CHECK_EQ(values.size(), std::size_t{3});
  CHECK(report.same_interface && report.kept.empty());
  CHECK_EQ(report.message, std::string("restored 3 variable(s) saved by c 1.0.0 (the same interface)"));
}

void a_wider_type_takes_the_state_a_narrower_one_refuses_it()
{
  iface_runtime::Schema wider = SCHEMA;
  wider["count"] = "uint64";
  wider["gain"] = "float64";
  wider["extra"] = "int8";
  auto [values, report] = iface_runtime::read_document(saved(), "c", "sha256:b", wider, {});
  CHECK(!report.same_interface);
  CHECK(report.kept == std::vector<std::string>{"extra"});
  CHECK_EQ(report.message, std::string("restored 3 variable(s) saved by c 1.0.0 (interface sha256:a); kept extra"));
  iface_runtime::Schema narrower = SCHEMA;
  narrower["count"] = "uint16";
  CHECK_THROWS(iface_runtime::read_document(saved(), "c", "sha256:a", narrower, {}), StateError,
    "state 'count' is uint32 in c 1.0.0 but uint16 in c");
  iface_runtime::Schema smaller = SCHEMA;
  smaller.erase("gain");
  CHECK_THROWS(iface_runtime::read_document(saved(), "c", "sha256:a", smaller, {}), StateError,
    "state 'gain' of c 1.0.0 has no place in c: its value would be lost");
  CHECK_THROWS(iface_runtime::read_document("{\"format\":\"other/2\"}", "c", "", SCHEMA, {}), StateError,
    "the state document's format is 'other/2', not 'iface-state/1'");
  CHECK_THROWS(iface_runtime::read_document("{", "c", "", SCHEMA, {}), StateError, "the state is not JSON");
}

}  // namespace

int main(int argc, char ** argv)
{
  types_parse_and_print();
  widening_is_the_shared_table(argc > 1 ? argv[1] : ".");
  strings_widen_by_their_bound();
  values_that_do_not_fit_are_refused();
  values_convert_both_ways();
  the_document_is_the_python_runtimes();
  a_wider_type_takes_the_state_a_narrower_one_refuses_it();
  return check::done("state");
}
