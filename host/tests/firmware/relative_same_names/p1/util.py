VALUE = "p1"
