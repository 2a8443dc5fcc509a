"""A plain Lindstedt-Poincare expansion of the van der Pol cycle over ``fractions.Fraction``.

Independent of the package: no flint, no z-form, no node tree.  Trigonometric
polynomials are dicts ``{k: (C_k, S_k)}`` of ``C_k cos(k tau) + S_k sin(k tau)``
multiplied with the product-to-sum formulas; ``x = sum mu**n x_n``,
``omega = sum mu**n w_n`` solve ``omega**2 x'' + x = mu omega x' (1 - x**2)`` with the
first harmonic of ``x`` equal to ``a cos(tau)``.  At order ``n`` the products of
order ``n - 1`` are formed with ``a_{n-1} = 0``, the sine balance gives ``a_{n-1}``,
and they are formed again with it (the straightforward way, twice the work).

Used by the tests as a reference and by ``benchmarks/bench_engine.py`` as the
specialised baseline.
"""

from __future__ import annotations

from fractions import Fraction

ZERO = Fraction(0)


def _add(f, g, s=1):
    out = dict(f)
    for k, (c, d) in g.items():
        c0, d0 = out.get(k, (ZERO, ZERO))
        out[k] = (c0 + s * c, d0 + s * d)
    return out


def _scale(f, q):
    return {k: (c * q, d * q) for k, (c, d) in f.items()}


def _mul(f, g):
    out = {}

    def put(k, c, d):
        if k < 0:  # cos(-k) = cos(k), sin(-k) = -sin(k)
            k, d = -k, -d
        c0, d0 = out.get(k, (ZERO, ZERO))
        out[k] = (c0 + c, d0 + d)

    for m, (a, b) in f.items():
        for n, (c, d) in g.items():
            # (a cos m + b sin m)(c cos n + d sin n)
            put(m + n, (a * c - b * d) / 2, (a * d + b * c) / 2)
            put(m - n, (a * c + b * d) / 2, (b * c - a * d) / 2)
    return out


def _deriv(f):
    return {k: (k * d, -k * c) for k, (c, d) in f.items() if k}


def vdp_lindstedt_fraction(N: int) -> tuple[list[Fraction], list[Fraction]]:
    """``(omega, amplitude)``: the coefficients of ``mu**0 .. mu**N`` of the van der Pol
    limit cycle's frequency and first-harmonic amplitude, exact."""
    a0 = Fraction(2)
    x = [{1: (a0, ZERO)}]
    w = [Fraction(1)]
    amp = [a0]

    def v_coeff(m):  # coefficient m of omega x'
        acc = {}
        for i in range(m + 1):
            acc = _add(acc, _scale(_deriv(x[m - i]), w[i]))
        return acc

    v = [v_coeff(0)]
    sq = [_mul(x[0], x[0])]  # x**2
    f = []  # (1 - x**2) v = v - x**2 v

    def f_coeff(m):
        acc = dict(v[m])
        for i in range(m + 1):
            acc = _add(acc, _mul(sq[i], v[m - i]), -1)
        return acc

    W = [Fraction(1)]  # omega**2
    xpp = [_deriv(_deriv(x[0]))]

    def rhs(n):  # f_{n-1} - sum_{i=1}^{n-1} W_i x''_{n-i}
        R = f[n - 1]
        for i in range(1, n):
            R = _add(R, _scale(xpp[n - i], W[i]), -1)
        return R

    def square_coeff(m):
        acc = {}
        for i in range((m + 1) // 2):
            acc = _add(acc, _mul(x[i], x[m - i]))
        acc = _add(acc, acc)
        if m % 2 == 0:
            acc = _add(acc, _mul(x[m // 2], x[m // 2]))
        return acc

    f.append(f_coeff(0))
    for n in range(1, N + 2):
        if n >= 2:
            m = n - 1
            sq.append(square_coeff(m))
            v.append(v_coeff(m))
            f.append(f_coeff(m))
            S = rhs(n).get(1, (ZERO, ZERO))[1]
            # d/da of the sine balance of (1 - x**2) omega x' at a = 2 is 2 (G = 2 sin + 3 sin 3)
            a_m = -S / 2
            amp.append(a_m)
            if n == N + 1:
                break
            da = {1: (a_m, ZERO)}
            x[m] = _add(x[m], da)
            xpp[m] = _deriv(_deriv(x[m]))
            dsq = _scale(_mul(x[0], da), 2)
            dv = _deriv(da)  # times w_0 = 1
            sq[m] = _add(sq[m], dsq)
            v[m] = _add(v[m], dv)
            f[m] = _add(_add(f[m], dv), _add(_mul(dsq, v[0]), _mul(sq[0], dv)), -1)
        R = rhs(n)
        C = R.get(1, (ZERO, ZERO))[0]
        # cos balance: C + W_n a0 = 0, W_n = 2 w_n + sum_{j=1}^{n-1} w_j w_{n-j}
        Wn = -C / a0
        W.append(Wn)
        w.append((Wn - sum((w[j] * w[n - j] for j in range(1, n)), ZERO)) / 2)
        R = _add(R, {1: (Wn * a0, ZERO)})
        x.append({k: (c / (1 - k * k), d / (1 - k * k)) for k, (c, d) in R.items() if k != 1})
        xpp.append(_deriv(_deriv(x[n])))
    return w[:N + 1], amp[:N + 1]
