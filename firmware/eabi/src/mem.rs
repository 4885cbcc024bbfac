//! `memcpy`, `memmove` and `memset` as byte loops (MSP430 C convention: `r12` destination,
//! `r13` source or fill byte, `r14` length; the destination returned in `r12`; `r11`, `r15`
//! scratch, caller-saved).
//!
//! They replace the `compiler-builtins` versions (`compiler-builtins-mem`), which copy word by
//! word with unrolled head and tail code: 674 B of flash in the flight image against 56 B here.
//! The flight code copies only small structures (at most a few hundred bytes, a handful of times
//! per step), so speed does not matter and flash does (issue #17). Verified bit for bit against
//! the host by `verify.sh` (operations `memcpy`, `memmove`, `memset`: random lengths, offsets and
//! overlaps in a 16-byte buffer).

use core::arch::global_asm;

global_asm!(
    r#"
    .section .text.memcpy,"ax",@progbits
    .globl memcpy
    .type memcpy,@function
    .p2align 1
memcpy:
    mov r12, r15
1:
    tst r14
    jz 2f
    mov.b @r13+, r11
    mov.b r11, 0(r15)
    inc r15
    dec r14
    jmp 1b
2:
    ret
    .size memcpy, .-memcpy

    .section .text.memmove,"ax",@progbits
    .globl memmove
    .type memmove,@function
    .p2align 1
memmove:
    cmp r13, r12
    jc 3f
    br #memcpy
3:
    add r14, r13
    mov r12, r15
    add r14, r15
1:
    tst r14
    jz 2f
    dec r13
    dec r15
    mov.b @r13, r11
    mov.b r11, 0(r15)
    dec r14
    jmp 1b
2:
    ret
    .size memmove, .-memmove

    .section .text.memset,"ax",@progbits
    .globl memset
    .type memset,@function
    .p2align 1
memset:
    mov r12, r15
1:
    tst r14
    jz 2f
    mov.b r13, 0(r15)
    inc r15
    dec r14
    jmp 1b
2:
    ret
    .size memset, .-memset
"#
);
