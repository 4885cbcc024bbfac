//! The nodes' telemetry as PUS-C packets (issue 31, item 3): each node's housekeeping as a
//! TM\[3,25\] parameter report, its mode changes and fault bits as TM\[5,x\] event reports,
//! and the housekeeping interval the ground sets (TC\[8,1\] function 8,
//! [`crate::uplink::kind::HOUSEKEEPING`]).
//!
//! Each report is written in place, field by field, at a fixed layout ([`attitude_report`],
//! [`reference_report`], [`write_event`]): no table of descriptors is linked into the images,
//! every `f32` goes as its IEEE 754 bits, big-endian, and a value the node does not have (no
//! attitude, no rate, no filter) as the quiet NaN `0x7FC0_0000`. The parameter tables
//! ([`ATTITUDE_PARAMETERS`], [`REFERENCE_PARAMETERS`]) describe the same layouts for the
//! ground (the packet dictionary, `acs tm`); the tests check that both agree, field by field
//! (`tests/housekeeping.rs`). The layouts, the event IDs and the command are tabulated in
//! `docs/operations.md`.
//!
//! # When
//! Each node keeps its own [`Housekeeping`] schedule: a report every
//! [`Housekeeping::interval`] control periods (at reset [`DEFAULT_INTERVAL`], 10 periods; the
//! first one in the first period after reset or after the ground changes it), none when the
//! ground sets 0; at most [`MAX_INTERVAL`] (an hour of 1 s periods), a larger value refused.
//! Events are reported as they happen: [`events`] compares the node's [`State`] (mode and
//! fault word) after a step with the one after the step before.
//!
//! # Sent
//! Each node image keeps a [`Downlink`] and calls it after each step (the reference node:
//! after each REF it makes), which writes the step's events, then its housekeeping report if
//! due, each on the stack, and hands each packet to the ground link as soon as it is written
//! (`acs_firmware::flight::downlink`); one TM sequence count per node, shared with its
//! verification reports. The reference image skips the call in a period in which it took a
//! telecommand: that period is its longest (a slew's planning), and its events come one REF
//! later, its schedule one period later. The processor-in-the-loop run and the rehearsal make
//! the same calls on the host (`host::sim::pil::uplink::Ground::telemetry`) and compare or
//! record the same bytes.
//!
//! # Events
//! | event ID | severity (subtype) | when | auxiliary data (2 B) |
//! |---:|---|---|---|
//! | [`MODE_CHANGED`] (1) | TM\[5,1\] informative | the mode changed (the reference node: the guidance kind) | old mode, new mode (1 B each) |
//! | [`FAULT_EVENT`] + *i* (0x100 + *i*) | TM\[5,2\] low | fault bit *i* raised | the new fault word |
//! | [`FAULT_EVENT`] + *i* | TM\[5,1\] informative | fault bit *i* cleared | the new fault word |
//!
//! A step reports at most 17 events (a mode change and 16 bits; the fault word has 12):
//! [`MAX_EVENTS`].

use crate::acs_loop::StepReport;
use crate::attitude_node::AttitudeNode;
use crate::link::messages::{GuidanceKind, Reference, Writer};
use crate::link::pus::{self, encode_tm_in_place, service, PusError, Severity, TmHeader};
use crate::link::sequence::SequenceCounter;
use crate::reference_node::ReferenceNode;
use crate::time::{Epoch, Utc};
use crate::uplink::telecommand::cuc;

/// The housekeeping structure ID of the attitude node.
pub const ATTITUDE_STRUCTURE: u16 = 1;
/// The housekeeping structure ID of the reference node.
pub const REFERENCE_STRUCTURE: u16 = 2;
/// The housekeeping interval at reset, control periods.
pub const DEFAULT_INTERVAL: u16 = 10;
/// The longest housekeeping interval the ground may set, control periods (3 600: an hour).
pub const MAX_INTERVAL: u16 = 3_600;
/// The event ID of a mode change.
pub const MODE_CHANGED: u16 = 1;
/// The event ID of fault bit 0; bit *i*'s is this + *i*.
pub const FAULT_EVENT: u16 = 0x100;
/// The most events one step can report.
pub const MAX_EVENTS: usize = 17;
/// The bytes of an event report's application data: event ID and 2 B of auxiliary data.
pub const EVENT_DATA_LEN: usize = 4;
/// The length of an event report packet (25 B).
pub const EVENT_REPORT_LEN: usize = pus::tm_packet_len(EVENT_DATA_LEN);
/// The value an absent `f32` parameter is sent as: the quiet NaN.
pub const ABSENT: f32 = f32::NAN;

/// The bytes of the attitude node's parameters (after the structure ID) for `n` tiles.
pub const fn attitude_parameters_len(n: usize) -> usize {
    98 + 8 * n
}

/// The application data of the attitude node's report for `n` tiles: structure ID and
/// parameters.
pub const fn attitude_data_len(n: usize) -> usize {
    2 + attitude_parameters_len(n)
}

/// The bytes of the reference node's parameters (after the structure ID).
pub const REFERENCE_PARAMETERS_LEN: usize = 43;
/// The application data of the reference node's report: structure ID and parameters.
pub const REFERENCE_DATA_LEN: usize = 2 + REFERENCE_PARAMETERS_LEN;
/// The length of the reference node's report packet (66 B).
pub const REFERENCE_REPORT_LEN: usize = pus::tm_packet_len(REFERENCE_DATA_LEN);

/// A node's housekeeping schedule: how many control periods between reports, set by the
/// ground.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Housekeeping {
    interval: u16,
    /// Periods before the next report.
    remaining: u16,
}

impl Default for Housekeeping {
    fn default() -> Self {
        Self::new()
    }
}

impl Housekeeping {
    /// The schedule at reset: every [`DEFAULT_INTERVAL`] periods, the first report now.
    pub const fn new() -> Self {
        Self {
            interval: DEFAULT_INTERVAL,
            remaining: 0,
        }
    }

    /// Periods between reports (0: none).
    pub fn interval(&self) -> u16 {
        self.interval
    }

    /// The ground's interval `periods` (0: no reports); false, and nothing changed, beyond
    /// [`MAX_INTERVAL`]. The next report is due in the next period.
    pub fn set_interval(&mut self, periods: u32) -> bool {
        if periods > u32::from(MAX_INTERVAL) {
            return false;
        }
        self.interval = periods as u16;
        self.remaining = 0;
        true
    }

    /// Called once a control period: true if a report is due in this one.
    pub fn due(&mut self) -> bool {
        if self.interval == 0 {
            return false;
        }
        if self.remaining == 0 {
            self.remaining = self.interval - 1;
            true
        } else {
            self.remaining -= 1;
            false
        }
    }
}

/// What a node's link layer counts, which its housekeeping reports: kept by the image that
/// receives the other node's packets (the library's nodes take a decoded packet or none).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct LinkCounts {
    /// Packets received that decoded (CRC, APID, length).
    pub received: u16,
    /// Packets received that were refused.
    pub refused: u16,
    /// Periods in which no packet arrived.
    pub missed: u16,
}

impl LinkCounts {
    /// Its three counts, as the reports carry them.
    fn write(&self, w: &mut Writer<'_>) {
        w.u16(self.received);
        w.u16(self.refused);
        w.u16(self.missed);
    }

    /// Counts one period's outcome: `None` nothing arrived, `Some(true)` a packet decoded,
    /// `Some(false)` one was refused (each count wraps).
    pub fn count(&mut self, outcome: Option<bool>) {
        let c = match outcome {
            None => &mut self.missed,
            Some(true) => &mut self.received,
            Some(false) => &mut self.refused,
        };
        *c = c.wrapping_add(1);
    }
}

/// A CUC time's six bytes (seconds, fraction; zeros without a time).
fn put_cuc(w: &mut Writer<'_>, t: Option<Epoch<Utc>>) {
    let (time, _) = cuc(t);
    w.u32(time.seconds);
    w.u16(time.fraction);
}

/// Writes the attitude node's housekeeping report TM\[3,25\] (structure
/// [`ATTITUDE_STRUCTURE`]) to the start of `out`: `node` after its step, `report` that step's
/// report, `link` the image's counts; returns its length
/// ([`pus::tm_packet_len`]`(`[`attitude_data_len`]`(N))`, 169 B for 6 tiles). The layout is
/// [`ATTITUDE_PARAMETERS`]'s. Errors as [`pus::encode_tm`].
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn attitude_report<const N: usize>(
    header: &TmHeader,
    node: &AttitudeNode<'_, N>,
    report: &StepReport,
    link: &LinkCounts,
    out: &mut [u8],
) -> Result<usize, PusError> {
    let len = attitude_data_len(N);
    let fill = |data: &mut [u8]| {
        let mut w = Writer { out: data, at: 0 };
        w.u16(ATTITUDE_STRUCTURE);
        w.u32(node.step_number());
        w.u8(report.mode.code() as u8);
        w.u8(node.coils_failed());
        w.u16(report.faults.bits());
        w.u16(node.housekeeping().interval());
        w.u16(node.steps_without_reference());
        link.write(&mut w);
        match &report.attitude {
            Some(q) => w.quaternion(q),
            None => w.f32s(&[ABSENT; 4]),
        }
        match &report.omega_body_radps {
            Some(v) => w.f32s(v.as_slice()),
            None => w.f32s(&[ABSENT; 3]),
        }
        for i in 0..crate::determination::mekf::STATES {
            w.f32(node.filter().map_or(ABSENT, |f| f.variance(i)));
        }
        w.f32s(report.dipole_body_am2.as_slice());
        w.bytes(&node.part_states());
        w.bytes(node.part_errors());
        w.f32s(node.wheels_commanded());
        for r in node.health().wheel_reads() {
            w.u16(*r as u16);
        }
    };
    encode_tm_in_place(
        header,
        service::HOUSEKEEPING,
        service::HOUSEKEEPING_REPORT,
        len,
        out,
        fill,
    )
}

/// The shadow code of a REF: 0 unknown (no models), 1 sunlit, 2 penumbra, 3 umbra, 4 antumbra.
fn shadow_code(r: &Reference) -> u8 {
    use crate::env::eclipse::Shadow;
    match r.illumination.map(|i| i.shadow) {
        None => 0,
        Some(Shadow::Sunlit) => 1,
        Some(Shadow::Penumbra) => 2,
        Some(Shadow::Umbra) => 3,
        Some(Shadow::Antumbra) => 4,
    }
}

/// The guidance kind's code: 0 none, 1 track, 2 slew.
fn guidance_code(kind: GuidanceKind) -> u8 {
    match kind {
        GuidanceKind::None => 0,
        GuidanceKind::Track => 1,
        GuidanceKind::Slew => 2,
    }
}

/// Writes the reference node's housekeeping report TM\[3,25\] (structure
/// [`REFERENCE_STRUCTURE`]) to the start of `out`: `node` and `reference`, the last REF it
/// made, `link` the image's counts; returns its length ([`REFERENCE_REPORT_LEN`], 66 B). The
/// layout is [`REFERENCE_PARAMETERS`]'s. Errors as [`pus::encode_tm`].
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn reference_report<const N: usize, const F: usize>(
    header: &TmHeader,
    node: &ReferenceNode<'_, N, F>,
    reference: &Reference,
    link: &LinkCounts,
    out: &mut [u8],
) -> Result<usize, PusError> {
    let fill = |data: &mut [u8]| {
        let mut w = Writer { out: data, at: 0 };
        w.u16(REFERENCE_STRUCTURE);
        put_cuc(&mut w, reference.clock_valid.then_some(reference.utc));
        w.u8(u8::from(reference.clock_valid) | u8::from(reference.elements_valid) << 1);
        w.u8(shadow_code(reference));
        w.u16(reference.faults);
        w.u16(node.housekeeping().interval());
        link.write(&mut w);
        let g = &reference.guidance;
        w.u16(g.id);
        w.u8(guidance_code(g.kind));
        w.quaternion(&g.target);
        put_cuc(&mut w, node.elements_epoch());
    };
    encode_tm_in_place(
        header,
        service::HOUSEKEEPING,
        service::HOUSEKEEPING_REPORT,
        REFERENCE_DATA_LEN,
        out,
        fill,
    )
}

/// What the events compare: a node's mode (the attitude node's [`crate::acs_loop::Mode::code`],
/// the reference node's guidance kind: 0 none, 1 track, 2 slew) and its fault word
/// ([`crate::acs_loop::Faults::bits`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct State {
    /// The mode's code.
    pub mode: u8,
    /// The fault word.
    pub faults: u16,
}

impl State {
    /// The attitude node's state after the step of `report`.
    pub fn of_step(report: &StepReport) -> State {
        State {
            mode: report.mode.code() as u8,
            faults: report.faults.bits(),
        }
    }

    /// The reference node's state in its REF `reference`: guidance kind and fault word.
    pub fn of_reference(reference: &Reference) -> State {
        State {
            mode: guidance_code(reference.guidance.kind),
            faults: reference.faults,
        }
    }
}

/// One event: its severity (the report's subtype), ID and auxiliary data.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Event {
    /// TM\[5,1\] or TM\[5,2\].
    pub severity: Severity,
    /// [`MODE_CHANGED`], or [`FAULT_EVENT`] + the bit.
    pub id: u16,
    /// The old and the new mode, or the new fault word (big-endian).
    pub aux: [u8; 2],
}

/// The events between two states ([`events`]): the mode change first, then each fault bit
/// that changed, from bit 0.
#[derive(Clone, Debug)]
pub struct Events {
    prev: State,
    new: State,
    /// 0: the mode; 1 + i: fault bit i; 17: done.
    next: u8,
}

/// The events from the state after one step, `prev`, to the state after the next, `new` (see
/// the [module docs](self)). A pure function: nothing is kept between calls.
pub fn events(prev: State, new: State) -> Events {
    Events { prev, new, next: 0 }
}

impl Iterator for Events {
    type Item = Event;

    fn next(&mut self) -> Option<Event> {
        while 17 > self.next {
            let k = self.next;
            self.next += 1;
            if let Some(e) = event_at(self.prev, self.new, u16::from(k)) {
                return Some(e);
            }
        }
        None
    }
}

/// Event `k` from `prev` to `new`, if it happened: `k` 0 the mode change, 1 + *i* fault bit
/// *i* raised or cleared (the order of [`events`]).
#[inline(always)]
fn event_at(prev: State, new: State, k: u16) -> Option<Event> {
    if k == 0 {
        return (prev.mode != new.mode).then_some(Event {
            severity: Severity::Informative,
            id: MODE_CHANGED,
            aux: [prev.mode, new.mode],
        });
    }
    let bit = k - 1;
    if (prev.faults ^ new.faults) >> bit & 1 == 0 {
        return None;
    }
    Some(Event {
        severity: if new.faults >> bit & 1 != 0 {
            Severity::Low
        } else {
            Severity::Informative
        },
        id: FAULT_EVENT + bit,
        aux: new.faults.to_be_bytes(),
    })
}

/// Writes the event report TM\[5,x\] of `event` to the start of `out`; returns its length
/// ([`EVENT_REPORT_LEN`], 25 B). Errors as [`pus::encode_tm`].
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn write_event(header: &TmHeader, event: &Event, out: &mut [u8]) -> Result<usize, PusError> {
    let [i0, i1] = event.id.to_be_bytes();
    let [a0, a1] = event.aux;
    encode_tm_in_place(
        header,
        service::EVENT,
        event.severity as u8,
        EVENT_DATA_LEN,
        out,
        |data| {
            if let Some(d) = data.first_chunk_mut::<EVENT_DATA_LEN>() {
                *d = [i0, i1, a0, a1];
            }
        },
    )
}

/// Writes the event reports from `prev` to `new` ([`events`]) back to back to the start of
/// `out`, each with `header` and the next count of `count`; returns the bytes written and the
/// number of events that did not fit (0 when `out` holds [`MAX_EVENTS`] ×
/// [`EVENT_REPORT_LEN`] bytes).
#[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
pub fn write_events(
    header: &TmHeader,
    count: &mut SequenceCounter,
    prev: State,
    new: State,
    out: &mut [u8],
) -> (usize, usize) {
    let mut written = 0;
    let mut left = 0;
    // one loop, no iterator: the images' flash
    for k in 0..17u16 {
        let Some(e) = event_at(prev, new, k) else {
            continue;
        };
        let rest = out.get_mut(written..).unwrap_or_default();
        if EVENT_REPORT_LEN > rest.len() {
            left += 1;
            continue;
        }
        let h = TmHeader {
            sequence_count: count.next_count(),
            ..*header
        };
        written += write_event(&h, &e, rest).unwrap_or(0);
    }
    (written, left)
}

/// A node's telemetry after each of its steps ([`Downlink::attitude`],
/// [`Downlink::reference`]): the events from its state after the step before (at reset: mode
/// 0, no fault), then its housekeeping report when [`Housekeeping::due`]. Each packet is
/// written on the caller's stack and handed to `send` as soon as it is complete (the node
/// images: `acs_firmware::flight::downlink`), counted by the node's TM sequence counter (its
/// verification reports' too) and stamped with the node's clock ([`cuc`]). The image keeps one,
/// and so does the host's copy of it (the processor-in-the-loop run, the rehearsal), which
/// sends the same bytes.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Downlink {
    /// The node's state after its step before: what the events compare against.
    prev: State,
    /// What the node's link layer counted (the image counts, the reports carry it).
    pub link: LinkCounts,
}

impl Downlink {
    /// The telemetry at reset: no step before (mode 0, no fault), nothing counted.
    pub const fn new() -> Self {
        Self {
            prev: State { mode: 0, faults: 0 },
            link: LinkCounts {
                received: 0,
                refused: 0,
                missed: 0,
            },
        }
    }

    /// The attitude node's telemetry after its step of `report` (see [`Downlink`]): its
    /// events, then its housekeeping report (structure [`ATTITUDE_STRUCTURE`]) if due. For
    /// the flight configuration's [`crate::flight::TILES`] tiles, whose report the node
    /// images send.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn attitude(
        &mut self,
        node: &mut AttitudeNode<'_, TILES>,
        report: &StepReport,
        count: &mut SequenceCounter,
        mut send: impl FnMut(&[u8]),
    ) {
        let apid = crate::link::messages::ATTITUDE_TC_APID;
        let clock = node.clock();
        self.events(apid, clock, State::of_step(report), count, &mut send);
        if node.housekeeping_mut().due() {
            let mut out = [0u8; pus::tm_packet_len(attitude_data_len(TILES))];
            let header = tm_header(apid, clock, count);
            if let Ok(n) = attitude_report(&header, node, report, &self.link, &mut out) {
                send(out.get(..n).unwrap_or_default());
            }
        }
    }

    /// The reference node's telemetry after it made `reference` (see [`Downlink`]): its
    /// events (the guidance kind as its mode), then its housekeeping report (structure
    /// [`REFERENCE_STRUCTURE`]) if due.
    #[cfg_attr(target_arch = "msp430", inline(never), optimize(size))]
    pub fn reference<const N: usize, const F: usize>(
        &mut self,
        node: &mut ReferenceNode<'_, N, F>,
        reference: &Reference,
        count: &mut SequenceCounter,
        mut send: impl FnMut(&[u8]),
    ) {
        let apid = crate::link::messages::REFERENCE_TC_APID;
        let clock = node.clock();
        self.events(
            apid,
            clock,
            State::of_reference(reference),
            count,
            &mut send,
        );
        if node.housekeeping_mut().due() {
            let mut out = [0u8; REFERENCE_REPORT_LEN];
            let header = tm_header(apid, clock, count);
            if let Ok(n) = reference_report(&header, node, reference, &self.link, &mut out) {
                send(out.get(..n).unwrap_or_default());
            }
        }
    }

    /// Sends the events from the state before to `new`, and keeps `new`.
    fn events(
        &mut self,
        apid: crate::link::space_packet::Apid,
        clock: Option<Epoch<Utc>>,
        new: State,
        count: &mut SequenceCounter,
        send: &mut impl FnMut(&[u8]),
    ) {
        // one loop, no iterator: the images' flash
        for k in 0..17u16 {
            let Some(event) = event_at(self.prev, new, k) else {
                continue;
            };
            let mut out = [0u8; EVENT_REPORT_LEN];
            let header = tm_header(apid, clock, count);
            if let Ok(n) = write_event(&header, &event, &mut out) {
                send(out.get(..n).unwrap_or_default());
            }
        }
        self.prev = new;
    }
}

/// The header of a node's next report: its APID, the next count of `count`, the time of
/// `clock` (status 0 and time 0 without one, [`cuc`]).
fn tm_header(
    apid: crate::link::space_packet::Apid,
    clock: Option<Epoch<Utc>>,
    count: &mut SequenceCounter,
) -> TmHeader {
    let (time, time_status) = cuc(clock);
    TmHeader {
        apid,
        sequence_count: count.next_count(),
        time_status,
        message_counter: 0,
        destination_id: 0,
        time,
    }
}

/// The names of the fault word's bits, bit 0 first ([`crate::acs_loop::Faults::bits`]): the
/// events' names on the ground.
pub const FAULT_BITS: [&str; 12] = [
    "device_read",
    "actuator",
    "orbit",
    "model",
    "field",
    "rate",
    "attitude",
    "saturated",
    "law",
    "clock",
    "extrapolated",
    "link",
];

/// The type of a housekeeping parameter, as the ground reads it.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum ParameterType {
    /// Unsigned, 8 bits.
    U8,
    /// Unsigned, 16 bits.
    U16,
    /// Signed, 16 bits.
    I16,
    /// Unsigned, 32 bits.
    U32,
    /// IEEE 754 single precision.
    F32,
}

impl ParameterType {
    /// Its size, bytes.
    pub const fn bytes(self) -> usize {
        match self {
            Self::U8 => 1,
            Self::U16 | Self::I16 => 2,
            Self::U32 | Self::F32 => 4,
        }
    }
}

/// One parameter of a housekeeping structure, or several of the same meaning (per tile, per
/// axis), as the packet dictionary and `acs tm` describe it.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Parameter {
    /// Its name (the dictionary's item, the CSV's column; `NAME_k` for element k of several).
    pub name: &'static str,
    /// Its type.
    pub ty: ParameterType,
    /// How many.
    pub count: usize,
    /// Its unit, empty if none.
    pub unit: &'static str,
    /// What it is.
    pub description: &'static str,
}

const fn p(
    name: &'static str,
    ty: ParameterType,
    count: usize,
    unit: &'static str,
    description: &'static str,
) -> Parameter {
    Parameter {
        name,
        ty,
        count,
        unit,
        description,
    }
}

use ParameterType::{F32, I16, U16, U32, U8};

/// The tiles of the flight configuration, whose count sets the attitude structure's length.
const TILES: usize = crate::flight::TILES;

/// The attitude node's housekeeping parameters (structure [`ATTITUDE_STRUCTURE`]), in order,
/// for the flight configuration's [`crate::flight::TILES`] tiles: what [`attitude_report`]
/// writes after the structure ID.
pub const ATTITUDE_PARAMETERS: &[Parameter] = &[
    p("STEP", U32, 1, "", "steps taken since reset (the next step's number)"),
    p("MODE", U8, 1, "", "mode: 0 detumble, 1 sun-safe, 2 slew, 3 tracking"),
    p("COILS_FAILED", U8, 1, "", "bit c: coil c failed"),
    p("FAULTS", U16, 1, "", "the step's fault word (docs/faults.md)"),
    p("HK_INTERVAL", U16, 1, "periods", "housekeeping interval (0: off)"),
    p("WITHOUT_REF", U16, 1, "steps", "steps in a row without a usable REF"),
    p("LINK_RECEIVED", U16, 1, "", "REF packets received (wraps)"),
    p("LINK_REFUSED", U16, 1, "", "REF packets refused (wraps)"),
    p("LINK_MISSED", U16, 1, "", "periods without a REF packet (wraps)"),
    p("Q", F32, 4, "", "filtered attitude, TEME to body, scalar first (NaN: none)"),
    p("RATE", F32, 3, "rad/s", "body rate from the gyros (NaN: none)"),
    p("VARIANCE", F32, 10, "", "filter covariance diagonal: attitude rad^2 (3), gyro bias (rad/s)^2 (3), magnetometer bias nT^2 (3), albedo (NaN: no filter)"),
    p("DIPOLE", F32, 3, "A.m^2", "commanded body dipole"),
    p("TILE_STATE", U8, TILES, "", "per tile: bit 0 out of service, 1 wheel failed, 2 wheel out of its allocation, 3 gyro held stuck, 4-7 read failures in a row (to 15)"),
    p("TILE_ERROR", U8, TILES, "", "per tile, its last device error: device (high nibble: 1 Sun sensor, 2 magnetometer, 3 gyro, 4 wheel) and kind (low nibble: 1 absent, 2 timeout, 3 out of range, 4 bus, 5 other); 0 none"),
    p("WHEEL_CMD", F32, TILES, "N.m.s", "per tile, the wheel momentum commanded"),
    p("WHEEL_READ", I16, TILES, "1e-7 N.m.s", "per tile, the wheel's read-back word (-32768: none)"),
];

/// The reference node's housekeeping parameters (structure [`REFERENCE_STRUCTURE`]), in
/// order: what [`reference_report`] writes after the structure ID.
pub const REFERENCE_PARAMETERS: &[Parameter] = &[
    p(
        "CLOCK_SECONDS",
        U32,
        1,
        "s",
        "the last REF's UTC as CUC seconds since 2000-01-01 (0: no clock)",
    ),
    p("CLOCK_FRACTION", U16, 1, "2^-16 s", "its CUC fraction"),
    p(
        "FLAGS",
        U8,
        1,
        "",
        "bit 0 clock valid, bit 1 element set held",
    ),
    p(
        "SHADOW",
        U8,
        1,
        "",
        "0 unknown, 1 sunlit, 2 penumbra, 3 umbra, 4 antumbra",
    ),
    p(
        "FAULTS",
        U16,
        1,
        "",
        "the REF's fault word (orbit, model, extrapolated)",
    ),
    p(
        "HK_INTERVAL",
        U16,
        1,
        "periods",
        "housekeeping interval (0: off)",
    ),
    p(
        "LINK_RECEIVED",
        U16,
        1,
        "",
        "STATUS packets received (wraps)",
    ),
    p("LINK_REFUSED", U16, 1, "", "STATUS packets refused (wraps)"),
    p(
        "LINK_MISSED",
        U16,
        1,
        "",
        "periods without a STATUS packet (wraps)",
    ),
    p("GUIDANCE_ID", U16, 1, "", "the guidance's id (0: none yet)"),
    p("GUIDANCE_KIND", U8, 1, "", "0 none, 1 track, 2 slew"),
    p(
        "TARGET",
        F32,
        4,
        "",
        "the guidance's target, TEME to body, scalar first",
    ),
    p(
        "EPOCH_SECONDS",
        U32,
        1,
        "s",
        "the element set's epoch, CUC seconds (0: none)",
    ),
    p("EPOCH_FRACTION", U16, 1, "2^-16 s", "its CUC fraction"),
];
