//! The acs flight firmware: reset → SGP4 elements → the ACS loop, one step per control period
//! (uplink, read tiles, models, determination, laws, actuators), for ever.
//!
//! The loop is [`acs::flight::OneImageLoop`] (the two nodes in one image) over the flight configuration [`acs::flight::CONFIG`]
//! and the tile mailboxes ([`acs_firmware::tiles`]); the uplink and the clock are in
//! [`acs_firmware::flight`].
#![no_std]
#![no_main]

use acs_firmware::{flight, tiles};

/// Entry point, called by the reset handler (`acs_firmware::rt`): coils off, then the loop.
#[no_mangle]
pub extern "C" fn main() -> ! {
    tiles::coils_off();
    run()
}

/// The loop over the flight configuration and the element set at reset, built in place (its
/// state lives in this frame; the element set's start-up temporaries in a callee's frame, gone
/// before the first step; without a valid element set it flies detumble and sun-safe); coils
/// off and a halt, which the watchdog turns into a reset, if the configuration is invalid.
/// The watchdog is kicked when the period starts and when the step is done: the longest
/// interval between kicks is one period less the step (0.91 s of its 1 s).
#[inline(never)]
fn run() -> ! {
    let mut slot = None;
    flight::init_loop(&mut slot);
    let (Some(acs), Some(mut clock)) = (slot.as_mut(), flight::reset_clock()) else {
        acs_firmware::safe_state();
        acs_firmware::fw_halt()
    };
    let mut bus = tiles::MailboxBus;
    // the last step's report (its attitude is what an uplinked slew is planned from)
    let mut report = acs::acs_loop::StepReport::empty(acs.mode());
    loop {
        acs_firmware::fw_period_start();
        acs_firmware::kick_watchdog();
        flight::take_uplink(acs, &mut clock, report.attitude.as_ref());
        acs.step_into(&mut bus, clock, acs::flight::CONTROL_PERIOD_S, &mut report);
        flight::publish(&report);
        acs_firmware::kick_watchdog();
        clock = clock.add(flight::PERIOD);
    }
}

/// No panic path in the flight image, proven at link time: the handler calls a symbol that
/// nothing defines, so an image in which any panic is reachable (a bounds check, an integer
/// division by zero, an `unwrap` the optimiser could not remove) fails to link, naming the
/// symbol. Where no panic is reachable, LTO and `--gc-sections` drop the handler and the
/// reference with it (`firmware/tools/loop-image` also checks that the linked ELF holds no
/// `panic` symbol).
#[panic_handler]
fn panic(_info: &core::panic::PanicInfo) -> ! {
    extern "C" {
        /// Deliberately undefined (see above).
        fn acs_flight_image_has_a_reachable_panic() -> !;
    }
    // SAFETY: never linked, so never called: a reachable call fails the build.
    unsafe { acs_flight_image_has_a_reachable_panic() }
}
