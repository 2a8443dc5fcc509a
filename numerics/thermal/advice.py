"""What ``kbm noise`` says when an averaged moment is more than ``Z_FLAG`` standard errors
from the simulated one (``validity`` in its JSON, the ``WARNING:`` line in its text).

The advice names only what the user can still do: ``--order 2`` where the second-order
amplitude averaging applies (a polynomial ``F``, :mod:`kbm.noise.stochastic_order2`) and is
not already given; ``--method fokker-planck`` only where the stationary Kramers solution
applies (a model at rest with a damping polynomial in ``x'``, :mod:`numerics.fokker_planck`)
and is not already shown.  Where its moments are shown (``moments.*.fokker_planck``, the
text's Fokker-Planck column) they owe nothing to averaging: the advice points at them as the
reference and says how far the simulation is from them, ``z_FP = (FP - simulated)/stderr``
(``validity.z_fokker_planck``).  Before, ``kbm noise sedf -p mu=0.1 -p Delta=3 -p beta=1 -p
D=0.05 --method fokker-planck`` advised "use --method fokker-planck" beside its own
Fokker-Planck column.
"""

from __future__ import annotations

from collections.abc import Mapping

from ..noise.validity import Z_FLAG, gap_z, validity_entry

__all__ = ["validity", "fokker_planck_route", "FP_ROUTE"]

#: the Fokker-Planck route when nothing is known against it (the remedy's default)
FP_ROUTE = "--method fokker-planck (the exact stationary state of a model at rest)"
_NAMES = {"a2": "<a^2>", "x2": "<x^2>"}


def fokker_planck_route(model, params: Mapping, why: str) -> str | None:
    """How to obtain the Fokker-Planck moments that a run did not report, or ``None`` where
    they do not apply (``why``: the report's ``fokker_planck_message``).

    ``"not requested"`` (``--no-fokker-planck``): rerun without it, if the model's damping
    is polynomial in ``x'`` (:func:`numerics.fokker_planck.velocity_terms`, the condition
    of the Hermite expansion); a solve refused for its cost: a larger ``--fp-budget``
    (``--method fokker-planck`` alone has the same budget, :mod:`numerics.noise.budget`);
    any other reason (a driven slider, a damping not polynomial in ``x'``): ``None``.
    """
    if why == "not requested":
        from kbm.errors import KBMError
        from kbm.model.conservative import split_conservative

        from ..fokker_planck import velocity_terms

        try:
            velocity_terms(split_conservative(model, {k: v for k, v in params.items()
                                                      if k != "v"}))
        except KBMError:
            return None
        return ("rerun without --no-fokker-planck (the stationary Kramers equation, which "
                "owes nothing to averaging)")
    if "not affordable" in why:
        return ("raise --fp-budget above the cost that the Fokker-Planck line states (the "
                "stationary Kramers equation, which owes nothing to averaging)")
    return None


def validity(moments: Mapping, order: int = 1, can_raise_order: bool = True,
             fp_route: str | None = FP_ROUTE, fp_error: Mapping | None = None) -> dict:
    """The gap ``(averaged - simulated)/stderr`` of each moment, the flag ``|z| > 4`` and
    what to do.

    Parameters
    ----------
    moments : mapping
        ``a2`` and ``x2``, each with ``averaged``, ``simulated``, ``stderr`` and, where the
        run solved the stationary Kramers equation, ``fokker_planck``.
    order : int
        The averaging's order, named in the advice.
    can_raise_order : bool
        Whether ``--order 2`` applies and is not given (the amplitude averaging of a
        polynomial ``F`` at order 1): only then is it advised.
    fp_route : str or None
        Where the moments have no ``fokker_planck`` value: how to obtain it
        (:func:`fokker_planck_route`), ``None`` where it does not apply.
    fp_error : mapping, optional
        The Fokker-Planck values' stated absolute error per moment (``None`` for a moment:
        not measured).  Where one exceeds the simulation's standard error, or is not
        measured, the column is no sharper than the simulation and is not called the
        reference: the advice asks for more of its digits (``--fp-budget``) instead.

    Returns
    -------
    dict
        ``z`` (per moment, ``None`` when a number is missing), ``flagged`` (bool),
        ``threshold``, ``advice`` (what to do when flagged, else ``""``) and, where both
        moments have a Fokker-Planck value and a simulated one, ``z_fokker_planck``
        (``(FP - simulated)/stderr`` per moment).
    """
    z, bad = gap_z(moments)
    fp_shown = all(moments[k].get("fokker_planck") is not None
                   and moments[k].get("simulated") is not None and moments[k].get("stderr")
                   for k in ("a2", "x2"))
    extra = {"z_fokker_planck": {
        k: (moments[k]["fokker_planck"] - moments[k]["simulated"]) / moments[k]["stderr"]
        for k in ("a2", "x2")}} if fp_shown else {}
    if not bad:
        return validity_entry(z, bad, **extra)
    worst = max(bad, key=lambda k: abs(z[k]))
    raise_order = ("--order 2 (second-order averaging)" if can_raise_order and order == 1
                   else None)
    loose = fp_shown and fp_error is not None and any(
        fp_error.get(k) is None or fp_error[k] > moments[k]["stderr"] for k in ("a2", "x2"))
    if loose:
        stated = ", ".join(f"{_NAMES[k]} +- {fp_error[k]:.2g}" if fp_error.get(k) is not None
                           else f"{_NAMES[k]} not measured" for k in ("a2", "x2"))
        remedy = ("the Fokker-Planck column is no sharper than the simulation here (its stated "
                  f"error: {stated}; the simulation's standard error is smaller): raise "
                  "--fp-budget for more of its digits")
        if raise_order:
            remedy += f"; for the averaged values, use {raise_order}"
    elif fp_shown:
        zf = extra["z_fokker_planck"]
        remedy = ("the Fokker-Planck column (the stationary Kramers equation, which owes "
                  "nothing to averaging) is the reference: its <a^2> and <x^2> are "
                  f"{zf['a2']:+.1f} and {zf['x2']:+.1f} standard errors from the simulated ones")
        if any(abs(v) > Z_FLAG for v in zf.values()):
            remedy += (f" (beyond {Z_FLAG:g} too: a step bias, try a smaller --dt; a run too "
                       "short for its standard error, a longer --t-end; or the Fokker-Planck "
                       "values' own stated error)")
        if raise_order:
            remedy += f"; for the averaged values, use {raise_order}"
    else:
        options = [r for r in (raise_order, fp_route) if r and r.startswith("--")]
        routes = (["use " + " or ".join(options)] if options else []) + [
            r for r in (fp_route,) if r and not r.startswith("--")]
        remedy = (" or ".join(routes) if routes else
                  "no other prediction applies here: the simulated values are the answer")
    return validity_entry(z, bad, f"the averaged {_NAMES[worst]} is {z[worst]:+.1f} standard "
                          f"errors from the simulated one (|z| > {Z_FLAG:g}): the "
                          f"{'first' if order == 1 else 'second'}-order averaging does not "
                          f"hold here (mu or D/mu too large, or a strong nonlinearity); "
                          f"{remedy}", **extra)
