#!/usr/bin/env bash
# One command: build the msp430-eabi test firmware (with and without the hardware multiplier) and
# the host driver, then check every helper in mspdebug's simulator against the host's native
# arithmetic, bit for bit. Extra arguments go to the driver, e.g.
#   firmware/eabi/verify.sh                  # verification (ends with "N passed, M failed")
#   firmware/eabi/verify.sh --scale 4        # 4x more cases
#   firmware/eabi/verify.sh --ops addf,mpyf  # some operations only
#   firmware/eabi/verify.sh --bench          # MCLK cycles per operation (README table)
# Needs: the pinned nightly with rust-src (.ci/nightly), mspdebug (apt-get install mspdebug).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
"$here/build-testfw.sh"
cargo build --release --quiet --manifest-path "$here/verify/Cargo.toml" --target-dir "$root/target/eabi-host"
exec "$root/target/eabi-host/release/msp430-eabi-verify" \
  --elf "soft=$root/target/eabi/testfw-soft.elf" --elf "hw16=$root/target/eabi/testfw-hw16.elf" "$@"
