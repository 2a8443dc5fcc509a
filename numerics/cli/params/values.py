"""The one parameter and option layer of the ``kbm`` commands: ``-p NAME=VALUE`` and ``--vary``.

Every command reads its parameters and ranges here, so that the names, the grammar and
the messages are the same everywhere:

* ``-p NAME=VALUE``: :func:`given` reads them; :func:`check` refuses a name the model
  does not have, with the valid ones listed (:class:`kbm.parameters.values.ParameterNames`: ``mu``,
  the physical names ``Delta``, ``lam``, the scaled ``delta = Delta/mu``,
  ``k = 2 pi/lam``, and ``D`` or ``T = D/mu`` where noise applies);
* ``--vary``: one grammar, :func:`parse_vary`::

      NAME=FROM:TO        a range (a grid of DEFAULT_POINTS = 8 values, or the interval a
                          continuation or a search runs over)
      NAME=FROM:TO:N      N equally spaced values (a continuation: about N points)
      NAME=FROM:TO:logN   N log-spaced values (FROM, TO > 0)
      NAME=A,B,C          the listed values (a single NAME=A is one value)

  **Order.**  A range is an interval: ``FROM < TO`` in every command, refused
  otherwise with the range turned round in the message.  One meaning of FROM:TO
  everywhere (the continuations, the edge searches and the map figures take intervals);
  where a direction matters it is said otherwise: a branch starts at ``-p NAME=VALUE``
  (default FROM), and a list ``NAME=C,B,A`` keeps the order typed.
* a store of finished points (``--store FILE --resume``): :func:`open_store` says when
  the file holds another run and nothing of this one;
* the values of the other options: :func:`within` (a bounded option, one wording "FLAG
  must be between A and B"), :func:`numbers` (comma-separated numbers), :func:`orders`
  (KBM orders).

The options themselves (flags, defaults, help) are defined once in
:data:`kbm.cli._common.OPTIONS` and :data:`numerics.cli.params.options.ENSEMBLE`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from kbm.cli._common import check
from kbm.cli._common import parse_params as given
from kbm.errors import KBMError, OrderError, ParameterError
from kbm.parameters.values import ParameterNames, parameter_value

__all__ = ["DEFAULT_POINTS", "MAX_POINTS", "Vary", "parse_vary", "given", "check", "positive",
           "wavenumber", "noise_params", "without_noise", "open_store", "numbers", "orders",
           "within", "USAGE"]

#: values of a range without ``:N``
DEFAULT_POINTS = 8
#: the largest grid one command computes
MAX_POINTS = 100_000
#: the forms ``--vary`` takes, for its messages
USAGE = ("--vary takes NAME=FROM:TO[:N] (N equally spaced, default 8), NAME=FROM:TO:logN "
         "(N log-spaced) or NAME=A,B,C")


@dataclass(frozen=True)
class Vary:
    """One ``--vary``: a range ``FROM:TO[:N|:logN]`` or a list ``A,B,C``.

    Attributes
    ----------
    name, text
        The parameter and the option's text as typed.
    start, stop
        FROM and TO of a range (``None`` for a list).
    count
        N of ``:N`` or ``:logN`` (``None`` when not given).
    log
        ``:logN``.
    listed
        The values of a list (``None`` for a range).
    """

    name: str
    text: str
    start: float | None = None
    stop: float | None = None
    count: int | None = None
    log: bool = False
    listed: tuple[float, ...] | None = None

    def values(self, default: int = DEFAULT_POINTS) -> np.ndarray:
        """The values, in the order typed (a range from FROM to TO)."""
        if self.listed is not None:
            return np.array(self.listed, float)
        n = self.count or default
        if self.log:
            return np.geomspace(self.start, self.stop, n)
        return np.linspace(self.start, self.stop, n)

    def interval(self, what: str, *, points: bool = True) -> tuple[float, float]:
        """``(FROM, TO)`` of a range for a continuation or a search (``what``), refused
        for a list or a log spacing (and for ``:N`` where ``points`` is false)."""
        if self.listed is not None or self.log or (self.count is not None and not points):
            form = "NAME=FROM:TO[:N]" if points else "NAME=FROM:TO"
            raise ParameterError(f"--vary {self.text}: {what} runs over an interval; give "
                                 f"--vary {self.name}=FROM:TO" + ("[:N]" if points else "")
                                 + f" (the form {form})")
        return self.start, self.stop

    def bounds(self) -> tuple[float, float]:
        """The interval ``(min, max)`` of a range."""
        return min(self.start, self.stop), max(self.start, self.stop)


def parse_vary(text: str) -> Vary:
    """Read one ``--vary`` (the grammar of the module docstring).

    Raises
    ------
    kbm.errors.ParameterError
        With the forms ``--vary`` takes and what was typed.
    """
    name, sep, spec = text.partition("=")
    name, spec = name.strip(), spec.strip()
    if not (sep and name and spec):
        raise ParameterError(f"{USAGE}; got {text!r}")
    parts = spec.split(":")
    try:
        if len(parts) == 1:
            listed = tuple(float(x) for x in spec.split(","))
        elif len(parts) not in (2, 3):
            raise ValueError
        else:
            lo, hi = float(parts[0]), float(parts[1])
            count = parts[2].strip() if len(parts) == 3 else None
            log = bool(count) and count.lower().startswith("log")
            n = None if count is None else int(count[3:] if log else count)
    except ValueError:
        raise ParameterError(f"{USAGE}; got {text!r}") from None
    if len(parts) == 1:
        bad = [x for x in listed if not math.isfinite(x)]
        if bad:
            raise ParameterError(f"--vary {name}: the values must be finite, got {bad[0]:g}")
        return Vary(name, text, listed=listed)
    if n is not None and not 1 <= n <= MAX_POINTS:
        raise ParameterError(f"--vary {name}: the number of values must be between 1 and "
                             f"{MAX_POINTS}, got {n}")
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ParameterError(f"--vary {name}: FROM and TO must be finite, got {spec!r}")
    if lo == hi and n != 1:
        raise ParameterError(f"--vary {name}: FROM = TO = {lo:g} is an empty range; give "
                             f"one value as --vary {name}={lo:g}")
    if lo > hi:
        tail = "" if len(parts) == 2 else ":" + parts[2].strip()
        raise ParameterError(f"--vary {text}: an empty range; a range is an interval with "
                             f"FROM < TO in every command: give --vary {name}={parts[1]}:"
                             f"{parts[0]}{tail} (a list {name}=A,B,C keeps the order typed)")
    if log and (lo <= 0 or hi <= 0):
        raise ParameterError(f"--vary {name}: a log range needs FROM, TO > 0, got {spec!r}")
    return Vary(name, text, lo, hi, n, log)


def wavenumber(model: object, params: Mapping[str, object]) -> None:
    """Refuse ``-p k=0`` where ``k`` is a slider's wavenumber ``2 pi/lam`` or divides in ``F``
    (``nu/k``): ``kbm cycle``, ``compare``, ``branch``, ``response`` died with a traceback.

    Raises
    ------
    kbm.errors.ParameterError
    """
    if "k" not in params:
        return
    from sympy import Pow, Symbol

    from kbm.parameters.names import lookup, names_of

    obj = lookup(model) if isinstance(model, str) else model
    F = obj.F if isinstance(obj.F, (tuple, list)) else (obj.F,)
    divides = any(p.base == Symbol("k") and p.exp.is_negative for f in F for p in f.atoms(Pow))
    if ("k" in names_of(obj).physical or divides) and parameter_value("k", params["k"]) == 0:
        raise ParameterError(f"k = {params['k']} gives no finite lam (k = 2*pi/lam): give the "
                             "wavenumber -p k=VALUE != 0, or the period -p lam=VALUE")


def within(value: float | None, flag: str, lo: float | None = None,
           hi: float | None = None) -> None:
    """Refuse the value of the option ``flag`` outside ``[lo, hi]``, or not finite where no
    bounds are given (a value ``None``, the option not given, passes).

    Raises
    ------
    kbm.errors.ParameterError
        ``"{flag} must be between {lo} and {hi}, got {value}"`` (``"... must be a finite
        number ..."`` without bounds).
    """
    if value is None:
        return
    if lo is None:
        if not math.isfinite(value):
            raise ParameterError(f"{flag} must be a finite number, got {value}")
    elif not lo <= value <= hi:
        raise ParameterError(f"{flag} must be between {_bound(lo)} and {_bound(hi)}, got "
                             f"{value}")


def positive(value: float | None, flag: str) -> None:
    """Refuse a value of the option ``flag`` that is not a positive finite number (``None``,
    the option not given, passes).

    Raises
    ------
    kbm.errors.ParameterError
        ``"{flag} must be a positive number, got {value}"``.
    """
    if value is not None and not (math.isfinite(value) and value > 0):
        raise ParameterError(f"{flag} must be a positive number, got {value:g}")


def _bound(x: float) -> str:
    """``100000``, ``1e-3``, ``1e6``: a bound as the messages write it."""
    if float(x).is_integer() and abs(x) < 1e6:
        return str(int(x))
    mantissa, exponent = f"{x:e}".split("e")
    return f"{mantissa.rstrip('0').rstrip('.')}e{int(exponent)}"


def numbers(text: str, flag: str) -> list[float]:
    """The comma-separated numbers of ``flag`` (``--convergence 0.1,0.2``, ``--start``;
    empty items skipped).

    Raises
    ------
    kbm.errors.ParameterError
        ``"{flag} takes comma-separated numbers, got {text!r}"``.
    """
    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise ParameterError(f"{flag} takes comma-separated numbers, got {text!r}") from None


def orders(text: str, flag: str = "--orders", *, none: bool = False) -> list[int]:
    """The KBM orders of ``flag`` (``"1,2"``; with ``none``, ``"none"``: none).

    Raises
    ------
    kbm.errors.OrderError
        For an item that is no integer, or no order >= 1.
    """
    if none and text.strip().lower() == "none":
        return []
    try:
        out = [int(s) for s in text.split(",") if s.strip()]
    except ValueError:
        raise OrderError(f"{flag} takes comma-separated integers, got {text!r}") from None
    if not out or min(out) < 1:
        raise OrderError(f"{flag} must list orders >= 1, got {text!r}")
    return out


def noise_params(params: Mapping[str, str]) -> tuple[dict[str, str], str | None]:
    """``(params with D, the name the noise was given by)`` from ``-p D=`` or ``-p T=``
    (``D = mu T``, exact).

    Raises
    ------
    kbm.errors.ParameterError
        For neither given (naming both), both, a negative value named as given, or
        ``T = 0`` (the commands that read their noise here need it).
    """
    from kbm.parameters.names import noise_from

    rest, D, name = noise_from(params, "T = 0 is the deterministic model, without noise")
    if D is None:
        raise ParameterError("give the noise intensity: -p D=VALUE (x'' + ... = sqrt(2 D) xi) "
                             "or the temperature -p T=VALUE (T = kT = D/mu)")
    if name == "T" and float(D) == 0:  # named as given (the check of D would say D = 0)
        raise ParameterError("T = 0 is the deterministic model, without noise: give a "
                             "temperature T > 0 (-p T=VALUE, T = kT = D/mu) or a noise "
                             "intensity D > 0 (-p D=VALUE)")
    rest = {k: _decimal(k, v) for k, v in rest.items()}
    return {**rest, "D": D if name == "D" else repr(float(D))}, name


def _decimal(name: str, text: object) -> object:
    """A ``-p`` value as typed where ``float`` reads it, else (``1/50``) its decimal value:
    ``float('1/50')`` was a ValueError traceback in ``kbm escape``, ``kbm spectrum``."""
    try:
        float(text)
    except (TypeError, ValueError):
        try:
            return repr(float(parameter_value(name, text)))
        except KBMError:  # no number: said where the value is checked, as before
            return text
    return text


def without_noise(params: Mapping[str, str],
                  need: str | None = None) -> tuple[dict[str, str], float]:
    """``(params without D, D as a number)`` of the values :func:`noise_params` returns,
    checked by :func:`kbm.parameters.names.noise_intensity` (``need``: why ``D = 0`` is
    refused)."""
    from kbm.parameters.names import noise_intensity

    rest = dict(params)
    return rest, noise_intensity(rest.pop("D"), need)


def open_store(path: str | None, resume: bool, what: str = "run"):
    """The :class:`numerics.store.PointStore` of ``--store FILE`` (``None`` without it).

    With ``--resume``, a file that holds finished chunks of other runs and none of this
    one is refused: nothing of it can be resumed (another model, parameters or grid).  The
    test is made at the command's first run only: a command of several runs (``kbm
    spectrum coupled-vdp`` over detunings) interrupted in its first leaves nothing of the
    later ones, which resume from scratch (before, the second detuning's run was refused
    as "another run" and the resumed command failed).

    Raises
    ------
    kbm.errors.ParameterError
        ``--resume`` without ``--store``.
    """
    if resume and not path:
        raise ParameterError(f"--resume continues a {what} kept by --store FILE: give the file")
    if not path:
        return None
    from numerics.store import PointStore, StoreError

    class _Store(PointStore):
        first = True  # (per store: the command's first run is the one tested)

        def run(self, definition: str, chunks: int):
            record = super().run(definition, chunks)
            count = "SELECT COUNT(*) FROM chunks WHERE run {} ?"
            first, self.first = self.first, False
            if self.resume and first and not self._db.execute(count.format("="),
                                                              (record.key,)).fetchone()[0]:
                others = self._db.execute(count.format("!="), (record.key,)).fetchone()[0]
                if others:
                    raise StoreError(
                        f"--resume: {self.path} holds {others} finished chunk"
                        f"{'' if others == 1 else 's'} of another "
                        f"{what} (a different model, parameters, grid or settings) and none "
                        f"of this one, so nothing can be resumed; give the same options as "
                        f"the stored {what}, drop --resume to add this one to the file, or "
                        "name a new file")
            return record

    return _Store(path, resume=resume)


def physical(names: ParameterNames, params: Mapping[str, object],
             axes: Mapping[str, np.ndarray], mu: object) -> tuple[dict, dict]:
    """``(params, axes)`` in the physical names (``delta -> Delta = mu delta``,
    ``k -> lam = 2 pi/k``), for the sliders' integrators, which take the physical ones;
    ``mu`` is the value used where ``-p mu`` is not given.

    Raises
    ------
    kbm.errors.ParameterError
        For a scaled axis while ``mu`` is an axis too (give the physical name), or a value
        that has no physical form (``k = 0``).
    """
    from kbm.parameters.names import to_physical

    fixed = {"mu": mu, **params} if "mu" not in axes and mu is not None else dict(params)
    out = {k: v for k, v in to_physical(names, fixed).items()}
    if "mu" not in params and "mu" in out:
        del out["mu"]
    new_axes = {}
    for name, values in axes.items():
        if name not in names.physical:
            new_axes[name] = values
            continue
        if "mu" in axes:
            raise ParameterError(f"{name} = {names.physical[name]} with mu varied: vary the "
                                 f"physical parameter instead")
        if "mu" not in fixed:
            raise ParameterError(f"{name} = {names.physical[name]} needs mu: give -p mu=VALUE")
        conv = [to_physical(names, {"mu": fixed["mu"], name: float(x)}) for x in values]
        (phys,) = [k for k in conv[0] if k != "mu"]
        new_axes[phys] = np.array([float(c[phys]) for c in conv])
    return out, new_axes

