#!/usr/bin/env python3
"""The figures of docs/campaigns.md's "What the campaigns found", from the `runs.csv` of
campaigns run by `acs sim SCENARIO --runs N --seed S --out DIR`.

    python3 tools/campaign_findings.py DIR...

For each DIR (its scenario read from `campaign.json`):
- `tracking`: the runs that fall back to SunSafe (the eclipse season), the spread of their
  epochs (days after the scenario's epoch), and the worst error after settling of the others
  (percentiles by nearest rank; a run without an "after" window counts as infinite);
- `detumble`: the time first below 0.5 deg/s (median, worst) and the runs whose rate at the end
  is not below 0.5 deg/s;
- `thesis-slew-noisy`: the runs that fall back during the plan, and the pointing error at the
  end of the plan (median);
- `sun-safe`: the runs and their requirement verdicts.
"""
import csv
import json
import math
import sys


def rank(values, p):
    """Nearest-rank percentile p (0-100) of values (inf sorts last)."""
    v = sorted(values)
    if not v:
        return math.nan
    k = max(1, math.ceil(p / 100.0 * len(v)))
    return v[k - 1]


def load(d):
    with open(f"{d}/runs.csv") as f:
        rows = list(csv.DictReader(f))
    scenario = json.load(open(f"{d}/campaign.json")).get("scenario", "?")
    return scenario, rows


def num(r, k):
    x = r.get(k, "")
    return float(x) if x not in ("", None) else math.nan


def tracking(d, rows):
    back = [r for r in rows if num(r, "fallbacks") > 0]
    days = sorted(num(r, "epoch_offset_days") for r in back)
    inside = [x for x in days if 30.0 <= x <= 150.0]
    print(f"{d}: tracking, {len(rows)} runs: {len(back)} fall back to SunSafe; their epochs "
          f"{days[0]:.1f}-{days[-1]:.1f} days after the scenario's (p1 {rank(days, 1):.1f}, "
          f"p99 {rank(days, 99):.1f}); {len(days) - len(inside)} outside 30-150 days")
    stay = [num(r, "error_after_settling_deg") for r in rows if num(r, "fallbacks") == 0]
    inf = sum(1 for x in stay if math.isinf(x))
    print(f"  the other {len(stay)}: worst error after settling p50 {rank(stay, 50):.3f} deg, "
          f"p95 {rank(stay, 95):.3f}, p99 {rank(stay, 99):.3f}; {inf} without an after window (inf)")


def detumble(d, rows):
    below = [num(r, "detumble_time_s") for r in rows]
    end = [num(r, "final_rate_degps") for r in rows]
    over = [int(r["run"]) for r, x in zip(rows, end) if not x < 0.5]
    print(f"{d}: detumble, {len(rows)} runs: first below 0.5 deg/s p50 {rank(below, 50):.0f} s, "
          f"max {max(below):.0f} s; rate at the end not below 0.5 deg/s in {len(over)} runs "
          f"(max {max(end):.3f} deg/s): {over[:40]}")


def thesis(d, rows):
    back = [r for r in rows if num(r, "fallbacks") > 0]
    end = [num(r, "plan_end_error_deg") for r in rows]
    print(f"{d}: thesis-slew-noisy, {len(rows)} runs: {len(back)} fall back during the plan; "
          f"error at the end of the plan p50 {rank(end, 50):.2f} deg")


def other(d, scenario, rows):
    met = sum(1 for r in rows if r["met"] == "1")
    umbra = ""
    if rows and "umbra_s" in rows[0]:
        u = [num(r, "umbra_s") for r in rows]
        umbra = f"; umbra held {min(u):.0f}-{max(u):.0f} s a run"
    print(f"{d}: {scenario}, {len(rows)} runs, every requirement met in {met}{umbra}")


def main(dirs):
    for d in dirs:
        scenario, rows = load(d)
        if scenario == "tracking":
            tracking(d, rows)
        elif scenario == "detumble":
            detumble(d, rows)
        elif scenario == "thesis-slew-noisy":
            thesis(d, rows)
        else:
            other(d, scenario, rows)


if __name__ == "__main__":
    main(sys.argv[1:])
