"""Modules that moved keep their old import paths: ``import host.rig.rigfile`` gives the
module ``host.rig.config.rigfile`` itself (one module under both names), imported only
when asked for. Standard library only (layer 0)."""

import importlib
import importlib.abc
import importlib.util
import sys


class MovedModules(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Serves ``<old>.<name>`` as ``<new>`` for each ``name: new`` of a package's table."""

    def __init__(self, old: str, moved: dict[str, str]):
        self.old, self.moved = old, moved

    def find_spec(self, fullname, path=None, target=None):
        parent, _, name = fullname.rpartition(".")
        if parent == self.old and name in self.moved:
            return importlib.util.spec_from_loader(fullname, self)
        return None

    def create_module(self, spec):
        module = importlib.import_module(self.moved[spec.name.rpartition(".")[2]])
        spec.loader_state = module.__spec__
        return module

    def exec_module(self, module):
        module.__spec__ = module.__spec__.loader_state  # (the import system gave it the old name's spec)


def keep_old_paths(old: str, moved: dict[str, str]) -> None:
    """Modules of package ``old`` that moved (``name -> its full name now``) import by
    their old names too."""
    if not any(isinstance(f, MovedModules) and f.old == old for f in sys.meta_path):
        sys.meta_path.append(MovedModules(old, moved))
