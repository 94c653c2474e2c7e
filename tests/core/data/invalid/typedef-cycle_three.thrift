typedef Second First // expect: typedef-cycle
typedef Third Second // expect: typedef-cycle
typedef First Third // expect: typedef-cycle
typedef list<Self> Self // expect: typedef-cycle
typedef i32 Fine
typedef Fine AlsoFine
