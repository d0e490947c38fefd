"""The README's commands work as printed in a clone: every shell line of its code blocks
is run from the repository's root (the fast ones) or, for make targets, checked with
``make -n``; the quick start for a user's repository is docs/ci.md's, which
test_package.py runs from the built wheel."""

import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

import pytest

from host.core import interpreter
from host.core.paths import REPO

pytestmark = pytest.mark.hil
README = REPO / "README.md"
COMMENT = re.compile(r"\s+#\s.*$")
MADE = ("build/mybot", "build/runs/mybot-default-seed0", "build/runs/rover-long-room-seed3")
"""What the README's commands write: removed after the test (it runs them in the clone); a
developer's own copies are put aside for it and back after."""


def shell_blocks(text: str) -> list[list[str]]:
    """Each ```sh block's command lines, comments cut."""
    blocks = re.findall(r"```sh\n(.*?)```", text, re.S)
    return [[COMMENT.sub("", line).strip() for line in b.splitlines() if line.strip()] for b in blocks]


def test_the_quick_start_is_the_ci_recipes_own():
    quick = shell_blocks(README.read_text())[0]
    assert quick == ["pip install mpy-fil", "mpy-fil setup", "pytest"], quick
    assert shell_blocks((REPO / "docs" / "ci.md").read_text())[0] == quick, "README and docs/ci.md disagree"


def test_every_make_command_of_the_readme_names_a_target():
    lines = [line for block in shell_blocks(README.read_text()) for line in block if line.startswith("make ")]
    assert len(lines) >= 5, lines
    env = {**os.environ, "MICROPYTHON": str(interpreter.find())}
    for line in lines:
        done = subprocess.run(["make", "-n", *line.split()[1:]], cwd=REPO, env=env, capture_output=True, text=True)
        assert done.returncode == 0, f"{line}: {done.stderr}"


def test_the_readmes_clone_commands_run_as_printed():
    blocks = shell_blocks(README.read_text())
    lines = [line for block in blocks[1:] for line in block if not line.startswith(("make ", "$EDITOR"))]
    assert any(line.startswith(".venv/bin/mpy-fil run") for line in lines), lines
    env = {**os.environ, "MICROPYTHON": str(interpreter.find()), "MPLBACKEND": "Agg"}
    runs_existed = (REPO / "build" / "runs").is_dir()
    with tempfile.TemporaryDirectory() as aside:  # (a developer's own, from running them by hand)
        kept = [m for m in MADE if (REPO / m).exists()]
        for made in kept:
            shutil.move(REPO / made, Path(aside) / made.replace("/", "_"))
        try:
            for line in lines:
                done = subprocess.run(
                    ["bash", "-c", line], cwd=REPO, env=env, capture_output=True, text=True, timeout=300
                )
                assert done.returncode == 0, f"{line}\n{done.stdout[-2000:]}{done.stderr[-2000:]}"
                assert "command not found" not in done.stderr, line
        finally:
            for made in MADE:
                shutil.rmtree(REPO / made, ignore_errors=True)
            for made in kept:
                shutil.move(Path(aside) / made.replace("/", "_"), REPO / made)
            runs = REPO / "build" / "runs"
            if not runs_existed and runs.is_dir() and not any(runs.iterdir()):
                runs.rmdir()
