"""The docs ship with the package and say what is so: every page is in the wheel and is a
topic of `mpy-fil docs`; every docs/NAME.md that help, a message or a page names exists;
every option a page names is an option of the command it names; the Rig API page
names every public attribute of Rig. (test_package.py runs `mpy-fil docs` from the
installed wheel.)"""

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from host import cli
from host.core import docs
from host.core.errors import ConfigError
from host.core.paths import REPO

PAGES = sorted(p.stem for p in (REPO / "docs").glob("*.md"))
TEXTS = [REPO / "README.md", REPO / "CHANGELOG.md", *sorted((REPO / "docs").glob("*.md"))]
NAMED = re.compile(r"\bdocs/([a-z0-9_-]+)\.md\b")  # (docs/NAME.md, as messages name a page)


def wheel_files() -> list[str]:
    """What setup.py puts in the wheel as package data, as its build_py computes it (the
    wheel is that build's tree), without building anything."""
    from distutils.core import run_setup  # (setuptools' own: its .pth puts it before the standard library's)

    here = os.getcwd()
    os.chdir(REPO)
    try:
        dist = run_setup("setup.py", script_args=["--quiet"], stop_after="config")
        build_py = dist.get_command_obj("build_py")
        build_py.ensure_finalized()
        return [
            Path(build_dir, name).relative_to(build_py.build_lib).as_posix()
            for _package, _src, build_dir, names in build_py.data_files
            for name in names
        ]
    finally:
        os.chdir(here)


def test_the_wheel_carries_every_docs_page_where_mpy_fil_docs_looks_when_installed():
    files = set(wheel_files())
    missing = [p for p in PAGES if f"host/_data/docs/{p}.md" not in files]
    assert not missing, f"expected every docs/*.md in the wheel under host/_data/docs, missing {missing}"
    assert not [f for f in files if "/tests/" in f], "the tests stay out"
    import tomllib

    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    assert project["readme"] == "README.md", "the README is the package's description (mpy-fil docs readme)"


def referenced_pages() -> dict[str, list[str]]:
    """Every docs/NAME.md named by the harness's code (help, messages), the Makefile and the
    pages themselves, with where."""
    sources = [
        *(REPO / "host").rglob("*.py"),
        *(REPO / "sim_plant").rglob("*.py"),
        *(REPO / "firmware").rglob("*.py"),
        *(REPO / "examples").rglob("*.py"),
        *(REPO / "examples").rglob("*.toml"),
        REPO / "Makefile",
        REPO / "setup.py",
        REPO / "pyproject.toml",
        *TEXTS,
    ]
    found: dict[str, list[str]] = {}
    for path in sources:
        if "tests" in path.relative_to(REPO).parts:
            continue
        for n, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            for name in NAMED.findall(line):
                found.setdefault(name, []).append(f"{path.relative_to(REPO)}:{n}")
    return found


def test_every_docs_page_that_help_a_message_or_a_page_names_is_a_topic_of_mpy_fil_docs():
    found = referenced_pages()
    assert len(found) > 15, sorted(found)  # (the scan sees them: docs/shim.md alone is named ~50 times)
    topics = docs.topics()
    unknown = {name: where[:3] for name, where in found.items() if name not in topics}
    assert not unknown, f"pages named that `mpy-fil docs` does not have: {unknown}"
    for name in found:
        assert docs.topic_name(f"docs/{name}.md") == name


def test_mpy_fil_docs_lists_the_topics_prints_one_and_names_the_nearest_for_a_wrong_one(capsys):
    assert cli.main(["docs"]) == 0
    listing = capsys.readouterr().out
    assert "  ci               mpy-fil in your own repository, and in its CI\n" in listing, listing
    assert all(re.search(rf"^  {re.escape(p)} ", listing, re.M) for p in [*PAGES, "readme"]), listing

    assert cli.main(["docs", "docs/ci.md"]) == 0
    assert capsys.readouterr().out == (REPO / "docs" / "ci.md").read_text()

    assert cli.main(["docs", "rig-file", "budgets"]) == 0
    budgets = capsys.readouterr().out
    assert budgets.startswith("### Budgets\n") and "## A robot as a body" not in budgets, budgets[:300]

    assert cli.main(["docs", "rig-fil"]) == cli.EXIT_USAGE
    err = capsys.readouterr().err
    assert err.startswith("mpy-fil docs: error: TOPIC: no page 'rig-fil'; did you mean rig-file or rig-api?"), err
    assert "wokwi-scenarios" in err and err.count("\n") == 1, "the whole list, on one line"

    assert cli.main(["docs", "rig-file", "Budgts"]) == cli.EXIT_USAGE
    assert "no heading 'Budgts' in rig-file; did you mean 'Budgets'" in capsys.readouterr().err

    assert cli.main(["docs", "ci", "--path"]) == 0
    assert capsys.readouterr().out.strip() == str(REPO / "docs" / "ci.md")


def test_mpy_fil_help_says_how_to_read_a_page_it_names():
    done = subprocess.run([sys.executable, "-m", "host.cli", "--help"], capture_output=True, text=True, cwd=REPO)
    assert "`mpy-fil docs NAME`" in " ".join(done.stdout.split()), done.stdout[-500:]
    assert re.search(r"^\s+docs\s+print a page of the documentation", done.stdout, re.M), done.stdout


# -- options the pages name ----------------------------------------------------------------

OTHER_TOOLS = {
    "python -m build": {"--no-isolation"},
    "pip": {"--no-deps", "--no-index", "--no-binary"},
    "git clone": {"--depth", "--branch"},
    "ruff": {"--check"},
    "valgrind": {"--tool"},
    "dask scheduler / worker": {
        "--host",
        "--port",
        "--dashboard-address",
        "--protocol",
        "--tls-ca-file",
        "--tls-cert",
        "--tls-key",
        "--nthreads",
        "--nworkers",
        "--no-dashboard",
    },  # fmt: skip
    "perf (docs/bench.md)": {"--call-graph"},
    "coverage report": {"--data-file"},
    "bwrap": {"--die-with-parent"},
    "wokwi-cli": {"--scenario"},
    "any command": {"--help", "--version"},
}
"""Options of other programs the pages name, by program."""
OPTION = re.compile(r"(?<![\w-])--[a-z][a-z0-9-]*")
LITERAL = re.compile(r"""["'](--[a-z][a-z0-9-]*)["']""")


def our_options() -> set[str]:
    """Every option a command of ours takes (mpy-fil, make's runners, the bench, the soak,
    the fuzzers): the option strings in the code."""
    found = set()
    for path in [*(REPO / "host").rglob("*.py"), *(REPO / "sim_plant").rglob("*.py")]:
        found |= set(LITERAL.findall(path.read_text(errors="replace")))
    return found


PYTEST_OPTIONS = """\
from _pytest.config import _prepareconfig
config = _prepareconfig(["-p", "no:cacheprovider"])
parser = config._parser
for group in [*parser._groups, parser._anonymous]:
    for option in group.options:
        print(*option.names())
"""


@pytest.fixture(scope="module")
def pytest_options() -> set[str]:
    """pytest's options in this environment, every name of each (``--junitxml`` is
    ``--junit-xml``'s), the plugin's and pytest-xdist's included."""
    done = subprocess.run([sys.executable, "-c", PYTEST_OPTIONS], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert done.returncode == 0, done.stderr
    names = set(done.stdout.split())
    assert {"--junitxml", "--hil-report", "-n"} <= names, sorted(names)
    return names


def mpy_fil_options() -> dict[str, set[str]]:
    """Each mpy-fil subcommand's options (and the top level's, under "")."""
    parser = cli.build_parser()
    options = {"": {o for a in parser._actions for o in a.option_strings}}
    for action in parser._actions:
        for name, sub in (getattr(action, "choices", None) or {}).items():
            if hasattr(sub, "_actions"):
                options[name] = {o for a in sub._actions for o in a.option_strings}
    return options


def named_options():
    """(page:line, the option, the text before it on its line) for every --option of the pages."""
    for path in TEXTS:
        for n, line in enumerate(path.read_text().splitlines(), 1):
            for m in OPTION.finditer(line):
                yield f"{path.relative_to(REPO)}:{n}", m.group(), line[: m.start()]


def test_every_option_a_page_names_exists_and_belongs_to_the_command_it_follows(pytest_options):
    """Before: docs/budgets.md named `mpy-fil run --plots`, an option no parser has."""
    ours = our_options() | pytest_options | set().union(*OTHER_TOOLS.values())
    subcommands = mpy_fil_options()
    unknown, misplaced = [], []
    for where, option, before in named_options():
        if option not in ours:
            unknown.append(f"{where}: {option}")
        command = re.findall(r"mpy-fil (\w[\w-]*)(?:(?!`).)*$", before)  # (mpy-fil SUB ... --option, one span)
        if command and command[-1] in subcommands and option not in subcommands[command[-1]] | subcommands[""]:
            misplaced.append(f"{where}: mpy-fil {command[-1]} has no {option}")
    assert len(list(named_options())) > 100
    assert not unknown, "options no parser has:\n" + "\n".join(unknown)
    assert not misplaced, "\n".join(misplaced)


# -- the Rig API page ------------------------------------------------------------------------


def test_the_rig_api_page_names_every_public_attribute_of_rig_with_an_example():
    from host.rig import Rig, RigSpec

    page = (REPO / "docs" / "rig-api.md").read_text()
    documented = set(re.findall(r"`rig\.(\w+)", page)) - {"toml"}  # (`rig.toml`: a rig file)
    rig = Rig(RigSpec("rover", seed=1))  # (not started: no process)
    public = {n for n in [*dir(Rig), *vars(rig)] if not n.startswith("_")}
    missing = sorted(public - documented)
    assert not missing, f"public attributes of Rig that docs/rig-api.md does not name as `rig.NAME`: {missing}"
    stale = sorted(documented - public)
    assert not stale, f"docs/rig-api.md names attributes Rig does not have: {stale}"
    methods = sorted(n for n in public if callable(getattr(Rig, n, None)))
    blocks = "\n".join(re.findall(r"```python\n(.*?)```", page, re.S))
    without = [n for n in methods if f"rig.{n}(" not in blocks and f".{n}(" not in blocks]
    assert not without, f"methods with no example in a ```python block: {without}"


def test_every_python_example_of_the_rig_api_page_compiles():
    page = (REPO / "docs" / "rig-api.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", page, re.S)
    assert len(blocks) >= 8
    for i, block in enumerate(blocks):
        try:
            compile(block, f"docs/rig-api.md block {i + 1}", "exec")
        except SyntaxError as e:
            raise AssertionError(f"docs/rig-api.md block {i + 1} does not compile: {e}\n{block}") from None


def test_a_topic_that_does_not_exist_is_refused_with_every_name(monkeypatch, tmp_path):
    (tmp_path / "alpha.md").write_text("# Alpha page\ntext\n")
    monkeypatch.setattr(docs, "DOCS", tmp_path)
    assert docs.topic_name("ALPHA.md") == "alpha"
    with pytest.raises(ConfigError, match=r"no page 'zzz' \(topics: alpha, readme;"):
        docs.topic_name("zzz")
    assert docs.title("alpha") == "Alpha page"
