namespace cpp included

struct Shared {
  1: string name
}
