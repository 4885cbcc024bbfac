#!/usr/bin/env python3
"""Static worst-case stack depth of an MSP430 image, from its disassembly.

usage: stack_depth.py ELF [ROOT ...] [--callees FN ...]   (default root: main)
       --callees: also print the depth through each direct callee of FN (where to look next)

For every function: its frame = 2 B of return address + 2 B per `push` + `n` of `sub #n, r1`
(and `add #-n, r1`) in the function body; then the deepest path of the direct call graph
(`call #addr`, and `br #addr` tail calls) from each root. In a sim-only link with a ROM beyond
64 KB (to measure an image that does not fit) the 16-bit call operands wrap: every function
starting at `addr + k·0x10000` is then taken as a possible callee (conservative). Indirect calls (`call rN`, `call @rN`, `call n(rN)`) and
recursion are reported, since they would make the bound unsound. Prints the deepest chain.
"""
import re
import subprocess
import sys

args = sys.argv[1:]
expand = []
if "--callees" in args:
    i = args.index("--callees")
    args, expand = args[:i], args[i + 1:]
elf = args[0]
roots = args[1:] or ["main"]
dis = subprocess.run(["llvm-objdump", "-d", "--no-show-raw-insn", "-C", elf],
                     capture_output=True, text=True, check=True).stdout
syms = {}
for line in subprocess.run(["llvm-nm", "-n", "-C", elf], capture_output=True, text=True,
                           check=True).stdout.splitlines():
    p = line.split(None, 2)
    if len(p) == 3 and p[1].lower() == "t":
        syms[int(p[0], 16)] = p[2]

frame, calls, indirect = {}, {}, {}
fn = None
for line in dis.splitlines():
    m = re.match(r"^([0-9a-f]+) <(.*)>:", line)
    if m:
        fn = m.group(2)
        frame[fn] = 2  # return address
        calls[fn] = set()
        continue
    if fn is None:
        continue
    ins = line.split("\t")[1:] if "\t" in line else []
    txt = " ".join(x.strip() for x in ins)
    if re.match(r"^push(\.w)?\s", txt):
        frame[fn] += 2
    m = re.match(r"^sub(\.w)?\s+#(\d+), r1$", txt)
    if m:
        frame[fn] += int(m.group(2))
    m = re.match(r"^add(\.w)?\s+#-(\d+), r1$", txt)
    if m:
        frame[fn] += int(m.group(2))
    m = re.match(r"^(call|br)\s+#(\d+)$", txt)
    if m:
        for k in range(8):
            target = syms.get(int(m.group(2)) + k * 0x10000)
            if target and target != fn:
                calls[fn].add(target)
    elif txt.startswith("call"):
        indirect.setdefault(fn, []).append(txt)

memo, warnings = {}, []


def depth(f, path):
    if f in path:
        warnings.append("recursion: " + " -> ".join(path + [f]))
        return 0, []
    if f in memo:
        return memo[f]
    best, chain = 0, []
    for c in calls.get(f, ()):
        d, ch = depth(c, path + [f])
        if d > best:
            best, chain = d, ch
    memo[f] = (frame.get(f, 0) + best, [f] + chain)
    return memo[f]


for r in roots:
    d, chain = depth(r, [])
    print(f"{r}: worst-case stack {d} B")
    for f in chain:
        print(f"  {frame.get(f, 0):5d}  {f[:110]}")
for f in expand:
    matches = [g for g in frame if f in g]
    for g in matches[:3]:
        print(f"{g[:110]}: frame {frame[g]} B; through each callee:")
        for c in sorted(calls.get(g, ()), key=lambda c: -depth(c, [g])[0]):
            print(f"  {depth(c, [g])[0]:5d}  {c[:110]}")
for f, c in indirect.items():
    warnings.append(f"indirect call in {f[:80]}: {c[0]}")
for w in sorted(set(warnings)):
    print("WARNING:", w)
