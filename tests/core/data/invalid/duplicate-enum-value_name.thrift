enum Mode {
  IDLE = 1,
  IDLE = 2 // expect: duplicate-enum-value
}
