//! The attitude node's flight image (issue #29): tile reads, determination, modes and fault
//! management, laws, allocation; the only node that commands actuators. Each control period:
//! take the ground's telecommand (sun-safe, the tiles: [`acs::uplink::apply_attitude`], answered
//! with its verification reports: [`acs::uplink::telecommand`]), take the
//! REF packet the reference node sent for this step (none, or one for another step or without a
//! valid clock: the step runs without reference, reported), step, send STATUS, publish, and
//! hand the step's telemetry to the ground link (its events, and its housekeeping when due:
//! [`acs::telemetry::Downlink::attitude`], [`flight::downlink`]). STATUS carries the resets
//! since power-on ([`acs_firmware::boot_count`]).
//!
//! Two builds (`firmware/Cargo.toml`): with feature `pil` the tiles, the link and the period
//! are the RAM mailboxes the processor-in-the-loop host drives ([`tiles::MailboxBus`],
//! [`node_link`]); without it (the flight build) the part's peripherals: the clocks and the
//! one-second Timer_A period with LPM3 between periods, the link over USCI_A0
//! ([`acs_firmware::periph`]), and the tile bus of [`acs::hal::msp430::tile_bus`] (the tiles'
//! sensors and wheel controllers on USCI_B0 I²C at its address map, the coils on Timer_B PWM
//! with direction pins). The telecommands and their reports go through the RAM mailbox
//! `GROUND` in both ([`flight::Ground`]).
#![no_std]
#![cfg_attr(not(feature = "pil"), feature(asm_experimental_arch))]
#![no_main]

use acs::acs_loop::StepReport;
use acs::attitude_node::AttitudeNode;
use acs::flight::{CONFIG, CONTROL_PERIOD_S, TILES};
use acs::link::messages::{Reference, ATTITUDE_TC_APID};
use acs::link::sequence::SequenceCounter;
use acs::telemetry::Downlink;
use acs::uplink::telecommand::ATTITUDE_TC_BYTES;
use acs_firmware::flight::Ground;
use acs_firmware::node_link::LINK_BYTES;
use acs_firmware::{flight, tiles};
#[cfg(feature = "pil")]
use acs_firmware::node_link;
#[cfg(not(feature = "pil"))]
use acs_firmware::periph;

#[cfg(not(feature = "pil"))]
acs_firmware::flight_vectors!();

/// Entry point, called by the reset handler (`acs_firmware::rt`): coils off, then the node.
#[no_mangle]
pub extern "C" fn main() -> ! {
    tiles::coils_off();
    run()
}

/// The node over the flight configuration and the tile mailboxes; coils off and a halt, which
/// the watchdog turns into a reset, if the configuration is invalid.
#[cfg(feature = "pil")]
#[inline(never)]
fn run() -> ! {
    let Ok(mut node) = AttitudeNode::<TILES>::new(&CONFIG) else {
        acs_firmware::safe_state();
        acs_firmware::fw_halt()
    };
    node.set_boot_count(acs_firmware::boot_count());
    let mut bus = tiles::MailboxBus;
    let mut report = StepReport::empty(node.mode());
    let mut count = SequenceCounter::new();
    let mut tm_count = SequenceCounter::new();
    let mut downlink = Downlink::new();
    let mut packet = [0u8; LINK_BYTES];
    loop {
        acs_firmware::fw_period_start();
        acs_firmware::kick_watchdog();
        take_telecommand(&mut tm_count, &mut node);
        let received = node_link::receive(&mut packet).and_then(|n| packet.get(..n));
        let reference = received.and_then(|p| Reference::from_packet(p).ok());
        downlink.link.count(received.map(|_| reference.is_some()));
        let status = node.step_into(
            &mut bus,
            reference.as_ref().map(|(r, _)| r),
            CONTROL_PERIOD_S,
            &mut report,
        );
        node_link::send(&status.to_packet(count.next_count()));
        flight::publish_codes(report.mode.code(), report.faults.bits());
        downlink.attitude(&mut node, &report, &mut tm_count, flight::downlink);
        acs_firmware::kick_watchdog();
    }
}

/// The node over the flight configuration and the part's peripherals (see the module docs);
/// coils off and a halt, which the watchdog turns into a reset, if the configuration is
/// invalid.
#[cfg(not(feature = "pil"))]
#[inline(never)]
fn run() -> ! {
    use acs::hal::msp430::pwm::PwmConfig;
    use acs::hal::msp430::tile_bus;
    use acs::hal::msp430::usci_i2c::I2cConfig;
    use acs_firmware::mmio::Mmio;

    periph::init_clocks();
    let mut bus = tile_bus::attitude_bus(
        Mmio,
        &I2cConfig::FLIGHT,
        PwmConfig::FLIGHT,
        acs_firmware::CycleDelay,
    );
    let mut link = periph::link();
    let Ok(mut node) = AttitudeNode::<TILES>::new(&CONFIG) else {
        acs_firmware::safe_state();
        acs_firmware::fw_halt()
    };
    node.set_boot_count(acs_firmware::boot_count());
    let mut report = StepReport::empty(node.mode());
    let mut count = SequenceCounter::new();
    let mut tm_count = SequenceCounter::new();
    let mut downlink = Downlink::new();
    let mut packet = [0u8; LINK_BYTES];
    loop {
        periph::wait_period();
        acs_firmware::fw_period_start();
        acs_firmware::kick_watchdog();
        take_telecommand(&mut tm_count, &mut node);
        let mut arrived = false;
        let reference = periph::receive_last(&mut link, &mut packet, |p| {
            arrived = true;
            let r = Reference::from_packet(p).ok().map(|(r, _)| r);
            downlink.link.count(Some(r.is_some()));
            r
        });
        if !arrived {
            downlink.link.count(None);
        }
        let status = node.step_into(&mut bus, reference.as_ref(), CONTROL_PERIOD_S, &mut report);
        periph::send(&mut link, &status.to_packet(count.next_count()));
        flight::publish_codes(report.mode.code(), report.faults.bits());
        downlink.attitude(&mut node, &report, &mut tm_count, flight::downlink);
        acs_firmware::kick_watchdog();
    }
}

/// The ground's mailbox (see [`flight::Ground`]).
#[no_mangle]
static mut GROUND: Ground<ATTITUDE_TC_BYTES> = Ground::EMPTY;

/// Takes the telecommand in [`GROUND`], if any, for the attitude node
/// ([`acs::uplink::apply_attitude`]); its reports counted by `tm_count`.
fn take_telecommand(tm_count: &mut SequenceCounter, node: &mut AttitudeNode<'static, TILES>) {
    let _ = flight::take_telecommand(
        &raw mut GROUND,
        ATTITUDE_TC_APID,
        tm_count,
        node,
        |n| n.clock(),
        |n, code, args| acs::uplink::apply_attitude(code, args, n),
    );
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
