//! The ground uplink (`acs::uplink`): every command applied as documented, and every refused
//! command leaving the loop and the clock as they were, with its typed error and status word.

use acs::acs_loop::Mode;
use acs::attitude::Quaternion;
use acs::flight::{FlightLoop, CONFIG};
use acs::link::messages::GuidanceKind;
use acs::orbit::sgp4::{Sgp4, ELEMENT_WORDS};
use acs::tiles::TileState;
use acs::time::{Epoch, Utc};
use acs::uplink::{apply, kind, status, UplinkError, ARG_WORDS};

mod common;

fn orbit() -> Sgp4 {
    common::flight_orbit()
}

fn words(first: &[u32]) -> [u32; ARG_WORDS] {
    let mut w = [0u32; ARG_WORDS];
    w[..first.len()].copy_from_slice(first);
    w
}

fn quaternion_words(q: [f32; 4]) -> Vec<u32> {
    q.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn commands_apply_and_refusals_change_nothing() {
    let mut acs = FlightLoop::new(&CONFIG, orbit()).unwrap();
    let t0 = Epoch::<Utc>::from_parts(9_210, 43_200, 0).unwrap();
    let mut clock = t0;
    let q = Quaternion::new_normalize(0.9, 0.1, -0.3, 0.2).unwrap();
    let qw = quaternion_words([q.q0, q.q1, q.q2, q.q3]);

    // unknown code, invalid quaternions and times: refused, nothing changes
    let refused = |acs: &mut FlightLoop, clock: &mut Epoch<Utc>, code: u16, args: &[u32]| {
        let mode = acs.mode();
        let before = *clock;
        let r = apply(code, &words(args), acs, clock, Some(&q));
        assert!(r.is_err(), "code {code} {args:?}");
        assert_eq!((acs.mode(), *clock), (mode, before));
        r.unwrap_err()
    };
    assert_eq!(
        refused(&mut acs, &mut clock, 99, &[]),
        UplinkError::UnknownCommand(99)
    );
    let zero = quaternion_words([0.0; 4]);
    let nan = quaternion_words([f32::NAN, 1.0, 0.0, 0.0]);
    for bad in [&zero, &nan] {
        assert_eq!(
            refused(&mut acs, &mut clock, kind::TRACK, bad),
            UplinkError::InvalidArgument
        );
    }
    for within in [0.0f32, -1.0, f32::INFINITY, f32::NAN] {
        let mut a = qw.clone();
        a.push(within.to_bits());
        assert_eq!(
            refused(&mut acs, &mut clock, kind::SLEW, &a),
            UplinkError::InvalidArgument
        );
    }
    // a second beyond the day (a leap second is the last one), nanoseconds beyond a second
    for bad in [[9_210, 86_401, 0], [9_210, 0, 2_000_000_000]] {
        assert_eq!(
            refused(&mut acs, &mut clock, kind::CLOCK, &bad),
            UplinkError::InvalidArgument
        );
    }
    for tile in [6u32, u32::MAX] {
        let e = refused(&mut acs, &mut clock, kind::MARK_FAILED, &[tile]);
        assert_eq!(e, UplinkError::InvalidArgument);
        assert_eq!(status(&Err(e)), 2);
    }

    // the clock, tile health, tracking and sun-safe
    let r = apply(
        kind::CLOCK,
        &words(&[9_300, 7, 5]),
        &mut acs,
        &mut clock,
        None,
    );
    assert_eq!(status(&r), 0);
    assert_eq!(clock, Epoch::<Utc>::from_parts(9_300, 7, 5).unwrap());
    assert!(apply(kind::MARK_FAILED, &words(&[2]), &mut acs, &mut clock, None).is_ok());
    assert_eq!(acs.tile_state(2), Some(TileState::Failed));
    assert!(apply(kind::RESTORE, &words(&[2]), &mut acs, &mut clock, None).is_ok());
    assert_eq!(acs.tile_state(2), Some(TileState::Working));
    // a coil (word 1 = 1): failed and out of its allocation, then back (issue #31)
    assert!(apply(
        kind::MARK_FAILED,
        &words(&[2, 1]),
        &mut acs,
        &mut clock,
        None
    )
    .is_ok());
    assert!(acs.health().coil_failed(2) && !acs.health().coil_in(2));
    assert_eq!(acs.tile_state(2), Some(TileState::Working));
    assert!(apply(kind::RESTORE, &words(&[2, 1]), &mut acs, &mut clock, None).is_ok());
    assert!(!acs.health().any_failed() && acs.health().coil_in(2));
    // no coil 3, no class 2, no coil beyond the index range: refused, nothing changed
    for bad in [[3u32, 1], [0, 2], [u32::MAX, 1], [65_537, 1]] {
        let e = refused(&mut acs, &mut clock, kind::MARK_FAILED, &bad);
        assert_eq!(e, UplinkError::InvalidArgument);
        assert!(!acs.health().any_failed());
    }
    assert!(apply(kind::TRACK, &words(&qw), &mut acs, &mut clock, None).is_ok());
    // the reference node's guidance: the attitude node takes it at the next step
    assert_eq!(acs.guidance().kind, GuidanceKind::Track);

    // a slew needs an attitude: refused by the loop without one
    let mut slew = qw.clone();
    slew.push(120f32.to_bits());
    let e = apply(kind::SLEW, &words(&slew), &mut acs, &mut clock, None).unwrap_err();
    assert!(matches!(e, UplinkError::Refused(_)));
    assert_eq!(status(&Err(e)), 3);
    assert_eq!(acs.guidance().kind, GuidanceKind::Track);
    let from = Quaternion::new_normalize(0.8, -0.2, 0.4, 0.1).unwrap();
    assert!(apply(kind::SLEW, &words(&slew), &mut acs, &mut clock, Some(&from)).is_ok());
    assert_eq!(acs.guidance().kind, GuidanceKind::Slew);
    assert!(apply(kind::SUN_SAFE, &words(&[]), &mut acs, &mut clock, None).is_ok());
    assert_eq!(acs.mode(), Mode::SunSafe);
}

/// An element set is checked whole: any single-bit error is refused naming a word, with the
/// elements in use kept (propagation unchanged); a good set replaces them.
#[test]
fn element_sets_are_checked_before_use() {
    let mut acs = FlightLoop::new(&CONFIG, orbit()).unwrap();
    let mut clock = Epoch::<Utc>::from_parts(9_210, 43_200, 0).unwrap();
    let good = orbit().to_words();
    for word in 0..ELEMENT_WORDS {
        for bit in [0, 13, 31] {
            let mut bad = good;
            bad[word] ^= 1 << bit;
            let e = apply(kind::ELEMENTS, &bad, &mut acs, &mut clock, None).unwrap_err();
            let UplinkError::BadElementWord(i) = e else {
                panic!("word {word} bit {bit}: {e:?}")
            };
            assert!(usize::from(i) < ELEMENT_WORDS);
            assert_eq!(status(&Err(e)), 0x100 + u16::from(i));
        }
    }
    assert!(apply(kind::ELEMENTS, &good, &mut acs, &mut clock, None).is_ok());
}
