//! TI MSP430 EABI helper functions (`__mspabi_*`) for the `msp430-none-elf` target, without libgcc.
//!
//! LLVM lowers soft-float and some integer operations on the MSP430 to calls of the TI EABI helper
//! functions (TI SLAA534, tables 6–10). `compiler-builtins` does not export those names, and Debian
//! has no msp430 libgcc, so a firmware that uses `f32`, `f64`, 32/64-bit integer multiply, divide or
//! variable shifts needs this crate to link. Link it from the firmware with
//! `use msp430_eabi as _;` (or any item use) so that the linker sees the symbols.
//!
//! Every symbol that LLVM 21's MSP430 backend can emit (without the hardware-multiplier subtarget
//! features) is provided:
//!
//! | group | symbols | where |
//! |---|---|---|
//! | integer | `mpyi mpyl mpyll divi divu remi remu divli divul remli remul divlli divull remlli remull slll srll sral` | [`int`] (assembly) |
//! | f32 | `addf subf mpyf divf cmpf fixfli fixful fixflli fixfull fltlif fltulf fltllif fltullf`, `__unordsf2`, `acs_sqrtf` | [`f32`] (assembly; 64-bit conversions via `compiler-builtins`) |
//! | memory | `memcpy memmove memset` (byte loops, smaller than `compiler-builtins`' ones) | [`mem`] (assembly) |
//! | f64 | `addd subd mpyd divd cmpd cvtfd cvtdf fixdli fixdul fixdlli fixdull fltlid fltuld fltllid fltulld` | [`f64`] (wrappers around `compiler-builtins`) |
//!
//! Calling conventions (verified on the disassembly of LLVM's calls, see README):
//! ordinary MSP430 C convention (arguments in R12..R15, then the stack; result in R12..R15;
//! R4..R10 callee-saved) except `mpyll`, `divlli divull remlli remull`, `addd subd mpyd divd cmpd`,
//! which use LLVM's `MSP430_BUILTIN` convention: first 64-bit argument in R8..R11, second in
//! R12..R15, result in R12..R15, R4..R10 preserved.
//!
//! Comparison helpers return a negative, zero or positive `i16`. **NaN:** LLVM lowers all six
//! ordered predicates (`==`, `!=`, `<`, `<=`, `>`, `>=`) to a test of the *same* helper's result,
//! so no return value can make all of them false for an unordered pair. `cmpf`/`cmpd` return −1
//! for unordered operands, which makes `==`, `!=`, `>`, `>=` (and `as` conversions to integers,
//! which rely on `>=`) correct and `<`, `<=` **wrongly true** with a NaN operand. Writing `b > a`
//! does not help when `b` is a constant (LLVM compiles `0.0 > x` as `x < 0.0`), and an `is_nan()`
//! test next to a comparison is folded into it: see `README.md` ("NaN and comparisons") and the
//! flight code's rules in `src/fmath.rs`; `tools/float_compare_check.py --ir` checks the image.
#![no_std]
#![cfg_attr(target_arch = "msp430", feature(asm_experimental_arch))]

#[cfg(target_arch = "msp430")]
pub mod f32;
#[cfg(target_arch = "msp430")]
pub mod f64;
#[cfg(target_arch = "msp430")]
pub mod int;
#[cfg(target_arch = "msp430")]
pub mod mem;
