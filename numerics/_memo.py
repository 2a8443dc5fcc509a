"""The one memo helper of :mod:`numerics`: bounded LRU caches that change the time, never the result.

Expensive, deterministic steps (lambdifying a model, compiling its flow, deriving
the first-order averaged equations used as a starting guess) are memoised with
:func:`memo` on hashable keys (models and bound models are hashable).  Every memo
is registered, so :func:`clear_caches` empties them all (tests, or after changing
``KBM_NO_JIT``; the switch is also part of the flow memo's key).
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import TypeVar

__all__ = ["memo", "clear_caches"]

F = TypeVar("F", bound=Callable)

_REGISTRY: list = []


def memo(maxsize: int = 32) -> Callable[[F], F]:
    """``functools.lru_cache(maxsize)``, registered for :func:`clear_caches`."""
    def wrap(fn: F) -> F:
        cached = functools.lru_cache(maxsize=maxsize)(fn)
        _REGISTRY.append(cached)
        return cached  # type: ignore[return-value]
    return wrap


def clear_caches() -> None:
    """Empty every memo of :mod:`numerics` (results do not change; only the time)."""
    for fn in _REGISTRY:
        fn.cache_clear()
