namespace py bar
const i64 MAX = 3
enum Color { RED = 1, GREEN = 2 }
struct Point { 1: required i64 x, 2: i32 y = 5, 4: optional string name, 3: required i32 z }
exception Oops { 1: string msg }
service Base { void ping() }
service Calc {
  i64 add(1: i32 a, 2: i64 b) throws (1: Oops o),
  void fire(1: i32 x)
}
