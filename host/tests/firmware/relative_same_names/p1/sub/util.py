VALUE = "p1.sub"
