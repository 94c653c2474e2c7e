/** Thrift features iface reads as Thrift does. */
include "included.thrift"
cpp_include "<vector>"
namespace cpp features
namespace py.twisted features.twisted
namespace * features

typedef i64 Timestamp
typedef list<string> (cpp.template = "std::list") Names
typedef included.Shared SharedAlias

const i32 MAX = 0x7fffffff
const double RATIO = 1.5e3
const list<i16> PRIMES = [2, 3, 5, 7]
const map<string, i32> CODES = {"a": 1, "b": 2}
const bool ENABLED = true
const uuid NIL = '00000000-0000-0000-0000-000000000000'
const Mode DEFAULT_MODE = Mode.FAST

enum Mode {
  SLOW = 1,
  FAST,
  TURBO = 10 (fast = "yes")
} (cpp.enum_strict)

senum Flavour { "vanilla", "chocolate" }

struct Keywords {
  1: i8 i8,
  2: string string,
  3: uuid uuid,
  4: binary binary,
  5: optional Mode mode = Mode.SLOW,
  6: required Timestamp at,
  7: set<Mode> modes = {},
  8: map<string, list<i32>> table,
  9: included.Shared shared,
  10: SharedAlias alias,
  11: Keywords & next,
  string no_id,
} (cpp.type = "Kw", annotation.without.value)

union Either {
  1: i32 number,
  2: string text
}

exception Failure {
  1: string message,
  2: i32 code = 500
}

service Base {
  void ping()
}

service Store extends Base {
  /** Reads a record. */
  Keywords get(1: i64 id) throws (1: Failure failure),
  oneway void notify(1: string event),
  list<Names> names(1: set<i32> ids, 2: Either which) (deprecated = "use get")
}
