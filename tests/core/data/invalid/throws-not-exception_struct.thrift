struct NotAnError {
  1: string message
}
service Store {
  void put(1: i32 x) throws (1: NotAnError e) // expect: throws-not-exception
}
