# A job scheduled from the main program that raises, while the main program spins on a flag
# with no call into the harness: on a board the job runs at the loop's first branch (a
# pending check), prints its traceback and the loop spins on; in the loop the run ends
# there, naming the job.
import micropython

done = False


def job(n):
    raise ValueError("job %d failed" % n)


micropython.schedule(job, 7)
while not done:
    pass
