from time import sleep_ms


def control_step(n):
    return 100 // (n - 3)


for n in range(10):
    control_step(n)
    sleep_ms(50)
