# micropython.schedule from a scheduled callback (the scheduler is locked while it runs):
# the queue takes the port's depth, then raises; what was queued runs afterwards, in order.
import micropython

queued, refused, ran = [], [], []


def job(n):
    ran.append(n)


def filler(_):
    for i in range(12):
        try:
            micropython.schedule(job, i)
            queued.append(i)
        except RuntimeError as e:
            refused.append((i, type(e).__name__, str(e)))


micropython.schedule(filler, None)
print("R queued", queued)
print("R refused", refused)
print("R ran", ran)
