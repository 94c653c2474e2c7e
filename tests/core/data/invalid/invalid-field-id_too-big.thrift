struct Big {
  40000: i32 x // expect: invalid-field-id
}
