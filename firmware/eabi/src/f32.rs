//! f32 helpers.
//!
//! First version: tail jumps to the `compiler-builtins` soft-float routines, whose C calling
//! convention (a in R12:R13, b in R14:R15, result in R12:R13) is the EABI helpers' own.
//! `cmpf` jumps to `__gesf2`, which returns −1 for unordered operands (see the crate docs).

use core::arch::global_asm;

global_asm!(
    r#"
    .macro TAIL name, target
    .section .text.\name,"ax",@progbits
    .globl \name
    .type \name,@function
    .p2align 1
\name:
    br #\target
    .size \name, .-\name
    .endm

    TAIL __mspabi_addf, __addsf3
    TAIL __mspabi_subf, __subsf3
    TAIL __mspabi_mpyf, __mulsf3
    TAIL __mspabi_divf, __divsf3
    TAIL __mspabi_cmpf, __gesf2
    TAIL __mspabi_fixfli, __fixsfsi
    TAIL __mspabi_fixful, __fixunssfsi
    TAIL __mspabi_fixflli, __fixsfdi
    TAIL __mspabi_fixfull, __fixunssfdi
    TAIL __mspabi_fltlif, __floatsisf
    TAIL __mspabi_fltulf, __floatunsisf
    TAIL __mspabi_fltllif, __floatdisf
    TAIL __mspabi_fltullf, __floatundisf
"#
);

/// Correctly rounded f32 square root (IEEE-754 round-to-nearest-even; `sqrt(-0) = -0`,
/// negative or NaN input → NaN, `sqrt(+inf) = +inf`). Exported for the flight code's
/// `fmath::sqrt` on the target.
#[no_mangle]
pub extern "C" fn acs_sqrtf(x: f32) -> f32 {
    let b = x.to_bits();
    let e = (b >> 23) & 0xff;
    let mut m = b & 0x007f_ffff;
    if b & 0x7fff_ffff == 0 {
        return x;
    }
    if e == 0xff {
        if m != 0 {
            return f32::from_bits(b | 0x0040_0000);
        }
        if b >> 31 != 0 {
            return f32::from_bits(0x7fc0_0000);
        }
        return x;
    }
    if b >> 31 != 0 {
        return f32::from_bits(0x7fc0_0000);
    }
    let mut ex = e as i16 - 127;
    if e == 0 {
        ex = -126;
        while m & 0x0080_0000 == 0 {
            m <<= 1;
            ex -= 1;
        }
    } else {
        m |= 0x0080_0000;
    }
    if ex & 1 != 0 {
        m <<= 1;
        ex -= 1;
    }
    // q = isqrt(m << 23), 24 bits; remainder decides the rounding (no exact ties exist).
    let mut rem: u64 = (m as u64) << 23;
    let mut q: u64 = 0;
    let mut bit: u64 = 1 << 46;
    while bit != 0 {
        if rem >= q + bit {
            rem -= q + bit;
            q = (q >> 1) + bit;
        } else {
            q >>= 1;
        }
        bit >>= 2;
    }
    let round = (rem > q) as u32;
    let q = q as u32;
    let bits = ((((ex / 2) + 127) as u32) << 23) + (q - 0x0080_0000) + round;
    f32::from_bits(bits)
}
