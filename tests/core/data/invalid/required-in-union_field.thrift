union Choice {
  1: required i32 a, // expect: required-in-union
  2: string b
}
