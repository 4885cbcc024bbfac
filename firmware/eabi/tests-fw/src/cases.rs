//! Test cases shared by the MSP430 test firmware and the host verifier.
//!
//! The same source is compiled twice: for `msp430-none-elf`, where every `+ - * /`, comparison,
//! `as` conversion, 32/64-bit multiply, divide and variable shift lowers to an `__mspabi_*` helper
//! call, and for the host, where the same expressions are native IEEE-754 / integer operations.
//! Inputs come from a deterministic xorshift32 generator, identical on both sides; each case
//! returns its result folded into two words (NaN results canonicalised, since IEEE leaves the NaN
//! payload open) and the inputs (for the host's failure report).

#![allow(clippy::unusual_byte_groupings)]

/// Cases per block (one hash per block).
pub const BLOCK: u16 = 256;

/// Deterministic xorshift32 generator.
pub struct Rng(u32);

impl Rng {
    /// Generator for block `block` of operation `op`: every block is independent.
    pub fn new(seed: u32, op: u16, block: u16) -> Rng {
        let mut x = seed ^ ((op as u32) << 16) ^ (block as u32) ^ 0x5bd1_e995;
        if x == 0 {
            x = 1;
        }
        let mut r = Rng(x);
        for _ in 0..4 {
            r.next();
        }
        r
    }

    /// Next 32-bit value.
    #[inline(always)]
    pub fn next(&mut self) -> u32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        x
    }
}

/// Fold a result word into a block hash (invertible in `v`: one differing word always shows).
#[inline(always)]
pub fn mix(h: u32, v: u32) -> u32 {
    (h.rotate_left(5) ^ v).wrapping_add(0x9e37_79b9)
}

const SPECIAL_F32: [u32; 32] = [
    0x0000_0000,
    0x8000_0000,
    0x7f80_0000,
    0xff80_0000,
    0x7fc0_0000,
    0x7fa0_0001,
    0xffc0_0001,
    0x0000_0001,
    0x8000_0001,
    0x007f_ffff,
    0x807f_ffff,
    0x0080_0000,
    0x8080_0000,
    0x7f7f_ffff,
    0xff7f_ffff,
    0x3f80_0000,
    0xbf80_0000,
    0x3f00_0000,
    0x4000_0000,
    0x3f7f_ffff,
    0x3f80_0001,
    0x0040_0000,
    0x0000_0002,
    0x3400_0000,
    0x4b00_0000,
    0x4f00_0000,
    0xcf00_0000,
    0x5f00_0000,
    0xdf00_0000,
    0x4f80_0000,
    0x3fff_ffff,
    0x0100_0000,
];

const SPECIAL_F64: [u64; 16] = [
    0x0000_0000_0000_0000,
    0x8000_0000_0000_0000,
    0x7ff0_0000_0000_0000,
    0xfff0_0000_0000_0000,
    0x7ff8_0000_0000_0000,
    0x0000_0000_0000_0001,
    0x000f_ffff_ffff_ffff,
    0x0010_0000_0000_0000,
    0x7fef_ffff_ffff_ffff,
    0x3ff0_0000_0000_0000,
    0xbff0_0000_0000_0000,
    0x41e0_0000_0000_0000,
    0xc1e0_0000_0000_0000,
    0x43e0_0000_0000_0000,
    0x47ef_ffff_ffff_ffff,
    0x36a0_0000_0000_0000,
];

const SPECIAL_I32: [u32; 8] = [
    0,
    1,
    0xffff_ffff,
    0x8000_0000,
    0x7fff_ffff,
    2,
    0xffff_0000,
    0x0000_ffff,
];

fn with_exp(sign_mant: u32, e: u32) -> u32 {
    (sign_mant & 0x807f_ffff) | ((e & 0xff) << 23)
}

/// An f32 bit pattern: a mix of uniform bit patterns, typical magnitudes, special values,
/// subnormals, tiny and huge exponents, values close to `rel` (cancellation, near-equality) and
/// short mantissas (exact products, halfway cases).
pub fn f32_bits(r: &mut Rng, rel: u32) -> u32 {
    let x = r.next();
    let y = r.next();
    let k = (x >> 4) & 31;
    match x & 15 {
        0..=4 => y,
        5..=7 => with_exp(y, 112 + k),
        8 => SPECIAL_F32[((y >> 8) & 31) as usize],
        9 => y & 0x807f_ffff,
        10 => with_exp(y, 1 + k),
        11 => with_exp(y, 223 + k),
        12 => {
            let e = (rel >> 23) & 0xff;
            let e = (e + (k & 3)).saturating_sub(1).min(254);
            with_exp(y, e)
        }
        13 => rel ^ (y & 0x8000_00ff),
        14 => {
            let m = (y & 0x807f_ffff) & !((1u32 << (k & 15)) - 1);
            with_exp(m, 110 + ((x >> 9) & 31))
        }
        _ => {
            let m = if y & 1 == 0 { 0x007f_ffff } else { 1 };
            with_exp(m | (y & 0x8000_0000), 100 + k * 2)
        }
    }
}

/// An f64 bit pattern (same classes as [`f32_bits`]).
pub fn f64_bits(r: &mut Rng, rel: u64) -> u64 {
    let x = r.next();
    let hi = r.next() as u64;
    let lo = r.next() as u64;
    let y = (hi << 32) | lo;
    let k = ((x >> 4) & 63) as u64;
    let with_exp = |m: u64, e: u64| (m & 0x800f_ffff_ffff_ffff) | ((e & 0x7ff) << 52);
    match x & 15 {
        0..=4 => y,
        5..=7 => with_exp(y, 990 + k),
        8 => SPECIAL_F64[((x >> 8) & 15) as usize],
        9 => y & 0x800f_ffff_ffff_ffff,
        10 => with_exp(y, 1 + k),
        11 => with_exp(y, 1983 + k),
        12 => with_exp(y, ((rel >> 52) & 0x7ff) ^ (k & 3)),
        13 => rel ^ (y & 0x8000_0000_0000_ffff),
        14 => with_exp(y & !((1u64 << (k & 31)) - 1), 1000 + (k & 31)),
        _ => f32_bits(r, 0) as u64 | ((x as u64) << 32),
    }
}

/// A 32-bit integer operand: uniform, small, special, negative small.
pub fn i32_bits(r: &mut Rng) -> u32 {
    let x = r.next();
    let y = r.next();
    match x & 15 {
        0..=6 => y,
        7..=10 => y >> ((x >> 4) & 31),
        11 => SPECIAL_I32[((x >> 4) & 7) as usize],
        12 => y & 0xffff,
        _ => 0u32.wrapping_sub(y >> ((x >> 4) & 31)),
    }
}

/// A 64-bit integer operand.
pub fn i64_bits(r: &mut Rng) -> u64 {
    let x = r.next();
    let hi = i32_bits(r) as u64;
    let lo = i32_bits(r) as u64;
    match x & 7 {
        0..=3 => (hi << 32) | lo,
        4 => lo,
        5 => ((hi << 32) | lo) >> (x >> 26),
        6 => 0u64.wrapping_sub(lo),
        _ => ((hi << 32) | lo) << (x >> 26),
    }
}

fn f32r(x: f32) -> (u32, u32) {
    if x.is_nan() {
        (0x7fc0_0000, 0)
    } else {
        (x.to_bits(), 0)
    }
}

fn f64r(x: f64) -> (u32, u32) {
    if x.is_nan() {
        (0, 0x7ff8_0000)
    } else {
        let b = x.to_bits();
        (b as u32, (b >> 32) as u32)
    }
}

fn w64(x: u64) -> (u32, u32) {
    (x as u32, (x >> 32) as u32)
}

fn nz32(x: u32) -> u32 {
    if x == 0 {
        1
    } else {
        x
    }
}

fn nz64(x: u64) -> u64 {
    if x == 0 {
        1
    } else {
        x
    }
}

/// The three-way result of `__mspabi_cmpf` as documented: −1, 0, 1, and −1 for unordered.
#[cfg(target_arch = "msp430")]
fn cmpf_raw(a: f32, b: f32) -> i16 {
    extern "C" {
        fn __mspabi_cmpf(a: f32, b: f32) -> i16;
    }
    // SAFETY: plain function of two floats.
    let r = unsafe { __mspabi_cmpf(a, b) };
    r.signum()
}

#[cfg(not(target_arch = "msp430"))]
fn cmpf_raw(a: f32, b: f32) -> i16 {
    match a.partial_cmp(&b) {
        Some(core::cmp::Ordering::Less) | None => -1,
        Some(core::cmp::Ordering::Equal) => 0,
        Some(core::cmp::Ordering::Greater) => 1,
    }
}

#[cfg(target_arch = "msp430")]
fn sqrtf(a: f32) -> f32 {
    extern "C" {
        fn acs_sqrtf(a: f32) -> f32;
    }
    // SAFETY: plain function of a float.
    unsafe { acs_sqrtf(a) }
}

#[cfg(not(target_arch = "msp430"))]
fn sqrtf(a: f32) -> f32 {
    a.sqrt()
}

/// Comparison operators as the MSP430 build evaluates them: exact, except that `<` and `<=`
/// are true when an operand is NaN (LLVM tests one helper result for every ordered predicate,
/// see the crate docs). On the host this emulation is the expectation. (`partial_cmp` is not
/// tested: core implements it with `<=` and `>=`, so its NaN result depends on how LLVM folds
/// it in each context.)
#[cfg(not(target_arch = "msp430"))]
fn cmp_flags<T: PartialOrd + Copy>(a: T, b: T) -> u32 {
    let un = a.partial_cmp(&b).is_none();
    let bits = [a < b || un, a <= b || un, a > b, a >= b, a == b, a != b];
    let mut f = 0;
    for (i, &v) in bits.iter().enumerate() {
        f |= (v as u32) << i;
    }
    f
}

#[cfg(target_arch = "msp430")]
#[inline(never)]
fn cmp_flags<T: PartialOrd + Copy>(a: T, b: T) -> u32 {
    let a = core::hint::black_box(a);
    let b = core::hint::black_box(b);
    let bits = [a < b, a <= b, a > b, a >= b, a == b, a != b];
    let mut f = 0;
    for (i, &v) in bits.iter().enumerate() {
        f |= (v as u32) << i;
    }
    f
}

/// Operation names, indexed by operation number.
pub const OPS: &[&str] = &[
    "addf", "subf", "mpyf", "divf", "cmpf", "sqrtf", "fixfli", "fixful", "fixflli", "fixfull",
    "fltlif", "fltulf", "fltllif", "fltullf", "fltif16", "cvtfd", "cvtdf", "addd", "subd", "mpyd",
    "divd", "cmpd", "fixdli", "fixdul", "fixdlli", "fixdull", "fltlid", "fltuld", "fltllid",
    "fltulld", "mpyi", "divi", "remi", "divu", "remu", "mpyl", "mpyl16", "divli", "remli", "divul",
    "remul", "mpyll", "mpyll32", "divlli", "remlli", "divull", "remull", "slll", "srll", "sral",
    "memcpy", "memmove", "memset",
];

/// Number of an operation by name.
pub fn op_number(name: &str) -> Option<u16> {
    OPS.iter().position(|&n| n == name).map(|i| i as u16)
}

/// One case of operation `op`: inputs (up to four words) and the result (two words).
pub fn case(op: u16, r: &mut Rng) -> ([u32; 4], (u32, u32)) {
    let f = f32::from_bits;
    let d = f64::from_bits;
    match op {
        0..=5 => {
            let a = f32_bits(r, 0);
            let b = f32_bits(r, a);
            let (x, y) = (f(a), f(b));
            let res = match op {
                0 => f32r(x + y),
                1 => f32r(x - y),
                2 => f32r(x * y),
                3 => f32r(x / y),
                4 => ((cmpf_raw(x, y) as u16 as u32), cmp_flags(x, y)),
                _ => f32r(sqrtf(x)),
            };
            ([a, b, 0, 0], res)
        }
        6..=9 | 15 => {
            let a = f32_bits(r, 0);
            let x = f(a);
            let res = match op {
                6 => ((x as i32) as u32, 0),
                7 => (x as u32, 0),
                8 => w64(x as i64 as u64),
                9 => w64(x as u64),
                _ => f64r(x as f64),
            };
            ([a, 0, 0, 0], res)
        }
        10..=14 => {
            let a = i64_bits(r);
            let lo = a as u32;
            let res = match op {
                10 => f32r(lo as i32 as f32),
                11 => f32r(lo as f32),
                12 => f32r(a as i64 as f32),
                13 => f32r(a as f32),
                _ => f32r(lo as i16 as f32),
            };
            ([lo, (a >> 32) as u32, 0, 0], res)
        }
        16 | 22..=25 => {
            let a = f64_bits(r, 0);
            let x = d(a);
            let res = match op {
                16 => f32r(x as f32),
                22 => ((x as i32) as u32, 0),
                23 => (x as u32, 0),
                24 => w64(x as i64 as u64),
                _ => w64(x as u64),
            };
            ([a as u32, (a >> 32) as u32, 0, 0], res)
        }
        17..=21 => {
            let a = f64_bits(r, 0);
            let b = f64_bits(r, a);
            let (x, y) = (d(a), d(b));
            let res = match op {
                17 => f64r(x + y),
                18 => f64r(x - y),
                19 => f64r(x * y),
                20 => f64r(x / y),
                _ => (0, cmp_flags(x, y)),
            };
            (
                [a as u32, (a >> 32) as u32, b as u32, (b >> 32) as u32],
                res,
            )
        }
        26..=29 => {
            let a = i64_bits(r);
            let lo = a as u32;
            let res = match op {
                26 => f64r(lo as i32 as f64),
                27 => f64r(lo as f64),
                28 => f64r(a as i64 as f64),
                _ => f64r(a as f64),
            };
            ([lo, (a >> 32) as u32, 0, 0], res)
        }
        30..=34 => {
            let a = i32_bits(r) as u16;
            let b = i32_bits(r) as u16;
            let b = if b == 0 { 1 } else { b };
            let res = match op {
                30 => a.wrapping_mul(b),
                31 => (a as i16).wrapping_div(b as i16) as u16,
                32 => (a as i16).wrapping_rem(b as i16) as u16,
                33 => a / b,
                _ => a % b,
            };
            ([a as u32, b as u32, 0, 0], (res as u32, 0))
        }
        35..=40 | 47..=49 => {
            let a = i32_bits(r);
            let b = i32_bits(r);
            let res = match op {
                35 => a.wrapping_mul(b),
                36 => (a as u16 as u32) * (b as u16 as u32),
                37 => (a as i32).wrapping_div(nz32(b) as i32) as u32,
                38 => (a as i32).wrapping_rem(nz32(b) as i32) as u32,
                39 => a / nz32(b),
                40 => a % nz32(b),
                47 => a << (b & 31),
                48 => a >> (b & 31),
                _ => ((a as i32) >> (b & 31)) as u32,
            };
            ([a, b, 0, 0], (res, 0))
        }
        50..=52 => {
            let w = [r.next(), r.next(), r.next(), r.next()];
            (w, mem_case(op, &w))
        }
        _ => {
            let a = i64_bits(r);
            let b = i64_bits(r);
            let res = match op {
                41 => a.wrapping_mul(b),
                42 => (a as u32 as u64) * (b as u32 as u64),
                43 => (a as i64).wrapping_div(nz64(b) as i64) as u64,
                44 => (a as i64).wrapping_rem(nz64(b) as i64) as u64,
                45 => a / nz64(b),
                _ => a % nz64(b),
            };
            (
                [a as u32, (a >> 32) as u32, b as u32, (b >> 32) as u32],
                w64(res),
            )
        }
    }
}

/// `memcpy` (50), `memmove` (51) or `memset` (52) on a 16-byte buffer holding the input words,
/// with length, offsets and fill byte taken from the inputs (lengths 0..=16, overlaps both
/// ways for `memmove`): the buffer folded into two words. The length is not a constant, so on
/// the MSP430 the copies are calls of the helpers.
fn mem_case(op: u16, w: &[u32; 4]) -> (u32, u32) {
    let mut buf = [0u8; 16];
    for (chunk, word) in buf.chunks_exact_mut(4).zip(w.iter()) {
        chunk.copy_from_slice(&word.to_le_bytes());
    }
    let sel = mix(w[0], w[3]);
    // in u32, then cast: usize is 16 bits on the MSP430
    let len = sel % 17;
    let room = 16 - len;
    let dst = ((sel >> 8) % (room + 1)) as usize;
    let src = ((sel >> 16) % (room + 1)) as usize;
    let len = len as usize;
    let len = core::hint::black_box(len);
    match op {
        50 => {
            let mut other = buf;
            other.reverse();
            if let (Some(to), Some(from)) = (buf.get_mut(dst..dst + len), other.get(src..src + len))
            {
                to.copy_from_slice(from);
            }
        }
        51 => buf.copy_within(src..src + len, dst),
        _ => {
            if let Some(to) = buf.get_mut(dst..dst + len) {
                to.fill((sel >> 24) as u8);
            }
        }
    }
    let mut h = (0u32, 0u32);
    for (i, chunk) in buf.chunks_exact(4).enumerate() {
        let v = u32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]);
        if i < 2 {
            h.0 = mix(h.0, v);
        } else {
            h.1 = mix(h.1, v);
        }
    }
    h
}
