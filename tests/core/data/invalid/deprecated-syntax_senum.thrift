senum Colours { // expect: deprecated-syntax
  "red", "green"
}
