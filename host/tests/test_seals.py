"""Every file of a trace folder is sealed by its header and checked by every command that
reads the folder: a file reversed, cut, deleted, edited or added after the run, a header
without its digest, a link in place of a file are refused with the file named, exit 2
(never 1, "differs")."""

import json
import os
import shutil

import pytest

from host.artefacts.checks import DamagedFolder
from host.artefacts.folder import load_trace
from host.tests.conftest import run_cli


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A second of the rover, recorded by ``mpy-fil run``."""
    out = tmp_path_factory.mktemp("seal") / "run"
    code, _, err = run_cli("run", "--app", "rover", "--duration", "1", "--out", out)
    assert code == 0, err
    return out


def copy_of(recorded, tmp_path):
    copy = tmp_path / "copy"
    shutil.copytree(recorded, copy, ignore=shutil.ignore_patterns("plots"))
    return copy


def reverse(path):
    path.write_bytes(b"\n".join(reversed(path.read_bytes().rstrip(b"\n").split(b"\n"))) + b"\n")


def cut(path):
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def edit_budgets(path):
    budgets = json.loads(path.read_text())
    budgets[0]["stats"]["misses"] = 0 if budgets[0]["stats"].get("misses") else 7
    path.write_text(json.dumps(budgets))


DAMAGES = {
    "trace.jsonl reversed": ("trace.jsonl", reverse, "trace.jsonl does not match its digest"),
    "trace.jsonl cut": ("trace.jsonl", cut, "trace.jsonl does not match its digest"),
    "trace.jsonl deleted": ("trace.jsonl", os.unlink, "trace.jsonl: missing (header.json seals it)"),
    "manifest.json deleted": ("manifest.json", os.unlink, "manifest.json: missing"),
    "budgets.json edited": ("budgets.json", edit_budgets, "budgets.json does not match its digest"),
    "a file added": ("notes.txt", lambda p: p.write_text("x\n"), "notes.txt: a file added after the run"),
}


@pytest.mark.parametrize("damage", sorted(DAMAGES))
def test_replay_plot_diff_and_shrink_refuse_a_folder_whose_files_changed_after_the_run(recorded, tmp_path, damage):
    name, change, expected = DAMAGES[damage]
    copy = copy_of(recorded, tmp_path)
    change(copy / name)
    out = tmp_path / "out"
    for command in (
        ("replay", copy, "--app", "rover", "--out", out / "replay"),
        ("plot", copy, "--out", out / "plot"),
        ("diff", recorded, copy, "--out", out / "diff"),
        ("diff", copy, recorded, "--out", out / "diff"),
        ("shrink", copy, "--app", "rover", "--out", out / "shrink", "--workers", "1"),
    ):
        code, text, err = run_cli(*command)
        assert code == 2 and expected in err and f"trace folder {copy}" in err, (command, code, text, err)
        assert "same" not in text, text
    assert not (out / "replay").exists() or not any((out / "replay").iterdir()), "nothing ran"


def test_a_header_without_its_digest_is_a_damaged_header(recorded, tmp_path):
    copy = copy_of(recorded, tmp_path)
    header = json.loads((copy / "header.json").read_text())
    del header["digest"]
    (copy / "header.json").write_text(json.dumps(header))
    with pytest.raises(DamagedFolder, match="header.json: no 'digest'"):
        load_trace(copy)
    code, _, err = run_cli("plot", copy, "--out", tmp_path / "plots")
    assert code == 2 and "no 'digest'" in err, err


def test_every_file_the_run_wrote_is_sealed_budgets_included(recorded):
    header = json.loads((recorded / "header.json").read_text())
    written = {p.name for p in recorded.iterdir() if p.is_file() and p.name != "header.json"}
    assert set(header["files"]) == written, (sorted(header["files"]), sorted(written))
    assert all(isinstance(d, str) and len(d) == 64 for d in header["files"].values()), header["files"]
    assert "budgets.json" in written and "trace.jsonl" in written and "manifest.json" in written


def test_a_link_or_fifo_in_place_of_a_sealed_file_is_named_and_never_read(recorded, tmp_path):
    copy = copy_of(recorded, tmp_path)
    (copy / "trace.jsonl").unlink()
    (copy / "trace.jsonl").symlink_to(recorded / "trace.jsonl")  # (the same bytes, through a link)
    with pytest.raises(DamagedFolder, match=r"trace.jsonl: not a regular file"):
        load_trace(copy)
    (copy / "trace.jsonl").unlink()
    os.mkfifo(copy / "trace.jsonl")  # (read, it would block for ever)
    with pytest.raises(DamagedFolder, match=r"trace.jsonl: not a regular file"):
        load_trace(copy)


def test_a_header_that_seals_a_name_outside_the_folder_is_refused(recorded, tmp_path):
    from host.artefacts import integrity

    copy = copy_of(recorded, tmp_path)
    header = json.loads((copy / "header.json").read_text())
    header["files"]["../run/console.log"] = header["files"]["console.log"]
    (copy / "header.json").write_text(json.dumps(integrity.seal(header)))
    with pytest.raises(DamagedFolder, match=r"not a name inside the folder"):
        load_trace(copy)


def test_the_outputs_later_commands_write_into_the_folder_are_not_part_of_its_seal(recorded, tmp_path):
    copy = copy_of(recorded, tmp_path)
    code, _, err = run_cli("plot", copy)
    assert code == 0 and (copy / "plots").is_dir(), err
    load_trace(copy)  # (plots/, replay/, diff/: made from the folder, not read back)


def test_the_budgets_verdicts_stamped_after_the_run_are_sealed_with_it(recorded, tmp_path):
    from host.rig.config.verdicts import stamp

    copy = copy_of(recorded, tmp_path)
    name = json.loads((copy / "budgets.json").read_text())[0]["name"]
    stamp(copy, [{"budget": name, "verdict": "held", "why": "within its limit"}])
    assert json.loads((copy / "budgets.json").read_text())[0]["verdict"] == "held"
    load_trace(copy)  # (the harness's own edit: sealed again)
    (copy / "budgets.json").write_text((copy / "budgets.json").read_text().replace("held", "missed"))
    with pytest.raises(DamagedFolder, match="budgets.json does not match its digest"):
        load_trace(copy)
