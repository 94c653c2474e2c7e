service Ping extends Pong { // expect: extends-cycle
    void ping()
}
service Pong extends Ping { // expect: extends-cycle
    void pong()
}
service Base {}
service Derived extends Base {}
