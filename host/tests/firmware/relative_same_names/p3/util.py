VALUE = "p3"
