#!/usr/bin/env python3
"""The campaign results table of docs/campaigns.md (and README's key figure) from the
`summary.json` of campaigns run by `acs sim SCENARIO --runs N --seed S --out DIR`.

    python3 tools/campaign_table.py DIR...

prints one markdown row per requirement of each campaign: runs, pass rate, its 95 % lower
confidence bound (Clopper-Pearson), the 99th percentile and the maximum, and the worst runs.
"""
import json
import sys


def fmt(x):
    if isinstance(x, str):
        return x
    if x is None:
        return "—"
    if x == int(x) and abs(x) < 1e6:
        return f"{int(x)}"
    return f"{x:.4g}"


def main(dirs):
    print("| scenario | truth | requirement | runs | met | pass rate | 95 % lower bound | p99 | max | worst runs |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for d in dirs:
        s = json.load(open(f"{d}/summary.json"))
        for m in s["metrics"]:
            if m["requirement"] is None:
                continue
            worst = ", ".join(f"{w['run']}" for w in m["worst"][:3])
            print(
                f"| `{s['scenario']}` | {s['truth']} | {m['text']} {m['requirement']} | {s['runs']} "
                f"| {m['passes']} | {100 * m['pass_rate']:.2f} % | {100 * m['lower_bound']:.3f} % "
                f"| {fmt(m['p99'])} | {fmt(m['max'])} | {worst} |"
            )
        a = s["all_requirements"]
        print(
            f"| `{s['scenario']}` | {s['truth']} | **every requirement** | {s['runs']} | {a['passes']} "
            f"| {100 * a['pass_rate']:.2f} % | {100 * a['lower_bound']:.3f} % | | | |"
        )


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
