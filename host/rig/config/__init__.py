"""A rig's configuration: rig files (TOML) read and checked into an ``App``, several boards'
rig files, board pin maps, timing budgets and their verdicts, 0.1 rig files migrated, our
apps by name."""
