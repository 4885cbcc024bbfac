//! The reference node's flight image (issue #29): the clock as uplinked, SGP4, Sun, shadow,
//! IGRF, guidance. Each control period: take the ground's telecommand (clock, elements, track,
//! slew: [`acs::uplink::apply_reference`]; a slew is planned from the attitude of the last
//! STATUS; answered with its verification reports: [`acs::uplink::telecommand`]),
//! take the STATUS packet the attitude node sent, answer with the REF for its next step,
//! publish, and hand its telemetry to the ground link (its events, and its housekeeping when
//! due: [`acs::telemetry::Downlink::reference`], [`flight::downlink`]) unless it took a
//! telecommand in that period (then with the next REF: the telecommand's period is the node's
//! longest, a slew's planning, and has no room for more). Its clock is not valid until the
//! ground sets it or a STATUS brings the attitude node's copy back (after a reset:
//! [`acs::reference_node`]).
//!
//! Two builds (`firmware/Cargo.toml`): with feature `pil` the link and the period are the RAM
//! mailboxes the processor-in-the-loop host drives ([`node_link`]) and the element set at reset
//! is the image's; without it (the flight build) the part's peripherals: the clocks and the
//! one-second Timer_A period with LPM3 between periods, the link over USCI_A0
//! ([`acs_firmware::periph`]), and the element set kept in two flash segments
//! ([`acs_firmware::element_flash`]: the newer valid record at reset, the image's words the
//! fall-back; each accepted ELEMENTS telecommand stored). The telecommands and their reports go
//! through the RAM mailbox `GROUND` in both ([`flight::Ground`]).
//!
//! In the flight build the node is paced by the attitude node: it answers each STATUS as soon
//! as its frame has arrived (the receive handler wakes it on the frame's delimiter,
//! [`periph::Events`]), so the REF reaches the attitude node some 80 ms after that node's
//! step, well before its next, whatever the phase between the two nodes' crystals. Its own
//! Timer_A period takes the telecommand once a second, and when no STATUS has come for two
//! periods sends a REF each period with the step counted on (an attitude node whose STATUS
//! frames are lost still gets its references). The order within an exchange (STATUS in, REF
//! for its next step out) is the PIL build's.
#![no_std]
#![no_main]
#![cfg_attr(not(feature = "pil"), feature(asm_experimental_arch))]

use acs::flight::{CONFIG, FIELD_COEFFS, TILES};
use acs::link::messages::{Reference, Status, REFERENCE_TC_APID};
use acs::link::sequence::SequenceCounter;
use acs::reference_node::ReferenceNode;
use acs::telemetry::Downlink;
use acs::uplink::telecommand::REFERENCE_TC_BYTES;
use acs_firmware::flight::{self, Ground};
#[cfg(feature = "pil")]
use acs_firmware::node_link;
use acs_firmware::node_link::LINK_BYTES;
#[cfg(not(feature = "pil"))]
use acs_firmware::{element_flash::ElementFlash, periph};

#[cfg(not(feature = "pil"))]
acs_firmware::flight_vectors!();

/// Entry point, called by the reset handler (`acs_firmware::rt`).
#[no_mangle]
pub extern "C" fn main() -> ! {
    run()
}

/// The node over the flight configuration and the element set at reset; a halt, which the
/// watchdog turns into a reset, if the configuration is invalid.
#[cfg(feature = "pil")]
#[inline(never)]
fn run() -> ! {
    let Ok(mut node) = ReferenceNode::<TILES, FIELD_COEFFS>::new(&CONFIG, flight::flight_orbit())
    else {
        acs_firmware::fw_halt()
    };
    let mut link = Link {
        count: SequenceCounter::new(),
        tm_count: SequenceCounter::new(),
        status: None,
        step: 0,
        downlink: Downlink::new(),
        took: false,
        reference: NO_REFERENCE,
    };
    loop {
        acs_firmware::fw_period_start();
        acs_firmware::kick_watchdog();
        let attitude = link.status.and_then(|s| s.attitude);
        link.took = flight::take_telecommand(
            &raw mut GROUND,
            REFERENCE_TC_APID,
            &mut link.tm_count,
            &mut node,
            |n| n.clock(),
            |n, code, args| acs::uplink::apply_reference(code, args, n, attitude.as_ref()),
        );
        link.exchange(&mut node);
        acs_firmware::kick_watchdog();
    }
}

/// The node over the flight configuration and the part's peripherals (see the module docs);
/// a halt, which the watchdog turns into a reset, if the configuration is invalid.
#[cfg(not(feature = "pil"))]
#[inline(never)]
fn run() -> ! {
    periph::init_clocks();
    let mut elements = ElementFlash::open();
    let Ok(mut node) =
        ReferenceNode::<TILES, FIELD_COEFFS>::new(&CONFIG, elements.orbit_at_reset())
    else {
        acs_firmware::fw_halt()
    };
    let mut link = Link {
        count: SequenceCounter::new(),
        tm_count: SequenceCounter::new(),
        status: None,
        step: 0,
        downlink: Downlink::new(),
        took: false,
        reference: NO_REFERENCE,
        uart: periph::link(),
    };
    let mut events = periph::Events::now();
    // periods since the last STATUS
    let mut quiet: u8 = 0;
    loop {
        let (tick, frame) = events.wait();
        acs_firmware::fw_period_start();
        acs_firmware::kick_watchdog();
        if tick {
            let attitude = link.status.and_then(|s| s.attitude);
            link.took |= flight::take_telecommand(
                &raw mut GROUND,
                REFERENCE_TC_APID,
                &mut link.tm_count,
                &mut node,
                |n| n.clock(),
                |n, code, args| {
                    acs::uplink::apply_reference(code, args, n, attitude.as_ref())?;
                    if code == acs::uplink::kind::ELEMENTS {
                        elements.keep(args);
                    }
                    Ok(())
                },
            );
            quiet = quiet.saturating_add(1);
        }
        // a STATUS is answered at once; without one for two periods, a REF each period
        let status = if frame {
            receive_status(&mut link.uart, &mut link.downlink)
        } else {
            None
        };
        if status.is_some() {
            quiet = 0;
            link.answer(&mut node, status);
        } else if tick && quiet >= 2 {
            link.downlink.link.count(None);
            link.answer(&mut node, None);
        }
        acs_firmware::kick_watchdog();
    }
}

/// The node's side of the link between periods.
struct Link {
    count: SequenceCounter,
    /// The sequence count of the verification reports (APID [`REFERENCE_TC_APID`]).
    tm_count: SequenceCounter,
    /// The last STATUS received.
    status: Option<Status>,
    /// The step the next REF is for: the last STATUS's next, counted on without one.
    step: u32,
    /// The node's telemetry ([`acs::telemetry::Downlink`]): its events, its housekeeping, the
    /// STATUS packets counted.
    downlink: Downlink,
    /// A telecommand was taken since the last REF: the next REF's telemetry waits for the one
    /// after.
    took: bool,
    /// The last REF, built in place each period ([`ReferenceNode::reference_into`]).
    reference: Reference,
    /// The link over USCI_A0 (flight build).
    #[cfg(not(feature = "pil"))]
    uart: periph::Link,
}

impl Link {
    /// Takes the STATUS packet, answers with the REF for the attitude node's next step, and
    /// publishes its faults. Out of line, and so are the packets' own steps: the packets live
    /// in their frames only, neither under the uplink's frame nor under the models'.
    #[cfg(feature = "pil")]
    #[inline(never)]
    fn exchange(&mut self, node: &mut ReferenceNode<'static, TILES, FIELD_COEFFS>) {
        self.status = receive_status(&mut self.downlink);
        if let Some(s) = &self.status {
            self.step = s.step.wrapping_add(1);
        }
        node.reference_into(self.step, self.status.as_ref(), &mut self.reference);
        send_reference(&self.reference, self.count.next_count());
        flight::publish_codes(0, self.reference.faults);
        self.step = self.step.wrapping_add(1);
        self.telemetry(node);
    }

    /// The telemetry after a REF, unless a telecommand was taken since the REF before.
    fn telemetry(&mut self, node: &mut ReferenceNode<'static, TILES, FIELD_COEFFS>) {
        if !core::mem::take(&mut self.took) {
            self.downlink
                .reference(node, &self.reference, &mut self.tm_count, flight::downlink);
        }
    }

    /// Answers `status` (the STATUS just received; `None`: none came for two periods, the
    /// step counted on) with the REF for the attitude node's next step, and publishes its
    /// faults (the flight build's [`Link::exchange`]).
    #[cfg(not(feature = "pil"))]
    #[inline(never)]
    fn answer(
        &mut self,
        node: &mut ReferenceNode<'static, TILES, FIELD_COEFFS>,
        status: Option<Status>,
    ) {
        self.status = status;
        if let Some(s) = &self.status {
            self.step = s.step.wrapping_add(1);
        }
        node.reference_into(self.step, self.status.as_ref(), &mut self.reference);
        send_reference(&mut self.uart, &self.reference, self.count.next_count());
        flight::publish_codes(0, self.reference.faults);
        self.step = self.step.wrapping_add(1);
        self.telemetry(node);
    }
}

/// The STATUS in `LINK_RX`, if a valid one came; counted in `downlink`.
#[cfg(feature = "pil")]
#[inline(never)]
fn receive_status(downlink: &mut Downlink) -> Option<Status> {
    let mut packet = [0u8; LINK_BYTES];
    let received = node_link::receive(&mut packet).and_then(|n| packet.get(..n));
    let status = received.and_then(|p| Status::from_packet(p).ok());
    downlink.link.count(received.map(|_| status.is_some()));
    status.map(|(s, _)| s)
}

/// The last valid STATUS that arrived over the link since the last call; each packet counted
/// in `downlink` (a period without one is counted by the caller).
#[cfg(not(feature = "pil"))]
#[inline(never)]
fn receive_status(uart: &mut periph::Link, downlink: &mut Downlink) -> Option<Status> {
    let mut packet = [0u8; LINK_BYTES];
    periph::receive_last(uart, &mut packet, |p| {
        let s = Status::from_packet(p).ok().map(|(s, _)| s);
        downlink.link.count(Some(s.is_some()));
        s
    })
}

/// Sends `reference` as its packet with sequence count `count` over the link.
#[cfg(not(feature = "pil"))]
#[inline(never)]
fn send_reference(uart: &mut periph::Link, reference: &Reference, count: u16) {
    periph::send(uart, &reference.to_packet(count));
}

/// Sends `reference` as its packet with sequence count `count`.
#[cfg(feature = "pil")]
#[inline(never)]
fn send_reference(reference: &Reference, count: u16) {
    node_link::send(&reference.to_packet(count));
}

/// The REF before the first ([`Link::reference`]: overwritten whole each period). All its
/// bytes zero (a zero target, not the identity; a zero illumination, as `None` is not zero):
/// a clear at reset, not a 126-byte copy from flash.
const NO_REFERENCE: Reference = Reference {
    step: 0,
    utc: acs::time::Epoch::DAY0,
    clock_valid: false,
    elements_valid: false,
    r_teme_km: None,
    sun_teme: None,
    illumination: Some(acs::env::eclipse::Illumination {
        fraction: 0.0,
        shadow: acs::env::eclipse::Shadow::Sunlit,
    }),
    b_teme_nt: None,
    albedo_teme: None,
    guidance: acs::link::messages::Guidance {
        id: 0,
        kind: acs::link::messages::GuidanceKind::None,
        target: acs::attitude::Quaternion {
            q0: 0.0,
            q1: 0.0,
            q2: 0.0,
            q3: 0.0,
        },
        rate_body_radps: acs::linalg::Vec3::new(0.0, 0.0, 0.0),
        h_ff_body_nms: acs::linalg::Vec3::new(0.0, 0.0, 0.0),
    },
    faults: 0,
};

/// The ground's mailbox (see [`flight::Ground`]).
#[no_mangle]
static mut GROUND: Ground<REFERENCE_TC_BYTES> = Ground::EMPTY;

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
