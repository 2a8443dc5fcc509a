"""The cost of a simulated spectrum, checked before it runs (:func:`check_cost`).

``kbm spectrum --trajectories 1000000000`` made a list of 1e9 indices and was killed by
the kernel after 40 s; ``--duration 1e12`` ended in a ``MemoryError`` traceback.  Each
simulation of :mod:`numerics.spectrum` now counts its integration steps and the samples it
holds in memory first, and refuses a run above :data:`numerics.noise.budget.STEP_BUDGET` or :data:`MEMORY_LIMIT`
with the numbers (the same step budget as ``kbm noise --budget``'s default).
"""

from __future__ import annotations

from kbm.errors import ParameterError

from ..noise.budget import STEP_BUDGET

__all__ = ["MEMORY_LIMIT", "check_cost"]

#: bytes of recorded samples held in memory at once at most
MEMORY_LIMIT = 2e9


def check_cost(trajectories: int, steps: float, held: float, *, budget: float = STEP_BUDGET,
               shared: int = 1) -> None:
    """Refuse a simulation of ``trajectories`` paths of ``steps`` integration steps each that
    holds ``held`` bytes of samples at once.

    Parameters
    ----------
    trajectories : int
    steps : float
        Integration steps of one trajectory (burn-in included).
    held : float
        Bytes of recorded samples in memory at once.
    budget : float
        The step limit of this run (:data:`numerics.noise.budget.STEP_BUDGET` over ``shared``).
    shared : int
        Runs the limit is shared by (the values of a ``--vary`` sweep), named in the message.

    Raises
    ------
    kbm.errors.ParameterError
        Naming the steps or bytes needed, the limit and what to change.
    """
    total = float(trajectories) * float(steps)
    among, sweep = (f" (the limit {STEP_BUDGET:.0e} shared by {shared} runs of the sweep)",
                    ", or fewer values of --vary") if shared > 1 else ("", "")
    if total > budget:
        raise ParameterError(
            f"the simulation needs {int(trajectories)} trajectories x {float(steps):.3g} steps "
            f"= {total:.3g} integration steps, above the limit {budget:.3g}{among}: give fewer "
            f"--trajectories, a shorter --duration or a coarser --resolution{sweep}")
    if held > MEMORY_LIMIT:
        raise ParameterError(
            f"the simulation would hold {held / 1e9:.3g} GB of recorded samples, above the "
            f"limit {MEMORY_LIMIT / 1e9:.3g} GB: give a shorter --duration or a coarser "
            "--resolution (or fewer --trajectories)")
