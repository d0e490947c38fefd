"""A Wokwi automation scenario (``*.test.yaml``) read into steps, each with its YAML line.

The format is Wokwi's (docs.wokwi.com/wokwi-ci/automation-scenarios): ``name``,
``version``, ``author``, ``steps``; each step a mapping of one key: ``delay`` (a time
with its unit, ``500ms``, ``2s``), ``wait-serial`` (text), ``write-serial`` (text, or a
list of byte values), ``set-control`` (``part-id``, ``control``, ``value``),
``expect-pin`` (``part-id``, ``pin``, ``value``); and ours: ``wait-pin`` (``part-id``,
``pin``, ``value``, optional ``timeout``), a top-level ``timeout`` (the run's, in
simulated time: Wokwi's ``--timeout``). A mistake is a :class:`ScenarioError` naming the
file, the line and the field.
"""

import re
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from host.core.errors import ConfigError
from host.core.nesting import too_deep

TIME = re.compile(r"^(\d+(?:\.\d*)?)\s*(ns|us|ms|s)$|^0(?:\.?0*)$", re.IGNORECASE)
UNIT_US = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}
DEFAULT_TIMEOUT_US = 30_000_000  # Wokwi's --timeout default: 30000 simulated ms
TOP_KEYS = ("name", "version", "author", "steps", "timeout")
STEP_KEYS = {
    "delay": None,
    "wait-serial": None,
    "write-serial": None,
    "set-control": ("part-id", "control", "value"),
    "expect-pin": ("part-id", "pin", "value"),
    "wait-pin": ("part-id", "pin", "value", "timeout"),
}
OPTIONAL = {"timeout"}


class ScenarioError(ConfigError):
    """A scenario file that cannot be run as written: names the file, line and field."""


@dataclass(frozen=True)
class Step:
    kind: str  # a STEP_KEYS key
    line: int  # the step's line in its file (from 1)
    args: dict = field(default_factory=dict)  # delay_us, text, data, part, control, pin, value, timeout_us

    def describe(self) -> str:
        a = self.args
        if self.kind == "delay":
            return f"delay {a['text']}"
        if self.kind == "wait-serial":
            return f"wait-serial {a['text']!r}"
        if self.kind == "write-serial":
            return f"write-serial {a['data']!r}"
        if self.kind == "set-control":
            return f"set-control {a['part']}.{a['control']} = {a['value']}"
        timeout = f" (timeout {a['timeout_text']})" if a.get("timeout_text") else ""
        return f"{self.kind} {a['part']}:{a['pin']} == {a['value']}{timeout}"


@dataclass(frozen=True)
class Scenario:
    path: Path
    name: str
    steps: tuple
    timeout_us: int = DEFAULT_TIMEOUT_US
    author: str = ""


def parse_time_us(text, where: str) -> int:
    """Wokwi's times: a number and its unit (``ns``, ``us``, ``ms``, ``s``), or 0."""
    if isinstance(text, bool) or not isinstance(text, (str, int, float)):
        raise ScenarioError(f"{where}: expected a time with its unit (500ms, 2s), got {text!r}")
    found = TIME.match(str(text).strip())
    if not found:
        missing = isinstance(text, (int, float)) or re.fullmatch(r"\s*[\d.]+\s*", str(text))
        what = "missing units" if missing else "not a time"
        raise ScenarioError(f"{where}: {what}: {text!r} (expected a number and ns, us, ms or s: 500ms, 2s)")
    if found.group(1) is None:
        return 0
    return round(float(found.group(1)) * UNIT_US[found.group(2).lower()])


def load_scenario(path) -> Scenario:
    """The scenario in ``path``; a ScenarioError names the file, line and field."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise ScenarioError(f"{path}: cannot read it: {getattr(e, 'strerror', None) or e}") from None
    deep = too_deep(text)
    if deep:  # (PyYAML's composer is recursive: seconds, then a RecursionError)
        raise ScenarioError(f"{path}: not a scenario: {deep}")
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
        data = loader.construct_document(node) if node is not None else None
    except RecursionError:  # (block style nests by indentation alone)
        raise ScenarioError(f"{path}: not a scenario: nested too deep for a scenario") from None
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        line = f":{mark.line + 1}" if mark is not None else ""
        raise ScenarioError(f"{path}{line}: not YAML: {getattr(e, 'problem', None) or e}") from None
    finally:
        loader.dispose()
    if not isinstance(data, dict):
        raise ScenarioError(f"{path}: expected a mapping with name, version and steps, got {type(data).__name__}")
    for key in data:
        if key not in TOP_KEYS:
            raise ScenarioError(f"{path}:{_key_line(node, key)}: unknown key {key!r} (known: {', '.join(TOP_KEYS)})")
    steps = data.get("steps")
    if not isinstance(steps, list) or not steps:
        raise ScenarioError(f"{path}:{_key_line(node, 'steps')}: steps: expected a list of steps")
    nodes = _value_node(node, "steps").value
    timeout_us = DEFAULT_TIMEOUT_US
    if "timeout" in data:
        timeout_us = parse_time_us(data["timeout"], f"{path}:{_key_line(node, 'timeout')}: timeout")
        if timeout_us <= 0:
            raise ScenarioError(f"{path}:{_key_line(node, 'timeout')}: timeout: expected a time above 0")
    parsed = tuple(_step(path, item, item_node.start_mark.line + 1) for item, item_node in zip(steps, nodes))
    return Scenario(path, str(data.get("name") or path.name), parsed, timeout_us, str(data.get("author") or ""))


def _value_node(node, key):
    for k, v in node.value:
        if k.value == key:
            return v
    return None


def _key_line(node, key) -> int:
    for k, _v in node.value:
        if k.value == key:
            return k.start_mark.line + 1
    return 1


def _step(path: Path, item, line: int) -> Step:
    where = f"{path}:{line}"
    if not isinstance(item, dict) or len(item) != 1:
        raise ScenarioError(f"{where}: a step is a mapping of one key (one of {', '.join(STEP_KEYS)}), got {item!r}")
    ((kind, value),) = item.items()
    if kind not in STEP_KEYS:
        raise ScenarioError(f"{where}: unknown step {kind!r} (steps: {', '.join(STEP_KEYS)})")
    where = f"{where}: {kind}"
    if kind == "delay":
        return Step(kind, line, {"delay_us": parse_time_us(value, where), "text": str(value)})
    if kind == "wait-serial":
        if not isinstance(value, (str, int, float)) or isinstance(value, bool) or str(value) == "":
            raise ScenarioError(f"{where}: expected the text to wait for, got {value!r}")
        return Step(kind, line, {"text": str(value)})
    if kind == "write-serial":
        return Step(kind, line, {"data": _serial_bytes(value, where)})
    return Step(kind, line, _fields(kind, value, where))


def _serial_bytes(value, where: str) -> bytes:
    """Wokwi's write-serial value: a string (UTF-8) or a list of byte values."""
    if isinstance(value, str) and value:
        return value.encode()
    if isinstance(value, list) and value and all(isinstance(v, int) and not isinstance(v, bool) for v in value):
        if all(0 <= v <= 255 for v in value):
            return bytes(value)
    raise ScenarioError(f"{where}: expected a string or a list of byte values (0 to 255), got {value!r}")


def _fields(kind: str, value, where: str) -> dict:
    keys = STEP_KEYS[kind]
    if not isinstance(value, dict):
        raise ScenarioError(f"{where}: expected a mapping with {', '.join(keys)}, got {value!r}")
    for key in value:
        if key not in keys:
            raise ScenarioError(f"{where}: unknown field {key!r} (fields: {', '.join(keys)})")
    for key in keys:
        if key not in value and key not in OPTIONAL:
            raise ScenarioError(f"{where}: {key}: missing")
    part = value["part-id"]
    if not isinstance(part, str) or not part:
        raise ScenarioError(f"{where}: part-id: expected a part's id, got {part!r}")
    args = {"part": part, "value": value["value"]}
    if kind == "set-control":
        if not isinstance(value["control"], str):
            raise ScenarioError(f"{where}: control: expected a control's name, got {value['control']!r}")
        args["control"] = value["control"]
        return args
    args["pin"] = str(value["pin"])
    if value["value"] not in (0, 1) or isinstance(value["value"], bool):
        raise ScenarioError(f"{where}: value: expected 0 or 1, got {value['value']!r}")
    if "timeout" in value:
        args["timeout_us"] = parse_time_us(value["timeout"], f"{where}: timeout")
        args["timeout_text"] = str(value["timeout"])
    return args
