//! # acs: attitude determination and control for the AraMiS modular satellite
//!
//! A `no_std`, allocation-free, f32 flight library for MSP430-class cores (16-bit, no FPU), built
//! from the AraMiS ACS thesis (seed 000) and its companions (seeds 001–004), with a host tool and
//! simulator behind the `host` feature.
//!
//! ## Conventions (kept everywhere)
//! - Inertial frame: TEME of date (SGP4's). Earth-fixed: TEME rotated by GMST (IAU-82).
//!   J2000 only as an output conversion ([`frames`]).
//! - Attitude: DCM `A` with `v_body = A · v_ref`; quaternions scalar-first with Shuster/Wertz's
//!   passive `A(q)`; see [`attitude`].
//! - Units: km and km/s for orbits, nT for magnetic fields, rad and rad/s inside, N·m, A·m²,
//!   kg·m²/s; degrees only at the edges. Units and frames are in names (`r_teme_km`).
//! - Time: split-precision [`time::Epoch`] with its scale in the type; never an f32 Julian date.
//! - Precision: f32 for flight results, each with a measured error bound in its docs.
#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]
#![deny(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    clippy::indexing_slicing,
    clippy::unreachable,
    clippy::todo,
    clippy::unimplemented
)]
#![forbid(unsafe_code)]
// Flight code writes "a < c or NaN" as `!(a >= c)`: the MSP430 evaluates `a < c` that way, and
// this form makes the host agree (`fmath` module docs, "Float comparisons in flight code").
// Range `contains` is `lo <= x && x <= hi` inside: flight code spells it out (`x >= lo && hi >= x`).
#![allow(
    clippy::neg_cmp_op_on_partial_ord,
    clippy::manual_range_contains,
    reason = "NaN-explicit comparisons for the MSP430 (fmath docs)"
)]
// On the MSP430 (nightly only: the target is tier 3), code that runs rarely (commands, uplinks,
// start-up, hourly refreshes) is optimised for size rather than speed: flash is the part's
// scarcest resource and these paths do not count in the step's cycle budget.
#![cfg_attr(target_arch = "msp430", feature(optimize_attribute))]

pub mod acs_loop;
pub mod attitude;
pub mod attitude_node;
pub mod control;
pub mod determination;
pub mod env;
pub mod flight;
pub mod fmath;
pub mod frames;
pub mod hal;
pub mod linalg;
pub mod link;
pub mod orbit;
pub mod planning;
pub mod reference_node;
pub mod telemetry;
pub mod tiles;
pub mod time;
pub mod tle;
pub mod two_node;
pub mod uplink;

#[cfg(feature = "host")]
pub mod host;
