//! Helpers shared by the integration tests: where the reference data is, a two-sided
//! `assert_close`, and a small error-statistics accumulator (max, RMS) for the figures the README
//! quotes.
//!
//! Use from a test file with `mod common;` (each integration test compiles its own copy, so
//! unused helpers are allowed).
#![allow(dead_code)]

use std::fmt;
use std::path::{Path, PathBuf};

/// The reference data of the tests, `tests/data/` of this repository (see its README for where
/// each file comes from).
pub fn data_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data")
}

/// A path inside `tests/data/`, e.g. `data_path("sgp4/dtusat.tle")`.
pub fn data_path(relative: &str) -> PathBuf {
    data_dir().join(relative)
}

/// Reads a text file of `tests/data/`; panics naming the file if it cannot.
pub fn read_data(relative: &str) -> String {
    let path = data_path(relative);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// Asserts `|actual − expected| ≤ tol` (two-sided; NaN always fails), naming `what` on failure.
#[track_caller]
pub fn assert_close(actual: f64, expected: f64, tol: f64, what: &str) {
    let error = (actual - expected).abs();
    // NaN anywhere fails: only a finite error within tolerance passes.
    if error.is_nan() || error > tol {
        panic!(
            "{what}: actual {actual:e}, expected {expected:e}, |error| {error:e} > tolerance {tol:e}"
        );
    }
}

/// Asserts `assert_close` on each component of two 3-vectors.
#[track_caller]
pub fn assert_close3(actual: [f64; 3], expected: [f64; 3], tol: f64, what: &str) {
    for (i, (a, e)) in actual.iter().zip(expected.iter()).enumerate() {
        assert_close(*a, *e, tol, &format!("{what}[{i}]"));
    }
}

/// Running error statistics: count, maximum of |error| (with where it happened) and RMS.
///
/// ```ignore
/// let mut s = Stats::new("DTUSAT position error, m");
/// s.add(err, "t=60 s");
/// println!("{s}"); // run with --nocapture to read it
/// ```
#[derive(Clone, Debug)]
pub struct Stats {
    label: String,
    count: usize,
    max: f64,
    sum_sq: f64,
    worst: String,
}

impl Stats {
    /// An empty accumulator with a label (say what and in which unit).
    pub fn new(label: &str) -> Self {
        Self {
            label: label.to_owned(),
            count: 0,
            max: 0.0,
            sum_sq: 0.0,
            worst: String::new(),
        }
    }

    /// Adds one error value (its absolute value is used); `at` says where, for the maximum.
    /// A NaN becomes the maximum, so it is never hidden.
    pub fn add(&mut self, error: f64, at: &str) {
        let e = error.abs();
        self.count += 1;
        self.sum_sq += e * e;
        if !self.max.is_nan() && (e.is_nan() || e > self.max) {
            self.max = e;
            self.worst = at.to_owned();
        }
    }

    /// Adds `|actual − expected|`.
    pub fn add_pair(&mut self, actual: f64, expected: f64, at: &str) {
        self.add(actual - expected, at);
    }

    /// Number of values added.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Largest |error| (0 when empty).
    pub fn max(&self) -> f64 {
        self.max
    }

    /// Root mean square of the errors (0 when empty).
    pub fn rms(&self) -> f64 {
        if self.count == 0 {
            0.0
        } else {
            (self.sum_sq / self.count as f64).sqrt()
        }
    }

    /// Where the largest error happened.
    pub fn worst(&self) -> &str {
        &self.worst
    }

    /// Prints the statistics (visible with `cargo test -- --nocapture`).
    pub fn print(&self) {
        println!("{self}");
    }
}

impl fmt::Display for Stats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: n = {}, max = {:.3e} (at {}), rms = {:.3e}",
            self.label,
            self.count,
            self.max,
            self.worst,
            self.rms()
        )
    }
}

/// Subsets of `tiles` (bit `i` set: tile `i` in the subset) that stand for every subset: tiles
/// equal to their predecessor (same orientation and equipment: the 4-per-face cube's faces)
/// enter the least squares and the allocators only through how many of a run are in a subset,
/// so the first `k` tiles of each run (`k` = 0..=run length) represent all the others: the
/// Gram matrices are accumulated by the same operations in the same order. Without such runs,
/// every one of the `2ⁿ` subsets (n ≤ 20).
pub fn tile_subsets(tiles: &[acs::tiles::Tile]) -> Vec<u32> {
    // runs of equal consecutive tiles: (first index, length)
    let mut runs: Vec<(usize, usize)> = Vec::new();
    for (i, t) in tiles.iter().enumerate() {
        match runs.last_mut() {
            Some((start, len))
                if tiles[*start].body_to_tile == t.body_to_tile
                    && tiles[*start].equipment == t.equipment =>
            {
                *len += 1
            }
            _ => runs.push((i, 1)),
        }
    }
    assert!(runs.len() <= 20 && tiles.len() <= 32);
    let mut masks = vec![0u32];
    for (start, len) in runs {
        masks = masks
            .iter()
            .flat_map(|m| (0..=len).map(move |k| m | (((1u32 << k) - 1) << start)))
            .collect();
    }
    masks
}

/// The f64 pseudoinverse and rank of the symmetric `m` (eigenvalues below 1e-9·λ_max dropped:
/// the f32 rounding of a rank-deficient geometry leaves ratios of ~1e-14).
pub fn pinv_sym64(m: &nalgebra::Matrix3<f64>) -> (nalgebra::Matrix3<f64>, u8) {
    let e = m.symmetric_eigen();
    let lmax = e.eigenvalues.amax();
    let mut p = nalgebra::Matrix3::zeros();
    let mut rank = 0;
    for k in 0..3 {
        if e.eigenvalues[k] > 1e-9 * lmax {
            let v = e.eigenvectors.column(k);
            p += v * v.transpose() / e.eigenvalues[k];
            rank += 1;
        }
    }
    (p, rank)
}

/// The eigenvalues of the symmetric `m`, largest first.
pub fn eigenvalues_sym64(m: &nalgebra::Matrix3<f64>) -> [f64; 3] {
    let e = m.symmetric_eigen().eigenvalues;
    let mut l = [e[0], e[1], e[2]];
    l.sort_by(|a, b| b.total_cmp(a));
    l
}

/// The noise margin of a rank decision of `acs::linalg::pseudoinverse`: the largest relative
/// threshold τ (to within 1 %, searched over 1e-30..1) at which the f32 Gram matrix `g` still
/// has rank ≥ `rank`, or 0 if it has a lower rank at every τ ≥ 1e-30. For a set whose exact
/// rank is `rank − 1` this is how far its rounding noise reaches; the callers' τ must be above it.
pub fn critical_tol(g: &acs::linalg::SymMat3, rank: u8) -> f64 {
    use acs::linalg::pseudoinverse::symmetric_pseudoinverse;
    let has = |tol: f64| symmetric_pseudoinverse(g, tol as f32).unwrap().rank >= rank;
    let (mut lo, mut hi) = (-30.0f64, 0.0f64);
    if !has(10f64.powf(lo)) {
        return 0.0;
    }
    if has(1.0) {
        return 1.0;
    }
    while hi - lo > 0.004 {
        let mid = 0.5 * (lo + hi);
        if has(10f64.powf(mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    10f64.powf(lo)
}

/// The factor that brings a tile bus's raw magnetometer words `pattern` (one pair per tile of
/// the flight configuration, raw units) to the magnitude of the on-board field model at `now`
/// on `orbit`: the loop refuses a field further than `acs_loop::FIELD_MAGNITUDE_TOLERANCE` from
/// the model's, so a scripted bus must read a field of the model's magnitude (its direction is
/// the pattern's). `None` if the model or the pattern gives no field.
pub fn field_scale(
    pattern: &[[f32; 2]],
    orbit: &acs::orbit::sgp4::Sgp4,
    now: &acs::time::Epoch<acs::time::Utc>,
) -> Option<f32> {
    use acs::flight::{CONFIG, FIELD_COEFFS};
    let state = orbit.propagate(now.span_since(&orbit.epoch())).ok()?;
    let gmst = acs::time::gmst_rad(&now.to_ut1(None).ok()?);
    let igrf = acs::env::igrf::Igrf::<FIELD_COEFFS>::from_epoch(
        CONFIG.igrf_model.model(),
        now,
        CONFIG.igrf_degree,
    )
    .ok()?;
    let model_nt = igrf.teme(&state.r_teme_km, gmst).ok()?.norm();
    let lsb = acs::tiles::MAGNETOMETER_LSB_NT;
    let readings: Vec<_> = pattern
        .iter()
        .map(|[x, y]| Some(acs::linalg::Vec2::new(x * lsb, y * lsb)))
        .collect();
    let tiles = CONFIG.tiles.as_slice();
    let pattern_nt = acs::determination::least_squares::magnetic_field_body(tiles, &readings)
        .ok()?
        .norm();
    (pattern_nt > 0.0).then(|| model_nt / pattern_nt)
}

/// The flight element set's orbit (`firmware/src/elements.rs`, `flight_tle`: the `tracking`
/// scenario's dawn-dusk orbit, epoch 2025-03-20 12:00 UTC), from its text.
pub fn flight_orbit() -> acs::orbit::sgp4::Sgp4 {
    let tle = acs::tle::Tle::parse(
        "1 90101U 25001A   25079.50000000  .00000000  00000-0  00000-0 0  9997",
        "2 90101  97.4000  90.0000 0001000   0.0000   0.0000 15.21936487    10",
    )
    .unwrap();
    acs::orbit::sgp4::Sgp4::new(&tle, acs::orbit::sgp4::Gravity::Wgs72).unwrap()
}

/// Deterministic pseudo-random numbers for the tests (64-bit LCG, Knuth's MMIX constants; no
/// dependency): `uniform()` in [0, 1).
pub struct Lcg(pub u64);

impl Lcg {
    /// The next number, uniform in [0, 1) (the top 53 bits of the state).
    pub fn uniform(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
