"""A rig as TOML text, commented: what ``mpy-fil import-wokwi`` writes (the rig file
loader reads it back to the same rig)."""

from host.core.tomltext import key, value


def _comment(lines: list) -> list[str]:
    return [f"# {line}" for line in lines]


def rig_toml(data: dict, notes: dict) -> str:
    """``data`` (a rig file's tables) as TOML; ``notes`` by part id (and ``"board"``) as comments."""
    out = [
        "# The rig of a Wokwi project, written by `mpy-fil import-wokwi` from diagram.json (docs/wokwi.md).",
        "# Each part is named by its diagram id. Go on from here: budgets, faults, worlds (docs/rig-file.md).",
        f"name = {value(data['name'])}",
        f"description = {value(data['description'])}",
        "",
        "[firmware]",
        *(f"{key(k)} = {value(v)}" for k, v in data["firmware"].items()),
        "",
        *_comment(notes.get("board", [])),
        "[board]",
        f"family = {value(data['board']['family'])}",
        "",
        "[board.pins]  # the board's pins the diagram wires, by the board's names",
        *(f"{key(k)} = {value(v)}" for k, v in data["board"]["pins"].items()),
        "",
        "[plant]",
    ]
    plant = data["plant"]
    out += [f"{key(k)} = {value(v)}" for k, v in plant.items() if k != "parts"]
    for entry in plant["parts"]:
        out += ["", *_comment(notes.get(entry["name"], [])), "[[plant.parts]]"]
        out += [f"{key(k)} = {value(v)}" for k, v in entry.items()]
    out += ["", "[wiring]  # board pin = plant signal (or probe:<name>)"]
    out += [f"{key(k)} = {value(v)}" for k, v in data["wiring"].items()]
    return "\n".join(out) + "\n"
