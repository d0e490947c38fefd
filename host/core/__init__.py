"""Foundation of the host side: errors, paths, the MicroPython interpreter (build and
discovery) and provenance. Standard library only: ``interpreter`` runs before the
project's virtual environment exists."""
