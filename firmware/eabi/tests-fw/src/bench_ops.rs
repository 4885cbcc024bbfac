//! Cycle-count operations and their typical operands, shared by the firmware and the host.
use crate::cases::Rng;

/// Passes over the operand sets between the two marks.
pub const REPS: u16 = 4;
/// Operand sets (pairs) per operation.
pub const SETS: usize = 16;

/// Operations timed by bench mode (index = operation number of bench mode).
pub const BENCH: &[&str] = &[
    "empty",
    "addf",
    "subf",
    "mpyf",
    "divf",
    "cmpf",
    "sqrtf",
    "fixfli",
    "f32_as_i32",
    "fltlif",
    "mpyi",
    "mpyl",
    "mpyl16",
    "divu",
    "divul",
    "divli",
    "srll",
    "addd",
    "mpyd",
    "divd",
];

fn typical_f32(r: &mut Rng) -> u32 {
    // Random sign and mantissa, magnitude in [2^-8, 2^8): the values flight code works with.
    let y = r.next();
    (y & 0x807f_ffff) | ((119 + (r.next() & 15)) << 23)
}

/// Typical operands of bench operation `name` (f64 operations get f64 bit patterns).
pub fn operands(name: &str, r: &mut Rng) -> (u64, u64) {
    match name {
        "sqrtf" => ((typical_f32(r) & 0x7fff_ffff) as u64, 0),
        "fltlif" => ((r.next() >> (r.next() & 15)) as u64, 0),
        "fixfli" | "f32_as_i32" => ((typical_f32(r) + (8 << 23)) as u64, 0),
        "mpyi" | "divu" => ((r.next() & 0xffff) as u64, (r.next() & 0xffff | 1) as u64),
        "mpyl" | "divli" => (r.next() as u64, r.next() as u64),
        "mpyl16" => ((r.next() & 0xffff) as u64, (r.next() & 0xffff) as u64),
        "divul" => (r.next() as u64, ((r.next() >> (r.next() & 15)) | 1) as u64),
        "srll" => (r.next() as u64, (r.next() & 31) as u64),
        "addd" | "mpyd" | "divd" => (
            (f32::from_bits(typical_f32(r)) as f64).to_bits() ^ (r.next() as u64),
            (f32::from_bits(typical_f32(r)) as f64).to_bits() ^ (r.next() as u64),
        ),
        _ => (typical_f32(r) as u64, typical_f32(r) as u64),
    }
}
