"""The ``-p`` values of the commands with noise, and the noise as an axis: ``--vary D=...``
or ``--vary T=...`` (``T = kT = D/mu``).

:func:`noisy_model` reads the values of ``kbm noise``, ``kbm escape`` and ``kbm spectrum``;
:func:`noise_axis_model` those of ``kbm spectrum --vary D`` or ``T``.  A value of the axis
that the command cannot take is refused naming the ``--vary`` the user typed: ``kbm
spectrum vdp -p mu=0.1 --vary T=-0.01:0.01`` said "give -p T=VALUE", and a negative value
later in the list was reported as ``D = mu T`` ("D = -0.001: ... -p D=VALUE"), both names
of options the user never gave.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from kbm.errors import ParameterError

from .values import DEFAULT_POINTS, Vary, check, given, noise_params

__all__ = ["noise_axis", "noisy_model", "noise_axis_model"]

#: what each name of the noise is, for the messages
_WHAT = {"D": "the noise intensity of sqrt(2 D) xi", "T": "the temperature kT = D/mu"}


def noise_axis(vary: Vary, points: int = DEFAULT_POINTS, need: str | None = None, *,
               given: dict[str, str] | None = None) -> np.ndarray:
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
    given : dict, optional
        The ``-p`` values, where ``mu`` has no default and is no axis (``kbm spectrum``):
        ``T = D/mu`` without ``mu > 0`` is refused naming the ``--vary`` (it was told as a
        ``-p`` error: "give -p D=VALUE").

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
    if given is not None:
        _given(vary, given)
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


def _given(vary: Vary, given: dict[str, str]) -> None:
    """Refuse ``--vary T`` without ``mu > 0`` (the noise given twice is refused by
    :func:`~.values.check`)."""
    from kbm.parameters.values import parameter_value

    if vary.name != "T":
        return
    other = "--vary D=FROM:TO (D = mu T)"
    if "mu" not in given:
        raise ParameterError(f"--vary {vary.text}: T = D/mu needs mu: give -p mu=VALUE, or "
                             f"the noise as {other}")
    if not parameter_value("mu", given["mu"]) > 0:
        raise ParameterError(f"--vary {vary.text}: T = D/mu is the temperature of the "
                             f"damping mu x' and needs mu > 0, got mu = {given['mu']}; give "
                             f"-p mu=VALUE > 0, or the noise as {other}")


def _named(model: "str | object", items: Iterable[str], varied: Iterable[str] = ()) -> dict:
    """The ``-p`` values read, the model (a built-in of one degree of freedom, or ``--rhs``)
    and every name (``-p`` and ``varied``) checked."""
    from kbm.model.builtins import SLIDERS
    from kbm.parameters.names import lookup

    if isinstance(model, str):
        lookup(model, ("one",))
    params = given(items)
    check(model, params, varied, extra=("v",) if model in SLIDERS else (), noise=True)
    return params


def noisy_model(model: "str | object", items: Iterable[str]) -> tuple[dict[str, str], str | None]:
    """The ``-p`` values of ``kbm noise``, ``kbm escape`` and ``kbm spectrum``: ``model`` a
    built-in of one degree of freedom (or a model, ``--rhs``), every name one of its
    (physical or scaled), ``mu``, the stage velocity ``v`` of a slider, and ``D`` or ``T =
    D/mu``; returns ``(values with D, the noise's name as given)``.

    Raises
    ------
    kbm.errors.ModelError, kbm.errors.ParameterError
        For an unknown model (the built-ins listed) or name (the valid ones listed).
    """
    return noise_params(_named(model, items))


def noise_axis_model(model: "str | object", items: Iterable[str], vary: Vary, points: int,
                     need: str | None = None) -> tuple[dict[str, str], str | None, np.ndarray]:
    """:func:`noisy_model` with the noise an axis, ``--vary D`` or ``--vary T``: the model and
    the names checked first, then the axis (:func:`noise_axis`, with the ``-p`` values);
    returns ``(values with D at the axis's first value, the noise's name, the axis's values
    as typed)``.

    Raises
    ------
    kbm.errors.ModelError, kbm.errors.ParameterError
        As :func:`noisy_model` and :func:`noise_axis`, the axis's refusals naming the
        ``--vary`` typed.
    """
    params = _named(model, items, [vary.name])
    values = noise_axis(vary, points, need, given=params)
    return (*noise_params({**params, vary.name: repr(float(values[0]))}), values)
