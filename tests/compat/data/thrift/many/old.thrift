namespace py foo
namespace java foo.j
const i32 MAX = 3
enum Color { RED = 1, GREEN = 2, BLUE = 3 }
struct Point { 1: required i32 x, 2: i32 y = 4, 3: optional string name }
exception Oops { 1: string msg }
service Base { void ping() }
service Calc extends Base {
  i32 add(1: i32 a, 2: i32 b) throws (1: Oops o),
  oneway void fire(1: i32 x)
}
