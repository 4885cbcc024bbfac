#!/usr/bin/env python3
"""Counts the calls of chosen functions inside one benchmark case, in mspdebug's simulator.

Usage (after `firmware/msp430-bench --groups GROUP` has built the image):
    python3 firmware/tools/count_calls.py "SGP4 propagate" [FUNCTION ...]

FUNCTION is a demangled symbol name (`llvm-nm -C`) of the benchmark image
`firmware/target/msp430-none-elf/release/bench`; the default list is the f32 EABI helpers and the
`fmath` kernels. The case is found by its position among the begin/end marks (the case names in
the order of `firmware/bench-host`'s output, read from `target/msp430/bench.json`). Every call is
counted, nested ones included (the f32 multiplications inside `fmath::sincos` count as
multiplications). Breakpoints: mspdebug's simulator stops at each call, so this is slow (about a
second per thousand calls). `__mspabi_subf` flips the sign and falls through into
`__mspabi_addf`: count it in a run of its own (with both breakpoints set, each subtraction is
counted twice; with only `addf`'s, subtractions are not counted).
"""
import json
import os
import re
import subprocess
import sys
from collections import Counter

FW = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(FW)
ELF = os.path.join(FW, "target", "msp430-none-elf", "release", "bench")
DEFAULT = ["__mspabi_mpyf", "__mspabi_addf", "__mspabi_divf",
           "acs::fmath::sincos", "acs::fmath::sin", "acs::fmath::cos", "acs::fmath::sqrt",
           "acs::fmath::atan2", "<acs::orbit::Phase>::radians"]


def main():
    case = sys.argv[1]
    wanted = sys.argv[2:] or DEFAULT
    names = list(json.load(open(os.path.join(ROOT, "target", "msp430", "bench.json")))["functions"])
    # marks: "overhead" begin/end first, then each case in the JSON order
    index = ["overhead"] + names
    if case not in index:
        sys.exit("unknown case %r; known: %s" % (case, ", ".join(names)))
    marks_before = 2 * index.index(case) + 1
    nm = subprocess.run(["llvm-nm", "-C", ELF], capture_output=True, text=True, check=True).stdout
    addr = {}
    for line in nm.splitlines():
        parts = line.split(None, 2)
        if len(parts) == 3 and parts[2] in wanted:
            addr[parts[2]] = parts[0]
    raw = subprocess.run(["llvm-nm", ELF], capture_output=True, text=True, check=True).stdout
    label = {}  # the simulator prints mangled names: map them by address
    for line in raw.splitlines():
        parts = line.split(None, 2)
        if len(parts) == 3:
            label.setdefault(parts[0], parts[2])
    cmds = ["prog " + ELF, "setbreak bench_mark"] + ["run"] * marks_before
    cmds += ["setbreak 0x" + a for a in addr.values()] + ["run"] * 100000
    p = subprocess.Popen(["mspdebug", "-q", "-n", "sim"] + cmds, stdout=subprocess.PIPE,
                         stderr=subprocess.STDOUT, text=True)
    by_label = {label[a]: n for n, a in addr.items()}
    seen, counts = 0, Counter()
    for line in p.stdout:
        m = re.match(r"^([^\s(].*):$", line.rstrip("\n"))
        if not m:
            continue
        lab = m.group(1)
        if seen < marks_before:
            seen += lab == "bench_mark"
            continue
        if lab == "bench_mark":
            break
        if lab in by_label:
            counts[by_label[lab]] += 1
    p.kill()
    print("calls inside %r:" % case)
    for n in wanted:
        if n in addr:
            print("%8d  %s" % (counts[n], n))


if __name__ == "__main__":
    main()
