namespace py shop
namespace java org.shop

const i32 MAX_ITEMS = 10
const string GREETING = "hello"

enum Color { RED = 1, GREEN = 2, BLUE = 3 }
enum Size { SMALL = 1, LARGE = 2 }

struct Item {
  1: required string name
  2: i32 count = 1
  3: optional Color color
  5: optional list<string> tags
}

exception OutOfStock { 1: string what }
exception Closed { 1: i32 until }

service Base {
  void ping()
}

service Shop extends Base {
  Item get(1: string name) throws (1: OutOfStock oos),
  i32 add(1: Item item, 2: i16 times),
  oneway void log(1: string line)
}

service Admin {
  void reset()
}
