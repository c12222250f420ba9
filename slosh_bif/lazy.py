"""Packages whose public names load their defining module on first use (PEP 562): a caller of one
part of a package (the impact model's orbits, say) does not pay for importing the others, which
keeps a command's start-up to what it runs."""

from __future__ import annotations

import importlib
import sys

__all__ = ["lazy_names"]


def lazy_names(package: str, where: dict):
    """``(__getattr__, __dir__)`` for the package ``package``: ``where`` maps each public name to
    the submodule (relative to the package) that defines it; a name is imported when first asked
    for and then kept in the package's namespace."""

    def __getattr__(name):
        if name in where:
            value = getattr(importlib.import_module(f"{package}.{where[name]}"), name)
            setattr(sys.modules[package], name, value)
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__():
        return sorted(set(vars(sys.modules[package])) | set(where))

    return __getattr__, __dir__
