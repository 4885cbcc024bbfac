#!/usr/bin/env python3
"""Generate the f32 IGRF coefficient tables of `acs::env::igrf` from an IAGA `.shc` file.

Usage (from the crate root; Python 3 standard library only):

    python3 tools/igrf_gen.py            # rewrite src/env/igrf/tables.rs from data/igrf/IGRF14.shc
    python3 tools/igrf_gen.py --check    # exit 1 if the committed tables.rs is out of date
    python3 tools/igrf_gen.py --shc data/igrf/IGRF15.shc   # a new IGRF generation

A new IGRF generation is a one-file change: drop IAGA's `.shc` file into `data/igrf/`, point
`--shc` at it (or replace IGRF14.shc), rerun, and the tests against the new reference data.

The `.shc` format (IAGA, "spherical harmonic coefficients"): `#` comment lines, then a header
line `N_MIN N_MAX N_TIMES SPLINE_ORDER N_STEPS [START END]`, a line with the N_TIMES epochs
(decimal years), then one line per coefficient: `n m value_at_each_epoch...`, with m >= 0 for
g_n^m and m < 0 for h_n^|m|. In IGRF files the last epoch is the prediction made from the
secular variation (for IGRF-14: 2030.0 = IGRF-2025 + 5 yr x SV), so linear interpolation in the
last interval *is* the secular-variation extrapolation.

Output (`src/env/igrf/tables.rs`), all f32, every table a separate `static` so that the linker
keeps only the ones a firmware refers to:
- `BONNET`: (n - 1)/n for n = 2..N, Bonnet's recursion of the Legendre polynomials
  n P_n = (2n - 1) u P_{n-1} - (n - 1) P_{n-2}, written P_n = t + ((n - 1)/n) (t - P_{n-2})
  with t = u P_{n-1}.
- per interval between two epochs, an anchor and a delta `[f32; 195]` table: the anchor
  (`EPOCH_yyyy`) holds the Schmidt-scaled coefficients N_n^m g_n^m, N_n^m h_n^m at one end of
  the interval, the delta (`DELTA_yyyy_zzzz`) their change from that end (yyyy) to the other
  (zzzz), so that the evaluator interpolates with one multiplication and one addition per
  coefficient (g = anchor + f delta, f the fraction of the interval from the anchor). Every
  other epoch is an anchor, shared by the intervals on both sides of it, with the parity that
  makes the current main-field model (the second-to-last epoch, 2025.0 for IGRF-14) one: the
  last two intervals (RECENT) take three tables, as three snapshots would.
  N_n^0 = 1 and N_n^m = sqrt(2 (n - m)! / (n + m)!) for m >= 1, so that
  P_n^m(cos t) = N_n^m sin^m t d^m P_n(u)/du^m (the evaluator works with the unnormalised
  derivatives d^m P_n/du^m). Each entry is the f32 nearest to the exact product of N_n^m and
  the file's decimal value (anchor) or the exact difference of two of them (delta): 50-digit
  decimal arithmetic, then correct rounding to f32. The unscaled (m = 0, and n = 1) anchor
  entries are the file's numbers rounded once to f32. Column order:
      m = 0:       g_1^0, g_2^0, ..., g_N^0
      m = 1..N:    g_m^m, h_m^m, g_{m+1}^m, h_{m+1}^m, ..., g_N^m, h_N^m
  (column order lets the evaluator run the recursion in n for one order m at a time with a
  handful of scalars, walking the tables with iterators: no index arithmetic, no scratch arrays.)
- `FULL`: every interval of the file; `RECENT`: the last two (from the last definitive model
  through the current model to its secular-variation prediction); `FLIGHT`: the last interval
  (the current model to its prediction) at degree FLIGHT_DEGREE (13, the on-board model since
  issue #29: the reference node of the two-node split has room for it; the flight image carries
  2 tables of 195 f32, 1 560 B, instead of RECENT's 2 340 B). At the file's own degree the
  flight model names the same two tables as the last interval of `FULL` and `RECENT` (no copy);
  below it (degree 8 until #29: 640 B) it gets its own tables `EPOCH_yyyy_N<d>` and
  `DELTA_yyyy_zzzz_N<d>`, the same f32 values in the same column order for n <= d.
"""

import argparse
import decimal
import math
import os
import struct
import sys
from fractions import Fraction

decimal.getcontext().prec = 50

# Degree of the flight tables (`FLIGHT`): the on-board field model (`acs::flight::IGRF_DEGREE`);
# 8 until issue #29 (item 6), the full 13 since.
FLIGHT_DEGREE = 13
# years the flight tables are extrapolated past their last epoch (issue #19)
FLIGHT_EXTRAPOLATE_YEARS = 5

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DEFAULT_SHC = os.path.join(ROOT, "data", "igrf", "IGRF14.shc")
DEFAULT_OUT = os.path.join(ROOT, "src", "env", "igrf", "tables.rs")


def read_shc(path):
    """Returns (title, epochs, coeffs) with coeffs[(n, m)] = list of values (m<0: h)."""
    title = None
    header = None
    epochs = None
    tokens = {}
    with open(path, "r", encoding="ascii") as f:
        for line in f:
            s = line.strip()
            if not s:
                continue
            if s.startswith("#"):
                if title is None:
                    title = s.lstrip("# ").strip()
                continue
            if header is None:
                header = [int(x) for x in s.split()[:5]]
                continue
            if epochs is None:
                epochs = [float(x) for x in s.split()]
                continue
            parts = s.split()
            n, m = int(parts[0]), int(parts[1])
            values = parts[2:]
            if len(values) != len(epochs):
                raise SystemExit(f"{path}: coefficient ({n},{m}) has {len(values)} values, "
                                 f"expected {len(epochs)}")
            tokens[(n, m)] = values
    n_min, n_max, n_times = header[0], header[1], header[2]
    if n_min != 1 or n_times != len(epochs):
        raise SystemExit(f"{path}: unexpected header {header}")
    return title or os.path.basename(path), n_max, epochs, tokens


def f32_nearest(x):
    """The f32 nearest to the exact rational `x` (ties to even), as a Python float."""
    x = Fraction(x)
    c = struct.unpack("<f", struct.pack("<f", float(x)))[0]  # within one f32 step of x
    bits = struct.unpack("<I", struct.pack("<f", c))[0]
    best = None
    for b in (bits - 1, bits, bits + 1):
        if not 0 <= b < 0x7F800000 and not 0x80000000 <= b < 0xFF800000:
            continue
        v = struct.unpack("<f", struct.pack("<I", b))[0]
        key = (abs(Fraction(v) - x), b & 1)
        if best is None or key < best[0]:
            best = (key, v)
    return best[1]


def rust_f32(value):
    """The shortest decimal literal that Rust parses to the f32 `value` (exact round trip)."""
    if value == 0.0:
        return "-0.0" if math.copysign(1.0, value) < 0 else "0.0"
    for digits in range(1, 10):
        t = f"{value:.{digits}g}"
        if struct.unpack("<f", struct.pack("<f", float(t)))[0] == value and \
                f32_nearest(Fraction(decimal.Decimal(t))) == value:
            break
    if "e" in t and abs(value) >= 1.0:
        t = format(decimal.Decimal(t), "f")  # 7e+01 -> 70
    if "e" not in t and "." not in t:
        t += ".0"
    return t


def column_order(n_max):
    """(n, m) pairs in column order (m outer, n inner)."""
    order = []
    for m in range(0, n_max + 1):
        for n in range(max(m, 1), n_max + 1):
            order.append((n, m))
    return order


def schmidt(n, m):
    """N_n^m to 50 digits (exactly 1 for m = 0)."""
    if m == 0:
        return decimal.Decimal(1)
    return (decimal.Decimal(2 * math.factorial(n - m)) / math.factorial(n + m)).sqrt()


def year_label(y):
    return f"{y:.1f}"


def generate(shc_path):
    title, n_max, epochs, tokens = read_shc(shc_path)
    steps = {round(b - a, 6) for a, b in zip(epochs, epochs[1:])}
    if len(steps) != 1:
        raise SystemExit(f"epochs are not evenly spaced: {epochs}")
    step = steps.pop()
    if step != int(step) or any(e != int(e) for e in epochs):
        raise SystemExit("epochs must be whole years with a whole-year step")
    n_coeffs = n_max * (n_max + 2)
    order = column_order(n_max)
    shc_rel = os.path.relpath(shc_path, ROOT)

    out = []
    w = out.append
    w(f"//! GENERATED by `tools/igrf_gen.py` from `{shc_rel}` ({title}): do not edit.")
    w("//!")
    w("//! Regenerate with `python3 tools/igrf_gen.py` (check with `--check`). Layout and")
    w("//! formulas: see the script's docstring and [`super`].")
    w("// The tables are data: each value is the nearest f32, in its shortest exact decimal form.")
    w("#![allow(clippy::excessive_precision, clippy::unreadable_literal)]")
    w("")
    w("use super::{Interval, Model};")
    w("")
    w(f"/// Maximum degree N of the tables.")
    w(f"pub(super) const N_MAX: usize = {n_max};")
    w(f"/// Number of Gauss coefficients per epoch, N(N+2).")
    w(f"pub(super) const N_COEFFS: usize = {n_coeffs};")
    w("")
    w("/// Bonnet's recursion constants (n - 1)/n for n = 2..=N_MAX.")
    w(f"pub(super) static BONNET: [f32; N_MAX - 1] = [")
    for n in range(2, n_max + 1):
        w(f"    {rust_f32(f32_nearest(Fraction(n - 1, n)))}, // n={n}")
    w("];")
    w("")
    # Anchors: every other epoch, with the parity that makes the second-to-last epoch (the
    # current main-field model) one, so that the last two intervals share it.
    parity = (len(epochs) - 2) % 2
    intervals = []  # (anchor index, other index) per interval
    for k in range(len(epochs) - 1):
        anchor = k if k % 2 == parity else k + 1
        intervals.append((anchor, k + 1 if anchor == k else k))

    def table(name, doc, value, degree=n_max):
        w(f"/// {doc}")
        size = "N_COEFFS" if degree == n_max else str(degree * (degree + 2))
        w(f"static {name}: [f32; {size}] = [")
        for n, m in column_order(degree):
            norm = schmidt(n, m)
            g = rust_f32(f32_nearest(Fraction(value(n, m) * norm)))
            if m == 0:
                w(f"    {g}, // g{n},{m}")
            else:
                h = rust_f32(f32_nearest(Fraction(value(n, -m) * norm)))
                w(f"    {g}, {h}, // g{n},{m} h{n},{m}")
        w("];")
        w("")

    def dec(n, m, k):
        return decimal.Decimal(tokens[(n, m)][k])

    recent = list(range(len(epochs) - 3, len(epochs)))

    def suffix(degree):
        return "" if degree == n_max else f"_N{degree}"

    def tables_of(idx, degree):
        ks = range(idx[0], idx[-1])
        for i in sorted({intervals[k][0] for k in ks}):
            table(f"EPOCH_{int(epochs[i])}{suffix(degree)}",
                  f"Schmidt-scaled Gauss coefficients N g, N h (nT) at {year_label(epochs[i])}, "
                  f"column order, n <= {degree}.",
                  lambda n, m, i=i: dec(n, m, i), degree)
        for k in ks:
            a_, o = intervals[k]
            table(f"DELTA_{int(epochs[a_])}_{int(epochs[o])}{suffix(degree)}",
                  f"Schmidt-scaled change N Δg, N Δh (nT) from {year_label(epochs[a_])} to "
                  f"{year_label(epochs[o])}, column order, n <= {degree}.",
                  lambda n, m, a_=a_, o=o: dec(n, m, o) - dec(n, m, a_), degree)

    tables_of(list(range(len(epochs))), n_max)
    current = list(range(len(epochs) - 2, len(epochs)))
    if FLIGHT_DEGREE > n_max:
        raise SystemExit(f"FLIGHT_DEGREE {FLIGHT_DEGREE} is above the file's degree {n_max}")
    if FLIGHT_DEGREE < n_max:
        # truncated copies; at the file's degree the flight model shares the full tables
        tables_of(current, FLIGHT_DEGREE)

    def model(name, idx, doc, degree=n_max, extrapolate=0):
        first, last = epochs[idx[0]], epochs[idx[-1]]
        ks = range(idx[0], idx[-1])
        n_tables = len({intervals[k][0] for k in ks}) + len(ks)
        count = degree * (degree + 2)
        size = n_tables * count * 4
        w(f"/// {doc}")
        w("///")
        w(f"/// {title}: epochs {year_label(first)} to {year_label(last)} every {int(step)} years, "
          f"degree {degree} ({n_tables} tables of {count} f32, {size} bytes of flash, plus "
          f"{(n_max - 1) * 4} bytes of constants shared by all models).")
        w(f"pub static {name}: Model = Model {{")
        w(f"    name: {title.split(' --')[0].replace(' ', '-')!r},".replace("'", '"'))
        w(f"    first_year: {int(first)},")
        w(f"    step_years: {int(step)},")
        w(f"    degree: {degree},")
        w(f"    extrapolate_years: {float(extrapolate)!r},")
        w("    intervals: &[")
        for k in ks:
            a_, o = intervals[k]
            sfx = suffix(degree)
            w(f"        Interval {{ anchor: &EPOCH_{int(epochs[a_])}{sfx}, "
              f"delta: &DELTA_{int(epochs[a_])}_{int(epochs[o])}{sfx}, from_end: {str(a_ > k).lower()} }},")
        w("    ],")
        w("};")
        w("")

    model("FULL", list(range(len(epochs))),
          "The whole model: every epoch of the file (for the host, the tests and mission analysis).")
    model("RECENT", recent,
          "The last definitive model, the current model and its secular-variation prediction, "
          "at full degree.")
    model("FLIGHT", current,
          f"The flight tables: the current model and its secular-variation prediction (the last "
          f"interval of [`RECENT`]: a mission flown after its epoch needs no earlier one) "
          + (f"at full degree ({n_max}; the same tables, issue #29) " if FLIGHT_DEGREE == n_max
             else f"truncated at degree {FLIGHT_DEGREE} ")
          + "(the flight image carries only what it evaluates; issue #17). Past its last epoch "
          f"the secular variation is extrapolated for {FLIGHT_EXTRAPOLATE_YEARS} more years, "
          "flagged ([`super::Igrf::is_extrapolated`]; issue #19): a mission must not lose its field "
          "reference on the day the tables end.",
          FLIGHT_DEGREE, FLIGHT_EXTRAPOLATE_YEARS)
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--shc", default=DEFAULT_SHC, help="IAGA .shc coefficient file")
    ap.add_argument("--out", default=DEFAULT_OUT, help="generated Rust file")
    ap.add_argument("--check", action="store_true", help="fail if --out is not up to date")
    args = ap.parse_args()
    text = generate(args.shc)
    if args.check:
        try:
            with open(args.out, "r", encoding="utf-8") as f:
                current = f.read()
        except FileNotFoundError:
            current = None
        if current != text:
            print(f"{args.out} is out of date: run python3 tools/igrf_gen.py", file=sys.stderr)
            return 1
        print(f"{args.out} is up to date")
        return 0
    with open(args.out, "w", encoding="utf-8") as f:
        f.write(text)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
