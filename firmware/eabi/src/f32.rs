//! f32 helpers: add, subtract, multiply, divide, compare, i32/u32 conversions and square root,
//! hand-written for the MSP430 (classic ISA), IEEE-754 binary32 with round-to-nearest-even,
//! subnormals in and out, bit-identical to a hardware FPU except for NaN payloads (every NaN
//! result is the quiet NaN 0x7FC0_0000). The 64-bit integer conversions are tail jumps to
//! `compiler-builtins` (same C convention: a in R12:R13, b in R14:R15, result in R12..R15).
//!
//! Common representation inside the routines: sign in bit 15 of a register, biased exponent `e`
//! as a signed word, 24-bit significand `m` in two words (hi word holds bits 23..16, bit 23 is the
//! implicit 1), and an extension word whose bit 15 is the guard bit and whose other bits (plus a
//! second sticky word) say whether anything non-zero lies below. Packing is
//! `hi = ((e - 1) << 7) + m_hi`, which carries a rounding overflow of the significand into the
//! exponent, turns `e = 1` with no implicit bit into a subnormal and `e = 254` overflowing into
//! infinity.

use core::arch::global_asm;

// Tail jumps for the 64-bit conversions.
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

    TAIL __mspabi_fixflli, __fixsfdi
    TAIL __mspabi_fixfull, __fixunssfdi
    TAIL __mspabi_fltllif, __floatdisf
    TAIL __mspabi_fltullf, __floatundisf
"#
);

// Shared tail of multiply and divide: range check, denormalisation, rounding, packing.
// In: r11 sign (bit 15), r10 e (signed), r9:r8 significand (24 bits, bit 23 set), r15 extension
// (bit 15 guard, bits 14..0 sticky), r14 more sticky bits. Saved r8, r9, r10 on the stack.
// Out: r13:r12, restores r8..r10 and returns.
global_asm!(
    r#"
    .section .text.__acs_f32_finish,"ax",@progbits
    .globl __acs_f32_finish
    .type __acs_f32_finish,@function
    .p2align 1
__acs_f32_finish:
    cmp #255, r10
    jge .Lfin_inf
    cmp #1, r10
    jl .Lfin_under
.Lfin_round:
    tst r14
    jz 1f
    bis #1, r15
1:  rla r15
    jnc .Lfin_pack
    jnz .Lfin_up
    bit #1, r8
    jz .Lfin_pack
.Lfin_up:
    inc r8
    adc r9
.Lfin_pack:
    dec r10
    swpb r10
    clrc
    rrc r10
    add r10, r9
    bis r11, r9
    mov r8, r12
    mov r9, r13
    pop r8
    pop r9
    pop r10
    ret
.Lfin_inf:
    mov #0x7f80, r13
    bis r11, r13
    clr r12
    pop r8
    pop r9
    pop r10
    ret
.Lfin_under:
    ; subnormal result: shift right by 1 - e (sticky kept in bit 0 of r15), then e = 1
    tst r14
    jz 2f
    bis #1, r15
2:  mov #1, r14
    sub r10, r14
    cmp #26, r14
    jlo 3f
    clr r9
    clr r8
    mov #1, r15
    jmp 5f
3:  clrc
    rrc r9
    rrc r8
    rrc r15
    jnc 4f
    bis #1, r15
4:  dec r14
    jnz 3b
5:  clr r14
    mov #1, r10
    jmp .Lfin_round
    .size __acs_f32_finish, .-__acs_f32_finish
"#
);

// Prologue/epilogue macros of the multiply (shared with the hardware-multiplier variant).
global_asm!(
    r#"
    .macro MPYF_PROLOGUE
    mov r13, r11
    xor r15, r11
    and #0x8000, r11
    mov r13, r10
    rla r10
    swpb r10
    mov.b r10, r10
    mov r15, r9
    rla r9
    swpb r9
    mov.b r9, r9
    and #0x7f, r13
    and #0x7f, r15
    cmp #255, r10
    jeq .Lmpyf_aspec
    cmp #255, r9
    jeq .Lmpyf_bspec
    tst r10
    jz .Lmpyf_asub
    bis #0x80, r13
.Lmpyf_aok:
    tst r9
    jz .Lmpyf_bsub
    bis #0x80, r15
.Lmpyf_bok:
    add r9, r10
    sub #126, r10
    .endm

    ; product >> 24 in r9:r8, bits 23..16 in r15 bits 15..8 (low byte 0), bits 15..0 in r14
    .macro MPYF_EPILOGUE
    bit #0x80, r9
    jnz 1f
    rla r15
    rlc r8
    rlc r9
    dec r10
1:  br #__acs_f32_finish
.Lmpyf_asub:
    mov r13, r8
    bis r12, r8
    tst r8
    jz .Lmpyf_zero
    mov #1, r10
2:  dec r10
    rla r12
    rlc r13
    bit #0x80, r13
    jz 2b
    jmp .Lmpyf_aok
.Lmpyf_bsub:
    mov r15, r8
    bis r14, r8
    tst r8
    jz .Lmpyf_zero
    mov #1, r9
3:  dec r9
    rla r14
    rlc r15
    bit #0x80, r15
    jz 3b
    jmp .Lmpyf_bok
.Lmpyf_aspec:
    bis r13, r12
    tst r12
    jnz .Lmpyf_nan
    ; a = inf: NaN if b is NaN or zero
    cmp #255, r9
    jne 4f
    bis r15, r14
    tst r14
    jnz .Lmpyf_nan
    jmp .Lmpyf_inf
4:  tst r9
    jnz .Lmpyf_inf
    bis r15, r14
    tst r14
    jz .Lmpyf_nan
    jmp .Lmpyf_inf
.Lmpyf_bspec:
    bis r15, r14
    tst r14
    jnz .Lmpyf_nan
    ; b = inf, a finite: NaN if a is zero
    tst r10
    jnz .Lmpyf_inf
    bis r13, r12
    tst r12
    jz .Lmpyf_nan
.Lmpyf_inf:
    mov #0x7f80, r13
    bis r11, r13
    clr r12
    jmp 5f
.Lmpyf_nan:
    mov #0x7fc0, r13
    clr r12
    jmp 5f
.Lmpyf_zero:
    mov r11, r13
    clr r12
5:  pop r8
    pop r9
    pop r10
    ret
    .endm
"#
);

// Multiply: r13:r12 = a * b.
#[cfg(not(feature = "hwmult16"))]
global_asm!(
    r#"
    .section .text.__mspabi_mpyf,"ax",@progbits
    .globl __mspabi_mpyf
    .type __mspabi_mpyf,@function
    .p2align 1
__mspabi_mpyf:
    push r10
    push r9
    push r8
    MPYF_PROLOGUE
    ; 24x24 product, shift-right method: multiplicand r13:r12, multiplier r15:r14 (consumed,
    ; receives the low product bits), accumulator r9:r8.
    clr r9
    clr r8
    clrc
    rrc r14
    .rept 16
    jnc 1f
    add r12, r8
    addc r13, r9
1:  rrc r9
    rrc r8
    rrc r14
    .endr
    clrc
    rrc r15
    .rept 8
    jnc 1f
    add r12, r8
    addc r13, r9
1:  rrc r9
    rrc r8
    rrc r15
    .endr
    MPYF_EPILOGUE
    .size __mspabi_mpyf, .-__mspabi_mpyf
"#,
);

// Multiply with the 16-bit hardware multiplier: four 16x16 products (the high words are at most
// 8 bits), interrupts disabled around the peripheral.
#[cfg(feature = "hwmult16")]
global_asm!(
    r#"
    .section .text.__mspabi_mpyf,"ax",@progbits
    .globl __mspabi_mpyf
    .type __mspabi_mpyf,@function
    .p2align 1
__mspabi_mpyf:
    push r10
    push r9
    push r8
    MPYF_PROLOGUE
    push r2
    dint
    nop
    mov r12, &0x0130
    mov r14, &0x0138
    mov &0x013a, r9
    mov r12, &0x0130
    mov &0x013c, r8
    mov r15, &0x0138
    add &0x013a, r8
    mov &0x013c, r12
    adc r12
    mov r13, &0x0130
    mov r14, &0x0138
    add &0x013a, r8
    addc &0x013c, r12
    mov r13, &0x0130
    mov r15, &0x0138
    add &0x013a, r12
    pop r2
    ; product words: r12 bits 47..32, r8 bits 31..16, r9 bits 15..0
    mov r9, r14
    swpb r12
    swpb r8
    mov.b r12, r9
    xor r9, r12
    mov.b r8, r15
    xor r15, r8
    bis r12, r15
    mov r8, r12
    mov r15, r8
    mov r12, r15
    MPYF_EPILOGUE
    .size __mspabi_mpyf, .-__mspabi_mpyf
"#,
);

// Divide: r13:r12 = a / b.
global_asm!(
    r#"
    .section .text.__mspabi_divf,"ax",@progbits
    .globl __mspabi_divf
    .type __mspabi_divf,@function
    .p2align 1
__mspabi_divf:
    push r10
    push r9
    push r8
    mov r13, r11
    xor r15, r11
    and #0x8000, r11
    mov r13, r10
    rla r10
    swpb r10
    mov.b r10, r10
    mov r15, r9
    rla r9
    swpb r9
    mov.b r9, r9
    and #0x7f, r13
    and #0x7f, r15
    cmp #255, r10
    jeq .Ldivf_aspec
    cmp #255, r9
    jeq .Ldivf_bspec
    tst r9
    jz .Ldivf_bsub
    bis #0x80, r15
.Ldivf_bok:
    tst r10
    jz .Ldivf_asub
    bis #0x80, r13
.Ldivf_aok:
    sub r9, r10
    add #127, r10
    cmp r15, r13
    jlo 1f
    jne 2f
    cmp r14, r12
    jhs 2f
1:  rla r12
    rlc r13
    dec r10
2:  ; non-restoring division, 25 quotient bits into r9:r8 (sentinel bit 7 leaves bit 31 last)
    mov #0x80, r8
    clr r9
    sub r14, r12
    subc r15, r13
.Ldivf_pos:
    setc
    rlc r8
    rlc r9
    jc .Ldivf_done
    rla r12
    rlc r13
    sub r14, r12
    subc r15, r13
    jge .Ldivf_pos
.Ldivf_neg:
    rla r8
    rlc r9
    jc .Ldivf_done
    rla r12
    rlc r13
    add r14, r12
    addc r15, r13
    jge .Ldivf_pos
    jmp .Ldivf_neg
.Ldivf_done:
    tst r13
    jge 3f
    add r14, r12
    addc r15, r13
3:  bis r12, r13
    clr r15
    clrc
    rrc r9
    rrc r8
    rrc r15
    mov r13, r14
    br #__acs_f32_finish
.Ldivf_bsub:
    mov r15, r8
    bis r14, r8
    tst r8
    jz .Ldivf_bzero
    mov #1, r9
4:  dec r9
    rla r14
    rlc r15
    bit #0x80, r15
    jz 4b
    jmp .Ldivf_bok
.Ldivf_bzero:
    ; x / 0: NaN if a is zero, else infinity
    tst r10
    jnz .Ldivf_inf
    bis r13, r12
    tst r12
    jz .Ldivf_nan
    jmp .Ldivf_inf
.Ldivf_asub:
    mov r13, r8
    bis r12, r8
    tst r8
    jz .Ldivf_zero
    mov #1, r10
5:  dec r10
    rla r12
    rlc r13
    bit #0x80, r13
    jz 5b
    jmp .Ldivf_aok
.Ldivf_aspec:
    bis r13, r12
    tst r12
    jnz .Ldivf_nan
    cmp #255, r9
    jeq .Ldivf_nan
    jmp .Ldivf_inf
.Ldivf_bspec:
    bis r15, r14
    tst r14
    jnz .Ldivf_nan
    jmp .Ldivf_zero
.Ldivf_inf:
    mov #0x7f80, r13
    bis r11, r13
    clr r12
    jmp 6f
.Ldivf_nan:
    mov #0x7fc0, r13
    clr r12
    jmp 6f
.Ldivf_zero:
    mov r11, r13
    clr r12
6:  pop r8
    pop r9
    pop r10
    ret
    .size __mspabi_divf, .-__mspabi_divf
"#
);

// Add and subtract: r13:r12 = a + b, a - b.
global_asm!(
    r#"
    .section .text.__mspabi_addf,"ax",@progbits
    .globl __mspabi_subf
    .type __mspabi_subf,@function
    .globl __mspabi_addf
    .type __mspabi_addf,@function
    .p2align 1
__mspabi_subf:
    xor #0x8000, r15
__mspabi_addf:
    push r10
    push r9
    push r8
    push r7
    push r6
    ; order by magnitude: |a| >= |b|
    mov r13, r10
    and #0x7fff, r10
    mov r15, r9
    and #0x7fff, r9
    cmp r9, r10
    jlo 1f
    jne 2f
    cmp r14, r12
    jhs 2f
1:  mov r12, r11
    mov r14, r12
    mov r11, r14
    mov r13, r11
    mov r15, r13
    mov r11, r15
    mov r10, r11
    mov r9, r10
    mov r11, r9
2:  mov r13, r7
    and #0x8000, r7
    mov r13, r8
    xor r15, r8
    mov r10, r13
    and #0x7f, r13
    mov r9, r15
    and #0x7f, r15
    rla r10
    swpb r10
    mov.b r10, r10
    rla r9
    swpb r9
    mov.b r9, r9
    clr r11
    cmp #255, r10
    jeq .Laddf_spec
    tst r9
    jz .Laddf_bsub
    bis #0x80, r15
    bis #0x80, r13
.Laddf_align:
    ; d = ea - eb; shift r15:r14:r11 right by d, sticky into bit 0 of r11
    sub r10, r9
    inv r9
    inc r9
    jz .Laddf_do
    cmp #26, r9
    jhs .Laddf_round
    cmp #16, r9
    jlo 3f
    mov r14, r11
    mov r15, r14
    clr r15
    sub #16, r9
    jz .Laddf_do
3:  cmp #8, r9
    jlo 5f
    swpb r11
    cmp #0x100, r11
    mov.b r11, r11
    jnc 4f
    bis #1, r11
4:  swpb r14
    mov r14, r6
    and #0xff00, r6
    bis r6, r11
    mov.b r14, r14
    swpb r15
    bis r15, r14
    clr r15
    sub #8, r9
    jz .Laddf_do
5:  clrc
    rrc r15
    rrc r14
    rrc r11
    jnc 6f
    bis #1, r11
6:  dec r9
    jnz 5b
.Laddf_do:
    tst r8
    jn .Laddf_sub
    add r14, r12
    addc r15, r13
    bit #0x100, r13
    jz .Laddf_round
    rra r13
    rrc r12
    rrc r11
    jnc 7f
    bis #1, r11
7:  inc r10
    cmp #255, r10
    jeq .Laddf_inf
    jmp .Laddf_round
.Laddf_sub:
    clr r6
    sub r11, r6
    subc r14, r12
    subc r15, r13
    mov r6, r11
    bis r12, r6
    bis r13, r6
    tst r6
    jz .Laddf_pzero
.Laddf_norm:
    bit #0x80, r13
    jnz .Laddf_round
    cmp #1, r10
    jeq .Laddf_round
    tst r13
    jnz 8f
    cmp #9, r10
    jlo 8f
    swpb r12
    swpb r11
    mov.b r12, r13
    xor r13, r12
    mov.b r11, r6
    xor r6, r11
    bis r6, r12
    sub #8, r10
    jmp .Laddf_norm
8:  rla r11
    rlc r12
    rlc r13
    dec r10
    jmp .Laddf_norm
.Laddf_round:
    rla r11
    jnc .Laddf_pack
    jnz 9f
    bit #1, r12
    jz .Laddf_pack
9:  inc r12
    adc r13
.Laddf_pack:
    dec r10
    swpb r10
    clrc
    rrc r10
    add r10, r13
    bis r7, r13
.Laddf_ret:
    pop r6
    pop r7
    pop r8
    pop r9
    pop r10
    ret
.Laddf_bsub:
    ; b is zero or subnormal (exponent field 0)
    mov r15, r6
    bis r14, r6
    tst r6
    jz .Laddf_bzero
    mov #1, r9
    tst r10
    jz 10f
    bis #0x80, r13
    jmp .Laddf_align
10: mov #1, r10
    jmp .Laddf_align
.Laddf_bzero:
    ; a + 0 = a, except +0 + -0 = +0
    tst r10
    jnz 11f
    mov r13, r6
    bis r12, r6
    tst r6
    jnz 12f
    tst r8
    jn .Laddf_pzero
    mov r7, r13
    jmp .Laddf_ret
11: bis #0x80, r13
    jmp .Laddf_pack
12: mov #1, r10
    jmp .Laddf_pack
.Laddf_pzero:
    clr r12
    clr r13
    jmp .Laddf_ret
.Laddf_spec:
    ; |a| is inf or NaN (and |b| <= |a|)
    mov r13, r6
    bis r12, r6
    tst r6
    jnz .Laddf_nan
    cmp #255, r9
    jne .Laddf_inf
    tst r8
    jn .Laddf_nan
.Laddf_inf:
    mov #0x7f80, r13
    bis r7, r13
    clr r12
    jmp .Laddf_ret
.Laddf_nan:
    mov #0x7fc0, r13
    clr r12
    jmp .Laddf_ret
    .size __mspabi_addf, .-__mspabi_addf
"#
);

// Three-way compare: r12 = -1 (a < b or unordered), 0 (a == b), 1 (a > b).
global_asm!(
    r#"
    .section .text.__mspabi_cmpf,"ax",@progbits
    .globl __mspabi_cmpf
    .type __mspabi_cmpf,@function
    .p2align 1
__mspabi_cmpf:
    mov r13, r11
    and #0x7fff, r11
    cmp #0x7f80, r11
    jlo 1f
    jne .Lcmpf_lt
    tst r12
    jnz .Lcmpf_lt
1:  mov r15, r11
    and #0x7fff, r11
    cmp #0x7f80, r11
    jlo 2f
    jne .Lcmpf_lt
    tst r14
    jnz .Lcmpf_lt
2:  mov r13, r11
    bis r15, r11
    and #0x7fff, r11
    bis r12, r11
    bis r14, r11
    tst r11
    jz .Lcmpf_eq
    tst r13
    jn 3f
    tst r15
    jn .Lcmpf_gt
    cmp r15, r13
    jlo .Lcmpf_lt
    jne .Lcmpf_gt
    cmp r14, r12
    jlo .Lcmpf_lt
    jne .Lcmpf_gt
.Lcmpf_eq:
    clr r12
    ret
3:  tst r15
    jge .Lcmpf_lt
    cmp r13, r15
    jlo .Lcmpf_lt
    jne .Lcmpf_gt
    cmp r12, r14
    jlo .Lcmpf_lt
    jne .Lcmpf_gt
    clr r12
    ret
.Lcmpf_lt:
    mov #-1, r12
    ret
.Lcmpf_gt:
    mov #1, r12
    ret
    .size __mspabi_cmpf, .-__mspabi_cmpf
"#
);

// i32/u32 -> f32: r13:r12 = (float) x.
global_asm!(
    r#"
    .section .text.__mspabi_fltlif,"ax",@progbits
    .globl __mspabi_fltlif
    .type __mspabi_fltlif,@function
    .globl __mspabi_fltulf
    .type __mspabi_fltulf,@function
    .p2align 1
__mspabi_fltlif:
    mov r13, r15
    and #0x8000, r15
    jz 1f
    inv r12
    inv r13
    inc r12
    adc r13
    jmp 1f
__mspabi_fltulf:
    clr r15
1:  mov r13, r14
    bis r12, r14
    tst r14
    jz 9f
    mov #158, r14
    tst r13
    jnz 2f
    mov r12, r13
    clr r12
    sub #16, r14
2:  cmp #0x100, r13
    jhs 3f
    swpb r13
    swpb r12
    mov.b r12, r11
    xor r11, r12
    bis r11, r13
    sub #8, r14
3:  tst r13
    jn 4f
    rla r12
    rlc r13
    dec r14
    jmp 3b
4:  bit #0x80, r12
    jz 5f
    bit #0x17f, r12
    jz 5f
    add #0x100, r12
    adc r13
    jnc 5f
    mov #0x8000, r13
    inc r14
5:  swpb r12
    swpb r13
    mov.b r12, r12
    mov.b r13, r11
    xor r11, r13
    bis r13, r12
    mov r11, r13
    dec r14
    swpb r14
    clrc
    rrc r14
    add r14, r13
    bis r15, r13
9:  ret
    .size __mspabi_fltlif, .-__mspabi_fltlif
"#
);

// f32 -> i32 / u32, truncating; out of range saturates, NaN gives 0 (Rust `as` semantics; LLVM
// adds its own range checks around the call anyway).
global_asm!(
    r#"
    .section .text.__mspabi_fixfli,"ax",@progbits
    .globl __mspabi_fixfli
    .type __mspabi_fixfli,@function
    .globl __mspabi_fixful
    .type __mspabi_fixful,@function
    .p2align 1
__mspabi_fixfli:
    mov r13, r15
    mov r13, r14
    rla r14
    swpb r14
    mov.b r14, r14
    cmp #127, r14
    jlo .Lfix_zero
    cmp #158, r14
    jhs 1f
    call #.Lfix_mag
    tst r15
    jge 2f
    inv r12
    inv r13
    inc r12
    adc r13
2:  ret
1:  ; |x| >= 2^31 or NaN
    cmp #255, r14
    jne 3f
    mov r13, r11
    and #0x7f, r11
    bis r12, r11
    tst r11
    jnz .Lfix_zero
3:  clr r12
    mov #0x8000, r13
    tst r15
    jn 2b
    mov #-1, r12
    mov #0x7fff, r13
    ret
__mspabi_fixful:
    mov r13, r14
    rla r14
    swpb r14
    mov.b r14, r14
    cmp #127, r14
    jlo .Lfix_zero
    tst r13
    jn .Lfix_zero
    cmp #159, r14
    jhs 4f
    br #.Lfix_mag
4:  cmp #255, r14
    jne 5f
    mov r13, r11
    and #0x7f, r11
    bis r12, r11
    tst r11
    jnz .Lfix_zero
5:  mov #-1, r12
    mov #-1, r13
    ret
.Lfix_zero:
    clr r12
    clr r13
    ret
.Lfix_mag:
    ; |x| = m * 2^(e - 150), 127 <= e <= 158: r13:r12 = floor(|x|)
    and #0x7f, r13
    bis #0x80, r13
    sub #150, r14
    jge 8f
    inv r14
    inc r14
    cmp #16, r14
    jlo 6f
    mov r13, r12
    clr r13
    sub #16, r14
    jz 9f
6:  cmp #8, r14
    jlo 7f
    swpb r12
    swpb r13
    mov.b r12, r12
    mov.b r13, r11
    xor r11, r13
    bis r13, r12
    mov r11, r13
    sub #8, r14
    jz 9f
7:  clrc
    rrc r13
    rrc r12
    dec r14
    jnz 7b
    ret
8:  jz 9f
10: rla r12
    rlc r13
    dec r14
    jnz 10b
9:  ret
    .size __mspabi_fixfli, .-__mspabi_fixfli
"#
);

// Square root: r13:r12 = sqrt(x), correctly rounded (bit-by-bit, two phases of 16-bit words).
global_asm!(
    r#"
    .section .text.acs_sqrtf,"ax",@progbits
    .globl acs_sqrtf
    .type acs_sqrtf,@function
    .p2align 1
acs_sqrtf:
    tst r13
    jn .Lsqrt_neg
    mov r13, r14
    rla r14
    swpb r14
    mov.b r14, r14
    cmp #255, r14
    jeq .Lsqrt_spec
    and #0x7f, r13
    tst r14
    jz .Lsqrt_sub
    bis #0x80, r13
.Lsqrt_ok:
    push r10
    bit #1, r14
    jnz 1f
    rla r12
    rlc r13
1:  add #127, r14
    rra r14
    push r14
    rla r12
    rlc r13
    clr r15
    clr r11
    mov #0x100, r10
2:  mov r15, r14
    add r10, r14
    cmp r14, r13
    jlo 3f
    sub r14, r13
    add r10, r14
    mov r14, r15
3:  rla r12
    rlc r13
    rra r10
    jnz 2b
    mov #0x8000, r10
4:  cmp r15, r13
    jlo 7f
    mov r11, r14
    add r10, r14
    cmp r15, r13
    jne 5f
    cmp r14, r12
    jlo 7f
5:  sub r14, r12
    subc r15, r13
    add r10, r14
    mov r14, r11
    adc r15
7:  rla r12
    rlc r13
    clrc
    rrc r10
    jnz 4b
    ; r15:r11 = s = 2q; remainder r13:r12
    bis r12, r13
    clrc
    rrc r15
    rrc r11
    tst r13
    jz 8f
    bit #1, r11
    jz 8f
    inc r11
    adc r15
8:  clrc
    rrc r15
    rrc r11
    pop r14
    dec r14
    swpb r14
    clrc
    rrc r14
    add r14, r15
    mov r11, r12
    mov r15, r13
    pop r10
    ret
.Lsqrt_sub:
    mov r13, r15
    bis r12, r15
    tst r15
    jz .Lsqrt_ret
    mov #1, r14
9:  dec r14
    rla r12
    rlc r13
    bit #0x80, r13
    jz 9b
    jmp .Lsqrt_ok
.Lsqrt_neg:
    mov r13, r14
    and #0x7fff, r14
    bis r12, r14
    tst r14
    jz .Lsqrt_ret
.Lsqrt_nan:
    mov #0x7fc0, r13
    clr r12
.Lsqrt_ret:
    ret
.Lsqrt_spec:
    mov r13, r14
    and #0x7f, r14
    bis r12, r14
    tst r14
    jnz .Lsqrt_nan
    ret
    .size acs_sqrtf, .-acs_sqrtf
"#
);

// Unordered test (LLVM calls it by its compiler-builtins name for `is_nan`-like folds, for
// `partial_cmp` and around every saturating `as` conversion): r12 = 1 if a or b is NaN, else 0.
// Defined here (before compiler-builtins in link order) because the generic one costs ~100 cycles.
global_asm!(
    r#"
    .section .text.__unordsf2,"ax",@progbits
    .globl __unordsf2
    .type __unordsf2,@function
    .p2align 1
__unordsf2:
    and #0x7fff, r13
    cmp #0x7f80, r13
    jlo 1f
    jne 3f
    tst r12
    jnz 3f
1:  and #0x7fff, r15
    cmp #0x7f80, r15
    jlo 2f
    jne 3f
    tst r14
    jnz 3f
2:  clr r12
    ret
3:  mov #1, r12
    ret
    .size __unordsf2, .-__unordsf2
"#
);
