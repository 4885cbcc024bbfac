//! Cycle-count mode: typical operands, one operation repeated between two `tf_mark` calls.
use crate::bench_ops::{operands, BENCH, SETS};
use crate::cases::Rng;
use core::hint::black_box;

/// Marker the host puts a breakpoint on.
#[no_mangle]
#[inline(never)]
pub extern "C" fn tf_mark() {
    // SAFETY: a no-op instruction.
    unsafe { core::arch::asm!("nop") }
}

extern "C" {
    fn __mspabi_cmpf(a: f32, b: f32) -> i16;
    fn acs_sqrtf(a: f32) -> f32;
    fn __mspabi_fixfli(a: f32) -> i32;
}

static mut SINK: u32 = 0;

macro_rules! timed {
    ($set:expr, $reps:expr, |$a:ident, $b:ident| $e:expr) => {{
        let set = $set;
        let mut acc = 0u32;
        tf_mark();
        for _ in 0..$reps {
            for &(x, y) in set.iter() {
                let $a = black_box(x);
                let $b = black_box(y);
                acc ^= black_box($e);
            }
        }
        tf_mark();
        acc
    }};
}

pub fn run(op: u16, reps: u16) {
    let name = BENCH.get(op as usize).copied().unwrap_or("empty");
    let mut r = Rng::new(0x1234_5678, op, 0);
    let mut set = [(0u64, 0u64); SETS];
    for s in set.iter_mut() {
        *s = operands(name, &mut r);
    }
    let mut s32 = [(0u32, 0u32); SETS];
    for (d, s) in s32.iter_mut().zip(set.iter()) {
        *d = (s.0 as u32, s.1 as u32);
    }
    let f = f32::from_bits;
    let d = f64::from_bits;
    let acc = match name {
        "addf" => timed!(s32, reps, |a, b| (f(a) + f(b)).to_bits()),
        "subf" => timed!(s32, reps, |a, b| (f(a) - f(b)).to_bits()),
        "mpyf" => timed!(s32, reps, |a, b| (f(a) * f(b)).to_bits()),
        "divf" => timed!(s32, reps, |a, b| (f(a) / f(b)).to_bits()),
        // SAFETY: plain functions of floats.
        "cmpf" => timed!(s32, reps, |a, b| unsafe { __mspabi_cmpf(f(a), f(b)) }
            as u32),
        "sqrtf" => timed!(s32, reps, |a, _b| unsafe { acs_sqrtf(f(a)) }.to_bits()),
        "fixfli" => timed!(s32, reps, |a, _b| unsafe { __mspabi_fixfli(f(a)) } as u32),
        "f32_as_i32" => timed!(s32, reps, |a, _b| f(a) as i32 as u32),
        "fltlif" => timed!(s32, reps, |a, _b| (a as i32 as f32).to_bits()),
        "mpyi" => timed!(s32, reps, |a, b| (a as u16).wrapping_mul(b as u16) as u32),
        "mpyl" => timed!(s32, reps, |a, b| a.wrapping_mul(b)),
        "mpyl16" => timed!(s32, reps, |a, b| (a as u16 as u32) * (b as u16 as u32)),
        "divu" => timed!(s32, reps, |a, b| ((a as u16) / (b as u16 | 1)) as u32),
        "divul" => timed!(s32, reps, |a, b| a / (b | 1)),
        "divli" => timed!(s32, reps, |a, b| ((a as i32) / ((b | 1) as i32)) as u32),
        "srll" => timed!(s32, reps, |a, b| a >> (b & 31)),
        "addd" => timed!(set, reps, |a, b| (d(a) + d(b)).to_bits() as u32),
        "mpyd" => timed!(set, reps, |a, b| (d(a) * d(b)).to_bits() as u32),
        "divd" => timed!(set, reps, |a, b| (d(a) / d(b)).to_bits() as u32),
        _ => timed!(s32, reps, |a, b| a ^ b),
    };
    // SAFETY: single-threaded firmware.
    unsafe { core::ptr::write_volatile(core::ptr::addr_of_mut!(SINK), acc) };
}
