"""A forced model at fixed parameters, as a flow over one response period.

The forced oscillator ``x'' + omega0**2 x = mu F(x, x', nu t)`` is turned into the
non-autonomous :class:`kbm.model.builtins.Oscillator` of
:meth:`kbm.model.forced.ForcedOscillator.with_time` (``nu`` a parameter) and compiled once
(:func:`numerics.flow.compile_model`, the numba DOP853 of :mod:`numerics.flow.jit` with
its variational equations); the detuning ``sigma`` only changes the value of
``nu = (p/q) omega0 + mu sigma`` and the period ``T = 2 pi p/nu``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from kbm.errors import ParameterError
from kbm.model.family import one_degree_form
from kbm.model.forced import ForcedOscillator, Resonance
from kbm.model.forced_builtins import get_forced_model

from numerics.errors import IntegrationError
from numerics.flow import Method, compile_model, extended_state, flow, template_flow

__all__ = ["ForcedSystem"]


class ForcedSystem:
    """The forced model bound to parameter values (``mu`` required), ``sigma`` free.

    Parameters
    ----------
    model
        A :class:`~kbm.model.forced.ForcedOscillator` or a built-in forced model's name.
    values
        Parameter values incl. ``mu`` (numbers or exact strings).
    resonance
        The declared resonance (default the model's).
    rtol
        Integrator tolerance (``atol`` the same).

    Raises
    ------
    kbm.errors.ParameterError
        If ``mu`` or a parameter of the model is missing.
    """

    def __init__(self, model: ForcedOscillator | str, values: Mapping[str, object], *,
                 resonance: Resonance | str | None = None, rtol: float = 1e-10):
        if isinstance(model, str):
            model = get_forced_model(model)
        model = one_degree_form(model)  # an N = 1 system of the coupled form
        vals = model.resolve(values)
        if "mu" not in vals:
            raise ParameterError("the forced system needs a value of mu (--param mu=0.1)")
        vals.pop("sigma", None)
        missing = [p for p in model.parameters if p not in vals and p not in model.detunings]
        if missing:
            raise ParameterError(f"model {model.name!r} needs values of {', '.join(missing)} "
                                 f"(e.g. --param {missing[0]}=1)")
        self.model = model
        self.resonance = Resonance.parse(resonance) if resonance is not None else model.resonance
        self.values = {k: float(v) for k, v in vals.items()}
        self.mu = self.values["mu"]
        self.omega0 = float(model.omega0.subs({k: v for k, v in vals.items()}))
        self.rtol = rtol
        own = {k: v for k, v in vals.items() if k in model.parameters}
        self._osc = model.with_time()
        self._cm = compile_model(self._osc, {**own, "mu": vals["mu"], "nu": 1})
        self._names = self._cm.template.names
        self._inu = self._names.index("nu")
        self._jit = template_flow(self._cm.template)
        self._own = own
        self._cms: dict[float, object] = {}
        self.evaluations = 0

    # -- frequencies ----------------------------------------------------------------
    def nu(self, sigma: float) -> float:
        """``nu = (p/q) omega0 + mu sigma``."""
        r = self.resonance
        return r.p / r.q * self.omega0 + self.mu * float(sigma)

    def period(self, sigma: float) -> float:
        """The response period ``2 pi p/nu``."""
        n = self.nu(sigma)
        if not n > 0:
            raise ParameterError(f"the forcing frequency nu = {n:.6g} at sigma = {sigma:.6g} is "
                                 "not positive; narrow the detuning range")
        return 2 * math.pi * self.resonance.p / n

    # -- the flow -------------------------------------------------------------------
    def flow(self, y0, sigma: float, n_out: int = 1, extended: bool = True) -> np.ndarray:
        """States at ``n_out + 1`` equally spaced times over one period from ``t = 0``.

        ``extended`` integrates the variational equations too (columns 2..5 hold the
        fundamental matrix ``(Phi11, Phi21, Phi12, Phi22)``, column 6 ``int div f``).

        Raises
        ------
        numerics.errors.IntegrationError
            If the integration fails.
        """
        T = self.period(sigma)
        self.evaluations += 1
        y = extended_state(y0[0], y0[1]) if extended else [float(y0[0]), float(y0[1])]
        if self._jit is not None:
            p = np.array(self._cm.pvec, dtype=float)
            p[self._inu] = self.nu(sigma)
            res = self._jit(y, T, p, self.rtol, self.rtol, n_out, 10**6)
            if res.status:
                raise IntegrationError(f"the compiled DOP853 failed before t = {T:.6g} at "
                                       f"sigma = {sigma:.6g}: {res.message}")
            return res.y
        cm = self._cms.get(sigma)
        if cm is None:
            cm = compile_model(self._osc, {**self._own, "mu": self.mu, "nu": self.nu(sigma)},
                               template=self._cm.template)
            self._cms = {sigma: cm}
        return flow(cm, extended_state(y0[0], y0[1]), T, n_out, Method.LSODA, self.rtol,
                    self.rtol)[:, :len(y)]
