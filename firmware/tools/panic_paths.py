#!/usr/bin/env python3
"""Panic paths of an MSP430 image: the functions that call into `core::panicking` (or any
symbol with `panic` in its name), from the disassembly.

usage: panic_paths.py ELF

The flight image's panic handler calls an undefined symbol, so a normal link fails as soon as a
panic is reachable, but the linker names only the handler. This names the callers (a bounds
check, an `unwrap`, a division by zero the optimiser could not remove), also in a sim-only link
beyond 64 KB (`loop-image`), where the 16-bit call operands wrap. Exit 1 if there is any.
"""
import re
import subprocess
import sys

elf = sys.argv[1]
nm = subprocess.run(["llvm-nm", "-n", "-C", elf], capture_output=True, text=True, check=True).stdout
panics, undefined = {}, []
for line in nm.splitlines():
    p = line.split(None, 2)
    if len(p) == 2 and p[0] == "U" and "panic" in p[1]:
        undefined.append(p[1])
    if len(p) == 3 and p[1].lower() == "t" and "panic" in p[2]:
        panics[int(p[0], 16) & 0xFFFF] = p[2]
if not panics and not undefined:
    print("no panic path")
    sys.exit(0)
dis = subprocess.run(["llvm-objdump", "-d", "--no-show-raw-insn", "-C", elf],
                     capture_output=True, text=True, check=True).stdout
fn, callers = None, set()
for line in dis.splitlines():
    m = re.match(r"^([0-9a-f]+) <(.*)>:", line)
    if m:
        fn = m.group(2)
        continue
    m = re.search(r"\t(call|br)\s+#(\d+)$", line)
    if m and fn and "panic" not in fn and (int(m.group(2)) & 0xFFFF) in panics:
        callers.add((fn, panics[int(m.group(2)) & 0xFFFF]))
print("PANIC PATHS: %s" % ", ".join(sorted(set(panics.values()) | set(undefined))))
for caller, target in sorted(callers):
    print("  %s -> %s" % (caller[:400], target))
sys.exit(1)
