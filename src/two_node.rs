//! The ACS loop as one composition of its two nodes (issue #29): the *reference* node
//! ([`crate::reference_node`]: clock, SGP4, Sun, shadow, IGRF, guidance) and the *attitude*
//! node ([`crate::attitude_node`]: tile reads, determination, modes and fault management, laws,
//! allocation; the only one that commands actuators), joined by their messages
//! ([`crate::link::messages`]: STATUS and REF, their bytes bit for bit as on the link).
//!
//! One [`TwoNodeLoop::step`] per control period: the reference node makes the REF for the step
//! at the step's UTC, the attitude node runs the step with it and answers STATUS. The API is
//! [`crate::acs_loop::AcsLoop`]'s, and so are the commands: `tests/two_node.rs` flies the
//! closed-loop scenarios through both and finds every step's report bit for bit the same. The
//! simulator and the one-image flight firmware still fly [`crate::acs_loop::AcsLoop`] until
//! the two node images replace it (issue #29); a team with one larger processor composes the
//! nodes in one image exactly as here.
//!
//! # Who owns which command
//! | command | node | why |
//! |---|---|---|
//! | sun-safe, mark a tile failed, restore a tile | attitude | a dead link never takes them away |
//! | track, slew | reference | the guidance and the slew planner are there; the attitude node takes a new command at the next step, from the REF |
//! | clock, element set | reference | the models are there |
//!
//! Attitudes follow [`crate::attitude`]: `v_body = A · v_ref` with the reference frame TEME of
//! date; quaternions scalar-first.

use crate::acs_loop::{AcsConfig, AcsError, Command, Faults, Mode, StepReport};
use crate::attitude::Quaternion;
use crate::attitude_node::AttitudeNode;
use crate::env::igrf::FULL_COEFFS;
use crate::hal::TileBus;
use crate::link::messages::{
    Guidance, Reference, Status, REFERENCE_PACKET_BYTES, STATUS_PACKET_BYTES,
};
use crate::link::sequence::SequenceCounter;
use crate::orbit::sgp4::Sgp4;
use crate::reference_node::ReferenceNode;
use crate::tiles::{Tile, TileState, MAX_TILES};
use crate::time::{Epoch, Utc};

/// The two nodes composed in one program, joined by their messages as bytes (bit for bit what
/// the link carries): for at most `N` ≤ 32 tiles (see [`AcsConfig`]), with room for `F` IGRF
/// coefficients on the reference node (`F` ≥ the configured degree's
/// [`crate::env::igrf::coefficient_count`]: 80 for degree 8, the default 195 for 13).
#[derive(Clone, Debug)]
pub struct TwoNodeLoop<'c, const N: usize = MAX_TILES, const F: usize = FULL_COEFFS> {
    reference: ReferenceNode<'c, N, F>,
    attitude: AttitudeNode<'c, N>,
    /// The attitude node's last STATUS, as the reference node received it.
    status: Option<Status>,
    /// The sequence counts of the REF and STATUS packets.
    reference_count: SequenceCounter,
    status_count: SequenceCounter,
    /// The last step's packets, as on the link.
    reference_packet: [u8; REFERENCE_PACKET_BYTES],
    status_packet: [u8; STATUS_PACKET_BYTES],
}

impl<'c, const N: usize, const F: usize> TwoNodeLoop<'c, N, F> {
    /// A loop in `Detumble` for the given configuration and orbit (an [`Sgp4`], or `None`: a
    /// loop without an element set, as after a corrupt one at start-up, still detumbles and
    /// keeps the Sun on its panel, the laws that need no reference, with [`Faults::orbit`] set
    /// each step until [`Self::set_orbit`] gives it one).
    pub fn new(config: &'c AcsConfig<N>, orbit: impl Into<Option<Sgp4>>) -> Result<Self, AcsError> {
        Ok(Self {
            reference: ReferenceNode::new(config, orbit)?,
            attitude: AttitudeNode::new(config)?,
            status: None,
            reference_count: SequenceCounter::new(),
            status_count: SequenceCounter::new(),
            reference_packet: [0; REFERENCE_PACKET_BYTES],
            status_packet: [0; STATUS_PACKET_BYTES],
        })
    }

    /// Replaces the element set the reference node propagates (an uplink: check the words with
    /// [`Sgp4::from_words`] first, so that a refused set leaves the one in use).
    pub fn set_orbit(&mut self, orbit: Sgp4) {
        self.reference.set_orbit(orbit);
    }

    /// The current mode.
    pub fn mode(&self) -> Mode {
        self.attitude.mode()
    }

    /// The reference node's guidance in force (a track or slew command takes effect at the
    /// next step, when the attitude node receives it in the REF).
    pub fn guidance(&self) -> &Guidance {
        self.reference.guidance()
    }

    /// The configured tiles (their run-time state: [`TwoNodeLoop::tile_state`]).
    pub fn tiles(&self) -> &[Tile] {
        self.attitude.tiles()
    }

    /// The run-time state of tile `tile`, `None` if there is no such tile.
    pub fn tile_state(&self, tile: usize) -> Option<TileState> {
        self.attitude.tile_state(tile)
    }

    /// Marks a tile failed (ground command or fault detection); its devices are no longer used
    /// and its wheel is stopped at the next step.
    pub fn mark_failed(&mut self, tile: usize) {
        self.attitude.mark_failed(tile);
    }

    /// Returns a tile to service (ground command, e.g. after a power cycle of a tile marked
    /// failed).
    pub fn restore(&mut self, tile: usize) {
        self.attitude.restore(tile);
    }

    /// Accepts a ground command, at the node that owns it (module docs); it takes effect at the
    /// next step. A slew is planned from the last determined attitude (`attitude`, reference →
    /// body), so it needs one.
    pub fn command(
        &mut self,
        command: Command,
        attitude: Option<&Quaternion>,
        now: Epoch<Utc>,
    ) -> Result<(), AcsError> {
        match command {
            Command::SunSafe => self.attitude.sun_safe(),
            Command::Track { target } => self.reference.track(target),
            Command::Slew { target, within_s } => {
                let attitude = attitude.ok_or(AcsError::CannotSlew)?;
                self.reference.slew(attitude, &target, within_s, now)?;
            }
        }
        Ok(())
    }

    /// Puts every actuator in the safe state: coils off, wheels hold their momentum.
    pub fn safe<B: TileBus>(&mut self, bus: &mut B) -> Faults {
        self.attitude.safe(bus)
    }

    /// One control step at UTC epoch `now`, `dt_s` seconds after the previous one.
    pub fn step<B: TileBus>(&mut self, bus: &mut B, now: Epoch<Utc>, dt_s: f32) -> StepReport {
        let mut report = StepReport::empty(self.mode());
        self.step_into(bus, now, dt_s, &mut report);
        report
    }

    /// [`TwoNodeLoop::step`] writing its report into `report` (every field is set): the
    /// reference node makes the REF for the step at `now`, which crosses to the attitude node
    /// as its packet; the attitude node's STATUS crosses back the same way.
    pub fn step_into<B: TileBus>(
        &mut self,
        bus: &mut B,
        now: Epoch<Utc>,
        dt_s: f32,
        report: &mut StepReport,
    ) {
        self.reference.set_clock(now);
        let step = self.attitude.step_number();
        let reference = self.reference.reference(step, self.status.as_ref());
        self.reference_packet = reference.to_packet(self.reference_count.next_count());
        let reference = Reference::from_packet(&self.reference_packet).ok();
        let status = self
            .attitude
            .step_into(bus, reference.as_ref().map(|(r, _)| r), dt_s, report);
        self.status_packet = status.to_packet(self.status_count.next_count());
        self.status = Status::from_packet(&self.status_packet)
            .ok()
            .map(|(s, _)| s);
    }

    /// The last step's REF and STATUS packets, as the link carries them.
    pub fn packets(&self) -> (&[u8], &[u8]) {
        (&self.reference_packet, &self.status_packet)
    }
}
