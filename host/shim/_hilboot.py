# Entry point of a firmware run: `micropython -m _hilboot`. Shakes hands with the host,
# makes asyncio keep its task queue in virtual time, then runs boot.py and main.py
# from the firmware's folder as a board does, reporting how the firmware ended.
import io
import sys

import _hil
import _hilframe as F


def _asyncio_in_virtual_time():
    # The C helper _asyncio stamps tasks with the process's own clock and compares
    # ticks with the unix port's period; the pure-Python queue uses time.ticks_ms.
    import asyncio
    import asyncio.core as core

    try:
        import asyncio.task as task
    except ImportError:
        raise ImportError(
            "this MicroPython has no frozen asyncio/task.py; build it with "
            "host/micropython/manifest.py (make setup) or freeze that file"
        )

    core.TaskQueue = task.TaskQueue
    core.Task = task.Task
    core._task_queue = task.TaskQueue()
    asyncio.Task = task.Task


def _find(name):
    for folder in sys.path:
        if folder and folder != ".frozen":
            path = folder + "/" + name
            try:
                with open(path) as f:
                    return path, f.read()
            except OSError:
                pass
    return None, None


def _run(name):
    path, source = _find(name)
    if source is None:
        return False
    exec(compile(source, name, "exec"), {"__name__": "__main__", "__file__": path})
    return True


def main():
    _hil.start()
    try:
        _asyncio_in_virtual_time()
        _run("boot.py")
        if not _run("main.py"):
            raise OSError("no main.py on the firmware path")
    except _hil.ResetRequest:
        _hil.finish(F.EXIT_RESET)
        sys.exit(0)
    except SystemExit as e:
        code = e.args[0] if e.args and isinstance(e.args[0], int) else 0
        _hil.finish(F.EXIT_SYSEXIT, code)
        raise
    except _hil.HostGone:
        sys.exit(3)
    except BaseException as e:  # noqa: BLE001  any firmware failure goes to the host
        buf = io.StringIO()
        sys.print_exception(e, buf)
        text = buf.getvalue()
        sys.stderr.write(text)
        _hil.finish(F.EXIT_SYSEXIT, 1, text)
        sys.exit(1)
    _hil.finish(F.EXIT_RETURN)


main()
