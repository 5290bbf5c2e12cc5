"""Lazy import of the optional `humanoid` extra (mujoco, jax, brax, rcsssmj) with a clear error."""

from __future__ import annotations

import importlib
from types import ModuleType

__all__ = ["require", "EXTRA_HINT"]

EXTRA_HINT = "pip install -e '.[humanoid]' in the teamenv checkout"


def require(module: str) -> ModuleType:
    """Import ``module`` (e.g. ``"brax.io.mjcf"``) or raise ImportError naming the extra."""
    try:
        return importlib.import_module(module)
    except ImportError as exc:  # pragma: no cover - exercised only without the extra
        raise ImportError(
            f"locomotion.humanoid needs {module.split('.')[0]!r}, part of the humanoid extra: "
            f"{EXTRA_HINT}  (original error: {exc})"
        ) from exc
