"""No run leaves a micropython process or a pty behind (runs last in hil_tests)."""

import os
from pathlib import Path

import pytest

from host.core import interpreter
from host.tests.conftest import our_ptys

pytestmark = pytest.mark.hil


def _our_micropythons() -> list[int]:
    exe = str(interpreter.find().resolve())
    found = []
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            stat = (proc / "stat").read_text()
            ppid = int(stat.rsplit(")", 1)[1].split()[1])
            if ppid == os.getpid() and os.readlink(proc / "exe") == exe:
                found.append(int(proc.name))
        except (OSError, ValueError, IndexError):
            continue
    return found


def test_a_stopped_rig_leaves_no_process_and_no_pty(make_rig):
    before = our_ptys()
    rig = make_rig("rover", seed=0)
    rig.run_for(0.5)
    pid = rig.target.proc.pid
    assert len(our_ptys()) == len(before) + 2
    rig.stop()
    assert not Path(f"/proc/{pid}").exists(), f"micropython pid {pid} still exists after stop()"
    assert our_ptys() == before


def test_no_micropython_process_or_pty_is_left_after_the_session_so_far():
    assert _our_micropythons() == [], "micropython processes left behind"
    assert our_ptys() == [], f"ptys left open: {our_ptys()}"
