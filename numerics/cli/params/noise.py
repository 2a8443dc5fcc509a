"""The noise as an axis: ``--vary D=...`` or ``--vary T=...`` (``T = kT = D/mu``).

A value of the axis that the command cannot take is refused naming the ``--vary`` the user
typed: ``kbm spectrum vdp -p mu=0.1 --vary T=-0.01:0.01`` said "give -p T=VALUE", and a
negative value later in the list was reported as ``D = mu T`` ("D = -0.001: ... -p
D=VALUE"), both names of options the user never gave.
"""

from __future__ import annotations

import numpy as np

from kbm.errors import ParameterError

from .values import DEFAULT_POINTS, Vary

__all__ = ["noise_axis"]

#: what each name of the noise is, for the messages
_WHAT = {"D": "the noise intensity of sqrt(2 D) xi", "T": "the temperature kT = D/mu"}


def noise_axis(vary: Vary, points: int = DEFAULT_POINTS,
               need: str | None = None) -> np.ndarray:
    """The values of a ``--vary D`` or ``--vary T`` axis as typed, each checked.

    Parameters
    ----------
    vary : Vary
        The axis, named ``D`` or ``T`` (its values finite: :func:`~.values.parse_vary`).
    points : int, optional
        The number of values of a range without ``:N`` (:data:`~.values.DEFAULT_POINTS`).
    need : str, optional
        Why zero noise is refused (``"a linewidth needs noise"``); ``None``: zero is the
        deterministic model and accepted (``kbm friction``).

    Returns
    -------
    numpy.ndarray
        The values, ``> 0`` (``>= 0`` where ``need`` is ``None``), in the order typed.

    Raises
    ------
    kbm.errors.ParameterError
        ``"--vary T=-0.01:0.01: T = -0.01 is negative; the temperature kT = D/mu must be
        > 0 (a linewidth needs noise): give --vary T with every value > 0"``.
    """
    values = vary.values(points)
    rule = ">= 0" if need is None else "> 0"
    why = need or f"{vary.name} = 0: the deterministic model"
    for x in values:
        if x > 0 or (x == 0 and need is None):
            continue
        said = "is negative" if x < 0 else "is no noise"
        raise ParameterError(f"--vary {vary.text}: {vary.name} = {x:g} {said}; "
                             f"{_WHAT[vary.name]} must be {rule} ({why}): give --vary "
                             f"{vary.name} with every value {rule}")
    return values
