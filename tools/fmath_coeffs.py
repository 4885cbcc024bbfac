#!/usr/bin/env python3
"""Derives the polynomial coefficients of the f32 kernels in `src/fmath.rs`.

Each kernel is  f(x) ≈ x + x^3 P(x^2)  (odd functions) or  1 - x^2/2 + x^4 Q(x^2)  (cosine) on a
reduced interval; P and Q are fitted for minimum maximum *relative* error of f (minimax) by
Lawson's iteratively reweighted least squares on 4000 Chebyshev-distributed points, in f64
(numpy), then rounded to f32. The printout gives the coefficients (as Rust f32 literals) and the
maximum relative error of the f64-evaluated polynomial with the f32-rounded coefficients, i.e.
the approximation error alone; the f32 evaluation error is measured by `tests/fmath.rs`.

Usage: python3 tools/fmath_coeffs.py   (needs numpy: pip install numpy)
"""
import numpy as np


def lawson(x, target, basis, weight, iters=400):
    """Minimise max |weight * (basis @ c - target)| by Lawson's algorithm."""
    A = basis * weight[:, None]
    b = target * weight
    w = np.full(len(x), 1.0 / len(x))
    c = None
    for _ in range(iters):
        sw = np.sqrt(w)
        c, *_ = np.linalg.lstsq(A * sw[:, None], b * sw, rcond=None)
        e = np.abs(A @ c - b)
        w = w * e
        w /= w.sum()
    return c


def cheb(a, b, n=4000):
    k = np.arange(n)
    return (a + b) / 2 + (b - a) / 2 * np.cos(np.pi * (k + 0.5) / n)


def f32(c):
    return np.array(c, dtype=np.float32).astype(np.float64)


def odd_kernel(name, fn, a, b, deg):
    """f(x) = x + x^3 P(x^2), P of degree deg-1, relative error."""
    x = cheb(a, b)
    x = x[x > 1e-4]
    z = x * x
    f = fn(x)
    basis = np.stack([x ** 3 * z ** j for j in range(deg)], axis=1)
    c = f32(lawson(x, f - x, basis, 1.0 / np.abs(f)))
    xs = np.linspace(1e-6, b, 200001)
    approx = xs + xs ** 3 * sum(cj * (xs * xs) ** j for j, cj in enumerate(c))
    err = np.max(np.abs(approx / fn(xs) - 1))
    report(name, "x + x^3 P(x^2) on [0, %.9g]" % b, c, err)


def cos_kernel(a, b, deg):
    x = cheb(a, b)
    z = x * x
    f = np.cos(x)
    basis = np.stack([z ** 2 * z ** j for j in range(deg)], axis=1)
    c = f32(lawson(x, f - (1 - z / 2), basis, 1.0 / f))
    xs = np.linspace(0, b, 200001)
    zs = xs * xs
    approx = 1 - zs / 2 + zs ** 2 * sum(cj * zs ** j for j, cj in enumerate(c))
    err = np.max(np.abs(approx / np.cos(xs) - 1))
    report("cos", "1 - x^2/2 + x^4 Q(x^2) on [0, %.9g]" % b, c, err)


def report(name, form, c, err):
    print("%s: %s, max relative approximation error %.3g (%.2f bits)" % (name, form, err, -np.log2(err)))
    for j, cj in enumerate(c):
        print("    %s_P%d: f32 = %r;" % (name.upper(), j, float(np.float32(cj))))


if __name__ == "__main__":
    q = np.pi / 4
    odd_kernel("sin", np.sin, 0, q, 3)
    cos_kernel(0, q, 3)
    odd_kernel("atan", np.arctan, 0, np.tan(np.pi / 8), 4)
    odd_kernel("asin", np.arcsin, 0, 0.5, 5)
