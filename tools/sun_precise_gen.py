#!/usr/bin/env python3
"""Generates the series constants of `src/env/sun/precise.rs` from Meeus's abridged VSOP87D
(`tests/data/vsop87_meeus_earth.csv`) and prints them as Rust (paste between the GENERATED marks).

Usage: python3 tools/sun_precise_gen.py [--write]   (numpy; --write replaces the block between
the GENERATED marks of src/env/sun/precise.rs, otherwise prints it)

Split of the Earth's series (L, R; the latitude B, at most 0.6", is dropped):
- harmonic terms, frequency k*6283.07585 rad/millennium with k = 1, 2 (the equation of the
  centre): every power of tau kept, folded into polynomials in tau that multiply the precise
  cos(kM'), sin(kM') (M' = the argument of the first L0 term);
- slow terms, frequency < 30 rad/millennium (periods > 200 years), all powers, together with the
  constant terms of L2..L5 and R1..R4: one least-squares polynomial in tau over 1950-2100;
- periodic terms: each argument written as an integer combination of the mean longitudes of
  Venus, Mars, Jupiter, Saturn, M' and the Moon's elongation D (found by search, residual
  frequency < 1e-3 rad/millennium), kept if amplitude * 0.101^power >= THRESHOLD_L (longitude) or
  THRESHOLD_R (radius), evaluated from a table (phase offset in 2^-16 turn).
"""
import itertools
import math
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
THRESHOLD_L = 200.0  # 1e-8 rad (0.41")
THRESHOLD_R = 300.0  # 1e-8 AU
TAU_MIN = -18263.0 / 365250.0  # 1950-01-01
TAU_MAX = 36891.0 / 365250.0  # 2101-01-01
SLOW_TOL = {"L": 5.0, "R": 50.0}  # 1e-8 rad (0.01"), 1e-8 AU
HARM_TOL = {"L": 5.0, "R": 50.0}  # a power of tau is kept if |coef| * 0.101^p >= this
E_RATE = 6283.07585
# Fundamental arguments: (name, phase at J2000 in rad, rate in rad per Julian millennium).
# Mean longitudes of VSOP87 (Simon et al. 1994) except M' (the first L0 term's argument) and D.
FUND = [
    ("e", 4.6692568, 6283.07585),
    ("v", 3.17614669, 10213.2855462),
    ("ma", 6.20348142, 3340.6124267),
    ("j", 0.59954691, 529.6909651),
    ("s", 0.87401675, 213.2990954),
    ("d", 5.198466741, 77713.7714681),
]


def load():
    rows = []
    with open(os.path.join(HERE, "..", "tests", "data", "vsop87_meeus_earth.csv")) as f:
        for line in f:
            if line.startswith("#") or line.startswith("series"):
                continue
            s, a, b, c = line.strip().split(",")
            rows.append((s[0], int(s[1]), float(a), float(b), float(c)))
    return rows


def kind(c):
    if c < 30.0:
        return "slow"
    for k in (1, 2):
        if abs(c - k * E_RATE) < 0.01:
            return k
    return "per"


def decompose(c):
    best = None
    for ks in itertools.product(range(-5, 6), range(-5, 6), range(-5, 6), range(-5, 6), range(-5, 6), range(-1, 2)):
        if sum(abs(k) for k in ks) > 10:
            continue
        f = sum(k * r for k, (_, _, r) in zip(ks, FUND))
        if abs(f - c) < 1e-2:
            w = sum(abs(k) for k in ks)
            if best is None or w < best[0]:
                best = (w, ks, f - c)
    return best


def f32(x):
    """Shortest decimal that rounds to the same f32 (what clippy accepts)."""
    r = np.format_float_scientific(np.float32(x), unique=True, trim="0")
    return r if ("e" in r or "." in r) else r + ".0"


def wrap16(x_rad):
    return int(round(x_rad / (2 * math.pi) * 65536.0)) % 65536


def main():
    rows = load()
    harm = {}  # (series, k) -> {power: (cos coef, sin coef)}
    slow = {"L": [], "R": []}
    per = {}  # ks -> {"L": (a, b), "R": (a, b)} a in 1e-8, b phase
    for s, p, a, b, c in rows:
        if s == "B":
            continue
        kd = kind(c)
        if kd == "slow":
            if s == "L" and p == 0 and c == 0.0:
                continue  # L0 constant: in the mean longitude
            if s == "L" and p == 1 and c == 0.0:
                continue  # L1 constant: the mean motion
            slow[s].append((p, a, b, c))
        elif kd in (1, 2):
            d = b - kd * FUND[0][1]
            cs = harm.setdefault((s, kd), {}).setdefault(p, [0.0, 0.0])
            cs[0] += a * math.cos(d)
            cs[1] -= a * math.sin(d)
        else:
            thr = THRESHOLD_L if s == "L" else THRESHOLD_R
            if a * TAU_MAX ** p < thr:
                continue
            if p != 0:
                raise SystemExit(f"periodic term with power {p} selected: extend the generator")
            dec = decompose(c)
            if dec is None:
                print(f"// skipped (no decomposition): {s}{p} {a} {b} {c}", file=sys.stderr)
                continue
            ks = dec[1]
            phase = b - sum(k * f[1] for k, f in zip(ks, FUND))
            per.setdefault(ks, {})[s] = (a, phase)
    # slow polynomials (least squares on Chebyshev nodes, monomials in tau), lowest degree whose
    # error over 1950-2100 is below SLOW_TOL
    x = np.cos(np.pi * (np.arange(400) + 0.5) / 400)
    taus = TAU_MIN + (x + 1) / 2 * (TAU_MAX - TAU_MIN)
    dense = np.linspace(TAU_MIN, TAU_MAX, 20001)
    polys = {}
    for s in ("L", "R"):
        def f(tt):
            y = np.zeros_like(tt)
            for p, a, b, c in slow[s]:
                y += a * np.cos(b + c * tt) * tt ** p
            return y
        for deg in range(0, 9):
            coef = np.polynomial.polynomial.polyfit(taus, f(taus), deg)
            err = np.abs(np.polynomial.polynomial.polyval(dense, coef) - f(dense)).max()
            if err < SLOW_TOL[s]:
                break
        polys[s] = (coef, err)
    out = []
    out.append("// BEGIN GENERATED by tools/sun_precise_gen.py from tests/data/vsop87_meeus_earth.csv: do not edit.")
    for s in ("L", "R"):
        coef, err = polys[s]
        unit = "rad" if s == "L" else "AU"
        out.append(f"/// Slow part of `{s}` (periods > 200 years, and the constants of the powers of tau above 1):")
        out.append(f"/// coefficients of tau^0..tau^{len(coef) - 1}, {unit}; fit error {err * 1e-8:.1e} {unit} over 1950-2100.")
        out.append(f"const SLOW_{s}: [f32; {len(coef)}] = [" + ", ".join(f32(v * 1e-8) for v in coef) + "];")
    for (s, k), pw in sorted(harm.items()):
        unit = "rad" if s == "L" else "AU"
        for j, name in ((0, "COS"), (1, "SIN")):
            cs = [pw.get(p, [0.0, 0.0])[j] for p in range(max(pw) + 1)]
            keep = [p for p, c in enumerate(cs) if abs(c) * TAU_MAX ** p >= HARM_TOL[s]]
            cs = cs[: (max(keep) + 1 if keep else 0)]
            trig = "cos" if j == 0 else "sin"
            out.append(f"/// `{s}`, terms of frequency {k}x{E_RATE} rad/millennium: coefficient of {trig}({k}M'), {unit}, tau^0..")
            out.append(f"const {s}{k}_{name}: [f32; {len(cs)}] = [" + ", ".join(f32(c * 1e-8) for c in cs) + "];")
    out.append("// Periodic terms: multipliers of (M', V, Ma, J, S, D); L: amplitude (rad), phase (2^-16 turn); R likewise (AU).")
    out.append("macro_rules! periodic_terms { ($t:ident) => {")
    for ks, d in sorted(per.items(), key=lambda kv: -max(v[0] for v in kv[1].values())):
        la, lp = d.get("L", (0.0, 0.0))
        ra, rp = d.get("R", (0.0, 0.0))
        out.append(f"    $t!([{', '.join(str(k) for k in ks)}], {f32(la * 1e-8)}, {wrap16(lp)}, {f32(ra * 1e-8)}, {wrap16(rp)});")
    out.append("}; }")
    out.append("// END GENERATED")
    text = "\n".join(out) + "\n"
    if "--write" in sys.argv:
        path = os.path.join(HERE, "..", "src", "env", "sun", "precise.rs")
        src = open(path).read()
        a = src.index("// BEGIN GENERATED")
        b = src.index("// END GENERATED")
        b = src.index("\n", b) + 1
        open(path, "w").write(src[:a] + text + src[b:])
    else:
        print(text, end="")


if __name__ == "__main__":
    main()
