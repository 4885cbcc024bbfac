//! Runtime: reset handler and interrupt vector table (MSP430x4xx, 16 vectors at 0xFFE0–0xFFFF).
//!
//! `Reset` (vector 0xFFFE) runs with no stack and no initialised memory:
//! 1. stack pointer R1 = `_stack_top` (top of RAM, from `link.x`/`memory.x`);
//! 2. watchdog running from reset: `WDTCTL` (0x0120) = [`WDT_KICK`] (watchdog mode, ACLK,
//!    32 768 counts: 1 s with the 32 768 Hz crystal), kicked by the loop ([`crate::kick_watchdog`])
//!    before and after every step; an image that stops stepping (a fatal error, [`crate::fw_halt`])
//!    is reset within 1 s and starts again;
//! 3. `.data` copied from its load image in flash (`__sidata`) to RAM (`__sdata..__edata`);
//! 4. `.bss` zeroed (`__sbss..__ebss`);
//! 5. the stack area `__ebss.._stack_top` painted with [`STACK_PAINT`], so that the stack
//!    high-water mark can be read back (the lowest word that no longer holds the pattern);
//! 6. `main` (the binary's `#[no_mangle] extern "C" fn main() -> !`) is called.
//!
//! Every other vector goes to `DefaultHandler` → [`crate::fw_unexpected_interrupt`]: safe state,
//! then halt. Two entries name a handler an image may define (`link.x` makes it
//! `DefaultHandler` otherwise): `TIMERA0_VECTOR` (0xFFEC, Timer_A CCR0, the control period)
//! and `USCIAB0RX_VECTOR` (0xFFF2, USCI_A0/B0 receive, the link's bytes); SLAS508K interrupt
//! vector table. The flight node images define both ([`crate::periph`]); the PIL, benchmark
//! and driver images neither (their tables are as before).

/// The 16-bit pattern the reset handler writes over the whole free stack area.
pub const STACK_PAINT: u16 = 0xA55A;

/// The `WDTCTL` word that starts the watchdog and clears its counter: `WDTPW` (0x5A00) |
/// `WDTCNTCL` (0x0008) | `WDTSSEL` (0x0004, ACLK), interval ÷32 768 (`WDTIS` = 0), watchdog
/// mode (a reset, not an interrupt, when it expires): 1 s at ACLK = 32 768 Hz (MSP430x4xx
/// family user's guide, SLAU056, "Watchdog Timer+"). In mspdebug's simulator, whose ACLK is
/// MCLK/256, 8 388 608 MCLK cycles.
pub const WDT_KICK: u16 = 0x5A0C;

core::arch::global_asm!(
    r#"
    .section .text.reset,"ax",@progbits
    .global Reset
    .type Reset,@function
Reset:
    mov #_stack_top, r1
    mov #{wdt}, &0x0120
    mov #__sidata, r12
    mov #__sdata, r13
    mov #__edata, r14
1:  cmp r14, r13
    jc 2f
    mov @r12+, r15
    mov r15, 0(r13)
    add #2, r13
    jmp 1b
2:  mov #__sbss, r13
    mov #__ebss, r14
3:  cmp r14, r13
    jc 4f
    mov #0, 0(r13)
    add #2, r13
    jmp 3b
4:  mov #_stack_top, r14
5:  cmp r14, r13
    jc 6f
    mov #{paint}, 0(r13)
    add #2, r13
    jmp 5b
6:  call #main
    br #fw_halt

    .section .text.DefaultHandler,"ax",@progbits
    .global DefaultHandler
    .type DefaultHandler,@function
DefaultHandler:
    br #fw_unexpected_interrupt

    .section .vector_table,"a",@progbits
    .rept 6
    .word DefaultHandler
    .endr
    .word TIMERA0_VECTOR
    .word DefaultHandler
    .word DefaultHandler
    .word USCIAB0RX_VECTOR
    .rept 5
    .word DefaultHandler
    .endr
    .word Reset
"#,
    paint = const STACK_PAINT,
    wdt = const WDT_KICK,
);
