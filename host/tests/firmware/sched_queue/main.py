# micropython.schedule from a scheduled callback (the scheduler is locked while it runs):
# the queue takes the port's depth, then raises; what was queued runs afterwards, in order.
# (Written as upstream's tests/micropython/schedule.py: the loops give a board the branches
# where it runs scheduled callbacks.)
import micropython

queued, refused, ran = [], [], []
done = False


def job(n):
    ran.append(n)


def filler(_):
    global done
    for i in range(12):
        try:
            micropython.schedule(job, i)
            queued.append(i)
        except RuntimeError as e:
            refused.append((i, type(e).__name__, str(e)))
    done = True


micropython.schedule(filler, None)
while not done:
    pass
while len(ran) < len(queued):
    pass
print("R queued", queued)
print("R refused", refused)
print("R ran", ran)
