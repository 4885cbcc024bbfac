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
- `SCHMIDT`: the Schmidt semi-normalisation factor of every term, in the column order
  described below: N_n^0 = 1, N_n^m = sqrt(2 (n - m)! / (n + m)!) for m >= 1, so that
  P_n^m(cos t) = N_n^m sin^m t d^m P_n(u)/du^m (the evaluator works with the unnormalised
  derivatives d^m P_n/du^m and folds N_n^m into the coefficients once per date);
- `BONNET`: ((2n - 1)/n, (n - 1)/n) for n = 2..N, Bonnet's recursion of the Legendre
  polynomials n P_n = (2n - 1) u P_{n-1} - (n - 1) P_{n-2}.
- one `[f32; 195]` snapshot per epoch, coefficients in column order:
      m = 0:       g_1^0, g_2^0, ..., g_N^0
      m = 1..N:    g_m^m, h_m^m, g_{m+1}^m, h_{m+1}^m, ..., g_N^m, h_N^m
  (column order lets the evaluator run the recursion in n for one order m at a time with a
  handful of scalars, walking the tables with iterators: no index arithmetic, no scratch arrays.)
- `FULL`: every epoch of the file; `RECENT`: the last three epochs (last definitive model,
  current model, and its secular-variation prediction).
"""

import argparse
import math
import os
import sys

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


def rust_f32(token):
    """A Rust f32 literal for a decimal token from the file (kept verbatim: exact decimal)."""
    float(token)  # validate
    t = token
    if "." not in t and "e" not in t.lower():
        t += ".0"
    if t.startswith("."):
        t = "0" + t
    if t.startswith("-."):
        t = "-0" + t[1:]
    return t


def column_order(n_max):
    """(n, m) pairs in column order (m outer, n inner)."""
    order = []
    for m in range(0, n_max + 1):
        for n in range(max(m, 1), n_max + 1):
            order.append((n, m))
    return order


def schmidt_factors(n_max):
    rows = []
    for n, m in column_order(n_max):
        if m == 0:
            rows.append((n, m, 1.0))
        else:
            rows.append((n, m, math.sqrt(2.0 * math.factorial(n - m) / math.factorial(n + m))))
    return rows


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
    norm = schmidt_factors(n_max)
    shc_rel = os.path.relpath(shc_path, ROOT)

    out = []
    w = out.append
    w(f"//! GENERATED by `tools/igrf_gen.py` from `{shc_rel}` ({title}): do not edit.")
    w("//!")
    w("//! Regenerate with `python3 tools/igrf_gen.py` (check with `--check`). Layout and")
    w("//! formulas: see the script's docstring and [`super`].")
    w("// The tables are data: keep every digit as written in the source file.")
    w("#![allow(clippy::excessive_precision, clippy::unreadable_literal)]")
    w("")
    w("use super::Model;")
    w("")
    w(f"/// Maximum degree N of the tables.")
    w(f"pub(super) const N_MAX: usize = {n_max};")
    w(f"/// Number of Gauss coefficients per epoch, N(N+2).")
    w(f"pub(super) const N_COEFFS: usize = {n_coeffs};")
    w(f"/// Number of (n, m) terms, one recursion entry each.")
    w(f"pub(super) const N_TERMS: usize = {len(order)};")
    w("")
    w("/// Schmidt semi-normalisation factors N_n^m in column order: 1 for m = 0,")
    w("/// sqrt(2 (n - m)! / (n + m)!) for m >= 1.")
    w(f"pub(super) static SCHMIDT: [f32; N_TERMS] = [")
    for n, m, f in norm:
        w(f"    {f!r}, // n={n} m={m}")
    w("];")
    w("")
    w("/// Bonnet's recursion constants ((2n - 1)/n, (n - 1)/n) for n = 2..=N_MAX.")
    w(f"pub(super) static BONNET: [[f32; 2]; N_MAX - 1] = [")
    for n in range(2, n_max + 1):
        w(f"    [{(2 * n - 1) / n!r}, {(n - 1) / n!r}], // n={n}")
    w("];")
    w("")
    names = []
    for k, epoch in enumerate(epochs):
        name = f"EPOCH_{int(epoch)}"
        names.append(name)
        w(f"/// Gauss coefficients (nT) at {year_label(epoch)}, column order.")
        w(f"static {name}: [f32; N_COEFFS] = [")
        for n, m in order:
            g = rust_f32(tokens[(n, m)][k])
            if m == 0:
                w(f"    {g}, // g{n},{m}")
            else:
                h = rust_f32(tokens[(n, -m)][k])
                w(f"    {g}, {h}, // g{n},{m} h{n},{m}")
        w("];")
        w("")

    def model(name, idx, doc):
        first, last = epochs[idx[0]], epochs[idx[-1]]
        size = len(idx) * n_coeffs * 4
        w(f"/// {doc}")
        w("///")
        w(f"/// {title}: epochs {year_label(first)} to {year_label(last)} every {int(step)} years "
          f"({len(idx)} tables of {n_coeffs} f32, {size} bytes of flash, plus "
          f"{len(order) * 4 + (n_max - 1) * 8} bytes of constants shared by all models).")
        w(f"pub static {name}: Model = Model {{")
        w(f"    name: {title.split(' --')[0].replace(' ', '-')!r},".replace("'", '"'))
        w(f"    first_year: {int(first)},")
        w(f"    step_years: {int(step)},")
        w(f"    snapshots: &[{', '.join('&' + names[i] for i in idx)}],")
        w("};")
        w("")

    model("FULL", list(range(len(epochs))),
          "The whole model: every epoch of the file (for the host, the tests and mission analysis).")
    model("RECENT", list(range(len(epochs) - 3, len(epochs))),
          "The flight default: the last definitive model, the current model and its "
          "secular-variation prediction.")
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
