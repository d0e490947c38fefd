"""What a report view (:class:`sim_plant.catalogue.base.ReportView`, ours or a user's) draws
with: the panel pieces and the telemetry readers, passed to its ``panels(trace, kit)`` so a
view imports nothing of the host (docs/own-parts.md)."""

from host.report.panels import US_PER_S, Line, Panel
from host.report.telemetry import console_text, firmware_t0_us, rows

__all__ = ["US_PER_S", "Line", "Panel", "console_text", "firmware_t0_us", "rows"]
