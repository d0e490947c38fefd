"""Wokwi projects as rigs: a folder with a ``diagram.json`` (and a ``wokwi.toml``) and its
MicroPython code runs here as a rig file would (``docs/wokwi.md``): the board part picks
the chip family, each part maps to a catalogue part named by its diagram ``id``, each
connection to wiring, each attribute to an option with its unit. :mod:`.project` is the
entry (``rig_from_project``, ``import-wokwi``), :mod:`.diagram` reads the file and its
nets, :mod:`.boards` the boards' pin names, :mod:`.parts` the part table."""
