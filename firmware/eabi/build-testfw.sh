#!/usr/bin/env bash
# Build the msp430-eabi test firmware for mspdebug's simulator, in two variants:
#   target/eabi/testfw-soft.elf  (no hardware multiplier)
#   target/eabi/testfw-hw16.elf  (feature hwmult16: 16-bit MPY peripheral)
# Uses the pinned nightly (.ci/nightly), core rebuilt from source, and the LLVM linker shipped
# with Rust (no msp430 gcc). Everything is passed explicitly, so no .cargo/config.toml applies.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
nightly="$(cat "$root/.ci/nightly")"
sysroot="$(rustc +"$nightly" --print sysroot)"
lld="$sysroot/lib/rustlib/x86_64-unknown-linux-gnu/bin/gcc-ld/ld.lld"
tdir="$root/target/eabi"
export RUSTFLAGS="-C linker=$lld -C linker-flavor=ld -C link-arg=-T$here/tests-fw/link.x -C link-arg=--gc-sections"
for variant in ${VARIANTS:-soft hw16}; do
  feats=()
  [ "$variant" = hw16 ] && feats=(--features hwmult16)
  cargo +"$nightly" build --release --quiet \
    --manifest-path "$here/tests-fw/Cargo.toml" --target msp430-none-elf \
    -Zbuild-std=core -Zbuild-std-features=compiler-builtins-mem \
    --target-dir "$tdir" "${feats[@]}"
  cp "$tdir/msp430-none-elf/release/msp430-eabi-testfw" "$tdir/testfw-$variant.elf"
done
