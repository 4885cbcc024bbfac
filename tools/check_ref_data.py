#!/usr/bin/env python3
"""Re-derive the reference files of `tests/data/` from the independent implementations they came
from, and print the largest difference per file (see `tests/data/README.md`).

    python3 -m venv /tmp/refcheck && /tmp/refcheck/bin/pip install ppigrf==2.1.0 sgp4 skyfield
    /tmp/refcheck/bin/python tools/check_ref_data.py

Checks (nothing is written; offline: skyfield's built-in timescale, no ephemeris file):
- `sgp4/*.e`: every row against Vallado's SGP4 as compiled by the `sgp4` package (gravity model
  from the file name, `tsince` = row time / 60); the `J2000` files after skyfield's TEME -> GCRS
  rotation at that instant.
- `igrf/igrf14_points.csv`: every point against ppigrf (`igrf` for north/east/down at the
  geodetic input, `igrf_gc` for br/btheta/bphi at the file's geocentric radius and colatitude).
- `attitude/wahba.json`: each `optimal_dcm` against the float64 SVD solution of its problem.
Not checked here: `sun/sun_de421.csv` (needs the DE421 ephemeris file), and the files that are
Vallado's published originals (`SGP4-VER.TLE`, `tcppver.out`; the crate's tests read them).
"""
import csv
import datetime
import glob
import json
import os
import sys
from importlib.metadata import version

import numpy as np

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data")


def stk_files():
    from sgp4.api import WGS72, WGS84, Satrec
    from skyfield.api import load
    from skyfield.sgp4lib import TEME

    ts = load.timescale(builtin=True)
    for path in sorted(glob.glob(os.path.join(DATA, "sgp4", "*.e"))):
        lines = open(path).read().splitlines()
        l1, l2 = (s.strip() for s in lines[1].split("TLE: ")[1].split("|"))
        j2000 = "CoordinateSystem J2000" in lines
        sat = Satrec.twoline2rv(l1, l2, WGS84 if "wgs84" in path else WGS72)
        start = lines.index("EphemerisTimePosVel") + 1
        dr = dv = 0.0
        n = 0
        for line in lines[start:]:
            if not line.strip() or line.startswith("END"):
                continue
            t, *row = (float(x) for x in line.split())
            err, r, v = sat.sgp4_tsince(t / 60.0)
            r, v = np.array(r) * 1e3, np.array(v) * 1e3
            if j2000:
                m = np.linalg.inv(TEME.rotation_at(ts.ut1_jd(sat.jdsatepoch + sat.jdsatepochF + t / 86400.0)))
                r, v = m @ r, m @ v
            dr = max(dr, np.max(np.abs(r - row[:3])))
            dv = max(dv, np.max(np.abs(v - row[3:])))
            n += 1
        print(f"sgp4/{os.path.basename(path)}: {n} rows, max |dr| {dr:.1e} m, max |dv| {dv:.1e} m/s "
              f"(sgp4 {version('sgp4')}, skyfield {version('skyfield')})")


def igrf_points():
    import ppigrf

    text = [l for l in open(os.path.join(DATA, "igrf", "igrf14_points.csv")) if not l.startswith("#")]
    worst = {}
    rows = list(csv.DictReader(text))
    for row in rows:
        x = {k: float(v) for k, v in row.items()}
        year = int(x["decimal_year"])
        start = datetime.datetime(year, 1, 1)
        date = start + (datetime.datetime(year + 1, 1, 1) - start) * (x["decimal_year"] - year)
        be, bn, bu = (float(np.ravel(c)[0]) for c in ppigrf.igrf(x["lon_deg"], x["lat_deg"], x["alt_km"], date))
        br, bt, bp = (
            float(np.ravel(c)[0]) for c in ppigrf.igrf_gc(x["r_km"], x["colat_deg"], x["lon_deg"], date)
        )
        for k, v in [("north_nt", bn), ("east_nt", be), ("down_nt", -bu), ("br_nt", br), ("btheta_nt", bt), ("bphi_nt", bp)]:
            worst[k] = max(worst.get(k, 0.0), abs(v - x[k]))
    print(f"igrf/igrf14_points.csv: {len(rows)} points, ppigrf {version('ppigrf')}, max |diff| nT:",
          ", ".join(f"{k} {v:.4f}" for k, v in worst.items()))


def wahba():
    problems = json.load(open(os.path.join(DATA, "attitude", "wahba.json")))["problems"]
    worst = 0.0
    for p in problems:
        b = sum(w * np.outer(bi, ri) for w, bi, ri in zip(p["weights"], p["body"], p["reference"]))
        u, _, vt = np.linalg.svd(b)
        a = u @ np.diag([1.0, 1.0, np.linalg.det(u) * np.linalg.det(vt)]) @ vt
        worst = max(worst, np.max(np.abs(a - np.array(p["optimal_dcm"]))))
    print(f"attitude/wahba.json: {len(problems)} problems, max |A_svd - optimal_dcm| {worst:.1e}")


if __name__ == "__main__":
    for check in (stk_files, igrf_points, wahba):
        try:
            check()
        except ImportError as e:
            print(f"{check.__name__}: skipped ({e})", file=sys.stderr)
