"""Time the coupled-oscillator tools against OSCILATE and a scipy shooting, in the same run.

Run: ``python benchmarks/bench_coupled.py``

1. Two cubic oscillators in 1:3 internal resonance, the system of OSCILATE's own example
   (Nayfeh & Mook 1979, sec. 6.6: damping ``2 mu_i x_i'``, all eight cubic terms
   ``alpha_1..alpha_8``, ``omega_2 = 3 omega_1 + sigma_1``), without the forcing (kbm's
   coupled engine averages autonomous systems): the first- and second-order slow flows by
   :func:`kbm.expansion.coupled.derive_coupled` (exact), against OSCILATE 1.0.7's
   ``Multiple_scales_oscillator(...).apply_MMS()`` at ``Ne = 1`` and ``Ne = 2``.  OSCILATE is
   installed by this script into its own virtual environment
   (``$KBM_BENCH_DIR``, default ``~/.cache/kbm-bench/oscilate``) with pip; it is not a
   dependency of the project.  Target: kbm's order 2 in under a tenth of OSCILATE's order 1.
2. A true cycle of the 4-dimensional ``coupled-vdp`` (mu = 0.05, c = 0.3, sigma = 0.1)
   with its four Floquet multipliers: :func:`numerics.shooting.coupled_orbit.coupled_cycle`'s Newton
   iterations from the section state (compiled DOP853 with the variational equations;
   warm), against the same Newton with :func:`scipy.integrate.solve_ivp` (DOP853) on the
   lambdified extended system, from the same start.  Target: 10 times faster.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

from kbm.model.coupled import CoupledOscillators
from kbm.expansion.resonance import InternalResonance
from kbm.expansion.coupled import derive_coupled
from numerics.shooting.coupled_orbit import coupled_cycle
from numerics.flow.coupled_flow import coupled_flow

F1 = ("-2*m1*xdot1 - al1*x1**3 - al2*x1**2*x2 - al3*x1*x2**2 - al4*x2**3")
F2 = ("-2*m2*xdot2 - al5*x1**3 - al6*x1**2*x2 - al7*x1*x2**2 - al8*x2**3")

OSCILATE_SCRIPT = textwrap.dedent("""
    import sys, time
    from sympy import symbols, Function
    from oscilate import MMS
    Ne = int(sys.argv[1])
    omega0, omega1, mu0, mu1 = symbols('omega_0 omega_1 mu_0 mu_1', real=True, positive=True)
    alphas = [symbols('alpha_%d' % i, real=True) for i in range(1, 9)]
    t = symbols('t')
    x0 = Function('x_0', real=True)(t)
    x1 = Function('x_1', real=True)(t)
    Eq0 = x0.diff(t, 2) + omega0**2*x0 + 2*mu0*x0.diff(t) + sum(alphas[i]*x0**(3-i)*x1**i for i in range(4))
    Eq1 = x1.diff(t, 2) + omega1**2*x1 + 2*mu1*x1.diff(t) + sum(alphas[4+i]*x0**(3-i)*x1**i for i in range(4))
    t0 = time.perf_counter()
    dyn = MMS.Dynamical_system(t, [x0, x1], [Eq0, Eq1], [omega0, omega1])
    eps = symbols('epsilon', real=True, positive=True)
    sigma1 = symbols('sigma_1', real=True)
    p, sub = MMS.scale_parameters((*alphas, mu0, mu1, sigma1), (*[1]*8, 1, 1, 1), eps)
    mms = MMS.Multiple_scales_oscillator(dyn, eps, Ne, omega0, sub, ratio_omegaMMS=1,
                                         ratio_omega_osc=[1, 3], detunings=[0, sigma1])
    mms.apply_MMS()
    print('SECONDS', time.perf_counter() - t0)
""")


def oscilate_python() -> Path | None:
    """The python of a virtual environment with OSCILATE (made on first use), or None."""
    root = Path(os.environ.get("KBM_BENCH_DIR", Path.home() / ".cache" / "kbm-bench")) / "oscilate"
    py = root / "bin" / "python"
    if not py.exists():
        try:
            subprocess.run([sys.executable, "-m", "venv", str(root)], check=True,
                           capture_output=True)
            subprocess.run([str(py), "-m", "pip", "install", "--quiet", "oscilate==1.0.7"],
                           check=True, capture_output=True, timeout=600)
        except (subprocess.SubprocessError, OSError) as exc:
            print(f"  OSCILATE could not be installed ({exc}); its timings are skipped")
            return None
    return py


def run_oscilate(py: Path, ne: int, timeout: float = 900) -> str:
    try:
        out = subprocess.run([str(py), "-c", OSCILATE_SCRIPT, str(ne)], capture_output=True,
                             text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return f"did not finish in {timeout:g} s"
    for line in out.stdout.splitlines():
        if line.startswith("SECONDS"):
            return f"{float(line.split()[1]):.2f} s"
    lines = out.stderr.strip().splitlines() or ["no output"]
    start = max((i for i, ln in enumerate(lines) if ln.split(":")[0].endswith("Error")),
                default=len(lines) - 1)
    return "failed: " + " ".join(ln.strip() for ln in lines[start:])[:200]


def kbm_times() -> tuple[float, float]:
    model = CoupledOscillators("duffing-1-3-general", (F1, F2), (1, 3),
                               internal=(InternalResonance(1, 2, 1, 3, "sigma1"),))
    out = []
    for order in (1, 2):
        t0 = time.perf_counter()
        derive_coupled(model, order)
        out.append(time.perf_counter() - t0)
    return out[0], out[1]


def scipy_cycle(y0: np.ndarray, T: float, values: dict, rtol: float = 1e-11):
    """The same Newton as numerics.shooting.coupled_orbit, with scipy's DOP853 on the lambdified
    extended system (state, monodromy)."""
    from kbm.model.coupled_builtins import get_coupled_model

    model = get_coupled_model("coupled-vdp")
    state = list(model.state)
    f = sp.Matrix([*state[2:], *model.accelerations()]).subs(
        {sp.Symbol(k): v for k, v in values.items()})
    J = f.jacobian(state)
    fn = sp.lambdify([state], list(f), "numpy")
    Jn = sp.lambdify([state], J, "numpy")

    def ext(t, y):
        Phi = y[4:].reshape(4, 4, order="F")
        return np.concatenate([fn(y[:4]), (np.asarray(Jn(y[:4]), float) @ Phi).ravel(order="F")])

    free = [0, 1, 3]
    y0 = y0.copy()
    for _ in range(30):
        sol = solve_ivp(ext, (0, T), np.concatenate([y0, np.eye(4).ravel(order="F")]),
                        method="DOP853", rtol=rtol, atol=1e-12)
        yT = sol.y[:, -1]
        r = yT[:4] - y0
        if np.max(np.abs(r)) < 1e-10 * max(1, np.max(np.abs(y0))):
            break
        Phi = yT[4:].reshape(4, 4, order="F")
        M = np.column_stack([Phi[:, free] - np.eye(4)[:, free], fn(yT[:4])])
        dz = np.linalg.solve(M, -r)
        y0[free] += dz[:-1]
        T += dz[-1]
    return T, np.linalg.eigvals(Phi)


def main() -> None:
    print("1. slow flows of two cubic oscillators in 1:3 internal resonance (N&M 6.6)")
    t1, t2 = kbm_times()
    print(f"  kbm.expansion.coupled.derive_coupled: order 1 {t1:.3f} s, order 2 {t2:.3f} s (exact)")
    py = oscilate_python()
    if py is not None:
        o1 = run_oscilate(py, 1)
        print(f"  OSCILATE 1.0.7 apply_MMS, Ne = 1: {o1}")
        o2 = run_oscilate(py, 2)
        print(f"  OSCILATE 1.0.7 apply_MMS, Ne = 2: {o2}")
        if o1.endswith(" s") and not o1.startswith(("failed", "did")):
            s1 = float(o1.split()[0])
            print(f"  ratio OSCILATE order 1 / kbm order 2: {s1 / t2:.0f}x (target >= 10: "
                  f"{s1 / t2 >= 10})")

    print("2. a true cycle of coupled-vdp (mu = 0.05, c = 0.3, sigma = 0.1), 4 multipliers")
    values = {"mu": 0.05, "c": 0.3, "sigma": 0.1}
    ref = coupled_cycle("coupled-vdp", values)  # warm: compiled flow loaded
    fl = coupled_flow("coupled-vdp", values)
    y = fl.states(np.ones(4) * [1, 1, 0, 0], 400.0, 1)[-1]
    from numerics.shooting.coupled_orbit import section_start
    y0, T0 = section_start(fl, y, 6 * 2 * np.pi)
    reps = 20
    t0 = time.perf_counter()
    for _ in range(reps):
        ours = coupled_cycle("coupled-vdp", values, start=y0, transient=0, period=T0)
    t_ours = (time.perf_counter() - t0) / reps
    t0 = time.perf_counter()
    T_sc, m_sc = scipy_cycle(y0, T0, values)
    t_sc = time.perf_counter() - t0
    diff = abs(T_sc - ours.period)
    dm = np.max(np.abs(np.sort(np.abs(m_sc)) - np.sort(np.abs(ours.floquet_multipliers))))
    print(f"  kbm (compiled DOP853 + variational equations): {t_ours * 1e3:.1f} ms per cycle")
    print(f"  scipy solve_ivp DOP853, the same Newton:        {t_sc * 1e3:.1f} ms per cycle")
    print(f"  ratio: {t_sc / t_ours:.0f}x (target >= 10: {t_sc / t_ours >= 10}); periods differ "
          f"by {diff:.1e}, multiplier moduli by {dm:.1e}; T = {ref.period:.12f}")


if __name__ == "__main__":
    main()
