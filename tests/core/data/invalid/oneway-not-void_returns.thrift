service Pinger {
  oneway i32 ping() // expect: oneway-not-void
}
