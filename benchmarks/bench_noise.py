"""Time the Langevin integrators of numerics.noise against fair baselines, in the same run.

Run: ``python benchmarks/bench_noise.py [effort [seed [parts]]]`` (effort 1 by default: about
two minutes on one core; the standard errors of part 2 fall like ``1/sqrt(effort)``; ``seed``
the root seed of part 2d, 17 by default; ``parts`` "12" by default, "1" or "2" for one; "3"
for part 3, about 15 minutes at effort 3 on a loaded machine; "4" for part 4).

1. **Raw step rate** on the CDC at rest (paper eq. 12 with noise: ``x'' + mu x' + Delta
   sin(2 pi x) + x = sqrt(2 D) xi``, mu = 0.1, Delta = 3, D = 0.1, kT = 1), one core, warm:
   the toolkit's kernels (BAOAB, one force evaluation per step, and Kloeden-Platen, two)
   against hand-written numba loops that use **the same generator** (the toolkit's
   xoshiro256** and three-point increments, called from the hand loop): a BAOAB loop
   with the force carried over and an Euler-Maruyama loop.  Target: toolkit BAOAB >= 1x
   the fastest hand BAOAB loop.  The hand BAOAB loop is timed one trajectory a loop as
   first written and 1, 2, 3, 4 and 6 trajectories a loop with the O part's noise factor
   folded into the increments (what a competent hand loop does: independent chains fill
   the core), lane by lane, and 2 and 3 a loop "in parts", in the order the toolkit's loop
   now runs a step (B, A, O, A of every lane, then every lane's force, then every lane's
   last B: :data:`numerics.noise.lanes._PHASES`); the toolkit's ``final_states`` runs the
   lanes its code generator chose (:func:`numerics.noise.lanes.lane_count`: 3 for a force
   with one ``sin``).  All end in the same states to the bit.  The BAOAB loops are timed
   in 41 interleaved rounds (the order reversed every other round), by CPU time of the
   thread (the machine is shared: the wall clock counts the time others hold the core) and
   by the wall clock; the ratios are the medians of the rounds' ratios, with their
   quartiles.  Each scheme's ``<x^2>`` at the timed step is printed against Boltzmann's
   (exact by quadrature), so that no rate is quoted for a wrong answer.  Measured (effort
   1, load 7.4-9.1 on 2 cores, three runs; CPU time, M steps/s medians, toolkit / it)::

       toolkit BAOAB (3 a loop)                56.1  56.3  56.6
       hand, 1 a loop                          33.5  33.6  33.7   1.68  1.68  1.68
       hand, 2 a loop, folded                  53.3  53.6  53.9   1.05  1.05  1.05
       hand, 3 a loop, folded                  51.3  51.6  51.9   1.09  1.09  1.09
       hand, 4 a loop, folded                  50.2  50.3  50.5   1.12  1.12  1.12
       hand, 6 a loop, folded                  49.7  49.9  50.1   1.13  1.13  1.13
       hand, 2 a loop, folded, in parts        54.0  54.4  54.6   1.04  1.03  1.04
       hand, 3 a loop, folded, in parts        56.7  57.0  57.3   0.99  0.99  0.99

   The toolkit is 1.05x the fastest hand loop written lane by lane (quartiles 1.05-1.06;
   before its loop ran in parts: 0.94x, 51 M steps/s) and at parity with a hand loop
   written in its own order: the same instructions but one ``vmulsd`` for a ``vxorpd`` per
   lane (``-Omega^2 x`` for ``-x``) and two more moves, 153 a three-lane iteration
   against 151; the last 1 % is not that multiplication (the force printed as ``-x`` ran
   as fast) and moved by 1.5 % between other orders of the same parts; a hand loop's rate
   moved by up to 10 % between runs (compilations): the hand loop 3 a loop in parts at
   51.3 in a fourth run (load 6.1).
2. **Force evaluations for equal weak error** on ``x'' + x = -x' - x^3 + sqrt(2 D) xi``
   (linear damping, quartic potential, D = kT = 1; ``<x^2>`` exact by quadrature of
   ``exp(-(x^2/2 + x^4/4)/kT)``).  The weak errors are exact, not sampled: BAOAB's own
   stationary density (Gaussian increments) is the fixed point of its transfer operator
   (:mod:`numerics.noise.invariant`), so its error at each step is resolved to 1e-8 where an
   ensemble resolves 1e-3.  Measured: BAOAB's order (2) and its expansion in even powers
   (the ``h^3`` coefficient vanishes), the order of the Richardson pair
   ``(4 E_{h/2} - E_h)/3`` (4; Talay & Tubaro 1990), and the step giving an error of 1e-4
   for BAOAB (Leimkuhler & Matthews, Appl. Math. Res. Express 2013, 34; 1 force evaluation
   per step), the pair (3 per coarse step) and the two-level estimator: BAOAB at the pair's
   step plus the pair's correction ``(4/3)(E_{h/2} - E_h)`` from a shorter coupled run, with
   Giles' optimal allocation (cost factor ``(1 + sqrt(16 rho/3))^2`` per step, ``rho`` the
   measured variance ratio of the pair's difference to ``E_h``).  In the same run the
   toolkit's pair ensemble (:func:`numerics.noise.extrapolate.richardson_moments`) is checked
   against the transfer operator and exact quadrature, and the toolkit's own two-level
   estimator (:func:`numerics.noise.extrapolate.two_level_moments`, what ``kbm noise
   --extrapolate`` runs) is timed against the toolkit's BAOAB kernel (Gaussian increments)
   at the steps of a 1e-4 bias, compared by work x variance, with both couplings of the
   correction: the synchronous pair and the antithetic triple (the default; Giles & Szpruch
   2014: a second fine run with each coarse step's two increments swapped, five force
   evaluations per coarse step).  Target: >= 3x fewer force evaluations than BAOAB where the
   pair applies (BAOAB's even expansion: dampings affine in ``x'``, Gaussian increments, a
   smooth potential).  Part e measures the ``h^2`` coefficient of the bias with the
   stationary runs' four-point increments and the three-point ones against the transfer
   operator's Gaussian value (what the step pilot measures).
3. **The increments of first passages and friction runs** (:func:`increments_of_passages`):
   three-point, four-point and Gaussian, against the exact Kramers-equation escape rate and
   the exact power balance of a pulled slider, at the default steps and larger ones.
4. **The event kernels** (:func:`events`, parts "4", about a minute): ``first_passages``
   and ``slip_stats`` in their lanes against hand BAOAB loops on the same generator, one
   and two trajectories a loop, the same times and records.
"""

from __future__ import annotations

import math
import os
import sys
import time

import numpy as np
from numba import njit
from scipy.integrate import quad

from kbm.model.builtins import custom_model
from numerics.noise import langevin_system
from numerics.noise.seeds import trajectory_states

MU, DELTA, D = 0.1, 3.0, 0.1
K = 2 * math.pi


def _boltzmann_x2(G, kT: float) -> float:
    def w(x):
        return math.exp(-G(x) / kT)

    opts = dict(epsabs=0, epsrel=1e-12, limit=400)
    return quad(lambda x: x * x * w(x), -30, 30, **opts)[0] / quad(w, -30, 30, **opts)[0]


def _hand_loops(inc):
    """Hand-written loops on the CDC at rest calling the toolkit's generator ``inc``: the
    final states (for the rate) and the time average of ``x^2`` (for the answer)."""

    @njit(cache=False)
    def baoab(states, n, h, sigma, mu, delta, k, average):
        out = np.empty((states.shape[0], 2))
        r3 = math.sqrt(3.0 * h)
        e = math.exp(-mu * h)
        c = math.sqrt((1.0 - e * e) / (2.0 * mu * h))
        for i in range(states.shape[0]):
            s = states[i].copy()
            x, v = 0.0, 0.0
            f = -x - delta * math.sin(k * x)
            sx = 0.0
            for _ in range(n):
                v += 0.5 * h * f
                x += 0.5 * h * v
                v = e * v + c * sigma * inc(s, r3)
                x += 0.5 * h * v
                f = -x - delta * math.sin(k * x)
                v += 0.5 * h * f
                if average:
                    sx += x * x
            out[i, 0], out[i, 1] = (sx / n, 0.0) if average else (x, v)
        return out

    @njit(cache=False)
    def euler(states, n, h, sigma, mu, delta, k, average):
        out = np.empty((states.shape[0], 2))
        r3 = math.sqrt(3.0 * h)
        for i in range(states.shape[0]):
            s = states[i].copy()
            x, v = 0.0, 0.0
            sx = 0.0
            for _ in range(n):
                a = -x - mu * v - delta * math.sin(k * x)
                x, v = x + v * h, v + a * h + sigma * inc(s, r3)
                if average:
                    sx += x * x
            out[i, 0], out[i, 1] = (sx / n, 0.0) if average else (x, v)
        return out

    return baoab, euler


def _hand_lanes(inc, lanes: int, in_parts: bool = False):
    """The hand BAOAB loop written ``lanes`` trajectories a loop (scalar states, each
    trajectory its generator ``inc``, the O part's noise factor folded into the increments'
    amplitude as the toolkit folds it): what a competent hand loop does to fill the core;
    the number of trajectories must be a multiple of ``lanes``.  Lane by lane, or
    ``in_parts`` as the toolkit's loop runs a step (:data:`numerics.noise.lanes._PHASES`):
    B, A, O, A of every lane, then every lane's force (its ``sin`` call), then every lane's
    last B."""
    src = ["def baoab_lanes(states, n, h, sigma, mu, delta, k):",
           "    out = np.empty((states.shape[0], 2))",
           "    e = math.exp(-mu * h)",
           "    amp = math.sqrt((1.0 - e * e) / (2.0 * mu * h)) * sigma * math.sqrt(3.0 * h)",
           f"    for i in range(0, states.shape[0], {lanes}):"]
    for j in range(lanes):
        src += [f"        s{j} = states[i + {j}].copy()",
                f"        x{j}, v{j} = 0.0, 0.0",
                f"        f{j} = -x{j} - delta * math.sin(k * x{j})"]
    src += ["        for _ in range(n):"]
    step = [("v{j} += 0.5 * h * f{j}", "x{j} += 0.5 * h * v{j}", "v{j} = e * v{j} + inc(s{j}, amp)",
             "x{j} += 0.5 * h * v{j}"), ("f{j} = -x{j} - delta * math.sin(k * x{j})",),
            ("v{j} += 0.5 * h * f{j}",)]
    for part in (step if in_parts else [sum(step, ())]):
        src += ["            " + line.format(j=j) for j in range(lanes) for line in part]
    src += [f"        out[i + {j}, 0], out[i + {j}, 1] = x{j}, v{j}" for j in range(lanes)]
    src += ["    return out"]
    space = {"np": np, "math": math, "inc": inc}
    exec("\n".join(src), space)  # noqa: S102 - the benchmark's own text
    return njit(cache=False)(space["baoab_lanes"])


def _best_rate(fn, steps: int, repeats: int = 3) -> float:
    """Steps per second of ``fn()``, the best of ``repeats`` (the machine is shared)."""
    best = math.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return steps / best


def _rounds(fns: dict, rounds: int = 11) -> tuple[dict, dict]:
    """Wall-clock and CPU (thread) seconds of each ``fns[name]()``, the functions timed in
    turn, ``rounds`` times each, the order reversed every other round (who goes first
    alternates; the machine is shared)."""
    names = list(fns)
    wall = {n: [] for n in names}
    cpu = {n: [] for n in names}
    for rep in range(rounds):
        for name in (names if rep % 2 == 0 else names[::-1]):
            t0, c0 = time.perf_counter(), time.thread_time()
            fns[name]()
            cpu[name].append(time.thread_time() - c0)
            wall[name].append(time.perf_counter() - t0)
    return ({n: np.array(v) for n, v in wall.items()}, {n: np.array(v) for n, v in cpu.items()})


def rates() -> None:
    params = {"mu": MU, "Delta": DELTA, "lam": 1, "Omega": 1}
    exact = _boltzmann_x2(lambda x: x * x / 2 + DELTA / K * (1 - math.cos(K * x)), D / MU)
    sig = math.sqrt(2 * D)
    m, t_rate, t_answer = 24, 2000.0, 20000.0  # 24: whole loops of 1, 2, 3, 4, 6 lanes
    st = trajectory_states(1, 0, m)
    y0 = np.zeros((m, 2))
    kits = {sch: langevin_system("cdc", params, D, sch) for sch in ("baoab", "kp")}
    inc = kits["baoab"].kernels._increment
    hand_baoab, hand_euler = _hand_loops(inc)
    lanes = kits["baoab"].kernels.LANES
    print("1. raw step rate on the CDC at rest (one core, warm; the BAOAB loops below best and "
          f"median of 41 interleaved rounds); Boltzmann <x^2> = {exact:.5f} (kT = 1); load "
          "average {:.2f} {:.2f} {:.2f} on {} cores".format(*os.getloadavg(), os.cpu_count()))
    rows = []
    for name, h in (("toolkit baoab", 0.01), ("toolkit kp", 0.005), ("hand BAOAB", 0.01),
                    ("hand Euler-Maruyama", 0.0005)):
        n, n_ans = round(t_rate / h), round(t_answer / h)
        if name.startswith("toolkit"):
            s = kits[name.split()[1]]
            k, p = s.kernels, s._p()
            k.final_states(p, s.sigma, y0[:7], 0.0, h, 10, st[:7])
            rate = _best_rate(lambda: k.final_states(p, s.sigma, y0, 0.0, h, n, st), m * n)
            if name == "toolkit baoab":
                kit_final = k.final_states(p, s.sigma, y0, 0.0, h, n, st)
            sums, _ = k.stationary_stats(p, s.sigma, y0, 0.0, h, 0, n_ans, st, s.omega0, 1,
                                         -5.0, 5.0, 4)
            x2 = sums[:, 0]
        else:
            fn = hand_baoab if name == "hand BAOAB" else hand_euler
            fn(st[:2], 10, h, sig, MU, DELTA, K, False)
            rate = _best_rate(lambda: fn(st, n, h, sig, MU, DELTA, K, False), m * n)
            if name == "hand BAOAB":
                same = float(np.max(np.abs(fn(st, n, h, sig, MU, DELTA, K, False) - kit_final)))
            x2 = fn(st, n_ans, h, sig, MU, DELTA, K, True)[:, 0]
        rows.append((name, h, rate, x2.mean(), x2.std(ddof=1) / math.sqrt(m)))
    s = kits["baoab"]
    k, p, h = s.kernels, s._p(), 0.01
    n_cmp, n = round(t_rate / h), round(500.0 / h)  # short timed runs, many rounds
    fns = {f"toolkit BAOAB ({lanes} a loop)":
           lambda: k.final_states(p, s.sigma, y0, 0.0, h, n, st),
           "hand BAOAB, 1 a loop": lambda: hand_baoab(st, n, h, sig, MU, DELTA, K, False)}
    diffs = []
    for w, parts in ((1, False), (2, False), (3, False), (4, False), (6, False), (2, True),
                     (3, True)):
        fn = _hand_lanes(inc, w, parts)
        fn(st[:w], 10, h, sig, MU, DELTA, K)
        diffs.append(float(np.max(np.abs(fn(st, n_cmp, h, sig, MU, DELTA, K) - kit_final))))
        fns[f"hand BAOAB, {w} a loop, folded{', in parts' if parts else ''}"] = (
            lambda fn=fn: fn(st, n, h, sig, MU, DELTA, K))
    wall, cpu = _rounds(fns, 41)
    tool = next(iter(fns))
    print(f"   {'scheme':22} {'h':>7} {'M steps/s':>10} {'<x^2>':>9}  (<x^2> - exact)/exact")
    for name, hr, rate, x2, se in rows:
        print(f"   {name:22} {hr:7.4g} {rate / 1e6:10.2f} {x2:9.5f}  {x2 / exact - 1:+.2e} "
              f"+- {se / exact:.0e}")
    print("   (wall clock, best of 3; the BAOAB loops in interleaved rounds below)")
    print(f"   the toolkit's BAOAB and every hand BAOAB loop end in the same states (largest "
          f"difference {max([same, *diffs]):g}); the hand loops call the toolkit's generator "
          "(xoshiro256**, three-point increments); 'folded': the O part's noise factor in the "
          "increments' amplitude, as the toolkit folds it")
    print(f"   {'BAOAB loop, 24 trajectories':34} {'M steps/s:':>10} {'CPU best':>8} "
          f"{'median':>7} {'wall best':>9} {'median':>7}   toolkit / it: CPU median "
          "(quartiles), wall median")
    for name in fns:
        rc = m * n / cpu[name] / 1e6
        rw = m * n / wall[name] / 1e6
        q = np.percentile(cpu[name] / cpu[tool], [25, 50, 75])
        print(f"   {name:34} {'':10} {rc.max():8.2f} {float(np.median(rc)):7.2f} "
              f"{rw.max():9.2f} {float(np.median(rw)):7.2f}   {'':14}{q[1]:5.2f} "
              f"({q[0]:.2f}-{q[2]:.2f}), {float(np.median(wall[name] / wall[tool])):.2f}")
    for which, hands in (("", [name for name in fns if name != tool]),
                         (" written lane by lane", [name for name in fns if name != tool
                                                    and not name.endswith("in parts")])):
        best = min(hands, key=lambda name: float(np.median(cpu[name])))
        q = np.percentile(cpu[best] / cpu[tool], [25, 50, 75])
        print(f"   the fastest hand loop{which} (median CPU time): {best}; toolkit / it (target "
              f">= 1) = {q[1]:.2f} median of the 41 rounds' ratios (quartiles {q[0]:.2f}-"
              f"{q[2]:.2f}), {cpu[best].min() / cpu[tool].min():.2f} best against best (CPU "
              f"time); wall clock {float(np.median(wall[best] / wall[tool])):.2f} median, "
              f"{wall[best].min() / wall[tool].min():.2f} best against best")
    q = np.percentile(cpu["hand BAOAB, 1 a loop"] / cpu[tool], [25, 50, 75])
    print(f"   ratio toolkit BAOAB / hand BAOAB one a loop as first written (same generator) = "
          f"{q[1]:.2f} median (quartiles {q[0]:.2f}-{q[2]:.2f}, CPU time)")
    print(f"   ratio toolkit KP / hand Euler-Maruyama, per step = {rows[1][2] / rows[3][2]:.2f} "
          "(Euler-Maruyama needs a 20x smaller step)")
    took = [[], []]
    for rep in range(7):
        for j in ((0, 1) if rep % 2 == 0 else (1, 0)):
            fn = (k.stationary_stats, k.stationary_stats4)[j]
            t0 = time.thread_time()
            fn(p, s.sigma, y0, 0.0, h, 0, n, st, s.omega0, 0, 0.0, 4.0, 40)
            took[j].append(time.thread_time() - t0)
    print(f"   the stationary run's kernel (four-point increments) / the three-point kernel (the "
          f"same loop, two trajectories a loop): time x"
          f"{float(np.median(took[1]) / np.median(took[0])):.2f} (medians of 7 interleaved, "
          "CPU time)")


def _crossing(hs, errs, target: float) -> float:
    """The step where ``|err|`` reaches ``target``, log-log interpolated between the points
    that bracket it."""
    la, lb = np.log(hs), np.log(np.abs(errs))
    for k in range(len(hs) - 1):
        if (lb[k] - math.log(target)) * (lb[k + 1] - math.log(target)) <= 0:
            w = (math.log(target) - lb[k]) / (lb[k + 1] - lb[k])
            return float(math.exp(la[k] + w * (la[k + 1] - la[k])))
    raise ValueError("the target error is not bracketed")


def equal_error(effort: float = 1.0, seed: int = 17) -> None:
    from numerics.noise.extrapolate import richardson_moments
    from numerics.noise.invariant import baoab_stationary_averages

    kT, target = 1.0, 1e-4
    exact = _boltzmann_x2(lambda x: x * x / 2 + x**4 / 4, kT)
    print(f"2. force evaluations per unit time for a relative weak error of {target:g} in <x^2> "
          f"of x'' + x = -x' - x^3 + sqrt(2 kT) xi (kT = 1; exact {exact:.10f} by quadrature)")
    print("   a. exact weak errors of BAOAB (Gaussian increments): its stationary density by the "
          "transfer operator (numerics.noise.invariant, 96 x 48 Chebyshev grid)")
    hs = (0.1, 0.15, 0.2, 0.3, 0.4)
    bias = {}
    for h in hs:
        (x2,), res = baoab_stationary_averages(lambda x: -x - x**3, 1.0, math.sqrt(2 * kT), h,
                                               [lambda z: z * z])
        bias[h] = x2 / exact - 1
        print(f"      h = {h:4.2f}: <x^2>_h = {x2:.10f}, error {bias[h]:+.4e} (residual "
              f"{res:.0e})")
    hh = np.array(hs)
    bb = np.array([bias[h] for h in hs])
    c2, c4 = np.linalg.lstsq(np.c_[hh**2, hh**4], bb, rcond=None)[0]
    c3 = np.linalg.lstsq(np.c_[hh**2, hh**3, hh**4], bb, rcond=None)[0][1]
    h_b = float(np.sqrt(target / abs(c2)))
    for _ in range(50):  # |c2 h^2 + c4 h^4| = target
        h_b = math.sqrt(target / abs(c2 + c4 * h_b**2))
    rich = {h: (4 * bias[h / 2] - bias[h]) / 3 for h in (0.2, 0.3, 0.4)}
    p_plain = math.log2(bias[0.2] / bias[0.1])
    p_rich = math.log(rich[0.4] / rich[0.3]) / math.log(4 / 3)
    print(f"      BAOAB error = {c2:+.4e} h^2 {c4:+.4e} h^4 (with an h^3 term: {c3:+.1e}, "
          f"none); measured order {p_plain:.2f} (h = 0.1, 0.2)")
    for h, r in rich.items():
        print(f"      Richardson pair (4 E_h/2 - E_h)/3 at h = {h:.2f}: error {r:+.4e}")
    print(f"      Richardson pair measured order {p_rich:.2f} (h = 0.3, 0.4)")
    h_r = _crossing(np.array([0.2, 0.3, 0.4]), np.array(list(rich.values())), target)
    evals_b, evals_r = 1 / h_b, 3 / h_r
    print("   b. the pair's correction on a shorter run (two-level estimator: BAOAB at h plus "
          "(4/3) (E_h/2 - E_h) from a coupled pair; Giles' optimal allocation): the variance "
          "of the pair's difference, measured by the toolkit's pair kernel")
    s = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, kT, "baoab")
    h_mc = round(h_r, 2)
    m, t_run = 64, round(20000 * effort / h_mc) * h_mc
    mom = richardson_moments(s, h_mc, trajectories=m, t_end=t_run, burn_in=20 * h_mc * 5,
                             seed=13)["x2"]
    var_full = (mom.stderr * math.sqrt(m)) ** 2
    var_diff = (3 * mom.correction_stderr * math.sqrt(m)) ** 2  # of E_h/2 - E_h
    rho = var_diff / var_full
    factor = (1 + math.sqrt(16 * rho / 3)) ** 2
    evals_2 = factor / h_r
    print(f"      at h = {h_mc}: var(E_h/2 - E_h)/var(E_h) = {rho:.4f} ({m} trajectories x "
          f"{t_run:g}); cost factor (1 + sqrt(16 rho/3))^2 = {factor:.3f}")
    from numerics.noise.extrapolate import _antithetic_rows
    n_burn = round(20 * 5)
    anti = _antithetic_rows(s, h_mc, n_burn, round(t_run / h_mc), 13, 0, m)[:, 0] * 0.75
    rho_a = float(anti.var(ddof=1)) / var_full
    factor_a = (1 + math.sqrt(16 * rho_a * 5 / 9)) ** 2
    evals_a = factor_a / h_r
    print(f"      antithetic (fine increments swapped, 5 evaluations per h): var(difference)"
          f"/var(E_h) = {rho_a:.5f}; cost factor (1 + sqrt(80 rho/9))^2 = {factor_a:.3f}")
    print("   c. the toolkit's pair ensemble at the same step (Monte Carlo, Gaussian "
          "increments), against the exact values:")
    se = mom.stderr / exact
    print(f"      E_h   {mom.coarse:.6f}: error {mom.coarse / exact - 1:+.2e} +- {se:.1e} "
          f"(transfer operator: {c2 * h_mc**2 + c4 * h_mc**4:+.2e})")
    print(f"      R(h)  {mom.extrapolated:.6f}: error {mom.extrapolated / exact - 1:+.2e} +- "
          f"{se:.1e} ({(mom.extrapolated - exact) / mom.stderr:+.1f} standard errors from "
          "exact quadrature)")
    print(f"   {'estimator':44} {'step for 1e-4':>13} {'evals/time':>11} {'vs BAOAB':>9}")
    for name, h, ev in (("BAOAB (1 per step)", h_b, evals_b),
                        ("Richardson pair h, h/2 (3 per h)", h_r, evals_r),
                        ("two-level: BAOAB at h + pair correction", h_r, evals_2),
                        ("two-level, antithetic correction", h_r, evals_a)):
        print(f"   {name:44} {h:13.4f} {ev:11.2f} {evals_b / ev:8.2f}x")
    print("   (target: >= 3x fewer force evaluations than BAOAB; the two-level cost counts the "
          "correction run at the allocation that gives the same statistical error)")
    toolkit_two_level(h_b, h_r, exact, effort, seed)
    increments(bias, exact, effort)


def increments(bias: dict, exact: float, effort: float = 1.0) -> None:
    """The ``h^2`` coefficient of BAOAB's bias with the ensembles' increments: the
    four-point Gauss-Hermite ones (the default stationary run) and the three-point ones,
    against the transfer operator's Gaussian value (what the step pilot measures)."""
    s = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, 1.0, "baoab")
    k, p = s.kernels, s._p()
    m = 64
    y0 = np.zeros((m, 2))
    print(f"   e. the h^2 coefficient of the bias of <x^2> by increments ({m} trajectories x "
          f"{round(80000 * effort)} time each; bias/h^2, relative)")
    for h in (0.3, 0.4):
        n = round(80000 * effort / h)
        row = [f"h = {h}: Gaussian (transfer operator) {bias[h] / h**2:+.4f}"]
        for name, fn in (("four-point", k.stationary_stats4), ("three-point", k.stationary_stats)):
            sums, _ = fn(p, s.sigma, y0, 0.0, h, 50, n, trajectory_states(8, 0, m), s.omega0,
                         1, -1.0, 1.0, 1)
            b = sums[:, 0] / exact - 1
            se = b.std(ddof=1) / math.sqrt(m)
            row.append(f"{name} {b.mean() / h**2:+.4f} +- {se / h**2:.4f}")
        print("      " + ", ".join(row))


def toolkit_two_level(h_b: float, h_r: float, exact: float, effort: float = 1.0,
                      seed: int = 17) -> None:
    """The toolkit's own estimator (:func:`numerics.noise.extrapolate.two_level_moments`,
    what ``kbm noise --extrapolate`` runs) at the step ``h_r`` against the toolkit's BAOAB
    kernel (Gaussian increments) at ``h_b``, both with a bias of 1e-4: the same trajectories
    and times, timed on one core, compared by work x variance (the cost of equal
    statistical error)."""
    from numerics.noise.extrapolate import two_level_moments

    s = langevin_system(custom_model("-xdot - x**3", name="quartic"), {"mu": 1.0}, 1.0, "baoab")
    m, t_run, burn = 256, 20.0 * round(250 * effort), 20.0
    hb = h_b
    hr = burn / math.ceil(burn / h_r)  # whole numbers of steps in burn and t_run
    k, p = s.kernels, s._p()
    y0 = np.zeros((m, 2))
    k.step_gauss_stats(p, s.sigma, y0[:2], 0.0, hb, 2, 2, trajectory_states(0, 0, 2), s.omega0)
    for coupling in ("synchronous", "antithetic"):  # compiled
        two_level_moments(s, hr, trajectories=4, t_end=10 * hr, burn_in=0.0, seed=0,
                          coupling=coupling)
    t0 = time.perf_counter()
    n_b, n_run = round(burn / hb), round(t_run / hb)
    rows = k.step_gauss_stats(p, s.sigma, y0, 0.0, hb, n_b, n_run, trajectory_states(seed, 0, m),
                              s.omega0)
    sec_b = time.perf_counter() - t0
    evals_b = m * (n_b + n_run)
    x2 = rows[:, 0]
    val_b, se_b = float(x2.mean()), float(x2.std(ddof=1) / math.sqrt(m))
    print(f"   d. the toolkit's two-level estimator (numerics.noise.extrapolate.two_level_moments"
          f", kbm noise --extrapolate) timed against the toolkit's BAOAB kernel, {m} "
          f"trajectories x {t_run:g} each (one core, warm)")
    print(f"      {'run':36} {'h':>7} {'force evals':>12} {'seconds':>8} {'<x^2> error':>12} "
          f"{'stderr':>8}")
    print(f"      {'BAOAB (Gaussian increments)':36} {hb:7.4f} {evals_b:12.4g} {sec_b:8.2f} "
          f"{val_b / exact - 1:+12.2e} {se_b / exact:8.1e}")
    for coupling in ("synchronous", "antithetic"):
        t0 = time.perf_counter()
        mom, sizes = two_level_moments(s, hr, trajectories=m, t_end=t_run, burn_in=burn,
                                       seed=seed, coupling=coupling)
        sec_2 = time.perf_counter() - t0
        two = mom["x2"]
        name = f"{coupling} ({sizes['coarse']} + {sizes['correction']} correction)"
        print(f"      {name:36} {hr:7.4f} {sizes['steps']:12.4g} "
              f"{sec_2:8.2f} {two.value / exact - 1:+12.2e} {two.stderr / exact:8.1e}  "
              f"({(two.value - exact) / two.stderr:+.1f} s.e. from exact)")
        ev = evals_b * se_b**2 / (sizes["steps"] * two.stderr**2)
        wall = sec_b * se_b**2 / (sec_2 * two.stderr**2)
        print(f"      BAOAB / two-level {coupling} at equal statistical error (work x "
              f"variance): force evaluations {ev:.2f}x, seconds {wall:.2f}x (each variance to "
              f"+-{200 / math.sqrt(m):.0f} %; the variance ratio of the correction "
              f"{two.variance_ratio:.4f})")

#: measurement kernels of part 3 (not the toolkit's: appended to the model's generated module
#: here, so that no unused kernel is compiled with every model): first passages and a pulled
#: slider's power balance with the three-point (law 3), four-point (4) or Gaussian (0)
#: increments, drawn as the toolkit's kernels draw them
_LAWS = """

@njit(cache=True)
def _dw(s, law, k, g2, amp, amp3):
    if law == 3:
        return _increment(s, amp3), g2
    if law == 4:
        return _increment4(s, amp), g2
    if k % 2 == 0:
        g1, g2 = _normal_pair(s)
        return amp * g1, g2
    return amp * g2, g2


@njit(cache=True)
def passages_law(p, sigma, h, n_max, xl, xr, states, law):
    m = states.shape[0]
    times = np.full(m, n_max * h)
    hit = np.zeros(m, dtype=np.bool_)
    amp = sigma * _noise_factor(p, h) * math.sqrt(h)
    amp3 = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)
    for i in range(m):
        s = states[i].copy()
        x, v, g2 = 0.0, 0.0, 0.0
        f = _first(0.0, x, v, p)
        for k in range(n_max):
            dw, g2 = _dw(s, law, k, g2, amp, amp3)
            x, v, f = _step(k * h, x, v, f, h, dw, p)
            if x <= xl or x >= xr or not math.isfinite(x):
                times[i], hit[i] = (k + 1) * h, True
                break
    return times, hit


@njit(cache=True)
def slider_power_law(p, sigma, h, n_burn, n_run, states, law):
    # per trajectory: <F_spring>, <x'^2>, (E_end - E_start)/T with the CDC slider's
    # E = x'^2/2 - mu delta/k cos(k x) + Omega^2 (x - v t)^2/2 (p = Omega, delta, k, mu, v)
    m = states.shape[0]
    out = np.zeros((m, 3))
    amp = sigma * _noise_factor(p, h) * math.sqrt(h)
    amp3 = sigma * _noise_factor(p, h) * math.sqrt(3.0 * h)
    for i in range(m):
        s = states[i].copy()
        x, v, g2, e0, af, av = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
        f = _first(0.0, x, v, p)
        for k in range(n_burn + n_run):
            if k == n_burn:
                e0 = (0.5 * v * v - p[3] * p[1] / p[2] * math.cos(p[2] * x)
                      + 0.5 * p[0] ** 2 * (x - p[4] * k * h) ** 2)
            dw, g2 = _dw(s, law, k, g2, amp, amp3)
            x, v, f = _step(k * h, x, v, f, h, dw, p)
            if k >= n_burn:
                af += spring((k + 1) * h, x, v, p)
                av += v * v
        e1 = (0.5 * v * v - p[3] * p[1] / p[2] * math.cos(p[2] * x)
              + 0.5 * p[0] ** 2 * (x - p[4] * (n_burn + n_run) * h) ** 2)
        out[i, 0], out[i, 1], out[i, 2] = af / n_run, av / n_run, (e1 - e0) / (n_run * h)
    return out
"""

_LAW_NAMES = {3: "three-point", 4: "four-point", 0: "Gaussian"}


def increments_of_passages(effort: float = 1.0) -> None:
    """Part 3: do first passages and the friction runs gain from four-point (or Gaussian)
    increments?  The escape rate of the CDC at rest (Delta = 2, lam = 1.3, kT = 0.15,
    mu = 0.2: E_b/kT = 7.09) from first passages to the next wells' bottoms against the
    exact rate of the Kramers equation (``kbm escape --method fokker-planck``: 4.5110e-4,
    converged to 1e-3), at the default step of ``kbm escape`` and at 2x and 4x it; one
    friction point (the CDC slider, mu = 1, Delta = 3, v = 0.1, D = 0.02) against the exact
    power balance of the continuous system, ``v <F> = mu <x'^2> - D + dE/dt`` (Ito's
    formula for ``E = x'^2/2 + G(x) + Omega^2 (x - v t)^2/2``), at the friction runs'
    step and 4x it.  Kloeden-Platen, as both run."""
    from numerics.escape.simulate import censored_rate
    from numerics.flow.numba_cache import _load
    from numerics.noise.langevin import natural_step

    fp_rate, xw = 4.5110e-4, 1.17063
    print("3. increments of first passages and friction runs (Kloeden-Platen)")
    mu = 0.2
    s = langevin_system("cdc", {"Delta": 2, "lam": 1.3, "Omega": 1, "mu": mu}, 0.15 * mu)
    mod = _load(open(s.kernels.__file__).read() + _LAWS)
    h0 = natural_step(s, per_period=40)
    n_max = math.ceil(200.0 / 3e-4 / h0)
    m = round(1000 * effort)
    print(f"   a. escape rate, first passages to +-x_w = +-{xw} from the well bottom, {m} "
          f"trajectories per row; exact (Kramers equation) {fp_rate:.4e}")
    for fac, laws in ((4, (3, 4, 0)), (2, (3, 4, 0)), (1, (3, 4))):
        h = h0 * fac
        for law in laws:
            t, hit = mod.passages_law(s._p(), s.sigma, h, math.ceil(n_max / fac), -xw, xw,
                                      trajectory_states(101 + law, 0, m), law)
            r, se = censored_rate(t, hit)
            print(f"      h = {h:.5f} ({fac}x default) {_LAW_NAMES[law]:12} {r:.4e} +- {se:.1e}"
                  f"  {r / fp_rate - 1:+.2%} ({(r - fp_rate) / se:+.1f} s.e.)")
    mu, v, D = 1.0, 0.1, 0.02
    s = langevin_system("cdc", {"mu": mu, "Delta": 3, "lam": 1, "Omega": 1, "v": v}, D)
    mod = _load(open(s.kernels.__file__).read() + _LAWS)
    h0 = natural_step(s, per_period=160)
    print(f"   b. friction point mu = {mu:g}, Delta = 3, v = {v:g}, D = {D:g}: mean spring force "
          "and the power balance's residual v<F> - mu<x'^2> + D - dE/T (exact: 0)")
    for fac, laws, m in ((4, (3, 4, 0), round(1024 * effort / 3)),
                         (1, (3, 4), round(512 * effort / 3))):
        h = h0 * fac
        for law in laws:
            r = mod.slider_power_law(s._p(), s.sigma, h, round(50 / h), round(1000 / h),
                                     trajectory_states(7 + law, 0, m), law)
            res = v * r[:, 0] - (mu * r[:, 1] - D) - r[:, 2]
            se_f = r[:, 0].std(ddof=1) / math.sqrt(m)
            se_r = res.std(ddof=1) / math.sqrt(m)
            print(f"      h = {h:.5f} ({fac}x default) {_LAW_NAMES[law]:12} {m} trajectories: "
                  f"<F> = {r[:, 0].mean():.5f} +- {se_f:.5f}, residual {res.mean():+.2e} +- "
                  f"{se_r:.1e} ({res.mean() / se_r:+.1f} s.e.)")


def _kick_drift(j: int, force: str) -> list[str]:
    """A hand BAOAB step of lane ``j`` (noise factor folded), ``force`` in ``x{j}``."""
    return [f"            v{j} += 0.5 * h * f{j}", f"            x{j} += 0.5 * h * v{j}",
            f"            v{j} = e * v{j} + inc(s{j}, amp)", f"            x{j} += 0.5 * h * v{j}",
            f"            f{j} = " + force.format(j=j), f"            v{j} += 0.5 * h * f{j}"]


def _hand_events(inc, lanes: int):
    """Hand BAOAB loops (the O part's noise factor folded in, the toolkit's generator
    ``inc``), ``lanes`` trajectories a loop: first passages of the CDC at rest (a loop runs
    until all its trajectories have left: a pair written out by hand) and the pulled CDC
    slider's records (mean spring force, slips and their slip force, backward jumps, in
    scalars).  The force and the times in the toolkit's order of operations, so that the
    paths are the toolkit's (a rounding of a time apart, a slider's path soon is another)."""
    js = range(lanes)
    src = ["def passages(states, n_max, h, amp, e, c, k, xl, xr):",
           "    m = states.shape[0]",
           "    times = np.full(m, n_max * h)",
           "    hit = np.zeros(m, dtype=np.bool_)",
           f"    for i in range(0, m, {lanes}):"]
    for j in js:
        src += [f"        r{j} = min(i + {j}, m - 1)", f"        s{j} = states[r{j}].copy()",
                f"        x{j}, v{j}, a{j} = 0.0, 0.0, True",
                f"        f{j} = -x{j} - c * math.sin(k * x{j})"]
    src += ["        for n in range(n_max):"]
    for j in js:
        src += _kick_drift(j, "-x{j} - c * math.sin(k * x{j})")
    for j in js:
        src += [f"            if a{j} and (x{j} <= xl or x{j} >= xr):",
                f"                a{j} = False",
                f"                times[r{j}], hit[r{j}] = (n + 1) * h, True"]
    src += ["            if not (" + " or ".join(f"a{j}" for j in js) + "):",
            "                break",
            "    return times, hit", "",
            "def slider(states, n_burn, n_run, h, amp, e, c, k, w0, vs, lam, gap):",
            "    m = states.shape[0]", "    out = np.zeros((m, 5))", "    t1 = n_burn * h",
            f"    for i in range(0, m, {lanes}):"]
    for j in js:
        src += [f"        r{j} = min(i + {j}, m - 1)", f"        s{j} = states[r{j}].copy()",
                f"        x{j}, v{j} = 0.0, 0.0",
                f"        f{j} = -c * math.sin(k * x{j}) - w0 * x{j}"]
    src += ["        for n in range(n_burn + n_run):",  # the times as the toolkit forms them
            "            t = n * h if n < n_burn else (t1 + (n - n_burn + 1) * h) - h"]
    for j in js:
        src += _kick_drift(j, "-c * math.sin(k * x{j}) + vs * (t + h) * w0 - w0 * x{j}")
    src += ["            if n == n_burn - 1:"]
    for j in js:
        src += [f"                wl{j} = math.floor(x{j} / lam + 0.5)",
                f"                tl{j}, top{j} = -1e300, -1e300",
                f"                sf{j}, sl{j}, fs{j}, fs2{j}, bk{j} = 0.0, 0.0, 0.0, 0.0, 0.0",
                f"                f{j} = -c * math.sin(k * x{j}) + vs * t1 * w0 - w0 * x{j}"]
    src += ["            if n >= n_burn:", "                t = t1 + (n - n_burn + 1) * h"]
    for j in js:
        src += [f"                g{j} = vs * t * w0 - w0 * x{j}", f"                sf{j} += g{j}",
                f"                top{j} = max(top{j}, g{j})",
                f"                u{j} = math.floor(x{j} / lam + 0.5)",
                f"                if u{j} != wl{j}:",
                f"                    if t - tl{j} > gap and u{j} > wl{j}:",
                f"                        sl{j} += 1.0", f"                        fs{j} += top{j}",
                f"                        fs2{j} += top{j} * top{j}",
                f"                    elif t - tl{j} > gap:",
                f"                        bk{j} += 1.0",
                f"                    tl{j}, top{j} = t, g{j}", f"                wl{j} = u{j}"]
    for j in js:
        src += [f"        out[r{j}, 0], out[r{j}, 1], out[r{j}, 2] = sf{j} / n_run, sl{j}, fs{j}",
                f"        out[r{j}, 3], out[r{j}, 4] = fs2{j}, bk{j}"]
    src += ["    return out"]
    space = {"np": np, "math": math, "inc": inc}
    exec("\n".join(src), space)  # noqa: S102 - the benchmark's own text
    return njit(cache=False)(space["passages"]), njit(cache=False)(space["slider"])


def events(effort: float = 1.0) -> None:
    """Part 4: the event kernels' steps per second (CPU time of the thread, 21 interleaved
    rounds, medians) against hand BAOAB loops on the same generator, one and two
    trajectories a loop (:func:`_hand_events`).  First passages: the CDC at rest (mu =
    0.2, Delta = 3, D = 0.1; the step and lines of ``kbm escape cdc -p mu=0.2 -p Delta=3``),
    200 trajectories in tasks of 13 as ``kbm escape`` cuts them; the toolkit's
    ``first_passages`` runs ``EVENT_LANES`` a loop, a lane taking the next trajectory when
    its own leaves.  Records: the CDC slider (mu = 1, Delta = 3, v = 1e-3, T = 0.01, the
    step of ``kbm friction cdc``; a burn-in of 50 for 50/v), 10 trajectories (a block of
    ``kbm friction``)."""
    from numerics.thermal.friction import _times

    print("4. event kernels against hand BAOAB loops (same generator, noise factor folded); "
          "load average {:.2f} {:.2f} {:.2f} on {} cores".format(*os.getloadavg(),
                                                                  os.cpu_count()))
    s = langevin_system("cdc", {"mu": 0.2, "Delta": 3, "lam": 1, "Omega": 1}, 0.1, "baoab")
    k, p = s.kernels, s._p()
    h, xs = 0.012662791779414857, 0.5281669331486846
    n_max, m, per = round(200 * effort / h), 200, 13
    st, y0 = trajectory_states(0, 0, m), np.zeros((m, 2))
    amp = s.sigma * k._noise_factor(p, h) * math.sqrt(3.0 * h)
    e, c = math.exp(-p[3] * h), p[1] * p[3]
    hands = {w: _hand_events(k._increment, w) for w in (1, 2)}

    def tasks(fn):
        out = [fn(i) for i in range(0, m, per)]
        return np.concatenate([o[0] for o in out]), np.concatenate([o[1] for o in out])

    fns = {f"toolkit first_passages ({k.EVENT_LANES} lanes)": lambda: tasks(
        lambda i: k.first_passages(p, s.sigma, y0[i:i + per], 0.0, h, n_max, -xs, xs,
                                   st[i:i + per]))}
    for w, (hp, _) in hands.items():
        fns[f"hand, {w} a loop"] = lambda hp=hp: tasks(
            lambda i: hp(st[i:i + per], n_max, h, amp, e, c, p[2], -xs, xs))
    ref = next(iter(fns.values()))()
    same = all(np.array_equal(f()[0], ref[0]) for f in fns.values())
    steps = float(np.sum(np.round(ref[0] / h)))
    _event_table(fns, steps, f"   a. first passages, {m} trajectories, {steps:.3g} steps (all "
                 f"loops give the same times: {same})")
    v, T = 1e-3, 0.01
    s = langevin_system("cdc", {"mu": 1.0, "Delta": 3, "lam": 1, "Omega": 1, "v": v}, T,
                        "baoab")
    k, p = s.kernels, s._p()
    run, _, h = _times(s, v, 1.0, 0.2 * effort)
    nb, nr, m = round(50 / h), round(run / h), 10
    st, y0 = trajectory_states(0, 0, m), np.zeros((m, 2))
    amp = s.sigma * k._noise_factor(p, h) * math.sqrt(3.0 * h)
    e, c, w0 = math.exp(-p[3] * h), p[1] * p[3], p[0] ** 2
    fns = {f"toolkit slip_stats ({k.EVENT_LANES} lanes)": lambda: k.slip_stats(
        p, s.sigma, y0, 0.0, h, nb, nr, st, 1.0, 2 * math.pi, v)}
    for w, (_, hs) in hands.items():
        fns[f"hand, {w} a loop"] = lambda hs=hs: hs(st, nb, nr, h, amp, e, c, p[2], w0, v,
                                                    1.0, 2 * math.pi)
    rows = [f() for f in fns.values()]
    diff = max(float(np.max(np.abs(r[:, 0] - rows[0][:, 0]) / np.abs(rows[0][:, 0])))
               for r in rows[1:])
    slips = all(np.array_equal(r[:, 1], rows[0][:, 1]) for r in rows[1:])
    _event_table(fns, m * (nb + nr), f"   b. the slider's records, {m} trajectories x {nb} + "
                 f"{nr} steps (the same slips: {slips}; mean forces within {diff:.0e})")


def _event_table(fns: dict, steps: float, title: str) -> None:
    """``fns`` timed in 21 interleaved rounds (CPU time): M steps/s and toolkit / it."""
    _, cpu = _rounds(fns, 21)
    print(f"{title}; M steps/s, CPU median (toolkit / it):")
    tool = next(iter(fns))
    for name in fns:
        q = np.percentile(cpu[name] / cpu[tool], [25, 50, 75])
        print(f"      {name:40} {steps / np.median(cpu[name]) / 1e6:7.2f}   {q[1]:.2f} "
              f"({q[0]:.2f}-{q[2]:.2f})")


if __name__ == "__main__":
    eff = float(sys.argv[1]) if len(sys.argv) > 1 else 1.0
    root = int(sys.argv[2]) if len(sys.argv) > 2 else 17
    parts = sys.argv[3] if len(sys.argv) > 3 else "12"
    if "1" in parts:
        rates()
    if "2" in parts:
        equal_error(eff, root)
    if "3" in parts:
        increments_of_passages(eff)
    if "4" in parts:
        events(eff)
