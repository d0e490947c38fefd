"""What a run leaves behind: the recorder (signals and ground truth in virtual time), the
link log (``trace.jsonl``), the trace folder (written and read back, :mod:`.checks` refusing a damaged one) and its
VCD, and :mod:`.integrity`: files whole or marked incomplete, a stop signal, a failed
write. Knows
nothing of processes or the link; it is handed data."""
