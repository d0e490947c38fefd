"""What a run leaves behind: the recorder (signals and ground truth in virtual time), the
link log (``trace.jsonl``), the trace folder (written and read back) and its VCD. Knows
nothing of processes or the link; it is handed data."""
