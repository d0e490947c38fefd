"""MicroPython versions side by side (docs/versions.md): each version has its own folder, patch
and identity; a rig file's ``[interpreter] version`` and ``pytest --mpy-version`` select one;
``$MICROPYTHON`` stands for a version asked for only when it is of that version; a version
built from MicroPython's own source says where to get it when none is named."""

import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

from host.core import interpreter
from host.core.errors import SetupError
from host.core.paths import REPO
from host.rig.config.rigfile import load_rig
from host.rig.targets.firmware import Firmware
from host.tests.test_rigfile_bounds import GOOD, refused

pytest_plugins = ("pytester",)  # (pytest --mpy-version, run in this process on a test file of its own)


def test_a_version_is_named_by_major_and_minor_and_an_unknown_one_names_the_known():
    assert interpreter.release("1.28.0").version == "1.28"
    assert interpreter.release("v1.26.1").build == "1.26.1+ds-1"
    assert interpreter.release(None).version == interpreter.DEFAULT_VERSION == "1.25"
    with pytest.raises(SetupError) as e:
        interpreter.release("1.9")
    assert "expected one of 1.25, 1.26, 1.27, 1.28" in str(e.value), e.value


def test_each_version_has_its_folder_patch_and_identity(monkeypatch):
    monkeypatch.delenv(interpreter.VERSION_ENV, raising=False)
    root = interpreter.build_root(checkout=True)
    assert interpreter.default_path(root) == root / "1.25.0+ds-1" / "micropython", "the default's folder moved"
    assert interpreter.default_path(root, "1.28") == root / "1.28.0" / "micropython"
    assert interpreter.variant_path("settrace", root, "1.26") == root / "1.26.1+ds-1" / "micropython-settrace"
    assert interpreter.patches("1.25") == interpreter.PATCHES
    assert interpreter.patches("1.28") == (interpreter.HERE / "1.28" / "hilcount.patch",)
    identities = {v: interpreter.identity("standard", v) for v in interpreter.RELEASES}
    assert len(set(identities.values())) == len(identities), f"expected an identity per version: {identities}"
    assert "MPY_LIB_DIR=$(TOP)/lib" in interpreter.make_options("standard", "1.28")
    assert "MPY_LIB_DIR=$(TOP)/lib" not in interpreter.make_options("standard", "1.26"), "Debian's needs none"


def _fake_build(monkeypatch, tmp_path) -> list[Path]:
    """The build with nothing fetched or compiled: each binary a script that says its
    version and the patches it was built with."""
    made = []

    def compile_(tree, log, variant, target, version=None):
        line = f"MicroPython v{interpreter.release(version).build} on {interpreter.patches_text(version)[:12]}"
        target.write_text(f"#!/bin/sh\necho '{line}'\n")
        target.chmod(0o755)
        made.append(target)

    monkeypatch.setattr(interpreter, "ensure_tools", lambda: None)
    monkeypatch.setattr(interpreter, "fetch_source", lambda root, version=None, source=None: tmp_path / "tree")
    monkeypatch.setattr(interpreter, "_compile", compile_)
    return made


def test_the_per_user_cache_keeps_each_versions_builds_beside_each_other(monkeypatch, tmp_path, capsys):
    """Before: one binary per version in the cache (``<version>/micropython``), taken as it
    was whatever built it: a harness with other patches or C modules (another release, another
    checkout's install) ran, or rebuilt over, the other's binary."""
    from host import cli

    monkeypatch.setattr(interpreter.paths, "CHECKOUT", False)  # (installed: the per-user cache)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    for name in ("MICROPYTHON", "MICROPYTHON_SETTRACE", interpreter.VERSION_ENV):
        monkeypatch.delenv(name, raising=False)
    made = _fake_build(monkeypatch, tmp_path)
    cache = tmp_path / "xdg" / "mpy-fil" / "micropython"
    first = interpreter.build(None, "1.28")
    key = interpreter.build_key("1.28")
    assert first == cache / "1.28.0" / key / "micropython", first
    assert interpreter.variant_path("settrace", None, "1.28") == first.with_name("micropython-settrace")

    ours = interpreter.patches_text
    monkeypatch.setattr(interpreter, "patches_text", lambda version=None: "other options\n" + ours(version))
    other_key = interpreter.build_key("1.28")
    assert other_key != key, "expected another build key for other patches"
    assert not interpreter._executable(interpreter.default_path(None, "1.28")), "expected no binary of this build yet"
    with pytest.raises(SetupError):  # (the first build's binary is not this build's)
        interpreter.find("1.28")
    second = interpreter.build(None, "1.28")
    assert second == cache / "1.28.0" / other_key / "micropython" and made == [first, second], made
    assert "on other option" in interpreter.version(second) and "on other option" not in interpreter.version(first)
    monkeypatch.setattr(interpreter, "patches_text", ours)
    assert interpreter.find("1.28") == first and interpreter.build(None, "1.28") == first
    assert len(made) == 2, f"expected the first build found again, not rebuilt: {made}"
    assert interpreter.build(None, "1.26") == cache / "1.26.1+ds-1" / interpreter.build_key("1.26") / "micropython"
    assert sorted(p.name for p in (cache / "1.28.0").iterdir()) == sorted([key, other_key])

    capsys.readouterr()
    assert cli.main(["setup", "--micropython", "1.28"]) == 0
    said = capsys.readouterr().out
    assert "micropython: MicroPython v1.28.0 on" in said and f"({first})" in said, said
    assert f"MicroPython 1.28 is in {first.parent} (build key {key}:" in said, said


def test_a_checkouts_build_is_its_own_and_unkeyed(monkeypatch):
    monkeypatch.setattr(interpreter.paths, "CHECKOUT", True)
    build = interpreter.build_root(checkout=True)
    assert interpreter.default_path(build, "1.28") == build / "1.28.0" / "micropython", "make setup's folder moved"
    cache = interpreter.build_root(checkout=False)
    assert interpreter.default_path(cache, "1.28") == cache / "1.28.0" / interpreter.build_key("1.28") / "micropython"
    keys = {interpreter.build_key(v) for v in interpreter.RELEASES}
    assert len(keys) == len(interpreter.RELEASES), f"expected a key per version: {keys}"


def test_every_versions_patch_counts_the_same_things():
    """Only where a counter goes may differ between versions, never what it counts: each
    patch's added lines that name a counter are those of the default's (the multiply's
    wide-result count aside, which 1.27 and later need no hunk for)."""

    def counters(path: Path) -> set[str]:
        added = [line[1:].strip() for line in path.read_text().splitlines() if line.startswith("+")]
        return {line for line in added if "mp_hil_cur->" in line or "mp_hil_counts." in line}

    default = counters(interpreter.PATCHES[0])
    for version in ("1.26", "1.27", "1.28"):
        (patch,) = interpreter.patches(version)
        missing = {c for c in default - counters(patch) if "wide++" not in c}
        assert not missing, f"{patch}: the default's counters missing: {sorted(missing)}"
        assert counters(patch) <= default | {"mp_hil_cur->wide++;  // mpy-fil: as below (a board's small int)"}


def test_the_selected_version_comes_from_the_environment_over_the_rig_file(monkeypatch, tmp_path):
    firmware = Firmware(tmp_path, [tmp_path], mpy_version="1.26")
    monkeypatch.delenv(interpreter.VERSION_ENV, raising=False)
    assert firmware.micropython() == "1.26"
    monkeypatch.setenv(interpreter.VERSION_ENV, "1.28")
    assert firmware.micropython() == "1.28", "pytest --mpy-version runs its version over the rig file's"


@pytest.fixture
def pico(tmp_path):
    folder = tmp_path / "pico_bot"
    folder.mkdir()
    shutil.copy(REPO / "examples" / "pico_bot" / "main.py", folder)
    return folder


def test_a_rig_file_names_its_boards_micropython(pico):
    path = pico / "rig.toml"
    path.write_text(GOOD.replace('entry = "main.py"', 'entry = "main.py"\n[interpreter]\nversion = "1.28.0"'))
    assert load_rig(path).interpreter.mpy_version == "1.28"
    refused(
        pico,
        GOOD.replace('entry = "main.py"', 'entry = "main.py"\n[interpreter]\nversion = "2.0"'),
        "[interpreter] version",
        "expected one of 1.25, 1.26, 1.27, 1.28",
    )


def _fake_micropython(tmp_path: Path, line: str) -> Path:
    path = tmp_path / f"mp-{line.split()[1]}"
    path.write_text(f"#!/bin/sh\necho '{line}'\n")
    path.chmod(0o755)
    return path


def test_micropython_stands_for_a_version_asked_for_only_when_it_is_that_version(tmp_path, monkeypatch):
    old = _fake_micropython(tmp_path, "MicroPython v1.25.0+ds-1 on 2025-05-04")
    monkeypatch.setenv("MICROPYTHON", str(old))
    monkeypatch.delenv(interpreter.VERSION_ENV, raising=False)
    monkeypatch.setattr(interpreter, "build_root", lambda checkout=None: tmp_path / "builds")
    monkeypatch.setenv("PATH", str(tmp_path / "empty"))
    assert interpreter.find() == old, "no version asked for: $MICROPYTHON, as always"
    assert interpreter.find("1.25") == old
    with pytest.raises(SetupError) as e:
        interpreter.find("1.28")
    assert "no MicroPython 1.28 interpreter" in str(e.value) and "--micropython 1.28" in str(e.value), e.value
    monkeypatch.setenv(interpreter.VERSION_ENV, "1.28")
    with pytest.raises(SetupError):
        interpreter.find()


def test_a_version_from_micropythons_source_says_where_to_get_it(tmp_path, monkeypatch):
    monkeypatch.delenv(interpreter.SOURCE_ENV, raising=False)
    with pytest.raises(SetupError) as e:
        interpreter.fetch_source(tmp_path, "1.28")
    assert interpreter.SOURCE_ENV in str(e.value) and "clone" in str(e.value), e.value
    tree = tmp_path / "tree"
    (tree / "py").mkdir(parents=True)
    (tree / "py" / "mpconfig.h").write_text(
        "#define MICROPY_VERSION_MAJOR (1)\n#define MICROPY_VERSION_MINOR (27)\n#define MICROPY_VERSION_MICRO (0)\n"
    )
    with pytest.raises(SetupError) as e:
        interpreter.fetch_source(tmp_path / "root", "1.28", source=str(tree))
    assert "MicroPython 1.27.0, not 1.28.0" in str(e.value), e.value


def test_a_tag_is_taken_from_a_git_repository_without_a_work_tree(tmp_path):
    repo = tmp_path / "repo"
    subprocess.run(["git", "init", "-q", str(repo)], check=True)
    (repo / "py").mkdir()
    (repo / "py" / "marker.c").write_text("/* v1.27.0 */\n")
    git = ["git", "-C", str(repo), "-c", "user.name=t", "-c", "user.email=t@t"]
    subprocess.run([*git, "add", "-A"], check=True)
    subprocess.run([*git, "commit", "-qm", "v1.27.0"], check=True)
    subprocess.run([*git, "tag", "v1.27.0"], check=True)
    bare = tmp_path / "bare.git"
    subprocess.run(["git", "clone", "-q", "--bare", str(repo), str(bare)], check=True)
    root = tmp_path / "root"
    root.mkdir()
    with pytest.raises(SetupError) as e:  # (no ports/unix/Makefile: the archive is unpacked, then checked)
        tree = interpreter.fetch_source(root, "1.27", source=str(bare))
        assert (tree / "py" / "marker.c").read_text() == "/* v1.27.0 */\n"
        raise SetupError("unpacked")
    assert str(e.value) == "unpacked", e.value
    commit = (interpreter._tree(root, "1.27") / ".mpy-fil-commit").read_text().strip()
    env = interpreter.build_env(interpreter._tree(root, "1.27"), "1.27")
    assert env["MICROPY_GIT_TAG"] == "v1.27.0" and commit.startswith(env["MICROPY_GIT_HASH"]), env
    with pytest.raises(SetupError) as e:
        interpreter.fetch_source(tmp_path / "root2", "1.28", source=str(bare))
    assert "has no tag v1.28.0" in str(e.value), e.value


def test_pytest_runs_every_rig_test_once_per_version_asked_for(pytester):
    pytester.makepyfile(
        test_ids="""
        import pytest

        @pytest.mark.parametrize("seed", [1, 2])
        def test_with_a_rig(make_rig, seed):
            pass

        def test_without_a_rig():
            pass
        """
    )
    out = pytester.runpytest("--collect-only", "-q", "--mpy-version", "1.25,1.28.0,1.25")
    ids = sorted(line for line in out.outlines if "::" in line)
    assert ids == [
        "test_ids.py::test_with_a_rig[mpy1.25-1]",
        "test_ids.py::test_with_a_rig[mpy1.25-2]",
        "test_ids.py::test_with_a_rig[mpy1.28-1]",
        "test_ids.py::test_with_a_rig[mpy1.28-2]",
        "test_ids.py::test_without_a_rig",
    ], out.outlines
    bad = pytester.runpytest("--collect-only", "-q", "--mpy-version", "1.9")
    assert bad.ret == pytest.ExitCode.USAGE_ERROR and "expected one of 1.25" in bad.stderr.str(), bad.stderr.lines


def _built(version: str) -> bool:
    try:
        return interpreter.version_problem(interpreter.find(version), version) is None
    except SetupError:
        return False


@pytest.mark.skipif(not _built("1.28"), reason="no MicroPython 1.28 built here (mpy-fil setup --micropython 1.28)")
def test_each_version_runs_its_own_interpreter_and_junit_and_the_manifest_name_it(pytester, tmp_path):
    pytester.makepyfile(
        test_two="""
        import json

        def test_rover(make_rig):
            rig = make_rig("rover", seed=1, record=True)
            rig.run_for(0.2)
            rig.stop()
            manifest = json.loads((rig.artefacts / "manifest.json").read_text())
            print("MANIFEST", manifest["interpreter"]["micropython"], manifest["interpreter"]["version"])
        """
    )
    junit, report = tmp_path / "junit.xml", tmp_path / "report.html"
    where = ("--hil-out", str(tmp_path), "--hil-report", str(report))
    out = pytester.runpytest("-s", "--mpy-version", "1.25,1.28", f"--junitxml={junit}", *where)
    assert out.ret == 0, out.outlines
    said = sorted(line[line.index("MANIFEST") :] for line in out.outlines if "MANIFEST" in line)
    assert len(said) == 2 and said[0].startswith("MANIFEST 1.25 MicroPython v1.25."), said
    assert said[1].startswith("MANIFEST 1.28 MicroPython v1.28."), said
    text = junit.read_text()
    assert 'name="micropython" value="1.25: MicroPython v1.25.' in text, text
    assert 'name="micropython" value="1.28: MicroPython v1.28.' in text, text
    assert 'name="test_rover[mpy1.25]"' in text and 'name="test_rover[mpy1.28]"' in text, text
    html = report.read_text()
    assert "MicroPython <code>1.25.0, 1.28.0</code>" in html, f"expected both versions named in {report}"
    assert "test_rover[mpy1.25]" in html and "test_rover[mpy1.28]" in html, f"expected each version's row in {report}"


def test_the_ci_matrix_has_a_row_for_every_version_with_its_build_folder_and_tag():
    """docs/ci.md's matrix over versions: a row per version the harness builds, each caching
    the folder setup builds into and cloning the tag a version from MicroPython's source needs."""
    text = (REPO / "docs" / "ci.md").read_text()
    workflow = text[text.index("### A matrix over MicroPython versions") :]
    rows = re.findall(r'- \{micropython: "([^"]+)", build: "([^"]+)"(?:, tag: "([^"]+)")?\}', workflow)
    assert [r[0] for r in rows] == list(interpreter.RELEASES), f"expected a row per version: {rows}"
    for version, build, tag in rows:
        rel = interpreter.release(version)
        assert (build, tag or None) == (rel.build, rel.tag), f"{version}: expected {rel.build}, {rel.tag}"
    cache = Path("/ws/.cache/mpy-fil/micropython")
    assert "path: .cache/mpy-fil/micropython/${{ matrix.build }}" in workflow, "expected the version's folder cached"
    for version, build, _ in rows:
        assert interpreter.default_path(cache, version).parent.parent == cache / build, version
    assert "pytest --mpy-version ${{ matrix.micropython }}" in workflow
    assert "mpy-fil setup --micropython ${{ matrix.micropython }}" in workflow


def test_coverage_builds_the_settrace_variant_of_each_version_it_runs(pytester, monkeypatch, tmp_path):
    """Before: ``--hil-coverage --mpy-version 1.28`` and ``mpy-fil run --coverage`` of a rig file
    of 1.28 built the default version's variant, and the 1.28 rigs stopped for want of theirs."""
    from host.coverage.session import prepare_run

    built = []
    monkeypatch.setattr(interpreter, "build_variant", lambda variant, version=None: built.append((variant, version)))
    pytester.makepyfile(test_none="def test_nothing():\n    pass\n")
    where = ("--hil-coverage-dir", str(tmp_path / "cov"))
    out = pytester.runpytest("--collect-only", "-q", "--hil-coverage", "--mpy-version", "1.25,1.28", *where)
    assert out.ret == 0 and built == [("settrace", "1.25"), ("settrace", "1.28")], (built, out.outlines)
    built.clear()
    monkeypatch.delenv(interpreter.VERSION_ENV, raising=False)
    assert prepare_run(tmp_path / "run", "1.28") == tmp_path / "run" / "coverage" / ".coverage"
    monkeypatch.setenv(interpreter.VERSION_ENV, "1.26")  # (pytest --mpy-version over the rig file's)
    prepare_run(tmp_path / "run", "1.28")
    assert built == [("settrace", "1.28"), ("settrace", "1.26")], built


def _settrace_built(version: str) -> bool:
    try:
        path = interpreter.find_variant("settrace", version)
    except SetupError:
        return False
    return interpreter.version_problem(path, version) is None


@pytest.mark.hil
@pytest.mark.skipif(
    not _settrace_built("1.28"),
    reason="no settrace variant of MicroPython 1.28 here (python3 -m host.core.interpreter build settrace "
    "--micropython 1.28)",
)
def test_a_rig_file_of_1_28_measures_its_coverage_on_1_28s_settrace_variant(make_rig, tmp_path):
    from coverage import CoverageData

    from host.tests.test_coverage import HIGH_LINE, IF_LINE, covbot

    rig_file = covbot(tmp_path / "bot", "[[0.5, 0.7]]")
    rig_file.write_text(rig_file.read_text() + '[interpreter]\nversion = "1.28"\n')
    data_file = tmp_path / ".coverage.bot"
    rig = make_rig(str(rig_file), coverage=data_file, record=True)
    rig.run_for(1.0)
    rig.stop()
    ran = json.loads((rig.artefacts / "manifest.json").read_text())["interpreter"]
    assert ran["micropython"] == "1.28" and ran["variant"] == "settrace", ran
    assert ran["version"].startswith("MicroPython v1.28.0") and ran["path"].endswith("micropython-settrace"), ran
    data = CoverageData(basename=str(data_file))
    data.read()
    main = str(rig_file.parent / "main.py")
    assert (IF_LINE, HIGH_LINE) in data.arcs(main), f"expected the pressed branch covered: {data.arcs(main)}"
