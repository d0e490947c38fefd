VALUE = "p2"
