service Mixed { // expect: mixed-service-forms
  i32 ping(1: i32 x),
  string name
}
