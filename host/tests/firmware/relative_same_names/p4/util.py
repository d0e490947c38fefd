VALUE = "p4"
