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
//! simulator, the `acs` tool, the campaigns and the tests fly this composition
//! ([`crate::flight::FlightLoop`]); the processor-in-the-loop run flies the
//! two node images (`acs-reference`, `acs-attitude`) against this composition
//! ([`TwoNodeLoop::step_over_link`]: the link's packets as the images exchange them, damaged
//! or lost as the harness damages theirs, and a reset of the reference node,
//! [`TwoNodeLoop::reset_reference`]); a team with one larger processor composes the nodes in
//! one image exactly as here.
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

/// Which way a packet crosses the link ([`TwoNodeLoop::step_over_link`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum LinkDirection {
    /// REF, reference node → attitude node.
    Reference,
    /// STATUS, attitude node → reference node.
    Status,
}

/// The two nodes composed in one program, joined by their messages as bytes (bit for bit what
/// the link carries): for at most `N` ≤ 32 tiles (see [`AcsConfig`]), with room for `F` IGRF
/// coefficients on the reference node (`F` ≥ the configured degree's
/// [`crate::env::igrf::coefficient_count`]: 80 for degree 8, the default 195 for 13).
#[derive(Clone, Debug)]
pub struct TwoNodeLoop<'c, const N: usize = MAX_TILES, const F: usize = FULL_COEFFS> {
    config: &'c AcsConfig<N>,
    reference: ReferenceNode<'c, N, F>,
    attitude: AttitudeNode<'c, N>,
    /// The attitude node's last STATUS, as the reference node received it.
    status: Option<Status>,
    /// The step the reference node's next REF is for: the last STATUS's next, counted on
    /// without one (as the reference image counts, `firmware/src/bin/reference.rs`).
    reference_step: u32,
    /// The sequence counts of the REF and STATUS packets.
    reference_count: SequenceCounter,
    status_count: SequenceCounter,
    /// The last step's packets, as on the link.
    reference_packet: [u8; REFERENCE_PACKET_BYTES],
    status_packet: [u8; STATUS_PACKET_BYTES],
    /// The last step's REF as the reference node made it.
    reference_made: Option<Reference>,
    /// What each node's link layer made of the last step's packet ([`TwoNodeLoop::received`]).
    received: [Option<bool>; 2],
}

impl<'c, const N: usize, const F: usize> TwoNodeLoop<'c, N, F> {
    /// A loop in `Detumble` for the given configuration and orbit (an [`Sgp4`], or `None`: a
    /// loop without an element set, as after a corrupt one at start-up, still detumbles and
    /// keeps the Sun on its panel, the laws that need no reference, with [`Faults::orbit`] set
    /// each step until [`Self::set_orbit`] gives it one).
    pub fn new(config: &'c AcsConfig<N>, orbit: impl Into<Option<Sgp4>>) -> Result<Self, AcsError> {
        Ok(Self {
            config,
            reference: ReferenceNode::new(config, orbit)?,
            attitude: AttitudeNode::new(config)?,
            status: None,
            reference_step: 0,
            reference_count: SequenceCounter::new(),
            status_count: SequenceCounter::new(),
            reference_packet: [0; REFERENCE_PACKET_BYTES],
            status_packet: [0; STATUS_PACKET_BYTES],
            reference_made: None,
            received: [None; 2],
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

    /// The wheels' and coils' health ([`crate::attitude_node::health`]).
    pub fn health(&self) -> &crate::attitude_node::health::ActuatorHealth<N> {
        self.attitude.health()
    }

    /// Fails coil `coil` and takes it out of its allocation (`failed`), or returns it to
    /// service ([`AttitudeNode::set_coil_failed`]); false if there is no such coil.
    pub fn set_coil_failed(&mut self, coil: usize, failed: bool) -> bool {
        self.attitude.set_coil_failed(coil, failed)
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
        self.step_over_link(bus, dt_s, report, |_, _| true);
    }

    /// One control step as the two node images make it, over a link that may lose or damage
    /// packets: the reference node keeps its own clock (set by the ground,
    /// [`crate::uplink::apply_reference`], or brought back by a STATUS after a reset) and counts
    /// its REFs' steps on from the last STATUS it received, as the reference image does. Each
    /// packet is handed to `link` (its direction, a copy of its bytes) before it is delivered:
    /// `link` may change the bytes (the receiver's CRC check then refuses the packet) or return
    /// `false` to drop it. With a link that delivers every packet intact and a clock the ground
    /// set to the first step's UTC, the same steps as [`TwoNodeLoop::step_into`].
    pub fn step_over_link<B: TileBus>(
        &mut self,
        bus: &mut B,
        dt_s: f32,
        report: &mut StepReport,
        mut link: impl FnMut(LinkDirection, &mut [u8]) -> bool,
    ) {
        let step = self
            .status
            .map_or(self.reference_step, |s| s.step.wrapping_add(1));
        let reference = self.reference.reference(step, self.status.as_ref());
        self.reference_step = step.wrapping_add(1);
        self.reference_packet = reference.to_packet(self.reference_count.next_count());
        self.reference_made = Some(reference);
        let mut delivered = self.reference_packet;
        let reference = link(LinkDirection::Reference, &mut delivered)
            .then(|| Reference::from_packet(&delivered).ok());
        self.received[0] = reference.as_ref().map(Option::is_some);
        let reference = reference.flatten();
        let status = self
            .attitude
            .step_into(bus, reference.as_ref().map(|(r, _)| r), dt_s, report);
        self.status_packet = status.to_packet(self.status_count.next_count());
        let mut delivered = self.status_packet;
        let status = link(LinkDirection::Status, &mut delivered)
            .then(|| Status::from_packet(&delivered).ok().map(|(s, _)| s));
        self.received[1] = status.as_ref().map(Option::is_some);
        self.status = status.flatten();
    }

    /// What the last step's packets were at their receivers, as the images count them
    /// ([`crate::telemetry::LinkCounts::count`]): the REF at the attitude node, then the STATUS at
    /// the reference node; each `None` if it was dropped, `Some(true)` if it decoded,
    /// `Some(false)` if it was refused.
    pub fn received(&self) -> [Option<bool>; 2] {
        self.received
    }

    /// The last step's REF as the reference node made it (`None` before the first step).
    pub fn reference_made(&self) -> Option<&Reference> {
        self.reference_made.as_ref()
    }

    /// A power-on reset of the reference node: a fresh node with `orbit` (its element set at
    /// reset) and no clock, no STATUS received, its REFs' steps and sequence counts from 0 (the
    /// reference image after a reset, `firmware/src/bin/reference.rs`); the attitude node flies
    /// on.
    pub fn reset_reference(&mut self, orbit: impl Into<Option<Sgp4>>) -> Result<(), AcsError> {
        self.reference = ReferenceNode::new(self.config, orbit)?;
        self.status = None;
        self.received[1] = None;
        self.reference_step = 0;
        self.reference_count = SequenceCounter::new();
        Ok(())
    }

    /// A power-on reset of the attitude node: a fresh node (in `Detumble`, step 0, no clock, no
    /// guidance accepted) and its STATUS sequence count from 0; the reference node flies on.
    pub fn reset_attitude(&mut self) -> Result<(), AcsError> {
        self.attitude = AttitudeNode::new(self.config)?;
        self.status_count = SequenceCounter::new();
        Ok(())
    }

    /// The reference node (the ground's track, slew, element set and clock commands go to it,
    /// [`crate::uplink::apply_reference`]).
    pub fn reference_node_mut(&mut self) -> &mut ReferenceNode<'c, N, F> {
        &mut self.reference
    }

    /// The attitude node (the ground's sun-safe and tile commands go to it,
    /// [`crate::uplink::apply_attitude`]).
    pub fn attitude_node_mut(&mut self) -> &mut AttitudeNode<'c, N> {
        &mut self.attitude
    }

    /// The last STATUS the reference node received (a slew is planned from its attitude).
    pub fn last_status(&self) -> Option<&Status> {
        self.status.as_ref()
    }

    /// The last step's REF and STATUS packets, as the link carries them.
    pub fn packets(&self) -> (&[u8], &[u8]) {
        (&self.reference_packet, &self.status_packet)
    }
}
