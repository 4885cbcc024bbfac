//! f64 helpers: wrappers around the `compiler-builtins` soft-float routines.
//!
//! f64 is not a flight precision on this target (it costs 10–30× an f32 operation); these exist so
//! that any Rust program links and computes correctly. `addd subd mpyd divd cmpd` use LLVM's
//! `MSP430_BUILTIN` convention (a in R8..R11, b in R12..R15) and are re-shuffled into the C
//! convention (a in R12..R15, b on the stack) of the `compiler-builtins` routine; the others have
//! the C convention already and are tail jumps.

use core::arch::global_asm;

global_asm!(
    r#"
    .macro BUILTIN64F name, target
    .section .text.\name,"ax",@progbits
    .globl \name
    .type \name,@function
    .p2align 1
\name:
    push r15
    push r14
    push r13
    push r12
    mov r8, r12
    mov r9, r13
    mov r10, r14
    mov r11, r15
    call #\target
    add #8, r1
    ret
    .size \name, .-\name
    .endm

    .macro TAILF name, target
    .section .text.\name,"ax",@progbits
    .globl \name
    .type \name,@function
    .p2align 1
\name:
    br #\target
    .size \name, .-\name
    .endm

    BUILTIN64F __mspabi_addd, __adddf3
    BUILTIN64F __mspabi_subd, __subdf3
    BUILTIN64F __mspabi_mpyd, __muldf3
    BUILTIN64F __mspabi_divd, __divdf3
    BUILTIN64F __mspabi_cmpd, __gedf2
    TAILF __mspabi_cvtfd, __extendsfdf2
    TAILF __mspabi_cvtdf, __truncdfsf2
    TAILF __mspabi_fixdli, __fixdfsi
    TAILF __mspabi_fixdul, __fixunsdfsi
    TAILF __mspabi_fixdlli, __fixdfdi
    TAILF __mspabi_fixdull, __fixunsdfdi
    TAILF __mspabi_fltlid, __floatsidf
    TAILF __mspabi_fltuld, __floatunsidf
    TAILF __mspabi_fltllid, __floatdidf
    TAILF __mspabi_fltulld, __floatundidf
"#
);
