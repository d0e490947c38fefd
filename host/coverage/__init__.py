"""Firmware coverage: the lines and branches of the firmware's files a run reached, in
coverage.py's data format (docs/coverage.md). :mod:`host.coverage.collector` gathers one
run's; :mod:`host.coverage.session` merges a session's and writes the HTML."""
