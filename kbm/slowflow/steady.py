"""Steady states of the forced slow flow: fixed points, stability, response curve, folds.

A fixed point ``(a, phi)`` of ``da/dt = A(a, phi; sigma)``, ``dphi/dt = B(a, phi; sigma)``
(:class:`~kbm.expansion.forced_result.SlowFlow`) is a periodic response of period ``2 pi p/nu``; it
is stable when both eigenvalues of the Jacobian ``d(A, B)/d(a, phi)`` have negative real
parts (below ``-1e-10 (1 + max |eigenvalue|)``: a centre of a conservative slow flow is
*neutral*, not stable).  At fixed ``sigma`` every fixed point in an amplitude window is
found by a scan of the domain ``a`` x ``phi in [0, 2 pi/p)`` (cells where both rates
change sign) and Newton's method; the frequency-response curve ``a(sigma)`` is then
followed from these seeds by pseudo-arclength continuation (:mod:`kbm.slowflow.continuation`),
round its folds (the jump points).  The trivial state ``a = 0`` of a purely parametric forcing is
classified by the slow flow linearised in Cartesian coordinates ``a e^{i phi}``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from .continuation import both_ways, trace
from ..expansion.forced_result import SlowFlow

__all__ = ["FixedPoint", "ResponseBranch", "ResponseCurve", "fixed_points", "response_curve",
           "backbone", "trivial_state", "classify"]


@dataclass(frozen=True)
class FixedPoint:
    """A steady response: amplitude, resonant phase, detuning, Jacobian eigenvalues."""

    sigma: float
    amplitude: float
    phase: float
    eigenvalues: tuple[complex, complex]

    @property
    def stable(self) -> bool:
        """Both eigenvalues in the open left half-plane (:func:`classify`)."""
        return classify(self.eigenvalues) == "stable"


@dataclass(frozen=True)
class ResponseBranch:
    """One connected branch of the response curve: arrays along the arc."""

    sigma: np.ndarray
    amplitude: np.ndarray
    phase: np.ndarray
    stable: np.ndarray
    reason: str


@dataclass(frozen=True)
class ResponseCurve:
    """The frequency-response curve at one order: branches, folds, trivial state."""

    order: int
    branches: tuple[ResponseBranch, ...]
    folds: tuple[FixedPoint, ...]
    trivial: tuple[tuple[float, str], ...] = ()

    def points(self) -> list[dict]:
        """``[{"sigma", "amplitude", "stable"}]`` along every branch (the trivial state
        ``a = 0`` included where it exists)."""
        out = [{"sigma": float(s), "amplitude": float(av), "stable": bool(st)}
               for b in self.branches for s, av, st in zip(b.sigma, b.amplitude, b.stable)]
        out += [{"sigma": s, "amplitude": 0.0, "stable": st == "stable"}
                for s, st in self.trivial]
        return out


def classify(eigenvalues, rel: float = 1e-10) -> str:
    """``"stable"``, ``"unstable"`` or ``"neutral"`` (largest real part within
    ``rel (1 + max |eigenvalue|)`` of zero)."""
    tol = rel * (1 + max(abs(e) for e in eigenvalues))
    top = max(e.real for e in eigenvalues)
    return "stable" if top < -tol else "unstable" if top > tol else "neutral"


def _eig(sf: SlowFlow, av: float, ph: float, s: float) -> tuple[complex, complex]:
    ev = np.linalg.eigvals(sf.jacobian(av, ph, s)[:, :2])
    return complex(ev[0]), complex(ev[1])


def _period(sf: SlowFlow) -> float:
    return 2 * math.pi / (sf.resonance.p if sf.resonance else 1)


def _newton(sf: SlowFlow, u: np.ndarray, sigma: float, max_iter: int,
            rtol: float) -> tuple[np.ndarray, bool]:
    """Newton's method on the slow flow's rates ``(a', phi') = 0`` from ``u = (a, phi)``:
    the last iterate and whether the iteration stopped before ``max_iter`` steps (a step
    below ``rtol (1 + |a|)``, a singular Jacobian or a non-finite iterate)."""
    for _ in range(max_iter):
        with np.errstate(all="ignore"):
            r = np.array(sf.rates(u[0], u[1], sigma), dtype=float).ravel()
            Jm = sf.jacobian(u[0], u[1], sigma)[:, :2]
        try:
            du = np.linalg.solve(Jm, -r)
        except np.linalg.LinAlgError:
            return u, True
        u = u + du
        if not np.all(np.isfinite(u)) or np.max(np.abs(du)) < rtol * (1 + abs(u[0])):
            return u, True
    return u, False


def _add_new(found: list, sf: SlowFlow, sigma: float, u: np.ndarray, per: float) -> None:
    """Append the fixed point at ``u`` to ``found`` unless it is there (phase mod ``per``)."""
    ph = float(u[1] % per)
    if not any(abs(f.amplitude - u[0]) < 1e-7 and
               min(abs(f.phase - ph), per - abs(f.phase - ph)) < 1e-6 for f in found):
        found.append(FixedPoint(float(sigma), float(u[0]), ph, _eig(sf, u[0], ph, sigma)))


def fixed_points(sf: SlowFlow, sigma: float, amplitudes: tuple[float, float] = (1e-3, 5.0), *,
                 n_a: int = 200, n_phi: int = 72) -> list[FixedPoint]:
    """Every fixed point with ``amplitudes[0] < a < amplitudes[1]`` at detuning ``sigma``.

    Parameters
    ----------
    sf
        The slow flow.
    sigma
        The detuning.
    amplitudes
        The amplitude window scanned.
    n_a, n_phi
        The scan's grid (``phi`` over one period ``2 pi/p`` of the slow flow).

    Raises
    ------
    kbm.errors.ParameterError
        For an empty or non-positive amplitude window.
    """
    lo, hi = amplitudes
    if not 0 < lo < hi:
        raise ParameterError(f"the amplitude window must satisfy 0 < a_min < a_max, got "
                             f"({lo}, {hi})")
    per = _period(sf)
    A = np.linspace(lo, hi, n_a)
    if A[1] > 2 * lo:
        # a window over decades: the first cell refined geometrically (ratio 1.1), where the
        # small responses far from resonance sit (forced Duffing, zeta = 0.02, alpha = 5,
        # h = 0.0128: a = 0.002..0.006 over sigma in [-1, 3] lay in the first linear cell
        # (1e-3, 0.026) and no fixed point was found, so no branch and no fold)
        k = math.ceil(math.log(A[1] / lo) / math.log(1.1))
        A = np.concatenate([np.geomspace(lo, A[1], k + 1)[:-1], A[1:]])
    P = np.linspace(0.0, per, n_phi + 1)
    AA, PP = np.meshgrid(A, P, indexing="ij")
    with np.errstate(all="ignore"):
        f1, f2 = sf.rates(AA, PP, sigma)
    s1, s2 = np.sign(f1), np.sign(f2)

    def changes(s):
        c = np.stack([s[:-1, :-1], s[1:, :-1], s[:-1, 1:], s[1:, 1:]])
        return (c.max(axis=0) > 0) & (c.min(axis=0) < 0)

    cells = np.argwhere(changes(s1) & changes(s2))
    found: list[FixedPoint] = []
    for i, j in cells:
        u = np.array([0.5 * (A[i] + A[i + 1]), 0.5 * (P[j] + P[j + 1])])
        u, stopped = _newton(sf, u, sigma, 40, 1e-13)
        if not (stopped and np.all(np.isfinite(u)) and lo * 0.5 < u[0] < hi * 1.5):
            continue
        r = np.array(sf.rates(u[0], u[1], sigma), dtype=float).ravel()
        if np.max(np.abs(r)) <= 1e-9 * (1 + abs(u[0])):
            _add_new(found, sf, sigma, u, per)
    return sorted(found, key=lambda f: f.amplitude)


def trivial_state(sf: SlowFlow, sigma: float, eps: float = 1e-6) -> str | None:
    """``"stable"``, ``"unstable"`` or ``"neutral"`` for ``a = 0`` (``None`` when it is not a
    steady state: external forcing).

    The Cartesian field ``z = a e^{i phi}`` is linearised by central differences at the
    origin (the field is odd in ``z`` to the order kept), its eigenvalues decide
    (:func:`classify` with the differences' accuracy)."""
    def field(u, v):
        av, ph = math.hypot(u, v), math.atan2(v, u)
        da, dp = (float(np.ravel(r)[0]) for r in sf.rates(av, ph, sigma))
        return np.array([da * math.cos(ph) - av * dp * math.sin(ph),
                         da * math.sin(ph) + av * dp * math.cos(ph)])

    with np.errstate(all="ignore"):
        probe = [field(eps * math.cos(t), eps * math.sin(t)) for t in (0.3, 1.9, 4.0)]
    if any(not np.all(np.isfinite(p)) or np.linalg.norm(p) > 1e3 * eps for p in probe):
        return None
    J = np.column_stack([(field(eps, 0) - field(-eps, 0)) / (2 * eps),
                         (field(0, eps) - field(0, -eps)) / (2 * eps)])
    return classify([complex(e) for e in np.linalg.eigvals(J)], rel=1e-7)


def _on_branches(branches, fp: FixedPoint) -> bool:
    """Whether a traced branch passes through ``fp`` (amplitude interpolated in sigma)."""
    for b in branches:
        s, av = b.sigma, b.amplitude
        for k in range(len(s)):
            if k + 1 < len(s) and (s[k] - fp.sigma) * (s[k + 1] - fp.sigma) <= 0 \
                    and s[k] != s[k + 1]:
                w = (fp.sigma - s[k]) / (s[k + 1] - s[k])
                ai = av[k] + w * (av[k + 1] - av[k])
                tol = 1e-3 * (1 + fp.amplitude) + 0.5 * abs(av[k + 1] - av[k])
                if abs(ai - fp.amplitude) < tol:
                    return True
            elif abs(s[k] - fp.sigma) < 1e-12 and abs(av[k] - fp.amplitude) < 1e-6:
                return True
    return False


def response_curve(sf: SlowFlow, sigmas: tuple[float, float],
                   amplitudes: tuple[float, float] = (1e-3, 5.0), *, n_points: int = 400,
                   seeds_at: int = 3) -> ResponseCurve:
    """The frequency-response curve of the slow flow over ``sigmas``, every branch found.

    Seeds are all fixed points at ``seeds_at`` equally spaced detunings (the ends
    included); each is continued in both directions to the ends of the range (or to
    ``a -> 0`` or out of the amplitude window), steps about ``(range)/n_points``.

    Returns
    -------
    ResponseCurve
        Branches (stable and unstable points), folds (jump points) and, for parametric
        forcing, the trivial state's stability on the grid.
    """
    lo, hi = float(sigmas[0]), float(sigmas[1])
    if not hi > lo:
        raise ParameterError(f"the detuning range must be increasing, got {lo} to {hi}")
    per = _period(sf)
    span = hi - lo
    ds = span / max(n_points, 10)

    def G(u):
        return np.array([np.ravel(r)[0] for r in sf.rates(u[0], u[1], u[2])], dtype=float)

    def J(u):
        return sf.jacobian(u[0], u[1], u[2])

    def inside(u):
        return amplitudes[0] * 0.5 < u[0] < amplitudes[1] * 1.5

    branches: list[ResponseBranch] = []
    folds: list[FixedPoint] = []
    for s0 in np.linspace(lo, hi, seeds_at):
        for fp in fixed_points(sf, float(s0), amplitudes):
            if _on_branches(branches, fp):
                continue
            u0 = np.array([fp.amplitude, fp.phase, fp.sigma])
            arcs = both_ways(lambda d: trace(
                G, J, u0, (lo, hi), direction=d, ds=ds, ds_max=4 * ds, ds_min=1e-9 * span,
                max_points=20 * n_points, inside=inside, periods=np.array([0.0, per, 0.0])))
            pts = [p.u for p in reversed(arcs[0].points)] + \
                [p.u for a in arcs[1:] for p in a.points[1:]]
            U = np.array(pts)
            stable = np.array([classify(_eig(sf, *u)) == "stable" for u in U])
            branches.append(ResponseBranch(U[:, 2], U[:, 0], U[:, 1] % per, stable,
                                           "; ".join(a.reason for a in arcs)))
            for arc in arcs:
                for f in arc.folds:
                    if not any(abs(f[2] - g.sigma) < 1e-9 * (1 + span) and
                               abs(f[0] - g.amplitude) < 1e-7 for g in folds):
                        folds.append(FixedPoint(float(f[2]), float(f[0]), float(f[1] % per),
                                                _eig(sf, *f)))
    trivial: list[tuple[float, str]] = []
    if trivial_state(sf, lo) is not None:
        trivial = [(float(s), trivial_state(sf, float(s))) for s in np.linspace(lo, hi, n_points)]
    return ResponseCurve(sf.order, tuple(branches), tuple(sorted(folds, key=lambda f: f.sigma)),
                         tuple(trivial))


def backbone(sf: SlowFlow, amplitudes, n_phi: int = 64) -> np.ndarray:
    """The backbone ``sigma(a)``: the detuning at which the phase rate averaged over ``phi``
    vanishes (the forcing's phase-dependent terms averaged out); to first order in a Duffing
    oscillator ``sigma = 3 alpha a^2/(8 omega0)`` (Nayfeh & Mook 4.1.1).

    The phase rate is affine in ``sigma`` only at first order; the root in ``sigma`` is
    found by the secant method from two evaluations (then refined)."""
    av = np.asarray(amplitudes, dtype=float)
    ph = np.linspace(0, 2 * math.pi, n_phi, endpoint=False)
    AA, PP = np.meshgrid(av, ph, indexing="ij")

    def mean_rate(s):
        with np.errstate(all="ignore"):
            return np.mean(sf.rates(AA, PP, s[:, None])[1], axis=1)

    s0, s1 = np.zeros_like(av), np.ones_like(av)
    f0, f1 = mean_rate(s0), mean_rate(s1)
    for _ in range(30):
        d = f1 - f0
        s2 = np.where(d != 0, s1 - f1 * (s1 - s0) / np.where(d != 0, d, 1), s1)
        s0, f0, s1 = s1, f1, s2
        f1 = mean_rate(s1)
        if np.max(np.abs(s1 - s0)) < 1e-13 * (1 + np.max(np.abs(s1))):
            break
    return s1
