"""One exception root for the harness; each error says what was expected, what
happened and where the artefacts are."""


class HarnessError(Exception):
    """Root of every error the harness raises."""


class SetupError(HarnessError):
    """The interpreter or a tool the harness needs is missing."""


class ConfigError(HarnessError):
    """A scenario, app, board or wiring setting is wrong; the message names the field."""


class LinkError(HarnessError):
    """The plant link failed (closed, corrupted, wrong protocol)."""


class LinkDamaged(LinkError):
    """A frame was damaged or lost on the link (the message names the counters)."""


class LinkTimeout(LinkError):
    """No complete frame arrived before the deadline."""


class FirmwareError(HarnessError):
    """The firmware raised; ``traceback`` holds MicroPython's traceback."""

    def __init__(self, message: str, traceback: str = "", console: str = ""):
        super().__init__(message)
        self.traceback = traceback
        self.console = console


class FirmwareExited(FirmwareError):
    """The firmware ended (returned or called sys.exit) where it was expected to run."""

    def __init__(self, message: str, code: int = 0, console: str = ""):
        super().__init__(message, console=console)
        self.code = code


class FirmwareHung(HarnessError):
    """The firmware stopped answering: the wall-clock watchdog stopped it."""


class OutputRefused(ConfigError):
    """A command was asked to write where it must not: through a link, over or around
    its own input, or onto something that is not a folder (``host/core/safefs.py``)."""
