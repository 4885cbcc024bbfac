//! `memcpy`, `memmove` and `memset` as small loops (MSP430 C convention: `r12` destination,
//! `r13` source or fill byte, `r14` length; the destination returned in `r12`; `r11`, `r15`
//! scratch, caller-saved).
//!
//! They replace the `compiler-builtins` versions (`compiler-builtins-mem`), which copy word by
//! word with unrolled head and tail code: 674 B of flash in the flight image against ≈ 90 B
//! here. `memcpy` and `memset` move words when the addresses and the length are even (the
//! flight code's structures are), bytes otherwise; `memmove` moves bytes.
//! The flight code copies small structures (at most a few hundred bytes) about 130 times a
//! step: words halve their cost there for 36 B of flash. Verified bit for bit against
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
    mov r12, r11
    bis r13, r11
    bis r14, r11
    bit #1, r11
    jnz 1f
3:
    tst r14
    jz 2f
    mov @r13+, r11
    mov r11, 0(r15)
    incd r15
    decd r14
    jmp 3b
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
    mov r12, r11
    bis r14, r11
    bit #1, r11
    jnz 1f
    mov.b r13, r13
    mov r13, r11
    swpb r11
    bis r11, r13
3:
    tst r14
    jz 2f
    mov r13, 0(r15)
    incd r15
    decd r14
    jmp 3b
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
