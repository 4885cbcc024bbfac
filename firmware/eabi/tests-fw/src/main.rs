//! Test and cycle-count firmware for the `msp430-eabi` helpers, run in mspdebug's simulator.
//!
//! The host (`../verify`) writes a parameter block at 0x0200, runs to `tf_done` and reads the
//! result words at 0x0400:
//! - mode 1 (verify): for each block `b < nblocks` of operation `op`, the hash of its
//!   [`cases::BLOCK`] results goes to word `b`;
//! - mode 2 (dump): the two result words of each case of block `block` go to words `2i, 2i+1`;
//! - mode 3 (bench): 32 "typical" operand sets are generated, then `tf_mark` is called, the
//!   operation runs `reps` times over them, and `tf_mark` is called again; the host reads the
//!   simulator's cycle counter at both marks.
#![no_std]
#![no_main]
#![feature(asm_experimental_arch)]

use core::ptr::{read_volatile, write_volatile};
use msp430_eabi as _;

mod bench;
#[allow(dead_code)]
mod bench_ops;
#[allow(dead_code)]
mod cases;

const IO: usize = 0x0200;
const RES: usize = 0x0400;
const RES_WORDS: usize = 0x1000 / 4;

fn rd16(i: usize) -> u16 {
    // SAFETY: the simulator's RAM at the fixed parameter block, written by the host.
    unsafe { read_volatile((IO + 2 * i) as *const u16) }
}

fn wr16(i: usize, v: u16) {
    // SAFETY: as above.
    unsafe { write_volatile((IO + 2 * i) as *mut u16, v) }
}

fn res(i: usize, v: u32) {
    if i < RES_WORDS {
        // SAFETY: the result area 0x0400..0x1400 (outside .data/.bss/stack, see link.x).
        unsafe { write_volatile((RES + 4 * i) as *mut u32, v) }
    }
}

core::arch::global_asm!(
    r#"
    .section .text.tf_reset,"ax",@progbits
    .globl tf_reset
    .type tf_reset,@function
tf_reset:
    mov #__stack_top, r1
    mov #__bss_start, r12
1:  cmp #__bss_end, r12
    jhs 2f
    clr 0(r12)
    incd r12
    jmp 1b
2:  call #tf_main
    .globl tf_done
    .type tf_done,@function
tf_done:
    jmp tf_done

    .section .vectors,"a",@progbits
    .word tf_reset
"#
);

/// Parameter block: 0 magic, 1 mode, 2 op, 3 nblocks, 4-5 seed, 6 block, 7 status, 8 reps.
#[no_mangle]
extern "C" fn tf_main() {
    let mode = rd16(1);
    let op = rd16(2);
    let nblocks = rd16(3);
    let seed = (rd16(4) as u32) | ((rd16(5) as u32) << 16);
    let block = rd16(6);
    match mode {
        1 => {
            for b in 0..nblocks {
                let mut r = cases::Rng::new(seed, op, b);
                let mut h = 0u32;
                for _ in 0..cases::BLOCK {
                    let (_, (x, y)) = cases::case(op, &mut r);
                    h = cases::mix(cases::mix(h, x), y);
                }
                res(b as usize, h);
            }
        }
        2 => {
            let mut r = cases::Rng::new(seed, op, block);
            for i in 0..cases::BLOCK as usize {
                let (_, (x, y)) = cases::case(op, &mut r);
                res(2 * i, x);
                res(2 * i + 1, y);
            }
        }
        3 => bench::run(op, rd16(8)),
        _ => {}
    }
    wr16(7, 0xd00e);
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    wr16(7, 0xdead);
    loop {}
}
