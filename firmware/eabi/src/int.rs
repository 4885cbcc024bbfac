//! Integer helpers: 16/32/64-bit multiply, divide, remainder and 32-bit variable shifts.
//!
//! Hand-written MSP430 (classic, non-X) assembly, no hardware multiplier unless feature
//! `hwmult16`. Register use follows the MSP430 C convention: arguments in R12..R15, result in
//! R12(..R15), R11..R15 clobbered, R4..R10 saved when used. The 64-bit ones use LLVM's
//! `MSP430_BUILTIN` convention (first argument R8..R11, second R12..R15).
//!
//! Division by zero is never called by Rust code (it checks first); these routines then return
//! an unspecified value without hanging.

use core::arch::global_asm;

// ---------------------------------------------------------------------------------------------
// 16-bit multiply: r12 = r12 * r13 (mod 2^16), msb-first shift-and-add, unrolled.
#[cfg(not(feature = "hwmult16"))]
global_asm!(
    r#"
    .section .text.__mspabi_mpyi,"ax",@progbits
    .globl __mspabi_mpyi
    .type __mspabi_mpyi,@function
    .p2align 1
__mspabi_mpyi:
    mov r12, r14
    clr r12
    .rept 16
    rla r12
    rla r13
    jnc 1f
    add r14, r12
1:
    .endr
    ret
    .size __mspabi_mpyi, .-__mspabi_mpyi
"#
);

// ---------------------------------------------------------------------------------------------
// 32-bit multiply: r13:r12 = r13:r12 * r15:r14 (mod 2^32), shift-right method over the 16 bits
// of blo and bhi at once: window {r10, r11, r14} (top, high, low words) shifted right each step;
// blo bit i adds a (32 bits) at the high word, bhi bit i adds alo at the top word. Everything
// above bit 31 of the product is discarded, so the top word needs no carry-in. When both high
// words are zero, a plain 16x16->32 product (window {r11, r14}).
#[cfg(not(feature = "hwmult16"))]
global_asm!(
    r#"
    .section .text.__mspabi_mpyl,"ax",@progbits
    .globl __mspabi_mpyl
    .type __mspabi_mpyl,@function
    .p2align 1
__mspabi_mpyl:
    clr r11
    tst r13
    jnz 2f
    tst r15
    jnz 2f
    clrc
    rrc r14
    .rept 16
    jnc 1f
    add r12, r11
1:  rrc r11
    rrc r14
    .endr
    mov r14, r12
    mov r11, r13
    ret
2:  push r10
    clr r10
    clrc
    rrc r14
    .rept 16
    jnc 1f
    add r12, r11
    addc r13, r10
1:  rra r15
    jnc 3f
    add r12, r10
3:  rra r10
    rrc r11
    rrc r14
    .endr
    mov r14, r12
    mov r11, r13
    pop r10
    ret
    .size __mspabi_mpyl, .-__mspabi_mpyl
"#
);

// ---------------------------------------------------------------------------------------------
// Hardware-multiplier variants (16-bit MPY peripheral: MPY 0x0130, OP2 0x0138, RESLO 0x013A,
// RESHI 0x013C). Interrupts are disabled around each use (SR saved and restored), so interrupt
// handlers may use the multiplier too.
#[cfg(feature = "hwmult16")]
global_asm!(
    r#"
    .section .text.__mspabi_mpyi,"ax",@progbits
    .globl __mspabi_mpyi
    .type __mspabi_mpyi,@function
    .p2align 1
__mspabi_mpyi:
    push r2
    dint
    nop
    mov r12, &0x0130
    mov r13, &0x0138
    mov &0x013a, r12
    pop r2
    ret
    .size __mspabi_mpyi, .-__mspabi_mpyi

    .section .text.__mspabi_mpyl,"ax",@progbits
    .globl __mspabi_mpyl
    .type __mspabi_mpyl,@function
    .p2align 1
__mspabi_mpyl:
    push r2
    dint
    nop
    mov r12, &0x0130
    mov r14, &0x0138
    mov &0x013a, r11
    mov r12, &0x0130
    mov &0x013c, r12
    mov r15, &0x0138
    add &0x013a, r12
    mov r13, &0x0130
    mov r14, &0x0138
    add &0x013a, r12
    pop r2
    mov r12, r13
    mov r11, r12
    ret
    .size __mspabi_mpyl, .-__mspabi_mpyl
"#
);

// ---------------------------------------------------------------------------------------------
// 16-bit unsigned divide: r12 = r12 / r13, remainder in r14 (restoring, quotient shifted into
// the dividend register).
global_asm!(
    r#"
    .section .text.__mspabi_divu,"ax",@progbits
    .globl __mspabi_divu
    .type __mspabi_divu,@function
    .p2align 1
__mspabi_divu:
    clr r14
    mov #16, r15
1:  rla r12
    rlc r14
    jc 2f
    cmp r13, r14
    jlo 3f
2:  sub r13, r14
    bis #1, r12
3:  dec r15
    jnz 1b
    ret
    .size __mspabi_divu, .-__mspabi_divu

    .section .text.__mspabi_remu,"ax",@progbits
    .globl __mspabi_remu
    .type __mspabi_remu,@function
    .p2align 1
__mspabi_remu:
    call #__mspabi_divu
    mov r14, r12
    ret
    .size __mspabi_remu, .-__mspabi_remu

    .section .text.__mspabi_divi,"ax",@progbits
    .globl __mspabi_divi
    .type __mspabi_divi,@function
    .p2align 1
__mspabi_divi:
    mov r12, r11
    xor r13, r11
    tst r12
    jge 1f
    inv r12
    inc r12
1:  tst r13
    jge 2f
    inv r13
    inc r13
2:  call #__mspabi_divu
    tst r11
    jge 3f
    inv r12
    inc r12
3:  ret
    .size __mspabi_divi, .-__mspabi_divi

    .section .text.__mspabi_remi,"ax",@progbits
    .globl __mspabi_remi
    .type __mspabi_remi,@function
    .p2align 1
__mspabi_remi:
    mov r12, r11
    tst r12
    jge 1f
    inv r12
    inc r12
1:  tst r13
    jge 2f
    inv r13
    inc r13
2:  call #__mspabi_divu
    mov r14, r12
    tst r11
    jge 3f
    inv r12
    inc r12
3:  ret
    .size __mspabi_remi, .-__mspabi_remi
"#
);

// ---------------------------------------------------------------------------------------------
// 32-bit unsigned divide: r13:r12 = r13:r12 / r15:r14, remainder in r15:r14.
global_asm!(
    r#"
    .section .text.__mspabi_divul,"ax",@progbits
    .globl __mspabi_divul
    .type __mspabi_divul,@function
    .p2align 1
__mspabi_divul:
    push r10
    push r9
    clr r10
    clr r11
    mov #32, r9
    tst r13
    jnz 1f
    ; dividend < 2^16: the first 16 quotient bits are zero
    mov r12, r13
    clr r12
    mov #16, r9
1:  rla r12
    rlc r13
    rlc r10
    rlc r11
    jc 2f
    cmp r15, r11
    jlo 3f
    jne 2f
    cmp r14, r10
    jlo 3f
2:  sub r14, r10
    subc r15, r11
    bis #1, r12
3:  dec r9
    jnz 1b
    mov r10, r14
    mov r11, r15
    pop r9
    pop r10
    ret
    .size __mspabi_divul, .-__mspabi_divul

    .section .text.__mspabi_remul,"ax",@progbits
    .globl __mspabi_remul
    .type __mspabi_remul,@function
    .p2align 1
__mspabi_remul:
    call #__mspabi_divul
    mov r14, r12
    mov r15, r13
    ret
    .size __mspabi_remul, .-__mspabi_remul

    .section .text.__mspabi_divli,"ax",@progbits
    .globl __mspabi_divli
    .type __mspabi_divli,@function
    .p2align 1
__mspabi_divli:
    mov r13, r11
    xor r15, r11
    push r11
    tst r13
    jge 1f
    inv r12
    inv r13
    inc r12
    adc r13
1:  tst r15
    jge 2f
    inv r14
    inv r15
    inc r14
    adc r15
2:  call #__mspabi_divul
    pop r11
    tst r11
    jge 3f
    inv r12
    inv r13
    inc r12
    adc r13
3:  ret
    .size __mspabi_divli, .-__mspabi_divli

    .section .text.__mspabi_remli,"ax",@progbits
    .globl __mspabi_remli
    .type __mspabi_remli,@function
    .p2align 1
__mspabi_remli:
    push r13
    tst r13
    jge 1f
    inv r12
    inv r13
    inc r12
    adc r13
1:  tst r15
    jge 2f
    inv r14
    inv r15
    inc r14
    adc r15
2:  call #__mspabi_divul
    mov r14, r12
    mov r15, r13
    pop r11
    tst r11
    jge 3f
    inv r12
    inv r13
    inc r12
    adc r13
3:  ret
    .size __mspabi_remli, .-__mspabi_remli
"#
);

// ---------------------------------------------------------------------------------------------
// 32-bit variable shifts: r13:r12 shifted by r14 (0..31; higher bits of the count ignored).
global_asm!(
    r#"
    .section .text.__mspabi_slll,"ax",@progbits
    .globl __mspabi_slll
    .type __mspabi_slll,@function
    .p2align 1
__mspabi_slll:
    and #31, r14
    jz 9f
    cmp #16, r14
    jlo 1f
    mov r12, r13
    clr r12
    sub #16, r14
    jz 9f
1:  cmp #8, r14
    jlo 2f
    swpb r12
    swpb r13
    mov.b r12, r15
    xor r15, r12
    mov.b r13, r11
    xor r11, r13
    bis r15, r13
    sub #8, r14
    jz 9f
2:  rla r12
    rlc r13
    dec r14
    jnz 2b
9:  ret
    .size __mspabi_slll, .-__mspabi_slll

    .section .text.__mspabi_srll,"ax",@progbits
    .globl __mspabi_srll
    .type __mspabi_srll,@function
    .p2align 1
__mspabi_srll:
    and #31, r14
    jz 9f
    cmp #16, r14
    jlo 1f
    mov r13, r12
    clr r13
    sub #16, r14
    jz 9f
1:  cmp #8, r14
    jlo 2f
    swpb r12
    swpb r13
    mov.b r12, r12
    mov.b r13, r15
    xor r15, r13
    bis r13, r12
    mov r15, r13
    sub #8, r14
    jz 9f
2:  clrc
    rrc r13
    rrc r12
    dec r14
    jnz 2b
9:  ret
    .size __mspabi_srll, .-__mspabi_srll

    .section .text.__mspabi_sral,"ax",@progbits
    .globl __mspabi_sral
    .type __mspabi_sral,@function
    .p2align 1
__mspabi_sral:
    and #31, r14
    jz 9f
    cmp #16, r14
    jlo 1f
    mov r13, r12
    rla r13
    subc r13, r13
    inv r13
    sub #16, r14
    jz 9f
1:  cmp #8, r14
    jlo 2f
    swpb r12
    swpb r13
    mov.b r12, r12
    mov.b r13, r15
    xor r15, r13
    bis r13, r12
    sxt r15
    mov r15, r13
    sub #8, r14
    jz 9f
2:  rra r13
    rrc r12
    dec r14
    jnz 2b
9:  ret
    .size __mspabi_sral, .-__mspabi_sral
"#
);

// ---------------------------------------------------------------------------------------------
// 64-bit multiply, divide, remainder (MSP430_BUILTIN convention: a in r8..r11, b in r12..r15,
// result in r12..r15). First version: wrappers that call compiler-builtins (C convention:
// a in r12..r15, b on the stack).
global_asm!(
    r#"
    .macro BUILTIN64 name, target
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

    BUILTIN64 __mspabi_mpyll, __muldi3
    BUILTIN64 __mspabi_divull, __udivdi3
    BUILTIN64 __mspabi_remull, __umoddi3
    BUILTIN64 __mspabi_divlli, __divdi3
    BUILTIN64 __mspabi_remlli, __moddi3
"#
);
