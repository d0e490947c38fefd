"""What a campaign's figures mean: each figure's readable label, its unit, whether it
counts things (integer bins), and which way is better; and, per judge, the figure a
campaign is judged by, which ranks its worst runs (``docs/campaigns.md``)."""

import math
from dataclasses import dataclass

from host.campaign.judges import figures_of


@dataclass(frozen=True)
class Metric:
    name: str
    label: str  # what a reader calls it
    unit: str = ""  # shown after the value ("%" scales a fraction by 100)
    higher_is_better: bool = False
    integer: bool = False  # counts: integer bins, no decimals

    @property
    def title(self) -> str:
        return f"{self.label} ({self.unit})" if self.unit else self.label

    def show(self, value) -> str:
        """The value as the page and the terminal print it."""
        if value is None or (isinstance(value, float) and math.isnan(value)):
            return "-"
        if self.unit == "%":
            return f"{value * 100:.1f} %"
        if self.integer:
            return f"{value:.0f}"
        return f"{value:.3g}{' ' + self.unit if self.unit else ''}"

    def scaled(self, value: float) -> float:
        """The value in the unit plots show it in (a fraction as a percentage)."""
        return value * 100 if self.unit == "%" else value


METRICS = {
    m.name: m
    for m in (
        Metric("coverage", "floor covered", "%", higher_is_better=True),
        Metric("mission_min", "mission time", "min"),
        Metric("reversals", "reversals at a wall", integer=True),
        Metric("wall_contacts", "side-wall touches", integer=True),
        Metric("home_off_m", "distance from home at the end", "m"),
        Metric("snags", "tether snags", integer=True),
        Metric("contacts", "contacts", integer=True),
        Metric("t_end_s", "run time (simulated)", "s"),
        Metric("wall_s", "wall time a run", "s"),
    )
}
JUDGED_BY = {
    "no_contact": ("contacts",),
    "generic": ("t_end_s",),
    "declared": ("coverage", "home_off_m", "contacts", "t_end_s"),  # the first its rig file's judge gives
}
"""The figure each generic judge's campaign is ranked by when the campaign names none (the
first of these its runs have); a catalogue judge declares its own (``FIGURES``)."""


def metric(name: str) -> Metric:
    """``name``'s metric; a figure not listed gets its name as label, lower is better, and
    a link fault counter (``link_*``) counts."""
    if name in METRICS:
        return METRICS[name]
    if name.startswith("link_"):
        return Metric(name, name.removeprefix("link_").replace("_", " "), integer=True)
    return Metric(name, name.replace("_", " "))


def judged_by(campaign: dict, results: list[dict] | None = None) -> tuple[str, bool]:
    """The figure a campaign ranks its runs by and whether its worst runs are its lowest:
    ``worst_by`` (or the judge's own figure: the first of :data:`JUDGED_BY`'s that the
    ``results`` have), and ``worst_low`` (or the figure's known direction: coverage
    higher is better, so its worst runs are the lowest)."""
    name = campaign.get("worst_by")
    if not name:
        judge = campaign.get("judge") or "generic"
        names = JUDGED_BY.get(judge) or figures_of(judge) or ("t_end_s",)
        present = {f for r in results or () for f in r["figures"]}
        name = next((n for n in names if n in present), names[0])
    low = campaign.get("worst_low")
    return name, metric(name).higher_is_better if low is None else bool(low)
