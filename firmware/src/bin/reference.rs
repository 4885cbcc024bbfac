//! The reference node's flight image (issue #29): the clock as uplinked, SGP4, Sun, shadow,
//! IGRF, guidance. Each control period: take the ground's command (clock, elements, track, slew:
//! [`acs::uplink::apply_reference`]; a slew is planned from the attitude of the last STATUS),
//! take the STATUS packet the attitude node sent, answer with the REF for its next step, and
//! publish. Its clock is not valid until the ground sets it or a STATUS brings the attitude
//! node's copy back (after a reset: [`acs::reference_node`]).
#![no_std]
#![no_main]

use acs::flight::{CONFIG, FIELD_COEFFS, TILES};
use acs::link::messages::{Reference, Status};
use acs::link::sequence::SequenceCounter;
use acs::reference_node::ReferenceNode;
use acs_firmware::node_link::{self, LINK_BYTES};
use acs_firmware::flight;

/// Entry point, called by the reset handler (`acs_firmware::rt`).
#[no_mangle]
pub extern "C" fn main() -> ! {
    run()
}

/// The node over the flight configuration and the element set at reset; a halt, which the
/// watchdog turns into a reset, if the configuration is invalid.
#[inline(never)]
fn run() -> ! {
    let Ok(mut node) = ReferenceNode::<TILES, FIELD_COEFFS>::new(&CONFIG, flight::flight_orbit())
    else {
        acs_firmware::fw_halt()
    };
    let mut link = Link {
        count: SequenceCounter::new(),
        status: None,
        step: 0,
    };
    loop {
        acs_firmware::fw_period_start();
        acs_firmware::kick_watchdog();
        let attitude = link.status.and_then(|s| s.attitude);
        flight::take_node_uplink(|kind, args| {
            acs::uplink::status(&acs::uplink::apply_reference(
                kind,
                args,
                &mut node,
                attitude.as_ref(),
            ))
        });
        link.exchange(&mut node);
        acs_firmware::kick_watchdog();
    }
}

/// The node's side of the link between periods.
struct Link {
    count: SequenceCounter,
    /// The last STATUS received.
    status: Option<Status>,
    /// The step the next REF is for: the last STATUS's next, counted on without one.
    step: u32,
}

impl Link {
    /// Takes the STATUS packet, answers with the REF for the attitude node's next step, and
    /// publishes its faults. Out of line, and so are the packets' own steps: the packets live
    /// in their frames only, neither under the uplink's frame nor under the models'.
    #[inline(never)]
    fn exchange(&mut self, node: &mut ReferenceNode<'static, TILES, FIELD_COEFFS>) {
        self.status = receive_status();
        if let Some(s) = &self.status {
            self.step = s.step.wrapping_add(1);
        }
        let reference = node.reference(self.step, self.status.as_ref());
        send_reference(&reference, self.count.next_count());
        flight::publish_codes(0, reference.faults);
        self.step = self.step.wrapping_add(1);
    }
}

/// The STATUS in `LINK_RX`, if a valid one came.
#[inline(never)]
fn receive_status() -> Option<Status> {
    let mut packet = [0u8; LINK_BYTES];
    node_link::receive(&mut packet)
        .and_then(|n| packet.get(..n))
        .and_then(|p| Status::from_packet(p).ok())
        .map(|(s, _)| s)
}

/// Sends `reference` as its packet with sequence count `count`.
#[inline(never)]
fn send_reference(reference: &Reference, count: u16) {
    node_link::send(&reference.to_packet(count));
}

/// No panic path in the flight image, proven at link time (as `src/main.rs`).
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    extern "C" {
        /// Deliberately undefined (see `src/main.rs`).
        fn acs_flight_image_has_a_reachable_panic() -> !;
    }
    // SAFETY: never linked, so never called: a reachable call fails the build.
    unsafe { acs_flight_image_has_a_reachable_panic() }
}
