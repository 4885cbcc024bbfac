#!/usr/bin/env python3
"""Rejects the comparisons that are wrong for a NaN operand on the MSP430 in flight code.

On the MSP430 LLVM lowers every float comparison to one call of `__mspabi_cmpf` and a sign test:
for a NaN operand `a < b` and `a <= b` are TRUE, while `==`, `!=`, `>`, `>=` are correct
(`firmware/eabi/README.md`, "NaN and comparisons"); `f32::min`, `max` and `clamp` are built on
such comparisons (or on `fminf`, ≈ 100 B). Host tests cannot see this, so flight code writes
`b > a` for `a < b`, `b >= a` for `a <= b`, and `acs::fmath::{min, max, clamp}` (written with
`>` only). The check is textual (it cannot tell floats from integers), so integer comparisons
are written the same way (`core::cmp::{min, max}` for integers).

Scans the flight modules (FLIGHT below) outside comments, string and char literals and
`#[cfg(test)]` items, and fails (exit 1, one `file:line: text` per hit) on:
  - a binary ` < ` or ` <= ` (rustfmt puts spaces around binary operators and none inside
    generics, `Option<T>`; `<<`, `<<=`, `->` and `=>` are not matched; a `<`/`<=` that starts
    or ends a line, where rustfmt breaks a long expression, is matched);
  - `.min(`, `.max(`, `.clamp(`, `f32::min`, `f32::max`, `f32::clamp` (and the `f64::` forms);
  - `.partial_cmp(` (core implements it with `<=`/`>=`, it may answer `Less` for a NaN);
  - a range's `.contains(` (`(lo..=hi).contains(&x)` is `lo <= x && x <= hi`);
  - a float literal or `f32::`/`consts::` constant left of ` > `/` >= ` (`0.0 > x`: LLVM compiles
    it as `x < 0.0`); other constants cannot be told from integers here, `--ir` catches them.
ALLOW lists the exceptions: (file, function) pairs, kept minimal.

The source rule is not enough by itself: LLVM moves a constant to the right of a comparison
(`0.0 > x` becomes `x < 0.0`, wrong again on the MSP430) and may swap two operands of different
kinds. `--ir` checks what reaches the code generator: it builds the flight image
(`firmware/`, the flags of `firmware/tools/loop-image`) with its optimised LLVM IR and fails on
any `fcmp olt`, `ole`, `ugt` or `uge` (the predicates the MSP430 evaluates wrongly for a NaN:
`ogt`, `oge`, `ult`, `ule`, `oeq`, `une`, `one`, `ueq`, `ord`, `uno` are correct), printing the
source line of each (from the IR's debug locations). `--ir FILE.ll` checks a given IR file.

usage: tools/float_compare_check.py [--ir [FILE.ll]]   (from anywhere; exit 0 when clean)
"""
import os
import re
import sys

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

# The flight modules: every file of the `acs` library under src/ that the no_std flight build
# compiles, i.e. everything except src/host/ (feature `host`), src/bin/ (the host tool) and
# src/planning/ (host-side planner maths: compiled by the no_std build but linked by neither the
# firmware nor any flight module; `firmware/tools/loop-image` lists no `planning` code, and the
# image's debug line tables name no file of it). Files the firmware does not link today (triad,
# quest, frames, tle, ...) are kept: they are flight-library code a firmware may link tomorrow.
# When a module is added under src/, add it here (the check fails on a file it does not know).
FLIGHT = [
    "src/lib.rs",
    "src/acs_loop.rs",
    "src/attitude_node/mod.rs",
    "src/attitude_node/actuation.rs",
    "src/attitude_node/estimation.rs",
    "src/attitude_node/faults.rs",
    "src/attitude_node/laws.rs",
    "src/attitude_node/modes.rs",
    "src/attitude_node/health.rs",
    "src/attitude_node/sensing.rs",
    "src/attitude_node/health.rs",
    "src/attitude_node/stuck.rs",
    "src/link/mod.rs",
    "src/link/messages.rs",
    "src/two_node.rs",
    "src/telemetry.rs",
    "src/reference_node/mod.rs",
    "src/reference_node/guidance.rs",
    "src/reference_node/models.rs",
    "src/attitude.rs",
    "src/control/mod.rs",
    "src/control/bdot.rs",
    "src/control/disturbance.rs",
    "src/control/magnetorquer.rs",
    "src/control/principal_axes.rs",
    "src/control/sizing.rs",
    "src/control/slew.rs",
    "src/control/slew_trajectory.rs",
    "src/control/sun_safe.rs",
    "src/control/tracking.rs",
    "src/control/wheels.rs",
    "src/determination/mod.rs",
    "src/determination/mekf.rs",
    "src/determination/least_squares.rs",
    "src/determination/pseudoinverse.rs",
    "src/determination/quest.rs",
    "src/determination/sun_sensor.rs",
    "src/determination/triad.rs",
    "src/determination/wahba_svd.rs",
    "src/env/mod.rs",
    "src/env/albedo.rs",
    "src/env/dipole.rs",
    "src/env/eclipse.rs",
    "src/env/igrf.rs",
    "src/env/igrf/tables.rs",
    "src/env/sun/mod.rs",
    "src/env/sun/precise.rs",
    "src/env/sun/schlyter.rs",
    "src/flight.rs",
    "src/fmath.rs",
    "src/frames/mod.rs",
    "src/frames/j2000.rs",
    "src/frames/nutation.rs",
    "src/frames/real.rs",
    "src/hal/mod.rs",
    "src/hal/drivers.rs",
    "src/hal/bus.rs",
    "src/hal/link.rs",
    "src/hal/msp430/mod.rs",
    "src/hal/msp430/element_store.rs",
    "src/hal/msp430/flash.rs",
    "src/hal/msp430/gpio.rs",
    "src/hal/msp430/pwm.rs",
    "src/hal/msp430/timer_a.rs",
    "src/hal/msp430/usci_i2c.rs",
    "src/hal/msp430/usci_uart.rs",
    "src/hal/msp430/tile_bus.rs",
    "src/linalg/mod.rs",
    "src/linalg/lsq.rs",
    "src/linalg/pseudoinverse.rs",
    "src/linalg/svd.rs",
    "src/link/mod.rs",
    "src/link/cobs.rs",
    "src/link/crc16.rs",
    "src/link/pus.rs",
    "src/link/sequence.rs",
    "src/link/space_packet.rs",
    "src/orbit/mod.rs",
    "src/orbit/dfloat.rs",
    "src/orbit/kepler.rs",
    "src/orbit/sgp4/mod.rs",
    "src/orbit/sgp4/init.rs",
    "src/orbit/sgp4/propagate.rs",
    "src/orbit/sgp4/words.rs",
    "src/tiles.rs",
    "src/time.rs",
    "src/tle.rs",
    "src/uplink/mod.rs",
    "src/uplink/telecommand.rs",
]
# Not flight code (see above).
NOT_FLIGHT_DIRS = ("src/host/", "src/bin/", "src/planning/")

# (file, function): the NaN-safe helpers themselves may use what they replace.
ALLOW = set()

OPERATOR = re.compile(r"(?:^|\s)<=?(?=\s|$)")
CALL = re.compile(r"\.(?:min|max|clamp|partial_cmp)\(|\bf(?:32|64)::(?:min|max|clamp)\b"
                  r"|\.\.=?[^;]*\)\.contains\(")
CONST_LEFT = re.compile(r"(?:^|[\s(!&|])-?(?:\d[\d_]*\.\d[\d_]*(?:e-?\d+)?(?:f32|f64)?"
                        r"|\d[\d_]*(?:e-?\d+|f32|f64)"
                        r"|(?:core::)?f(?:32|64)::(?:consts::)?[A-Z][A-Z0-9_]*)\s+>=?\s")
FN = re.compile(r"\bfn\s+([A-Za-z_][A-Za-z0-9_]*)")


def strip(text):
    """The text with comments, string and char literals blanked (newlines kept)."""
    out, i, n = [], 0, len(text)

    def blank(s):
        return re.sub(r"[^\n]", " ", s)

    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(blank(text[i:j]))
            i = j
        elif text.startswith("/*", i):
            depth, j = 1, i + 2
            while j < n and depth:
                if text.startswith("/*", j):
                    depth, j = depth + 1, j + 2
                elif text.startswith("*/", j):
                    depth, j = depth - 1, j + 2
                else:
                    j += 1
            out.append(blank(text[i:j]))
            i = j
        elif re.match(r'b?r#*"', text[i:i + 40]) and (i == 0 or not (text[i - 1].isalnum()
                                                                      or text[i - 1] == "_")):
            m = re.match(r'b?r(#*)"', text[i:])
            end = text.find('"' + m.group(1), i + m.end())
            j = n if end < 0 else end + 1 + len(m.group(1))
            out.append(blank(text[i:j]))
            i = j
        elif c == '"':
            j = i + 1
            while j < n and text[j] != '"':
                j += 2 if text[j] == "\\" else 1
            out.append(blank(text[i:j + 1]))
            i = j + 1
        elif c == "'":
            m = re.match(r"'(?:\\(?:x[0-9a-fA-F]{2}|u\{[0-9a-fA-F]+\}|.)|[^\\'\n])'", text[i:])
            if m:  # a char literal (otherwise a lifetime or label)
                out.append(blank(m.group(0)))
                i += m.end()
            else:
                out.append(c)
                i += 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def test_lines(code):
    """Line numbers (0-based) inside `#[cfg(test)]` items."""
    lines, skip, i = code.split("\n"), set(), 0
    while i < len(lines):
        if re.match(r"\s*#\[cfg\(test\)\]", lines[i]):
            depth, started, j = 0, False, i
            while j < len(lines):
                skip.add(j)
                depth += lines[j].count("{") - lines[j].count("}")
                started = started or "{" in lines[j]
                if (started and depth <= 0) or (not started and lines[j].rstrip().endswith(";")
                                                 and j > i):
                    break
                j += 1
            i = j + 1
        else:
            i += 1
    return skip


def check(rel):
    with open(os.path.join(ROOT, rel), encoding="utf-8") as f:
        text = f.read()
    raw, code = text.split("\n"), strip(text).split("\n")
    skip, hits, function = test_lines("\n".join(code)), [], None
    for k, line in enumerate(code):
        m = FN.search(line)
        if m:
            function = m.group(1)
        if k in skip or (rel, function) in ALLOW:
            continue
        if OPERATOR.search(line) or CALL.search(line) or CONST_LEFT.search(line):
            hits.append(f"{rel}:{k + 1}: {raw[k].strip()}")
    return hits


def ir_check(path):
    """Wrong-for-NaN float comparisons in an optimised LLVM IR file, with their source lines."""
    import subprocess
    if path is None:
        fw = os.path.join(ROOT, "firmware")
        out = os.path.join(fw, "target", "nan-ir")
        env = dict(os.environ)
        env["RUSTFLAGS"] = (
            "-C linker-flavor=ld -C link-arg=-Tmemory.x -C link-arg=-Tlink.x "
            "-C link-arg=--gc-sections -C link-arg=--noinhibit-exec "
            f"-C linker={fw}/tools/ld.lld -C llvm-args=-inline-threshold=25")
        env.pop("CARGO_TARGET_DIR", None)
        subprocess.run(["cargo", "rustc", "--release", "--bin", "acs-firmware", "--features",
                        "size-map", "--target-dir", out, "--", "--emit=llvm-ir,link"],
                       cwd=fw, env=env, check=True)
        deps = os.path.join(out, "msp430-none-elf", "release", "deps")
        lls = sorted((os.path.join(deps, f) for f in os.listdir(deps)
                      if f.startswith("acs_firmware-") and f.endswith(".ll")),
                     key=os.path.getmtime)
        path = lls[-1]
    with open(path, encoding="utf-8") as f:
        text = f.read()
    meta = dict(re.findall(r"^!(\d+) = (?:distinct )?(.*)$", text, re.M))

    def file_of(scope):
        for _ in range(200):
            d = meta.get(scope, "")
            m = re.search(r"\bfile: !(\d+)", d)
            if m and ("DISubprogram" in d or "DILexicalBlock" in d):
                fd = meta.get(m.group(1), "")
                name = re.search(r'filename: "([^"]*)"', fd)
                return name.group(1) if name else "?"
            m = re.search(r"\bscope: !(\d+)", d)
            if not m:
                break
            scope = m.group(1)
        return "?"

    hits, counts = [], {}
    for m in re.finditer(r"fcmp (?:[a-z]+ )*?(olt|ole|ogt|oge|ult|ule|ugt|uge|oeq|une|one|ueq|"
                         r"ord|uno|true|false) (?:float|double)[^\n]*?(?:, !dbg !(\d+))?$",
                         text, re.M):
        counts[m.group(1)] = counts.get(m.group(1), 0) + 1
        if m.group(1) not in ("olt", "ole", "ugt", "uge"):
            continue
        where = "?"
        loc = meta.get(m.group(2) or "", "")
        line, scope = re.search(r"line: (\d+)", loc), re.search(r"scope: !(\d+)", loc)
        if line and scope:
            where = f"{file_of(scope.group(1))}:{line.group(1)}"
        hits.append(f"fcmp {m.group(1)} at {where}")
    print(f"{path}: float comparisons by predicate: "
          + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())))
    for h in hits:
        print(h)
    if not counts:
        print("no float comparison found: not the flight image's IR?", file=sys.stderr)
        return 1
    if hits:
        print(f"{len(hits)} comparison(s) in the flight image that the MSP430 evaluates wrongly "
              "for a NaN (fmath module docs, \"Float comparisons in flight code\")",
              file=sys.stderr)
        return 1
    print("flight image: no float comparison that a NaN makes wrong on the MSP430")
    return 0


def main():
    if len(sys.argv) > 1 and sys.argv[1] == "--ir":
        return ir_check(sys.argv[2] if len(sys.argv) > 2 else None)
    unknown = []
    for dirpath, _, files in os.walk(os.path.join(ROOT, "src")):
        for name in files:
            rel = os.path.relpath(os.path.join(dirpath, name), ROOT).replace(os.sep, "/")
            if (rel.endswith(".rs") and rel not in FLIGHT
                    and not rel.startswith(NOT_FLIGHT_DIRS)):
                unknown.append(rel)
    hits = [h for rel in FLIGHT for h in check(rel)]
    for u in sorted(unknown):
        print(f"{u}: not classified: add it to FLIGHT (or to NOT_FLIGHT_DIRS) in {__file__}")
    for h in hits:
        print(h)
    if hits or unknown:
        print(f"{len(hits)} comparison(s) that a NaN makes wrong on the MSP430: with a constant "
              "`c`, write `!(x >= c)` for `x < c`, `!(x > c)` for `x <= c`; with two variables "
              "`b > a` for `a < b`, `b >= a` for `a <= b`; `fmath::min/max` for min/max/clamp "
              "(src/fmath.rs docs, \"Float comparisons in flight code\")", file=sys.stderr)
        return 1
    print(f"float comparisons NaN-proof: {len(FLIGHT)} flight files clean")
    return 0


if __name__ == "__main__":
    sys.exit(main())
