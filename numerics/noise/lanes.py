"""The kernels' loops over several trajectories at once, printed for a model.

A Langevin step is a chain of dependent operations (the kick waits for the force at the
new ``x``, the next position for the kick), so one trajectory a loop leaves the core mostly
idle; ``lanes`` independent trajectories in one loop body fill it.  numba has no register
arrays, so the loops of ``final_states``, ``first_passages`` and ``slip_stats`` are written
out lane by lane as source (:func:`lanes_source`; one line template per lane,
:func:`_each`; the steps of ``final_states`` and ``first_passages`` in their parts, each
part for every lane, where the step's calls allow: :func:`steps_in_parts`) and appended
by :mod:`numerics.noise.codegen` after the kernels they call (:mod:`numerics.noise._kernels`,
:mod:`numerics.noise._passage_kernels`).  Each lane performs the operations of its
trajectory alone, on its own generator, so every number is the one the trajectory has alone
(``tests/test_noise_kernels.py``, ``tests/test_noise_lanes.py``).  The number of lanes is
chosen from the library calls of one step (:func:`lane_count`).
"""

from __future__ import annotations

import sympy as sp

from kbm.model.builtins import Oscillator
from kbm.symbols import xdot as V

__all__ = ["lane_count", "lanes_source", "steps_in_parts"]


def lane_count(model: Oscillator, scheme: str, events: bool = False) -> int:
    """Trajectories per loop by the library calls (``sin``, ``exp``, ...) of one step (BAOAB
    one force, Kloeden-Platen two accelerations).

    ``final_states``: none, 6 (polynomial forces: each chain a few arithmetic latencies, six
    fill the core); one, 3 (three chains hide a call's latency; four and six gain nothing);
    more, 2.  Measured on one core of a shared machine (CPU time, medians;
    ``benchmarks/bench_noise.py``), each step in its parts (:func:`lanes_source`), 2, 3, 4,
    6 lanes: BAOAB on the CDC at rest 54.6, 56.6, 56.2, 56.5 M steps/s (lane by lane, as
    before, 47, 52, 45, 44); on the quartic oscillator ``x'' = -x' - x - x^3`` 171, 232,
    299, 320 (BAOAB) and 144, 200, 202, 221 (Kloeden-Platen); Kloeden-Platen on the CDC
    32.2, 30.3, 29.9, 29.5 (load 3-9 on 2 cores).

    ``events`` (``first_passages``, ``slip_stats``: loops that test every step for an event,
    an exit or a crossing): none, 3; else 2 (a call clobbers every vector register, so each
    lane's state and tests are spilled around it).  Measured the same way, 2, 3, 4, 6
    lanes (M steps/s): first passages in the well ``x'' = -(x' + x + x^3)/2`` (200
    trajectories in tasks of 13) 106, 131, 117, 89 (Kloeden-Platen), 138, 163, 159, 132
    (BAOAB); of the CDC (``kbm escape cdc -p mu=0.2 -p Delta=3 -p D=0.1``) 39, 34, 29, 22
    (Kloeden-Platen), 59, 54, 48, 37 (BAOAB); the CDC slider's records (``kbm friction
    cdc``, mu = 1, T = 0.01, v = 1e-3) 42, 35, 35, 34 (Kloeden-Platen), 71, 60, 61, 59
    (BAOAB), the quartic well's 108, 123, 121, 128 and 148, 161, 169, 153 (load 3-5 on 2
    cores)."""
    acc = model.acceleration()
    calls = len(sp.sympify(acc.subs(V, 0) if scheme == "baoab" else acc).atoms(sp.Function))
    calls *= 2 if scheme == "kp" else 1
    if events:
        return 3 if calls == 0 else 2
    return 6 if calls == 0 else 3 if calls == 1 else 2


def steps_in_parts(model: Oscillator, scheme: str, friction_const: bool) -> bool:
    """Whether the loops of ``final_states`` and ``first_passages`` run each step in its
    parts, each part for every lane before the next (:func:`lanes_source`): when every
    library call of a step is in its last part (BAOAB with a constant friction
    ``friction_const``: the force; Kloeden-Platen with none), so that the calls follow each
    other with all the lanes' arithmetic before them (LLVM moves no work across a call:
    lane by lane, one lane's call comes before the next lane's step).

    Against lane by lane (the same bytes; 11 interleaved rounds, CPU time, load 4-9 on 2
    cores): ``final_states`` BAOAB on the CDC at rest 1.12x (56.4 against 50.4 M steps/s,
    three lanes), on the quartic oscillator ``x'' = -x' - x - x^3`` 1.05x, Kloeden-Platen
    there 1.10x; first passages (200 trajectories in tasks of 13, ``bench_noise.py`` part
    4's case) BAOAB on the CDC 1.07x, in the quartic well 1.04x (BAOAB) and 1.11x
    (Kloeden-Platen).  Not in parts: Kloeden-Platen with calls (its first acceleration's
    call is in the first part; on the CDC ``final_states`` 1.00x, first passages 0.99x, the
    slider's records 0.97x) and BAOAB whose friction depends on the state (the O part's
    ``exp`` call; van der Pol's ``final_states`` 0.91x, 0.97x with the O part a part of its
    own).  ``slip_stats`` stays lane by lane (BAOAB on the CDC slider 1.01x in parts)."""
    if scheme == "baoab":
        return friction_const
    return not model.acceleration().atoms(sp.Function)


def _each(lanes: int, *templates: str) -> list[str]:
    """The lines ``templates`` once per lane, ``{j}`` the lane (lane 0's lines first)."""
    return [t.format(j=j) for j in range(lanes) for t in templates]


def _any(lanes: int, template: str) -> str:
    """``(template for lane 0) or (... lane 1) or ...``."""
    return " or ".join(f"({template.format(j=j)})" for j in range(lanes))


#: one step of lane ``j`` at ``t`` (its own generator ``s{j}``, state and carried force)
_STEP = "x{j}, v{j}, f{j} = _step({t}, x{j}, v{j}, f{j}, h, _increment(s{j}, amp), p)"
#: :data:`_STEP` in its parts (``_open``, ``_last``, ``_close`` of the kernels), each part
#: printed for every lane before the next: the calls of the model (``sin``, ...) follow
#: each other with every lane's arithmetic before them, where lane by lane a call came
#: between one lane's step and the next lane's (LLVM's scheduler does not move work across
#: a call); the same operations of each lane in the same order, so the same numbers
_PHASES = ("w{j} = _increment(s{j}, amp)",
           "x{j}, v{j}, xb{j}, vb{j}, a{j} = _open({t}, x{j}, v{j}, f{j}, h, w{j}, p)",
           "g{j} = _last({t}, xb{j}, vb{j}, h, p)",
           "x{j}, v{j}, f{j} = _close(x{j}, v{j}, xb{j}, vb{j}, a{j}, g{j}, h, w{j})")


def _steps(lanes: int, indent: str, t: str, in_parts: bool) -> list[str]:
    """One step of every lane at the time ``t`` (an expression in ``j``): :data:`_PHASES`,
    each part for every lane, if ``in_parts``, else :data:`_STEP` lane by lane."""
    parts = _PHASES if in_parts else (_STEP,)
    return [ln for part in parts for ln in _each(lanes, indent + part.replace("{t}", t))]
#: lane ``j`` at trajectory ``r{j}``'s start
_START = ("s{j} = states[r{j}].copy()", "x{j}, v{j} = y0[r{j}, 0], y0[r{j}, 1]",
          "f{j} = _first(t0, x{j}, v{j}, p)")


def _head(name: str, args: str, doc: str, lanes: int, row: str, n: str,
          in_parts: bool = False) -> list[str]:
    """The start of a loop function ``name(args)``: lane ``j`` at trajectory ``row`` (an
    expression in ``j``), then ``n`` steps of every lane from ``t0`` (unchecked;
    :func:`_steps`)."""
    return (["@njit(cache=True)", f"def {name}({args}):", f'    """{doc}"""']
            + _each(lanes, "    r{j} = " + row, *("    " + s for s in _START))
            + [f"    for k in range({n}):", "        t = t0 + k * h"]
            + _steps(lanes, "        ", "t", in_parts))


def _final(lanes: int, in_parts: bool) -> list[str]:
    """``final_states``' loop (each step in its parts if ``in_parts``)."""
    return (_head("_advance_lanes", "p, y0, t0, h, n, states, i, amp, out",
                  f"Trajectories ``i .. i + {lanes - 1}`` of ``final_states``, {lanes} a loop.",
                  lanes, "i + {j}", "n", in_parts)
            + _each(lanes, "    out[r{j}, 0], out[r{j}, 1] = _finite(x{j}, v{j})"))


def _passages(lanes: int, in_parts: bool) -> list[str]:
    """``first_passages``' loop: each lane takes the next trajectory when its own leaves or
    is censored (:func:`_passage_take`, :func:`_passage_end` of the kernels); the lanes run
    together, each at its own step ``k{j}`` (in its parts if ``in_parts``), until one of
    them leaves or the nearest censoring; a lane with no trajectory left (``r{j} = -1``)
    runs on, unread."""
    out = _any(lanes, "r{j} >= 0 and (x{j} <= xl or x{j} >= xr or not math.isfinite(x{j}))")
    return (["@njit(cache=True)",
             "def _passages_lanes(p, y0, t0, h, n_max, xl, xr, states, amp, times, hit):",
             f'    """``first_passages``, {lanes} trajectories a loop (n_max >= 1)."""']
            + _each(lanes, "    r{j}, s{j}, x{j}, v{j}, f{j} = _passage_take(p, y0, t0, states, "
                    "{j})", "    k{j} = 0")
            + [f"    nxt = {lanes}", "    while True:", "        top = -1"]
            + _each(lanes, "        if r{j} >= 0 and k{j} > top:", "            top = k{j}")
            + ["        if top < 0:", "            return", "        done = n_max - top",
               "        for c in range(n_max - top):"]
            + _steps(lanes, "            ", "t0 + (k{j} + c) * h", in_parts)
            + [f"            if {out}:", "                done = c + 1", "                break"]
            + _each(lanes, "        k{j} += done",
                    "        if _passage_end(r{j}, k{j}, x{j}, h, n_max, xl, xr, times, hit):",
                    "            r{j}, s{j}, x{j}, v{j}, f{j} = _passage_take(p, y0, t0, states, "
                    "nxt)", "            k{j} = 0", "            nxt += 1"))


def _slips(lanes: int) -> list[str]:
    """``slip_stats``' loop: trajectories ``i .. last`` (``last`` repeated in the lanes past
    it), the burn-in unchecked, then the run with each step's records
    (:func:`_slip_record`); False (rows not written) when a lane's state was not finite
    after the burn-in or at a step of the run.  The run's test is a flag, no exit: a branch
    out of the loop each step cost 10 % (CPU time, the CDC slider, BAOAB, two lanes: 63
    against 68 M steps/s, the hand loop with no test 70)."""
    finite = " and ".join(f"math.isfinite(x{j} + v{j})" for j in range(lanes))
    return (_head("_slips_lanes", "p, amp, y0, t0, h, n_burn, n_run, states, lam, min_gap, "
                  "v_stage, out, i, last", f"Rows ``i .. min(i + {lanes - 1}, last)`` of "
                  f"``slip_stats``, {lanes} a loop.", lanes, "min(i + {j}, last)", "n_burn")
            + [f"    if not ({finite}):", "        return False", "    t1 = t0 + n_burn * h"]
            + _each(lanes, "    f{j} = _first(t1, x{j}, v{j}, p)",
                    "    acc{j} = _slip_init(x{j}, lam)")
            + ["    ok = True", "    for k in range(n_run):", "        t = t1 + (k + 1) * h"]
            + _steps(lanes, "        ", "t - h", False)
            + [f"        ok = ok & {finite.replace(' and ', ' & ')}"]
            + _each(lanes, "        acc{j} = _slip_record(acc{j}, t, x{j}, v{j}, p, lam, min_gap, "
                    "v_stage)")
            + ["    if not ok:", "        return False"]
            + _each(lanes, "    _slip_row(out, r{j}, acc{j}, n_run)")
            + ["    return True"])


def lanes_source(lanes: int, events: int | None = None, in_parts: bool = False) -> str:
    """The source of ``LANES`` (``lanes``), ``EVENT_LANES`` (``events``, by default
    ``lanes``) and of the loops over that many trajectories at once (``final_states``'
    ``lanes``, the others ``events``: :func:`lane_count`), every lane with its own
    generator (a copy of ``states[r]``) and scalar state:

    - ``_advance_lanes(p, y0, t0, h, n, states, i, amp, out)``: ``n`` steps of
      trajectories ``i .. i + lanes - 1`` of ``final_states``, the final states written to
      ``out`` (NaN when non-finite);
    - ``_passages_lanes(p, y0, t0, h, n_max, xl, xr, states, amp, times, hit)``: every
      trajectory of ``first_passages``, a lane taking the next trajectory as soon as its
      own leaves (a pair run together until one left, as before, ran the other alone);
    - ``_slips_lanes(p, amp, y0, t0, h, n_burn, n_run, states, lam, min_gap, v_stage, out,
      i, last)``: rows ``i .. min(i + lanes - 1, last)`` of ``slip_stats`` (``last``
      repeated in the lanes past it: a block's remainder in one loop, or one trajectory
      alone), False with no row written when a state turns non-finite.

    ``in_parts``: the loops of ``final_states`` and ``first_passages`` run each step in its
    parts (:data:`_PHASES`: every lane's increment, then every lane's ``_open``, ``_last``
    and ``_close`` of the kernels); else lane by lane (:func:`steps_in_parts`).

    The stationary kernels (``_stats`` of :mod:`numerics.noise._pair_kernels`) stay two a
    loop: written out the same way in six lanes for van der Pol (Kloeden-Platen) and three
    for the CDC (BAOAB), they ran 1.02x and 0.99x as fast as two a loop (medians of 21
    interleaved rounds, CPU time, the same bytes).

    Raises
    ------
    ValueError
        For ``lanes < 1`` or ``events < 1``.
    """
    events = lanes if events is None else events
    if min(lanes, events) < 1:
        raise ValueError(f"lanes must be >= 1, got {lanes} and {events}")
    loops = (_final(lanes, in_parts), _passages(events, in_parts), _slips(events))
    return (f"LANES = {lanes}\nEVENT_LANES = {events}\n\n\n"
            + "\n\n\n".join("\n".join(f) for f in loops) + "\n")
