"""Interface files at the edges of what ``check`` accepts, for the every-command test.

Each is a (name, text) pair; the test keeps those that ``check`` accepts (no error) and
runs every command and every target over them. Hand-written cases stand at the limits
of the language (numbers at the edges of their types, the deepest nesting allowed,
every escape, long typedef chains, names close to reserved ones); ``random_cases``
adds seeded, grammar-shaped interfaces that mix the features.
"""

from __future__ import annotations

import random

BASE_TYPES = ["bool", "i8", "i16", "i32", "i64", "u8", "u16", "u32", "u64", "float32", "float64", "string",
              "wstring", "binary", "uuid", "char", "octet", "byte", "int8", "uint64", "double", "float"]

HAND_WRITTEN: list[tuple[str, str]] = [
    ("limits.iface", '''component limits version "1.0.0"
namespace ros2 limits_msgs
/** Values at the edges of their types. */
message Edges {
    i8 a = -128,
    i8 b = 127,
    u8 c = 255,
    i16 d = -32768,
    u16 e = 65535,
    i32 f = -2147483648,
    u32 g = 4294967295,
    i64 h = -9223372036854775808,
    i64 i = 9223372036854775807,
    u64 j = 18446744073709551615,
    u64 k = 0xFFFFFFFFFFFFFFFF,
    float32 l = 3.4028234e38,
    float32 m = -3.4028234e38,
    float64 n = 1.7976931348623157e308,
    float64 o = -1.7976931348623157e308,
    float64 p = 4.9e-324,
    float64 q = 1e-400,
    float32 r = 1e-50,
    float64 s = -0.0,
    bool t = true,
    char u = 255,
    octet v = 0
}
publishes Edges on "/edges"
'''),
    ("strings.iface", '''component strings version "1.0.0"
namespace ros2 strings_msgs
message Texts {
    string quotes = "say \\"hi\\" and 'bye'",
    string escapes = "tab\\there\\\\back",
    string unicode = "caf\\u00e9 \\u4e2d\\u6587 \\uD83D\\uDE00 ✓ 𝄞",
    string<=1 one = "x",
    string empty = "",
    wstring wide = "wide \\u00fc",
    string hash = "# not a comment // nor this /* or this */",
    string percent = "%s %d {{ }} ${HOME} $(rm -rf /) `id`",
    string xml = "<tag attr='1'>&amp;</tag>",
    string yaml = ": - ? | > ! & * %",
    string single = 'single quoted'
}
const string GREETING = "hello\\u0021"
publishes Texts on "/texts"
'''),
    ("deep_types.thrift", "struct Deep {\n  1: " + "list<" * 64 + "i32" + ">" * 64 + " x\n}\n"),
    ("deep_values.thrift", "const list<list<list<i32>>> X = [[[1, 2], [3]], [[4]], []]\n"
                           "const map<string, list<i32>> M = {\"a\": [1], \"b\": []}\n"
                           "const set<string> S = [\"x\", \"y\"]\n"),
    ("typedef_chain.thrift", "typedef i32 T0\n" + "".join(f"typedef T{i} T{i + 1}\n" for i in range(150))
     + "struct UsesChain {\n  1: T150 value = 3\n}\nconst T150 C = 7\n"),
    ("big_arrays.iface", '''component big version "1.0.0"
namespace ros2 big_msgs
message Arrays {
    u8[4294967295] huge_fixed,
    i32[<=9223372036854775807] huge_bounded,
    string<=18446744073709551615 huge_string,
    float64[1] one,
    bool[] flags,
    string<=3[<=2] small
}
publishes Arrays on "/arrays"
'''),
    ("enums.thrift", '''enum Extremes {
  LOW = -2147483648,
  HIGH = 2147483647,
  ZERO = 0
}
enum Implicit { A, B, C = 10, D }
struct UsesEnum {
  1: Extremes e = Extremes.HIGH,
  2: Implicit i = D
}
const Extremes E = LOW
'''),
    ("recursive.thrift", '''struct Node {
  1: i32 value,
  2: list<Node> children,
  3: optional Node parent (cpp.ref = "true"),
  4: map<string, Node> named
}
union Either { 1: Node node, 2: string text }
exception Failure { 1: string why, 2: Node where }
service Tree {
  Node root() throws (1: Failure f),
  oneway void poke(1: Node n),
  list<Node> all(1: set<i32> ids, 2: map<i32, Either> extra)
}
service Forest extends Tree {
  void plant(1: Node seed)
}
'''),
    ("names.iface", '''component class version "0.0.1"
namespace ros2 names_msgs
message delete {
    i32 new_,
    i32 self_,
    i32 return_value
}
message ModuleBaseLike { u64 timestamp, i32 x }
message Msg1 { i32 a }
message msg_two { i32 b }
publishes delete on "/delete"
publishes ModuleBaseLike on "/fmu/out/module_base_like"
subscribes Msg1 on "~/relative"
subscribes msg_two on "/{ns}/sub"
'''),
    ("everything.iface", '''/** A component with every set. */
component everything version "3.2.1"
namespace ros2 everything_msgs

const i32 MAX = 10
const float64 RATE = 2.5e-3

enum Mode { IDLE = 0, RUN = 1, FAULT = 2 }

/** Pose with a covariance. */
message Pose {
    const u8 FRAME_WORLD = 0
    float64 x = 0.0 (unit = "m"),
    float64 y = 0.0 (unit = "m"),
    float64[36] covariance,
    Mode mode = Mode.IDLE
}

service Plan {
    request { Pose goal, float64 tolerance = 0.1 }
    response { bool ok, string<=64 message }
}

action Move {
    goal { Pose target }
    result { bool reached }
    feedback { float64 remaining (unit = "m") }
}

configuration params {
    float64 max_speed = 1.5 (unit = "m/s", range = "0..3"),
    i32 retries = 3 (min = 0, max = 10),
    bool verbose = false,
    Mode start_mode = Mode.RUN,
    string name = "robot",
    float64[] gains = [1.0, 2.0],
    u8 tiny = 0 (range = "0..")
}

state status { Mode mode, u64 ticks, Pose last }

service diagnostics {
    request { u8 cmd }
    response { string result }
}

subscribes Pose on "/pose" (qos.depth = 10, qos.reliability = "best_effort")
publishes Pose on "/pose_out" (qos.durability = "transient_local")
provides Plan on "/plan"
calls Move on "/move"
provides Move on "/move_here"
provides diagnostics on "/everything/diagnostics"
'''),
    ("empty_bodies.iface", '''component empty version "1.0.0"
namespace ros2 empty_msgs
message Nothing {}
service Ping { request {} response {} }
action Wait { goal {} result {} feedback {} }
configuration none {}
state blank {}
publishes Nothing on "/nothing"
provides Ping on "/ping"
provides Wait on "/wait"
'''),
    ("px4_shaped.iface", '''component px4_shaped version "1.0.0"
message SensorThing {
    u64 timestamp,
    float32[3] xyz,
    u8 flags,
    char[8] label
}
configuration params {
    float32 gain = 0.5 (range = "0..1", unit = "m/s"),
    i32 mode = 2 (min = -5, max = 5),
    bool enabled = true
}
publishes SensorThing on "/fmu/out/sensor_thing"
subscribes SensorThing on "/fmu/in/sensor_thing"
'''),
    ("only_comments.thrift", "// nothing here\n/* at all */\n# really\n"),
    ("thrift_misc.thrift", '''namespace cpp misc
namespace py misc.gen
namespace * misc
cpp_include "<vector>"
typedef map<string, list<set<i64>>> Index
const Index EMPTY = {}
const binary B = "bytes"
const uuid U = "00000000-4444-cccc-ffff-0123456789ab"
senum Colours { "red", "green" }
struct Annotated {
  1: required string name (api.doc = "x"),
  2: optional i64 id = 0x7fffffff,
  -1: i32 negative_id,
  3: double d = 1e300
} (thrift.uri = "urn:x")
'''),
]


#: Inputs that ``check`` may refuse; when it accepts one, every command must still work with it.
HOSTILE: list[tuple[str, str]] = [
    ("lone_surrogate.iface", 'message M { string s = "\\uD800" }\npublishes M on "/m"\n'),
    ("low_surrogate_const.thrift", 'const string S = "a\\uDC00b"\n'),
    ("infinity.iface", 'message M { float64 a = 1e999 }\npublishes M on "/m"\n'),
    ("minus_infinity_const.thrift", "const double X = -1e999\n"),
    ("five_thousand_digits.iface", f'message M {{ i64 a = {"9" * 5000} }}\npublishes M on "/m"\n'),
    ("five_thousand_digits_const.thrift", f"const i64 X = {'1' * 5000}\nconst list<i64> L = [{'2' * 5000}]\n"),
    ("huge_field_id.thrift", f"struct S {{ {'3' * 5000}: i32 x }}\n"),
    ("huge_enum.thrift", f"enum E {{ A = {'4' * 5000} }}\n"),
    ("huge_array.iface", f'message M {{ u8[{"5" * 5000}] a }}\npublishes M on "/m"\n'),
    ("float32_overflow.iface", 'message M { float32 a = 1e39 }\npublishes M on "/m"\n'),
    ("infinite_ranges.iface", 'component rng\nconfiguration params {\n'
     '    float64 a = 1.0 (range = "0..inf"),\n    float64 b = 1.0 (range = "nan..2"),\n'
     '    float32 c = 1.0 (min = "-inf", max = "1e999"),\n    i32 d = 1 (range = "-1e400..5")\n}\n'
     'message M { i32 x }\nsubscribes M on "/m"\n'),
    ("control_characters.iface", 'component ctl\nmessage M {\n    string bell = "\\u0007\\u001b[2J\\u0000",\n'
     '    string bidi = "\\u202eevil\\u2066"\n}\n'
     'publishes M on "/a\\u001b[31m"\nsubscribes M on "/b\\u0085"\n'),
    ("raw_controls.thrift", 'const string S = "bell\x07 escape\x1b[2J del\x7f c1\x85 bidi\u202e"\n'
     "/** doc with \x1b]0;title\x07 */\nstruct S { 1: i32 x }\n"),
    ("case_collision.iface", 'component casey\nnamespace ros2 casey_msgs\nmessage Pose { u64 timestamp, i32 x }\n'
     'message POSE { u64 timestamp, i32 y }\npublishes Pose on "/fmu/out/pose"\n'
     'publishes POSE on "/fmu/out/pose2"\n'),
    ("module_base.iface", 'component module_base\nmessage M { u64 timestamp, i32 x }\n'
     'publishes M on "/fmu/out/m"\n'),
    ("long_name.iface", f'component c\nmessage {"A" * 300} {{ i32 x }}\npublishes {"A" * 300} on "/t"\n'),
    ("non_bmp.iface", '/** 𝄞 music and 😀 faces */\ncomponent nonbmp\nmessage M {\n'
     '    string s = "𝄞😀\\uD834\\uDD1E" (unit = "😀")\n}\npublishes M on "/m"\n'),
    ("deep_values.thrift", "const list<i32> X = " + "[" * 70 + "]" * 70 + "\n"),
    ("unterminated_comment.iface", 'message M { i32 x }\npublishes M on "/m"\n/* never closed\nmessage N {}\n'),
]


def random_cases(seed: int, count: int) -> list[tuple[str, str]]:
    """``count`` seeded interfaces mixing messages, services, actions, parameters, wiring and values."""
    rng = random.Random(seed)
    out = []
    for k in range(count):
        out.append((f"random_{seed}_{k}.iface", _random_interface(rng, k)))
    return out


def _value(rng: random.Random, t: str) -> str | None:
    if t in ("i8", "int8", "byte"):
        return str(rng.randint(-128, 127))
    if t in ("u8", "char", "octet"):
        return str(rng.randint(0, 255))
    if t in ("i16", "u16", "i32", "u32", "i64", "u64", "uint64"):
        lo, hi = {"i16": (-2**15, 2**15 - 1), "u16": (0, 2**16 - 1), "i32": (-2**31, 2**31 - 1),
                  "u32": (0, 2**32 - 1), "i64": (-2**63, 2**63 - 1)}.get(t, (0, 2**64 - 1))
        return str(rng.choice([lo, hi, 0, rng.randint(lo, hi)]))
    if t in ("float32", "float"):
        return rng.choice(["0.0", "-1.5", "3.4e38", "1e-30", "42"])
    if t in ("float64", "double"):
        return rng.choice(["0.0", "-2.5e300", "1.7976931348623157e308", "1e-320", "7"])
    if t == "bool":
        return rng.choice(["true", "false"])
    if t in ("string", "wstring"):
        return rng.choice(['""', '"plain"', '"quote \\" inside"', '"\\u00e9\\u4e2d"', '"line\\nbreak"',
                           '"tab\\t"', '"\\uD83D\\uDE00"'])
    return None


def _random_interface(rng: random.Random, k: int) -> str:
    name = f"comp{k}"
    lines = [f'component {name} version "{rng.randint(0, 9)}.{rng.randint(0, 9)}.{rng.randint(0, 9)}"',
             f"namespace ros2 {name}_msgs"]
    messages = []
    scalar = [t for t in BASE_TYPES if t not in ("binary", "uuid")]
    for i in range(rng.randint(1, 5)):
        mname = f"Msg{i}"
        fields = []
        for j in range(rng.randint(0, 6)):
            t = rng.choice(scalar)
            suffix = rng.choice(["", "", "[]", f"[{rng.randint(1, 8)}]", f"[<={rng.randint(1, 8)}]"])
            if t in ("string", "wstring") and rng.random() < 0.3:
                t = f"{t}<={rng.randint(1, 50)}"
            if messages and rng.random() < 0.2:
                t, suffix = rng.choice(messages), rng.choice(["", "[]"])
            default = _value(rng, t) if not suffix and rng.random() < 0.5 else None
            fields.append(f"    {t}{suffix} f{j}" + (f" = {default}" if default is not None else ""))
        if rng.random() < 0.3:
            fields.append(f"    const i32 LIMIT_{i} = {rng.randint(-100, 100)}")
        lines.append(f"message {mname} {{\n" + ",\n".join(fields) + "\n}")
        messages.append(mname)
        if rng.random() < 0.8:
            lines.append(f'{rng.choice(["publishes", "subscribes"])} {mname} on "/{name}/m{i}"')
    if rng.random() < 0.5:
        lines.append(f"service Srv {{\n    request {{ {rng.choice(messages)} in_ }}\n"
                     f"    response {{ bool ok }}\n}}\nprovides Srv on \"/{name}/srv\"")
    if rng.random() < 0.4:
        lines.append(f"action Act {{\n    goal {{ i32 g }}\n    result {{ {rng.choice(messages)} r }}\n"
                     f"    feedback {{ float32 p }}\n}}\nprovides Act on \"/{name}/act\"")
    if rng.random() < 0.6:
        params = []
        for j in range(rng.randint(1, 4)):
            t = rng.choice(["bool", "i32", "float64", "float32", "string", "u8"])
            default = _value(rng, t)
            rng_ann = ' (range = "0..100")' if t in ("i32", "u8") and default and 0 <= int(default) <= 100 else ""
            params.append(f"    {t} p{j} = {default}{rng_ann}")
        lines.append("configuration params {\n" + ",\n".join(params) + "\n}")
    if rng.random() < 0.4:
        lines.append(f"state st {{ u64 ticks, {rng.choice(messages)} last }}")
    return "\n".join(lines) + "\n"
