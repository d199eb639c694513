"""Names of a package imported on first use (PEP 562), so that a light import stays light."""

from __future__ import annotations

from typing import Any, Callable


def lazy_getattr(package: str, table: dict, namespace: dict) -> Callable[[str], Any]:
    """A module ``__getattr__`` for ``package``: name -> the submodule (in table) that defines it,
    imported on first use and then kept in the package's namespace."""
    def __getattr__(name: str) -> Any:
        if name in table:
            import importlib
            value = getattr(importlib.import_module(f".{table[name]}", package), name)
            namespace[name] = value
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")
    return __getattr__
