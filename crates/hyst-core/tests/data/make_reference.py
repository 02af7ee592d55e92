#!/usr/bin/env python3
"""Generate high-precision reference data for the hyst-core special functions.

Run from anywhere:

    python3 crates/hyst-core/tests/data/make_reference.py

Writes, next to this script:

    lambert_w0.csv       x,w0         principal-branch Lambert W, x in [0, 1e300]
    wright_omega.csv     y,omega      Wright omega w(y) = W0(e^y), y in [-700, 1e20]
                                      (plus a few underflow points below -700)
    langevin_series.txt  n,c_n        Taylor coefficients of L(x) = coth x - 1/x
    langevin.csv         x,langevin   L(x), x in [-50, 50]

Everything is deterministic: fixed grids and a fixed-seed random.Random.
Every input is an exact IEEE double (it is generated as a Python float and
written with 17 significant digits, which round-trips exactly); every
reference value is computed by mpmath at >= 60 significant digits on that
exact double and then correctly rounded to the nearest double before being
written with 17 significant digits, so `str::parse::<f64>` in Rust recovers
exactly that correctly rounded double.
"""

import math
import os
import random
import sys

import mpmath
from mpmath import mp, mpf

DPS = 60
mp.dps = DPS

HERE = os.path.dirname(os.path.abspath(__file__))
SEED = 20240611


# ---------------------------------------------------------------- helpers


def to_double(v):
    """Correctly rounded (round-to-nearest-even) double of an mpf.

    mpmath prints 45 significant digits, Python's float() parser is correctly
    rounded; the double rounding could only matter if v were within 1e-45
    (relative) of a midpoint between two doubles.
    """
    v = mpf(v)
    if v == 0:
        return 0.0
    return float(mpmath.nstr(v, 45, min_fixed=1, max_fixed=0))


def fmt(x):
    """17 significant digits: parses back to exactly the same double."""
    x = float(x)
    if x == 0.0:
        return "0" if math.copysign(1.0, x) > 0 else "-0"
    s = "%.17g" % x
    assert float(s) == x
    return s


def uniq_sorted(xs):
    out = sorted(set(float(x) for x in xs))
    return out


def pow10(e):
    """Correctly rounded 10**e (via mpmath, so independent of the platform libm)."""
    return to_double(mpf(10) ** mpf(e))


def log_grid(lo_exp, hi_exp, n):
    """n points 10**e for e evenly spaced in [lo_exp, hi_exp] (inclusive)."""
    return [pow10(lo_exp + (hi_exp - lo_exp) * i / (n - 1)) for i in range(n)]


E = None  # set in main(): correctly rounded e
INV_E = None  # correctly rounded 1/e


def write_csv(name, header, rows):
    path = os.path.join(HERE, name)
    with open(path, "w", newline="\n") as f:
        f.write(header + "\n")
        for a, b in rows:
            f.write("%s,%s\n" % (fmt(a), fmt(b)))
    print("wrote %-22s %5d rows" % (name, len(rows)))


# ---------------------------------------------------------------- Lambert W0


def w0_ref(x):
    """W0(x) for an exact double x >= 0, correctly rounded to a double."""
    x = mpf(x)
    if x == 0:
        return 0.0
    with mp.workdps(DPS + 20):
        w = mpmath.lambertw(x)
        assert mpmath.im(w) == 0
        w = mpmath.re(w)
        # Independent check: w * e^w == x.
        r = abs(w * mpmath.exp(w) - x) / x
        assert r < mpf(10) ** (-(DPS - 5)), (x, w, r)
        return to_double(w)


def lambert_inputs(rng):
    xs = [0.0, 1e-300, 1e-200, 1e-100, 1e-20, 1e-10, 1e-5, 1e300]
    # Extremes of the double range inside [0, 1e300].
    xs += [5e-324, 2.2250738585072014e-308, 1e-308, 1e-250, 1e-150, 1e-50]
    # Dense log grid across the whole range (step 10^3).
    xs += log_grid(-300, 300, 201)
    # Finer log grid where W changes curvature.
    xs += log_grid(-6, 6, 97)
    # Random points: log-uniform across the range and uniform in [0, 20].
    xs += [pow10(rng.uniform(-300, 300)) for _ in range(120)]
    xs += [rng.uniform(0.0, 20.0) for _ in range(50)]
    xs += [rng.uniform(0.0, 1.0) for _ in range(30)]
    # Near 1/e and near e (W0(e) = 1 exactly).
    for c in (INV_E, E):
        xs.append(c)
        y = c
        z = c
        for _ in range(4):
            y = math.nextafter(y, math.inf)
            z = math.nextafter(z, -math.inf)
            xs += [y, z]
        for d in (1e-12, 1e-8, 1e-4, 1e-2):
            xs += [c * (1 + d), c * (1 - d)]
    # x = k e^k (so W0(x) ~ k).
    xs += [to_double(k * mpmath.exp(k)) for k in range(1, 31)]
    # Exact integers.
    xs += [float(k) for k in range(1, 101)]
    xs += [1e3, 1e4, 1e5, 1e6, 1e9, 1e12, 1e15, 2.0 ** 53, 1e18, 1e100, 1e200]
    xs = [x for x in xs if 0.0 <= x <= 1e300]
    return uniq_sorted(xs)


# ---------------------------------------------------------------- Wright omega


def omega_mp(y):
    """Wright omega at an exact double y, as a high-precision mpf."""
    y = mpf(y)
    with mp.workdps(DPS + 30):
        tol = mpf(10) ** (-(DPS + 10))
        if y > 2:
            # Solve f(w) = w + ln w - y = 0 by Newton from w = y - ln y.
            # f is increasing and concave, so Newton converges monotonically.
            w = y - mpmath.log(y)
            for _ in range(200):
                f = w + mpmath.log(w) - y
                dw = f / (1 + 1 / w)
                w -= dw
                if abs(dw) <= tol * abs(w):
                    break
            else:
                raise RuntimeError("Newton did not converge for y=%s" % y)
        else:
            w = mpmath.re(mpmath.lambertw(mpmath.exp(y)))
        # Cross-check with the other method where both are cheap.
        if -50 < y < 50:
            w2 = mpmath.re(mpmath.lambertw(mpmath.exp(y)))
            assert abs(w - w2) <= mpf(10) ** (-(DPS - 5)) * abs(w), (y, w, w2)
        # Residual check: w + ln w == y.
        r = abs(w + mpmath.log(w) - y)
        assert r <= mpf(10) ** (-(DPS - 5)) * max(1, abs(y)), (y, w, r)
        return +w


def omega_ref(y):
    return to_double(omega_mp(y))


def omega_inputs(rng):
    ys = []
    # Dense grid on [-700, 700], step 3.5.
    ys += [-700.0 + 3.5 * i for i in range(401)]
    # Around 0.
    ys += [0.0]
    for k in range(1, 17):
        ys += [pow10(-k), -pow10(-k)]
    ys += [1e-20, -1e-20, 1e-100, -1e-100, 1e-300, -1e-300]
    ys += [s * v for s in (1.0, -1.0) for v in (0.125, 0.25, 0.5, 0.75, 1.5)]
    # Around +-1 (omega(1) = 1 exactly).
    for c in (1.0, -1.0):
        ys.append(c)
        a = b = c
        for _ in range(3):
            a = math.nextafter(a, math.inf)
            b = math.nextafter(b, -math.inf)
            ys += [a, b]
        for d in (1e-12, 1e-8, 1e-4, 1e-2):
            ys += [c + d, c - d]
    # Integers 1..50 and their negatives.
    ys += [float(k) for k in range(1, 51)]
    ys += [-float(k) for k in range(1, 51)]
    # Log-spaced up to 1e20 (8 per decade).
    ys += log_grid(0, 20, 161)
    # Random points.
    ys += [rng.uniform(-700.0, 700.0) for _ in range(60)]
    ys += [rng.uniform(-5.0, 5.0) for _ in range(30)]
    ys += [pow10(rng.uniform(0, 20)) for _ in range(60)]
    # Underflow tail below -700 (the reference drops below f64::MIN_POSITIVE
    # near y = -708.4 and rounds to zero below about y = -745.13).
    ys += [-705.0, -708.0, -708.5, -709.0, -710.0, -720.0, -730.0, -740.0,
           -745.0, -745.5, -746.0, -750.0, -800.0, -1000.0]
    ys += [1e20]
    ys = [y for y in ys if -1000.0 <= y <= 1e20]
    return uniq_sorted(ys)


# ---------------------------------------------------------------- Langevin


def langevin_mp(x):
    x = mpf(x)
    if x == 0:
        return mpf(0)
    # coth(x) - 1/x cancels ~2*log10(1/|x|) digits for small |x|: add them.
    extra = 0
    if abs(x) < 1:
        extra = int(2 * -mpmath.log10(abs(x))) + 10
    with mp.workdps(DPS + 10 + extra):
        v = mpmath.coth(x) - 1 / x
        return +v


def langevin_coeffs(nmax):
    with mp.workdps(DPS + 20):
        out = []
        for n in range(1, nmax + 1):
            c = mpf(2) ** (2 * n) * mpmath.bernoulli(2 * n) / mpmath.factorial(2 * n)
            out.append((n, c))
        return out


def langevin_inputs(rng):
    xs = [0.0]
    pos = [1e-300, 1e-100, 1e-20, 1e-12, 1e-8, 1e-6, 1e-4, 1e-3, 0.01, 0.05,
           0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.5, 2.0, 3.0,
           5.0, 10.0, 20.0, 30.0, 40.0, 50.0]
    xs += pos + [-v for v in pos]
    # Log grid 1e-6 .. 50, both signs.
    g = log_grid(-6, to_double(mpmath.log10(50)), 41)
    xs += g + [-v for v in g]
    # Uniform grid on [-5, 5] (step 0.125, exact in binary).
    xs += [-5.0 + 0.125 * i for i in range(81)]
    # Random points.
    xs += [rng.uniform(-50.0, 50.0) for _ in range(30)]
    xs += [rng.uniform(-1.0, 1.0) for _ in range(20)]
    xs = [x for x in xs if -50.0 <= x <= 50.0]
    return uniq_sorted(xs)


# ---------------------------------------------------------------- main


def main():
    print("mpmath %s, mp.dps = %d (working precision up to %d digits)"
          % (mpmath.__version__, DPS, DPS + 30))

    global E, INV_E
    E = to_double(mpmath.e)
    INV_E = to_double(1 / mpmath.e)

    rng = random.Random(SEED)
    xs = lambert_inputs(rng)
    write_csv("lambert_w0.csv", "x,w0", [(x, w0_ref(x)) for x in xs])

    rng = random.Random(SEED + 1)
    ys = omega_inputs(rng)
    write_csv("wright_omega.csv", "y,omega", [(y, omega_ref(y)) for y in ys])

    path = os.path.join(HERE, "langevin_series.txt")
    with open(path, "w", newline="\n") as f:
        f.write("n,c_n\n")
        for n, c in langevin_coeffs(20):
            f.write("%d,%s\n" % (n, fmt(to_double(c))))
    print("wrote %-22s %5d rows" % ("langevin_series.txt", 20))

    rng = random.Random(SEED + 2)
    xs = langevin_inputs(rng)
    write_csv("langevin.csv", "x,langevin",
              [(x, to_double(langevin_mp(x))) for x in xs])
    return 0


if __name__ == "__main__":
    sys.exit(main())
