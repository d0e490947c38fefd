# An error at the bottom of a deep call chain: a traceback longer than a link frame.
def descend(n):
    if n == 0:
        raise ValueError("the bottom of the chain")
    return descend(n - 1) + 1


descend(150)
