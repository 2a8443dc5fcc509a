"""The built-in coupled systems (names used on the command line).

``coupled-vdp``    two van der Pol oscillators in 1:1 resonance, dissipatively coupled,
                   with a detuning written in F (issue 23):
                   ``F1 = (1 - x1^2) x1' + c (x2' - x1')``,
                   ``F2 = (1 - x2^2) x2' + c (x1' - x2') - 2 sigma x2``
``duffing-1-3``    two cubic oscillators in 1:3 internal resonance with a potential
                   coupling ``V = k x1^3 x2`` and light damping, the second forced near its
                   frequency (Nayfeh & Mook 1979, secs. 6.6, 6.6.2):
                   ``F1 = -2 zeta1 x1' - alpha1 x1^3 - 3 k x1^2 x2``,
                   ``F2 = -2 zeta2 x2' - alpha2 x2^3 - k x1^3 + h cos(theta)``,
                   ``omega = (1, 3)``, ``nu = 3 + mu sigma`` (``h = 0``: free)
``sedf-dimer``     two self-excited sliders of the paper's eq. (3) on the potential,
                   coupled by a spring ``K = mu kappa``, pulled by the stage at ``v``
                   (default 0: at rest), the self-excitation attached to the stage as in
                   ``sedf_comoving``: ``F_i = -(beta (x_i - v t)^2 - 1) x_i' - delta
                   sin(k x_i) - kappa (x_i - x_j)``, drive ``v t``, ``delta = Delta/mu``,
                   ``k = 2 pi/lam`` (``Omega = 1``)
``sedf-chain``     ``N`` such sliders in a chain with free ends (``sedf-chain`` is N = 4,
                   ``sedf-chain-N`` any N up to 256): ``-kappa (2 x_i - x_{i-1} - x_{i+1})``
``quadratic-1-2``  two oscillators with quadratic coupling in 1:2 internal resonance,
                   ``omega2 = 2 + mu sigma1``, forced near the higher mode,
                   ``nu = 2 + mu sigma2`` (Nayfeh & Mook 1979, sec. 6.5.1):
                   ``F1 = -2 zeta1 x1' - alpha1 x1 x2``,
                   ``F2 = -2 zeta2 x2' - alpha2 x1^2 + h cos(theta)``, ``theta = nu t``
"""

from __future__ import annotations

from collections.abc import Sequence

from ..errors import ModelError
from .coupled import CoupledOscillators
from ..expansion.resonance import InternalResonance

__all__ = ["COUPLED_MODELS", "get_coupled_model", "coupled_model_names", "sedf_chain",
           "coupled_custom",
           "is_coupled_name"]

COUPLED_MODELS: dict[str, CoupledOscillators] = {
    "coupled-vdp": CoupledOscillators(
        "coupled-vdp",
        ("(1 - x1**2)*xdot1 + c*(xdot2 - xdot1)",
         "(1 - x2**2)*xdot2 + c*(xdot1 - xdot2) - 2*sigma*x2"),
        (1, 1),
        description="two van der Pol oscillators, dissipative coupling c, detuning sigma of "
                    "the second (its frequency 1 + mu sigma)",
        defaults={"c": "0.3", "sigma": "0"}, internal=("1:1",)),
    "duffing-1-3": CoupledOscillators(
        "duffing-1-3",
        ("-2*zeta1*xdot1 - alpha1*x1**3 - 3*k*x1**2*x2",
         "-2*zeta2*xdot2 - alpha2*x2**3 - k*x1**3 + h*cos(theta)"),
        (1, 3),
        description="two cubic oscillators in 1:3 internal resonance, potential coupling "
                    "k x1^3 x2, the second forced near its frequency, nu = 3 + mu sigma "
                    "(Nayfeh & Mook 1979, secs. 6.6, 6.6.2; h = 0: free)",
        defaults={"zeta1": "0", "zeta2": "0", "alpha1": "1", "alpha2": "1", "k": "1",
                  "h": "0"},
        internal=("1:3", InternalResonance(2, 3, 1, 1, forcing=True)),
        nu0=3, nu_detuning="sigma"),
    "quadratic-1-2": CoupledOscillators(
        "quadratic-1-2",
        ("-2*zeta1*xdot1 - alpha1*x1*x2", "-2*zeta2*xdot2 - alpha2*x1**2 + h*cos(theta)"),
        (1, 2),
        description="two oscillators with quadratic coupling in 1:2 internal resonance "
                    "(omega2 = 2 omega1 + mu sigma1), forced near the higher mode "
                    "(nu = 2 + mu sigma2) (Nayfeh & Mook 1979, sec. 6.5.1)",
        defaults={"zeta1": "0", "zeta2": "0", "alpha1": "1", "alpha2": "1", "h": "0"},
        internal=(InternalResonance(1, 2, 1, 2, "sigma1"),
                  InternalResonance(2, 3, 1, 1, forcing=True)),
        nu0=2, nu_detuning="sigma2"),
}


_SEDF_PHYSICAL = {"delta": "Delta/mu", "k": "2*pi/lam"}
_SEDF_DEFAULTS = {"beta": "1", "lam": "1", "kappa": "1", "v": "0"}


def sedf_chain(n: int, name: str | None = None) -> CoupledOscillators:
    """``n`` SEDF sliders (paper eq. 3, v = 0) in a chain with free ends, neighbours coupled
    by springs ``mu kappa``.

    Raises
    ------
    kbm.errors.ModelError
        For ``n`` outside ``2..256``.
    """
    if not 2 <= n <= 256:
        raise ModelError(f"a chain of sliders has 2 to 256 sliders, got {n}")
    F = []
    for i in range(1, n + 1):
        spring = " - ".join(f"kappa*(x{i} - x{j})" for j in (i - 1, i + 1) if 1 <= j <= n)
        F.append(f"-(beta*(x{i} - v*t)**2 - 1)*xdot{i} - delta*sin(k*x{i}) - {spring}")
    return CoupledOscillators(
        name or f"sedf-chain-{n}", tuple(F), (1,) * n,
        description=f"{n} self-excited sliders (paper eq. 3; the self-excitation attached to "
                    "the stage, as sedf_comoving) in a chain with free ends, springs "
                    "mu*kappa between neighbours, pulled at v (0: at rest)",
        defaults=_SEDF_DEFAULTS, physical=_SEDF_PHYSICAL, drive=("v*t",) * n,
        internal=tuple(f"1:1@{i},{i + 1}" for i in range(1, n)))


COUPLED_MODELS["sedf-dimer"] = sedf_chain(2, "sedf-dimer")
COUPLED_MODELS["sedf-chain"] = sedf_chain(4, "sedf-chain")


def is_coupled_name(name: object) -> bool:
    """Whether ``name`` names a coupled built-in (``sedf-chain-N`` for any ``N`` included)."""
    return isinstance(name, str) and (name in COUPLED_MODELS
                                      or name.startswith("sedf-chain-"))


def coupled_model_names() -> list[str]:
    """The names of the built-in coupled systems."""
    return sorted(COUPLED_MODELS)


def get_coupled_model(name: str) -> CoupledOscillators:
    """The built-in system ``name``: a coupled one, or a one-degree-of-freedom model of
    :mod:`kbm.model.builtins` or :mod:`kbm.model.forced_builtins` as the case ``N = 1``.

    Raises
    ------
    kbm.errors.ModelError
        For an unknown name (the known ones are listed), or a driven one-degree-of-freedom
        model.
    """
    if name in COUPLED_MODELS:
        return COUPLED_MODELS[name]
    if name.startswith("sedf-chain-") and name[len("sedf-chain-"):].isdigit():
        return sedf_chain(int(name[len("sedf-chain-"):]))
    from .forced_builtins import FORCED_MODELS, get_forced_model
    from .builtins import MODELS, get_model

    if name in MODELS:  # the cases N = 1 are members of the one type as they are
        return get_model(name)
    if name in FORCED_MODELS:
        return get_forced_model(name)
    raise ModelError(f"unknown model {name!r}; the built-in coupled systems are "
                     f"{', '.join(coupled_model_names())}, the one-degree-of-freedom "
                     f"models are {', '.join(sorted(MODELS))} and the forced ones "
                     f"{', '.join(sorted(FORCED_MODELS))}")


def coupled_custom(rhs: Sequence[str], omega0: Sequence[object] | str | None = None, *,
                   name: str = "custom", nu0: object = None,
                   detuning: str = "sigma") -> CoupledOscillators:
    """A user's system from one right-hand side per degree of freedom.

    ``omega0`` is a list or a comma-separated string (``"1,3"``); default all 1.  With
    ``nu0`` the right-hand sides may hold the forcing angle ``theta = nu t``,
    ``nu = nu0 + mu detuning``.

    Raises
    ------
    kbm.errors.ModelError
        For mismatched counts (both are named), unreadable expressions, or a right-hand
        side that uses none of the state variables.
    """
    n = len(rhs)
    if omega0 is None:
        w: Sequence[object] = ["1"] * n
    elif isinstance(omega0, str):
        w = [s.strip() for s in omega0.split(",")]
    else:
        w = list(omega0)
    if len(w) != n:
        raise ModelError(f"{n} right-hand sides (--rhs) but {len(w)} frequencies (--omega0 "
                         f"{omega0}): give one frequency per degree of freedom")
    model = CoupledOscillators(name, tuple(rhs), tuple(w),
                               description=f"user system of {n} degrees of freedom",
                               nu0=nu0, nu_detuning=detuning if nu0 is not None else None)
    state = set(model.state)
    for i, f in enumerate(model.F, 1):
        if f != 0 and not (f.free_symbols & state):
            raise ModelError(f"F{i} = {rhs[i - 1]} depends on none of the state variables "
                             f"{', '.join(map(str, model.state))}: write the system in them "
                             "(one --rhs per degree of freedom)")
    return model
