#!/usr/bin/env python3
"""Code bytes of an MSP430 image by `acs` module.

usage: code_by_module.py ELF [N]   (N: rows to print, default 40)

Every instruction's bytes go to the outermost `acs::` function of its inlining chain (from the
debug line tables, `llvm-symbolizer --inlining`), outside the loop itself (`acs_loop`) when the
chain has one; code with no `acs` frame goes to its symbol (`[lib] ...`: the EABI helpers,
compiler-builtins, libm), and so does every byte of a function of the firmware crate
(`acs_firmware::...`), whatever it inlined (its inlining frames depend on the checkout's path). Needs the image's debug information
(the firmware's release profile keeps it; it is not loaded into flash).
"""
import collections
import re
import subprocess
import sys

elf = sys.argv[1]
rows_to_print = int(sys.argv[2]) if len(sys.argv) > 2 else 40
dis = subprocess.run(["llvm-objdump", "-d", "--no-show-raw-insn", "-C", elf],
                     capture_output=True, text=True, check=True).stdout
rows, fn = [], None
for line in dis.splitlines():
    m = re.match(r"^([0-9a-f]+) <(.*)>:", line)
    if m:
        fn = m.group(2)
        continue
    m = re.match(r"^\s*([0-9a-f]+):\s", line)
    if m:
        rows.append((int(m.group(1), 16), fn))
# instruction sizes from consecutive addresses (MSP430 instructions are 2-8 bytes)
insns = [(rows[i][0], rows[i + 1][0] - rows[i][0], rows[i][1]) for i in range(len(rows) - 1)
         if 0 < rows[i + 1][0] - rows[i][0] <= 8]
query = "\n".join(hex(a) for a, _, _ in insns) + "\n"
out = subprocess.run(["llvm-symbolizer", "--obj=" + elf, "--inlining", "--functions=linkage",
                      "-C"], input=query, capture_output=True, text=True, check=True).stdout
by_module = collections.Counter()
for (_, size, symbol), block in zip(insns, out.split("\n\n")):
    lines = [l for l in block.strip().split("\n") if l]
    names = [lines[j] for j in range(0, len(lines) - 1, 2)]
    acs = [f for f in names if "acs::" in f and "acs_firmware" not in f.split("<")[0]]
    if (symbol or "").startswith("acs_firmware::"):
        # a function of the firmware crate keeps every byte, what it inlined too: which of its
        # inlined frames its debug information keeps varies with the crates' hashes, and so with
        # the path of the checkout (cargo hashes the path of `acs`, a dependency outside the
        # firmware's workspace)
        acs = []
    if acs:
        outside_loop = [f for f in acs if "acs_loop" not in f]
        f = outside_loop[-1] if outside_loop else acs[-1]
        m = re.search(r"acs::([a-z_0-9]+(::[a-z_0-9]+)?)", f)
        key = m.group(1) if m else f[:40]
    else:
        key = "[lib] " + (symbol or "?")[:70]
    by_module[key] += size
for key, size in by_module.most_common(rows_to_print):
    print(f"{size:7d}  {key}")
print(f"{sum(by_module.values()):7d}  total code")
