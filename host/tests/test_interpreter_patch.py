"""The counting patch (host/core/micropython/hilcount.patch): applied once to the unpacked
source, taken off and applied again when its text changes, and part of the build's
identity, so a changed patch rebuilds the interpreter (host/core/interpreter.py)."""

import shutil

import pytest

from host.core import interpreter


@pytest.fixture
def tree(tmp_path):
    """A copy of the files the patches touch, as the build left them (patched)."""
    try:
        source = interpreter._tree(interpreter.build_root())
    except Exception as e:  # noqa: BLE001
        pytest.skip(f"no MicroPython source here ({e})")
    if not (source / interpreter.APPLIED).is_file():
        pytest.skip(f"the source at {source} was not patched by this build (run make setup)")
    copy = tmp_path / "src"
    touched = ("py/vm.c", "py/gc.c", "py/runtime.c", "py/mpz.c", "py/hilcount.h")
    threads = ("ports/unix/mpthreadport.c", "ports/unix/mpthreadport.h")  # (threadstate.patch)
    for name in (*touched, *threads, interpreter.APPLIED):
        (copy / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(source / name, copy / name)
    return copy


def test_the_patch_comes_off_and_goes_on_again_when_it_changes(tree, monkeypatch):
    text = interpreter.patches_text()
    before = (tree / "py/vm.c").read_text()
    interpreter.patch_tree(tree)  # the same text: nothing to do
    assert (tree / "py/vm.c").read_text() == before
    assert "mp_hil_cur->ops[*ip]++" in before, "expected the patched VM to count at each dispatch"
    monkeypatch.setattr(interpreter, "patches_text", lambda version=None: "")
    interpreter.patch_tree(tree)  # no patches now: the tree as Debian's source has it
    assert "mp_hil" not in (tree / "py/vm.c").read_text()
    assert not (tree / "py/hilcount.h").exists() or not (tree / "py/hilcount.h").read_text().strip()
    assert not (tree / interpreter.APPLIED).exists()
    monkeypatch.setattr(interpreter, "patches_text", lambda version=None: text)
    interpreter.patch_tree(tree)
    assert (tree / "py/vm.c").read_text() == before
    assert (tree / interpreter.APPLIED).read_text() == text


def test_the_patch_is_part_of_the_builds_identity(monkeypatch):
    standard = interpreter.identity("standard")
    assert standard != interpreter.identity("settrace")
    text = interpreter.patches_text()
    monkeypatch.setattr(interpreter, "patches_text", lambda version=None: text + "\n")
    assert interpreter.identity("standard") != standard, "a changed patch must change the build's identity"
