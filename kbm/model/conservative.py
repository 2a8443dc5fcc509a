"""Split an autonomous oscillator into a conservative force and a small damping.

For strongly nonlinear (energy-balance) averaging the equation of a model,
``x'' = -omega0**2 x + mu F(x, x')``, is written at given parameter values as

``x'' = -g(x) + mu h(x, x')``,  ``g(x) = -x''(x, x' = 0)``,
``h(x, x') = (x''(x, x') - x''(x, 0))/mu``,

so that ``h`` vanishes at ``x' = 0``; the potential is ``G(x) = int_0^x g``.
The whole conservative force ``g`` (e.g. the slider's ``Omega**2 x + Delta
sin(k x)``) is kept at order one, only ``h`` is a perturbation.

References
----------
S. Coppola and R. H. Rand, "Averaging using elliptic functions: approximation
of limit cycles", Acta Mechanica 81 (1990) 125-142.
S. B. Yuste and J. D. Bejarano, "Extension and improvement to the
Krylov-Bogoliubov methods using elliptic functions", Int. J. Control 49 (1989).
N. N. Bogoliubov and Y. A. Mitropolsky, *Asymptotic Methods in the Theory of
Non-Linear Oscillations*, chapter on systems close to non-linear conservative ones.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import numpy as np
import sympy as sp

from ..errors import ModelError, ParameterError
from .builtins import Oscillator, get_model
from ..symbols import mu, parse, t, x, xdot

__all__ = ["ConservativeSplit", "NotConfiningError", "SplitLine", "split_conservative"]


class NotConfiningError(ModelError):
    """The potential ``G(x)`` does not grow to infinity on both sides: orbits escape."""


@dataclass(frozen=True)
class ConservativeSplit:
    """``x'' = -g(x) + mu h(x, xdot)`` at fixed parameter values.

    Attributes
    ----------
    model : kbm.model.builtins.Oscillator
        The model split.
    g : sympy.Expr
        The conservative force, in ``x`` only.
    h : sympy.Expr
        The perturbation divided by ``mu``, in ``x`` and ``xdot``; zero at ``xdot = 0``.
    G : sympy.Expr
        The potential ``int_0^x g`` (or the user's ``V(x) - V(0)``).
    mu : float
        The small parameter.
    params : Mapping[str, float]
        The values of the model's parameters used (scaled names, floats).
    user_potential : bool
        Whether ``G`` came from the ``potential`` argument.
    """

    model: Oscillator
    g: sp.Expr
    h: sp.Expr
    G: sp.Expr
    mu: float
    params: Mapping[str, float] = field(default_factory=dict)
    user_potential: bool = False
    #: ``(g, g', G, h)`` already lambdified (a :class:`SplitLine` binds them per value); else
    #: :meth:`numpy_functions` lambdifies the expressions
    functions: tuple | None = field(default=None, compare=False, repr=False)
    #: ``(g, G)`` for Python floats and ``dh/dxdot`` (numpy), already lambdified, or ``None``
    scalar: tuple | None = field(default=None, compare=False, repr=False)
    h_velocity: Callable | None = field(default=None, compare=False, repr=False)

    @property
    def conservative(self) -> bool:
        """``True`` when ``h`` is identically zero (every orbit is periodic)."""
        return sp.expand(self.h) == 0

    def numpy_functions(self) -> tuple[Callable, Callable, Callable, Callable]:
        """``(g, dg/dx, G, h)`` as vectorised numpy functions.

        Returns
        -------
        tuple of callable
            ``g(x)``, ``g'(x)``, ``G(x)`` and ``h(x, v)``; each broadcasts and
            returns float arrays of the broadcast shape.
        """
        if self.functions is not None:
            return self.functions
        return _vectorised(sp.lambdify(x, self.g, "numpy"),
                           sp.lambdify(x, sp.diff(self.g, x), "numpy"),
                           sp.lambdify(x, self.G, "numpy"),
                           sp.lambdify((x, xdot), self.h, "numpy"))


    def scalar_functions(self) -> tuple[Callable, Callable]:
        """``(g, G)`` lambdified with the :mod:`math` module (scalar speed).

        Raises
        ------
        NameError, TypeError, sympy.printing.codeprinter.PrintMethodNotImplementedError
            When a function of ``g`` or ``G`` has no :mod:`math` form.
        """
        if self.scalar is not None:
            return self.scalar
        return sp.lambdify(x, self.g, "math"), sp.lambdify(x, self.G, "math")

    def h_velocity_function(self) -> Callable:
        """``dh/dxdot`` as a numpy function of ``(x, xdot)`` (broadcasting)."""
        if self.h_velocity is not None:
            return self.h_velocity
        return sp.lambdify((x, xdot), sp.diff(self.h, xdot), "numpy")


def _vectorised(g, dg, G, h) -> tuple[Callable, Callable, Callable, Callable]:
    """The four functions of :meth:`ConservativeSplit.numpy_functions` from lambdified ones
    (broadcast, float arrays)."""
    def vec1(f):
        return lambda z: np.broadcast_to(np.asarray(f(z), dtype=float), np.shape(z)) + 0.0

    def hv(z, v):
        zz, vv = np.broadcast_arrays(np.asarray(z, float), np.asarray(v, float))
        return np.broadcast_to(np.asarray(h(zz, vv), dtype=float), zz.shape) + 0.0

    return vec1(g), vec1(dg), vec1(G), hv


def _check_confining(G: sp.Expr, g: sp.Expr, model: Oscillator, Gf=None, gf=None) -> None:
    """Raise :class:`NotConfiningError` unless ``G`` grows to infinity on both sides (``Gf``,
    ``gf``: the functions of ``G`` and ``g`` if already lambdified)."""
    Gf = sp.lambdify(x, G, "numpy") if Gf is None else Gf
    gf = sp.lambdify(x, g, "numpy") if gf is None else gf
    inner = np.linspace(-100.0, 100.0, 20001)
    try:
        with np.errstate(all="ignore"):
            ref = float(np.max(np.abs(np.broadcast_to(Gf(inner), inner.shape))))
            far = np.array([1e4, 1e5, 1e6])
            Gp = np.broadcast_to(Gf(far), far.shape)
            Gm = np.broadcast_to(Gf(-far), far.shape)
            gp, gm = float(gf(1e6)), float(gf(-1e6))
    except (NameError, TypeError) as exc:  # a function numpy does not know (e.g. hyper)
        raise ModelError(
            f"the potential G(x) = {G} of model {model.name!r} has no numpy form ({exc}); "
            "give the conservative part's potential explicitly (potential=...)") from None
    ok = (np.all(np.isfinite(Gp)) and np.all(np.isfinite(Gm))
          and min(Gp[-1], Gm[-1]) > 100.0 * (1.0 + ref) and gp > 0 and gm < 0
          and np.all(np.diff(Gp) > 0) and np.all(np.diff(Gm) > 0))
    if not ok:
        raise NotConfiningError(
            f"the conservative force g(x) = {g} of model {model.name!r} does not confine: "
            f"its potential G(x) = {G} does not grow to +infinity on both sides, so there "
            "are unbounded orbits (rotations or escapes) and no outer period annulus; give "
            "a restoring linear part (e.g. Omega > 0 in params) or a confining `potential`")


def split_conservative(model: Oscillator | str, params: Mapping[str, object] | None = None,
                       *, potential: str | sp.Expr | None = None) -> ConservativeSplit:
    """Split ``model`` at ``params`` into ``g(x)``, ``h(x, xdot)`` and ``G(x)``.

    Parameters
    ----------
    model : kbm.model.builtins.Oscillator or str
        The oscillator or a built-in name.
    params : Mapping[str, object], optional
        Values of ``mu`` and of every parameter (physical names such as
        ``Delta``, ``lam`` are converted by :meth:`Oscillator.resolve`).
    potential : str or sympy.Expr, optional
        A potential ``V(x)``; then ``g = V'`` and ``x''(x, 0) + V'(x)`` must
        vanish.  Default: ``G = int_0^x g`` computed by sympy.

    Returns
    -------
    ConservativeSplit

    Raises
    ------
    kbm.errors.NonAutonomousError
        For a driven model (stage velocity ``v != 0``).
    kbm.errors.ParameterError
        If ``mu`` is missing or zero, or a parameter has no value.
    kbm.errors.ModelError
        If ``potential`` does not match the model's force, or ``G`` cannot be
        integrated in closed form (then pass ``potential``).
    NotConfiningError
        If ``G`` does not grow to infinity on both sides.

    Examples
    --------
    >>> s = split_conservative("sedf", {"mu": 0.1, "Delta": 1.5, "beta": 1, "lam": 1})
    >>> s.g
    x + 3*sin(2*pi*x)/2
    >>> s.h
    -x**2*xdot + xdot
    """
    if isinstance(model, str):
        model = get_model(model)
    model.require_autonomous("the energy-balance averaging")
    vals = model.resolve(params)
    if "mu" not in vals:
        raise ParameterError("the energy-balance averaging needs a value of mu in params "
                             "(e.g. params={'mu': 0.1})")
    mu_val = vals["mu"]
    if mu_val == 0:
        raise ParameterError("mu = 0 in params: there is no perturbation to average; give "
                             "mu != 0")
    subs = {sp.Symbol(k): v for k, v in vals.items() if k != "mu"}
    acc = model.acceleration().subs(subs)
    missing = sorted(s.name for s in acc.free_symbols - {x, xdot, mu, t})
    if missing:
        raise ParameterError(f"give values for {', '.join(missing)} in params "
                             f"(e.g. params={{'{missing[0]}': 1, ...}})")
    g_model, h = _force_and_perturbation(acc, mu_val)
    if potential is not None:
        V = parse(potential) if not isinstance(potential, sp.Basic) else potential
        V = V.subs(subs)
        extra = V.free_symbols - {x}
        if extra:
            raise ModelError(f"the potential {V} depends on {', '.join(sorted(map(str, extra)))}; "
                             "it must be a function of x and the model's parameters only")
        g = sp.diff(V, x)
        rest = sp.simplify(g - g_model)
        if rest != 0:
            raise ModelError(
                f"the potential's force V'(x) = {g} differs from the model's force at xdot = 0, "
                f"g(x) = {g_model}, by {rest}; the remainder must vanish at xdot = 0: change "
                "`potential` so that V'(x) = g(x), or leave potential=None")
        G = sp.simplify(V - V.subs(x, 0))
        user = True
    else:
        g = g_model
        G = _potential(g)
        if G.has(sp.Integral):
            raise ModelError(f"sympy cannot integrate g(x) = {g} in closed form; pass its "
                             "antiderivative as `potential`")
        user = False
    if sp.expand(h.subs(xdot, 0)) != 0:  # pragma: no cover - by construction
        raise ModelError("the perturbation h does not vanish at xdot = 0")
    _check_confining(G, g, model)
    fvals = {k: float(v) for k, v in vals.items() if k != "mu"}
    return ConservativeSplit(model=model, g=g, h=h, G=G, mu=float(mu_val),
                             params=MappingProxyType(fvals), user_potential=user)


def _force_and_perturbation(acc: sp.Expr, mu_val) -> tuple[sp.Expr, sp.Expr]:
    """``(g, h)`` of ``x'' = acc = -g(x) + mu h(x, x')`` at ``mu = mu_val`` (``mu F`` with
    ``F(x, 0) != 0`` stays in ``g`` at its value)."""
    acc0 = acc.subs(xdot, 0)
    h = sp.expand((acc - acc0) / mu).subs(mu, mu_val)
    return sp.expand(-acc0.subs(mu, mu_val)), h


def _potential(g: sp.Expr) -> sp.Expr:
    """``G = int_0^x g`` expanded (still holding an ``Integral`` where sympy cannot)."""
    G = sp.integrate(g, (x, 0, x))
    return G if G.has(sp.Integral) else sp.expand(G)


class SplitLine:
    """:func:`split_conservative` along one parameter: ``line(p)`` is the split at
    ``vary = p`` (the other values as given).

    The energy-balance branch of ``kbm branch`` splits its model at some hundred values of
    one parameter; each split integrates ``g`` and lambdifies five functions.  A line does
    that once, with the values that move with ``vary``
    (:attr:`kbm.parameters.bound.ParameterLine.changed`, e.g. ``delta = Delta/mu``) kept as
    symbols, and per value substitutes them exactly into ``g``, ``h``, ``G`` and binds the
    lambdified functions.  ``line(p)`` equals ``split_conservative(model, {**params, vary: p})`` in
    its values (a test compares them); where the shortcut does not apply (``mu`` varied, a
    ``potential`` given, a potential sympy integrates only piecewise) every value is split from
    scratch.

    Parameters
    ----------
    model, params
        As for :func:`split_conservative` (``vary`` may be among ``params``).
    vary
        The parameter that varies.
    at
        A value of ``vary`` at which the model can be bound.
    potential
        As for :func:`split_conservative`.
    """

    def __init__(self, model: Oscillator | str, params: Mapping[str, object] | None,
                 vary: str, at: float, *, potential: str | sp.Expr | None = None):
        from ..parameters.bound import ParameterLine

        if isinstance(model, str):
            model = get_model(model)
        model.require_autonomous("the energy-balance averaging")
        self.model, self.params, self.vary = model, dict(params or {}), vary
        self.potential = potential
        self.line = ParameterLine(model, self.params, vary, at)
        base = self.line.base
        changed = self.line.changed
        self._symbolic = None
        if potential is not None or "mu" in changed or "mu" not in base.values \
                or base.values["mu"] == 0 or base.model != model:
            return
        mu_val = base.values["mu"]
        subs = {sp.Symbol(k): v for k, v in base.values.items()
                if k != "mu" and k not in changed}
        acc = model.acceleration().subs(subs)
        syms = tuple(sp.Symbol(k) for k in changed)
        if acc.free_symbols - {x, xdot, mu, t, *syms}:
            return  # a missing value: split_conservative names it
        g, h = _force_and_perturbation(acc, mu_val)
        G = _potential(g)
        if G.has(sp.Integral, sp.Piecewise):
            return
        args = (x, *syms)
        lam = {k: sp.lambdify(args, e, "numpy")
               for k, e in (("g", g), ("dg", sp.diff(g, x)), ("G", G))}
        lam["h"] = sp.lambdify((x, xdot, *syms), h, "numpy")
        lam["hv"] = sp.lambdify((x, xdot, *syms), sp.diff(h, xdot), "numpy")
        try:
            lam["sg"] = sp.lambdify(args, g, "math")
            lam["sG"] = sp.lambdify(args, G, "math")
        except Exception:  # noqa: BLE001 - no math form: the consumers fall back to numpy
            lam["sg"] = lam["sG"] = None
        self._symbolic = (syms, g, h, G, lam, float(mu_val))

    def __call__(self, value: float) -> ConservativeSplit:
        """The split at ``vary = value``.

        Raises
        ------
        kbm.errors.ParameterError, NotConfiningError, kbm.errors.ModelError
            As :func:`split_conservative` at that value.
        """
        if self._symbolic is None:
            return split_conservative(self.model, {**self.params, self.vary: value},
                                      potential=self.potential)
        syms, g, h, G, lam, mu_val = self._symbolic
        bound = self.line(value)
        exact = {s: bound.values[s.name] for s in syms}
        nums = tuple(float(v) for v in exact.values())
        gv, hv, Gv = (e.xreplace(exact) for e in (g, h, G))
        lg, ldg, lG, lh = lam["g"], lam["dg"], lam["G"], lam["h"]
        functions = _vectorised(lambda z: lg(z, *nums), lambda z: ldg(z, *nums),
                                lambda z: lG(z, *nums), lambda z, v: lh(z, v, *nums))
        _check_confining(Gv, gv, self.model, functions[2], functions[0])
        fvals = {k: float(v) for k, v in bound.values.items() if k != "mu"}
        sg, sG, lhv = lam["sg"], lam["sG"], lam["hv"]
        scalar = None if sg is None else (lambda z: sg(z, *nums), lambda z: sG(z, *nums))
        return ConservativeSplit(model=self.model, g=gv, h=hv, G=Gv, mu=mu_val,
                                 params=MappingProxyType(fvals), user_potential=False,
                                 functions=functions, scalar=scalar,
                                 h_velocity=lambda z, v: lhv(z, v, *nums))
