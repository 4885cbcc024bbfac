//! Processor-in-the-loop simulation: the two node flight images (issue #29: `acs-reference`,
//! `firmware/src/bin/reference.rs`; `acs-attitude`, `firmware/src/bin/attitude.rs`) fly each in
//! its own `mspdebug` MSP430 simulator against the host simulator's truth, in lockstep with the
//! host composition of the same nodes ([`crate::two_node::TwoNodeLoop`] over [`CONFIG`],
//! [`HostLoop`]), and everything the images produce is checked bit for bit against the host's:
//! actuator commands, both nodes' packets, mode, faults, the verification reports of every
//! telecommand and every telemetry packet (events, housekeeping).
//!
//! # The images
//! Each image loops: `fw_period_start()` (the host's break point), take the telecommand in its
//! ground mailbox (`GROUND`: the packet in, its verification reports out,
//! `acs_firmware::flight::take_telecommand`; each node applies only its own commands, another
//! node's is refused with failure code 0x104), take the packet in its `LINK_RX`/`LINK_RX_LEN` mailbox, do its
//! work, put its packet in `LINK_TX`/`LINK_TX_LEN`, publish `STEP_MODE`/`STEP_FAULTS`, and hand
//! its telemetry packets to `fw_downlink` (`acs_firmware::flight::downlink`: the host stops at
//! its entry, a break point kept all run, and reads each packet from R12 and R13; the host
//! composition's are [`crate::telemetry::Downlink`]'s through the mirror,
//! [`uplink::Ground::telemetry`]; the reference image sends none in a period in which it took a
//! telecommand). The
//! attitude image also has the tile mailboxes ([`TILE_MAILBOXES`], [`bus`]); its packet is
//! STATUS(k), which it sends after step k using the REF delivered to it if that was made for
//! step k with a valid clock. The reference image answers STATUS(k) with REF(k + 1) (without a
//! STATUS it counts its steps on by itself); its `STEP_MODE` is 0 and its `STEP_FAULTS` the
//! REF's fault bits. Each [`Target`] reads its image's addresses from the ELF ([`ImageMap`],
//! with the node's mailbox set, [`mailboxes`]).
//!
//! # One control period k
//! 1. The reference image runs one period on its telecommands of the period and the STATUS(k − 1)
//!    packet the attitude image sent (none before step 0: the first period carries the element
//!    set and the clock, so REF(0) exists); its `LINK_TX` is REF(k).
//! 2. The host applies the same telecommands to the composition's nodes, then steps it
//!    ([`crate::two_node::TwoNodeLoop::step_over_link`]) on the simulator through a
//!    [`bus::Recorder`], which records the raw readings in the tile mailboxes' format: the
//!    attitude image reads exactly the values the host read. The image's REF(k) is compared
//!    with the host's (`packets().0`), and its reports and fault bits.
//! 3. The attitude image gets the readings (`mw` into its `TILE_*` mailboxes), its telecommands and
//!    the REF(k) the reference *image* made in its `LINK_RX`, and runs one period; its
//!    `CMD_WHEEL_NMS`, `CMD_DIPOLE_AM2`, `STEP_MODE`, `STEP_FAULTS`, its reports and its
//!    STATUS(k) packet are compared with the host's (`packets().1`).
//! 4. The STATUS(k) packet goes to the reference image's `LINK_RX` at the next period, and the
//!    f64 truth is integrated over the period with the commands (those the composition gave
//!    the simulator, proven equal to the image's by step 3).
//!
//! The first difference anywhere stops the run ([`Mismatch`], naming the node and the field).
//! The host composition is stepped as the images run: the reference node keeps its own clock,
//! set by the clock uplink (the scenario's start) and advanced one period per REF, and counts
//! its REFs' steps from the STATUS it received; with every packet delivered that is
//! [`crate::two_node::TwoNodeLoop::step_into`], which sets the clock to the step's UTC each
//! step, to the bit.
//!
//! # Ground commands
//! The telecommands follow the schedule a rehearsal's host run follows too
//! ([`super::rehearsal::Operations`]): the scenario's orbit and clock reach the reference image
//! as telecommands like the other commands: at the first period the element set
//! ([`Sgp4::to_words`] of the scenario's TLE, function 4) and the clock (the scenario's start,
//! function 5), then each ground command at the period the host simulator's `run` would give
//! it (time ≤ the truth's time), then a rehearsal script's packets ([`PilOptions::script`]), to
//! the node of their APID, as written. Each command is a TC\[8,1\] ([`Uplink::telecommand`], both reports asked for) to the node that owns it
//! ([`owner`]: track 2, slew 3, elements 4, clock 5 the reference node; sun-safe 1, mark
//! failed 6, restore 7 the attitude node), through that image's `GROUND` mailbox; the host
//! takes the same packet on the composition's node ([`uplink::Ground::take`]:
//! [`crate::uplink::telecommand::take`] with [`crate::uplink::apply_reference`] or
//! [`crate::uplink::apply_attitude`], what the images run) and the reports must match byte for
//! byte: sequence count, the node's clock as CUC time, request ID, failure code. The reference
//! image takes its telecommand before its link mailbox, so it plans a slew from the attitude of
//! the STATUS it received the period before (STATUS(k − 2) for REF(k)); the host gives
//! `apply_reference` that attitude too.
//!
//! Three quarters of the way through the run (not in a rehearsal, whose telecommands are the
//! schedule's alone, so that the host run sends the same), one period also carries commands
//! whose arguments are NaN and infinities ([`non_finite_uplinks`]: the readings are raw integers, so the
//! telecommands are where non-finite floats reach the images), sent to both nodes (the element
//! set to the reference node only: it does not fit the attitude node's mailbox): the
//! reference node must refuse each for its argument and the attitude node as not its own, with
//! the same reports on both sides, and both fly on bit for bit (issue 19: the MSP430's float
//! comparisons are wrong for a NaN where the host's are not, so the host alone cannot show
//! what an image does with one).
//!
//! An image takes one telecommand per period (`take_telecommand` before its work); when a
//! period carries several, the host calls `take_telecommand` again for each after the first, as
//! a debugger does: at its entry it saves the registers, and after it returns it reads the
//! reports, writes the next packet, restores the registers (the call's arguments and return
//! address are still in place) and runs it again. The function reads the node's clock itself,
//! so each telecommand is stamped with the clock as the ones before it left it, as on the
//! host. The cycles of these extra calls are left out of the period's.
//!
//! # The link-fault case
//! After the scenario (unless [`PilOptions::link_faults`] is off) the run goes on for
//! [`LINK_FAULT_STEPS`] periods (30 s) in which the link drops or damages packets in both
//! directions ([`damage`]: of every five periods in each direction two drop the packet, two
//! flip one byte, a header byte or a payload/CRC byte, which the receiver's CRC or header
//! check refuses, and one delivers it intact). The images' packets are damaged by the harness
//! between `LINK_TX` and `LINK_RX`, the composition's by the same function through
//! [`crate::two_node::TwoNodeLoop::step_over_link`]: both receive the same bytes. Then the
//! reference image has a power-on reset ([`Target::power_on_reset`]: `reset`, its RAM filled
//! with zeros, its start-up run) while the attitude image keeps stepping; the STATUS in flight
//! is lost with its RAM, and the composition's reference node is replaced by a fresh one
//! ([`crate::two_node::TwoNodeLoop::reset_reference`]). The ground uplinks the element set
//! again in that period (so the reset element set, the flight set in the image's flash, is
//! replaced before the first REF on both sides), but not the clock: the reference node has
//! none until the next STATUS brings the attitude node's copy back
//! ([`crate::reference_node::ReferenceNode::reference`]). [`RECOVERY_STEPS`] periods follow.
//! Both sides must stay identical throughout; `pil.json`'s `link_fault` says what the case
//! did (packets dropped and corrupted, steps the attitude node flew without a REF, periods
//! until the reference clock was back).
//!
//! # Cycles
//! The cycles of a period are the MCLK cycles between two `fw_period_start` stops of an image:
//! uplink, link, work, publish, as on the part (with the hardware multiplier, `simio add
//! hwmult`). `pil.json` keeps the one-image keys for the attitude image (`cycles_max`,
//! `cycles_mean`, `cycles_by_mode`, `stack_bytes`, `flash_bytes`,
//! `watchdog_recovery_cycles`) and gives both nodes' under `node_cycles` ([`PilSummary`]).
//! After the run the watchdog's recovery from a halt is checked on both images
//! ([`Target::halt_and_recover`]).
//!
//! # Requirements
//! The scenario flies the flight configuration: its tiles are the flight tiles ([`TILES`] of
//! them) and its control period [`CONTROL_PERIOD_S`]; the truth side (inertia, disturbances,
//! noise) is the scenario's. `mspdebug` must be installed (`apt-get install mspdebug`) and both
//! images built for the MSP430FG4619 map (`firmware/pil` does both).
//!
//! # Relation to `acs sim`
//! The host side is `acs sim`'s run of the same scenario (same simulator, same random draws,
//! the loop's commands bit for bit those of `acs_loop::AcsLoop`, `tests/two_node.rs`; the
//! element set through [`Sgp4::from_words`], which propagates bit for bit as the set that wrote
//! the words) except that ground commands arrive as the uplink carries them: a slew's target
//! DCM goes up as a quaternion and comes back as `new_normalize(q).to_dcm()`, not bit for bit
//! the original, and the slew is planned from the attitude of an older STATUS, so the two runs
//! are the same up to the first slew command and differ at the noise level from it on
//! (`slew`: `run.csv` identical for steps 0–119, different from the slew command's step 120
//! on: its coil dipoles at the 1e-8 A·m² level, then the whole state). The
//! link-fault case's steps come after the scenario's and are not in `run.csv`.
//!

pub mod bus;
pub mod elf;
pub mod mspdebug;
pub mod uplink;

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use self::bus::{Commands, Readings, Recorder, COILS, ERROR_KINDS_LEN};
use self::elf::{Elf, EM_MSP430};
use self::mspdebug::{Mspdebug, MspdebugError, Registers};
use self::uplink::{mode_code, mode_name, tc_bytes, Uplink};
pub use self::uplink::{owner, HostLoop, Node};
use super::rehearsal::{Mirror, Operations, ScriptPacket};
use super::scenarios::Scenario;
use super::{Sample, SimError, Simulator};
use crate::acs_loop::StepReport;
use crate::attitude::Quaternion;
use crate::flight::{CONFIG, CONTROL_PERIOD_S, TILES};
use crate::link::messages::Reference;
use crate::orbit::sgp4::{Sgp4, ELEMENT_WORDS};
use crate::two_node::LinkDirection;
use crate::uplink::telecommand::REPORTS_LEN;

/// The longest packet of the link mailboxes (`firmware/src/node_link.rs`, `LINK_BYTES`).
pub const LINK_BYTES: usize = 128;

/// The mailboxes of both node images and their sizes in bytes: the published codes and the
/// link (`firmware/src/flight.rs`, `firmware/src/node_link.rs`); the ground's mailbox
/// `GROUND` is the node's size ([`ground_bytes`]).
pub const NODE_MAILBOXES: [(&str, usize); 6] = [
    ("STEP_MODE", 2),
    ("STEP_FAULTS", 2),
    ("LINK_TX", LINK_BYTES),
    ("LINK_TX_LEN", 2),
    ("LINK_RX", LINK_BYTES),
    ("LINK_RX_LEN", 2),
];

/// The attitude image's tile mailboxes (`firmware/src/tiles.rs`, [`bus`]) and their sizes.
/// ([`ERROR_KINDS_LEN`]: the kinds of the read and read-back failures.)
pub const TILE_MAILBOXES: [(&str, usize); 12] = [
    ("TILE_SUN", 4 * TILES),
    ("TILE_SUN_SEEN", 2),
    ("TILE_MAG", 4 * TILES),
    ("TILE_GYRO", 2 * TILES),
    ("TILE_READ_ERRORS", 4),
    ("ACTUATOR_REFUSE", 2),
    ("CMD_WHEEL_NMS", 4 * TILES),
    ("CMD_DIPOLE_AM2", 4 * COILS),
    ("TILE_WHEEL", 2 * TILES),
    ("COIL_READ", 2 * COILS),
    ("READBACK_ERRORS", 2),
    ("ERROR_KINDS", ERROR_KINDS_LEN),
];

/// The bytes of `node`'s ground mailbox (`acs_firmware::flight::Ground`): the telecommand's
/// and the reports' lengths (2 B each), the telecommand ([`uplink::tc_bytes`]), the reports
/// ([`REPORTS_LEN`]).
pub fn ground_bytes(node: Node) -> usize {
    4 + tc_bytes(node) + REPORTS_LEN
}

/// The mailboxes of `node`'s image: `GROUND` ([`ground_bytes`]), [`NODE_MAILBOXES`], and for
/// the attitude node [`TILE_MAILBOXES`].
pub fn mailboxes(node: Node) -> Vec<(&'static str, usize)> {
    let mut all = vec![("GROUND", ground_bytes(node))];
    all.extend(NODE_MAILBOXES);
    if node == Node::Attitude {
        all.extend(TILE_MAILBOXES);
    }
    all
}

/// The image's stack paint pattern (`firmware/src/rt.rs`).
const STACK_PAINT: u16 = 0xA55A;

/// Why a processor-in-the-loop run could not be made (a difference between image and host is
/// not an error: it is the run's result, [`Mismatch`]).
#[derive(Debug)]
pub enum PilError {
    /// The image or the scenario cannot be flown (missing file or symbol, wrong layout,
    /// a scenario that is not the flight configuration's).
    Input(String),
    /// The simulator process failed.
    Mspdebug(MspdebugError),
    /// The image did something the protocol does not expect (halted, stopped elsewhere,
    /// left a command untaken).
    Image(String),
    /// The host simulator failed.
    Sim(SimError),
    /// A step's readings do not fit the mailboxes.
    Record(bus::RecordError),
}

impl std::fmt::Display for PilError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Input(m) => f.write_str(m),
            Self::Mspdebug(e) => write!(f, "{e}"),
            Self::Image(m) => write!(f, "flight image: {m}"),
            Self::Sim(e) => write!(f, "simulator: {e}"),
            Self::Record(e) => write!(f, "{e}"),
        }
    }
}

impl From<MspdebugError> for PilError {
    fn from(e: MspdebugError) -> Self {
        Self::Mspdebug(e)
    }
}

impl From<SimError> for PilError {
    fn from(e: SimError) -> Self {
        Self::Sim(e)
    }
}

/// The addresses the host needs, from a node image's symbol table.
#[derive(Clone, Debug)]
pub struct ImageMap {
    /// The node whose image this is.
    pub node: Node,
    mailboxes: Vec<(&'static str, u32)>,
    period_start: u32,
    halt: u32,
    /// The reset handler (`Reset`), where a watchdog reset enters.
    reset: Option<u32>,
    take_telecommand: u32,
    /// `fw_downlink`, where the image hands each telemetry packet to the ground link.
    downlink: u32,
    /// `__ebss` and `_stack_top`: the painted stack area.
    stack: Option<(u32, u32)>,
    /// `__sdata` (or `__sbss`) and `_stack_top`: the RAM a power-on reset clears.
    ram: Option<(u32, u32)>,
    /// The resets count (`BOOTS`, `acs_firmware::boot_count`: a count and its complement), if
    /// the image keeps one (the attitude image).
    boots: Option<u32>,
    /// Flash bytes of the image.
    pub flash_bytes: u32,
}

impl ImageMap {
    /// The map of `elf`, `node`'s image, checking that every mailbox of the node
    /// ([`mailboxes`]) is there with the host's size.
    pub fn of(elf: &Elf, node: Node) -> Result<Self, PilError> {
        if elf.machine != EM_MSP430 {
            return Err(PilError::Input(format!(
                "not an MSP430 image (e_machine {})",
                elf.machine
            )));
        }
        let mut found = Vec::new();
        for (name, size) in mailboxes(node) {
            let s = elf.symbol(name).ok_or_else(|| {
                PilError::Input(format!(
                    "the image has no mailbox `{name}` (not the {} node's image?)",
                    node.name()
                ))
            })?;
            if s.size != 0 && s.size as usize != size {
                return Err(PilError::Input(format!(
                    "mailbox `{name}` is {} B in the image, {size} B on the host",
                    s.size
                )));
            }
            found.push((name, s.addr));
        }
        let function = |name: &str| {
            elf.symbol(name)
                .map(|s| s.addr)
                .ok_or_else(|| PilError::Input(format!("the image has no function `{name}`")))
        };
        let take_telecommand = elf
            .rust_function(&["acs_firmware", "flight", "take_telecommand"])
            .ok_or_else(|| {
                PilError::Input(
                    "the image has no (single) `acs_firmware::flight::take_telecommand`".into(),
                )
            })?;
        let (period_start, halt, downlink) = (
            function("fw_period_start")?,
            function("fw_halt")?,
            function("fw_downlink")?,
        );
        if downlink == period_start || downlink == halt {
            return Err(PilError::Input(
                "`fw_downlink` shares its address with `fw_period_start` or `fw_halt` (folded \
                 by the linker)"
                    .into(),
            ));
        }
        let top = elf.symbol("_stack_top");
        let stack = elf.symbol("__ebss").zip(top).map(|(b, t)| (b.addr, t.addr));
        let ram = elf
            .symbol("__sdata")
            .or_else(|| elf.symbol("__sbss"))
            .zip(top)
            .map(|(b, t)| (b.addr, t.addr));
        Ok(Self {
            node,
            mailboxes: found,
            period_start,
            halt,
            reset: elf.symbol("Reset").map(|s| s.addr),
            take_telecommand: take_telecommand.addr,
            downlink,
            stack,
            ram,
            boots: elf.symbol("BOOTS").map(|s| s.addr),
            flash_bytes: elf.flash_bytes(),
        })
    }

    /// The address of mailbox `name`.
    pub fn mailbox(&self, name: &str) -> Option<u32> {
        self.mailboxes
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, a)| *a)
    }
}

/// What one control period of a node produced, on either side.
#[derive(Clone, Debug, PartialEq)]
pub struct StepOutputs {
    /// The command mailboxes after the step (the attitude node's; all zero for the reference
    /// node, which commands no actuator).
    pub commands: Commands,
    /// The packet the node sent (`LINK_TX`; the reference node's REF, the attitude node's
    /// STATUS), as the link carries it.
    pub packet: Vec<u8>,
    /// `STEP_MODE` code.
    pub mode: u16,
    /// `STEP_FAULTS` bits.
    pub faults: u16,
    /// The verification reports of each telecommand of the period (`GROUND`'s reports).
    pub reports: Vec<Vec<u8>>,
    /// The telemetry packets the node sent after its step (`fw_downlink`): its events, then
    /// its housekeeping report when due ([`crate::telemetry::Downlink`]).
    pub telemetry: Vec<Vec<u8>>,
}

/// The longest telemetry packet a node sends (the attitude node's housekeeping report): a
/// longer one is an image fault.
pub const MAX_DOWNLINK_BYTES: usize = 256;

/// One difference between the image's and the host's outputs of a step.
#[derive(Clone, Debug, PartialEq)]
pub enum Difference {
    /// A wheel momentum command, kg·m²/s.
    Wheel {
        /// Tile.
        tile: usize,
        /// Host value.
        host: f32,
        /// Image value.
        target: f32,
    },
    /// A coil dipole command, A·m².
    Dipole {
        /// Coil.
        coil: usize,
        /// Host value.
        host: f32,
        /// Image value.
        target: f32,
    },
    /// The mode after the step.
    Mode {
        /// Host code.
        host: u16,
        /// Image code.
        target: u16,
    },
    /// The fault bits of the step.
    Faults {
        /// Host bits.
        host: u16,
        /// Image bits.
        target: u16,
    },
    /// The packet the node sent: its length and its first differing byte.
    Packet {
        /// `REF` or `STATUS`.
        name: &'static str,
        /// Host bytes.
        host: Vec<u8>,
        /// Image bytes.
        target: Vec<u8>,
    },
    /// The verification reports of a telecommand.
    Reports {
        /// Its command code.
        kind: u16,
        /// Host bytes.
        host: Vec<u8>,
        /// Image bytes.
        target: Vec<u8>,
    },
    /// The telemetry packets after the step (events, housekeeping), back to back.
    Telemetry {
        /// Host bytes.
        host: Vec<u8>,
        /// Image bytes.
        target: Vec<u8>,
    },
}

impl std::fmt::Display for Difference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let value = |x: &f32| format!("{x:.9e} (0x{:08x})", x.to_bits());
        match self {
            Self::Wheel { tile, host, target } => write!(
                f,
                "wheel {tile} momentum, kg·m²/s: host {}, target {}",
                value(host),
                value(target)
            ),
            Self::Dipole { coil, host, target } => write!(
                f,
                "coil {coil} dipole, A·m²: host {}, target {}",
                value(host),
                value(target)
            ),
            Self::Mode { host, target } => write!(
                f,
                "mode: host {}, target {}",
                mode_name(*host),
                mode_name(*target)
            ),
            Self::Faults { host, target } => {
                write!(f, "fault bits: host 0x{host:02x}, target 0x{target:02x}")
            }
            Self::Packet { name, host, target } => {
                let at = host
                    .iter()
                    .zip(target)
                    .position(|(a, b)| a != b)
                    .unwrap_or(host.len().min(target.len()));
                let byte = |p: &[u8]| {
                    p.get(at)
                        .map_or_else(|| "(none)".to_string(), |b| format!("0x{b:02x}"))
                };
                write!(
                    f,
                    "{name} packet: host {} B, target {} B, first difference at byte {at}: host {}, target {}",
                    host.len(),
                    target.len(),
                    byte(host),
                    byte(target)
                )
            }
            Self::Reports { kind, host, target } => write!(
                f,
                "telecommand {kind}: host reports {}, target reports {}",
                hex(host),
                hex(target)
            ),
            Self::Telemetry { host, target } => {
                write!(f, "telemetry: host {}, target {}", hex(host), hex(target))
            }
        }
    }
}

/// Bytes as hex, for a mismatch's message.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// The differences between the host's and the image's outputs of one step of `node` (empty:
/// identical bit for bit). `kinds`: the command codes of the node's telecommands of the
/// period.
pub fn compare(
    node: Node,
    host: &StepOutputs,
    target: &StepOutputs,
    kinds: &[u16],
) -> Vec<Difference> {
    let mut out = Vec::new();
    let pairs = |a: &[f32], b: &[f32]| -> Vec<(usize, f32, f32)> {
        a.iter()
            .zip(b)
            .enumerate()
            .filter(|(_, (x, y))| x.to_bits() != y.to_bits())
            .map(|(i, (x, y))| (i, *x, *y))
            .collect()
    };
    for (tile, host, target) in pairs(&host.commands.wheel_nms, &target.commands.wheel_nms) {
        out.push(Difference::Wheel { tile, host, target });
    }
    for (coil, host, target) in pairs(&host.commands.dipole_am2, &target.commands.dipole_am2) {
        out.push(Difference::Dipole { coil, host, target });
    }
    if host.packet != target.packet {
        out.push(Difference::Packet {
            name: match node {
                Node::Reference => "REF",
                Node::Attitude => "STATUS",
            },
            host: host.packet.clone(),
            target: target.packet.clone(),
        });
    }
    if host.mode != target.mode {
        out.push(Difference::Mode {
            host: host.mode,
            target: target.mode,
        });
    }
    if host.faults != target.faults {
        out.push(Difference::Faults {
            host: host.faults,
            target: target.faults,
        });
    }
    for (i, kind) in kinds.iter().enumerate() {
        let h = host.reports.get(i).cloned().unwrap_or_default();
        let t = target.reports.get(i).cloned().unwrap_or_default();
        if h != t {
            out.push(Difference::Reports {
                kind: *kind,
                host: h,
                target: t,
            });
        }
    }
    if host.telemetry != target.telemetry {
        out.push(Difference::Telemetry {
            host: host.telemetry.concat(),
            target: target.telemetry.concat(),
        });
    }
    out
}

/// The first step at which an image and the host differ.
#[derive(Clone, Debug, PartialEq)]
pub struct Mismatch {
    /// The node whose image differs.
    pub node: Node,
    /// Step index (0 first).
    pub step: usize,
    /// Time since the start, s.
    pub t_s: f64,
    /// The host's mode code after the step.
    pub host_mode: u16,
    /// The attitude image's mode code after the step (after the step before, for a
    /// difference of the reference image, which runs first).
    pub target_mode: u16,
    /// Every difference of the step.
    pub differences: Vec<Difference>,
}

impl std::fmt::Display for Mismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "step {} (t = {:.3} s), {} node, mode {} on the host, {} on the target:",
            self.step,
            self.t_s,
            self.node.name(),
            mode_name(self.host_mode),
            mode_name(self.target_mode)
        )?;
        for d in &self.differences {
            write!(f, "\n  {d}")?;
        }
        Ok(())
    }
}

/// The figures of one node image over a run.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeFigures {
    /// The node.
    pub node: Node,
    /// Largest MCLK cycles of one control period.
    pub cycles_max: u64,
    /// Mean MCLK cycles of one control period (rounded).
    pub cycles_mean: u64,
    /// Per mode of the satellite (the attitude node's after the step): (mode name, steps, max
    /// cycles, mean cycles).
    pub cycles_by_mode: Vec<(&'static str, usize, u64, u64)>,
    /// Stack high-water mark of the run, bytes (painted words left; the reference image's
    /// largest over its two lives, before and after its reset), if the image has the paint
    /// symbols.
    pub stack_bytes: Option<u32>,
    /// Flash bytes of the image.
    pub flash_bytes: u32,
    /// MCLK cycles from a forced halt (`fw_halt`) after the run to the image's next period
    /// start, through the watchdog's reset (`None`: not tried, the run stopped on a mismatch).
    pub watchdog_recovery_cycles: Option<u64>,
}

/// What the link-fault case did (`pil.json`'s `link_fault`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LinkFaultFigures {
    /// Packets dropped, both directions.
    pub dropped: usize,
    /// Packets delivered with a byte flipped, both directions.
    pub corrupted: usize,
    /// Steps of the case in which the attitude node flew without a usable REF
    /// ([`crate::attitude_node::Faults::link`]).
    pub steps_without_reference: usize,
    /// Periods from the reference image's reset to its first REF with a valid clock again
    /// (`None`: not back by the end of the case).
    pub clock_back_after_steps: Option<usize>,
}

/// The result of a run: `target/msp430/pil.json`.
#[derive(Clone, Debug, PartialEq)]
pub struct PilSummary {
    /// Scenario name.
    pub scenario: String,
    /// Steps of the scenario flown (up to and including a mismatching one).
    pub steps: usize,
    /// Steps of the link-fault case flown after the scenario ([`LINK_FAULT_STEPS`] with the
    /// link damaged, then the reference image's reset and [`RECOVERY_STEPS`]).
    pub link_fault_steps: usize,
    /// Steps whose outputs differ (0 or 1: the first stops the run).
    pub mismatches: usize,
    /// Largest MCLK cycles of one control period of the attitude image (which flies the
    /// control period), over every step flown.
    pub cycles_max: u64,
    /// Mean MCLK cycles of one control period of the attitude image (rounded).
    pub cycles_mean: u64,
    /// The attitude image's per mode (after the step): (mode name, steps, max cycles, mean
    /// cycles).
    pub cycles_by_mode: Vec<(&'static str, usize, u64, u64)>,
    /// The attitude image's stack high-water mark, bytes.
    pub stack_bytes: Option<u32>,
    /// Flash bytes of the attitude image.
    pub flash_bytes: u32,
    /// The attitude image's watchdog recovery, MCLK cycles ([`NodeFigures`]).
    pub watchdog_recovery_cycles: Option<u64>,
    /// Each node's figures, in [`Node::ALL`]'s order.
    pub nodes: Vec<NodeFigures>,
    /// What the link-fault case did.
    pub link_fault: LinkFaultFigures,
}

fn json_option<T: ToString>(v: Option<T>) -> String {
    v.map_or_else(|| "null".to_string(), |x| x.to_string())
}

fn json_by_mode(by_mode: &[(&'static str, usize, u64, u64)]) -> String {
    let modes: Vec<String> = by_mode
        .iter()
        .map(|(m, n, max, mean)| {
            format!(r#""{m}": {{"steps": {n}, "cycles_max": {max}, "cycles_mean": {mean}}}"#)
        })
        .collect();
    format!("{{{}}}", modes.join(", "))
}

impl PilSummary {
    /// The summary as `pil.json`, its keys in the order of the contract (`scenario`, `steps`,
    /// `mismatches`, `cycles_max`, `cycles_mean`), then `cycles_by_mode`, `stack_bytes`,
    /// `flash_bytes`, `watchdog_recovery_cycles` (these six the attitude image's), `nodes`,
    /// `link_fault_steps`, `node_cycles` (per node: `max`, `mean`, `by_mode`,
    /// `stack_bytes`, `flash_bytes`, `watchdog_recovery_cycles`) and `link_fault`
    /// ([`LinkFaultFigures`]: `dropped`, `corrupted`, `steps_without_reference`,
    /// `clock_back_after_steps`).
    pub fn to_json(&self) -> String {
        let name = serde_json::to_string(&self.scenario).unwrap_or_else(|_| "\"\"".into());
        let names: Vec<String> = self
            .nodes
            .iter()
            .map(|n| format!("\"{}\"", n.node.name()))
            .collect();
        let per_node: Vec<String> = self
            .nodes
            .iter()
            .map(|n| {
                format!(
                    "    \"{}\": {{\"max\": {}, \"mean\": {}, \"by_mode\": {}, \"stack_bytes\": {}, \"flash_bytes\": {}, \"watchdog_recovery_cycles\": {}}}",
                    n.node.name(),
                    n.cycles_max,
                    n.cycles_mean,
                    json_by_mode(&n.cycles_by_mode),
                    json_option(n.stack_bytes),
                    n.flash_bytes,
                    json_option(n.watchdog_recovery_cycles)
                )
            })
            .collect();
        format!(
            "{{\n  \"scenario\": {name},\n  \"steps\": {},\n  \"mismatches\": {},\n  \"cycles_max\": {},\n  \"cycles_mean\": {},\n  \"cycles_by_mode\": {},\n  \"stack_bytes\": {},\n  \"flash_bytes\": {},\n  \"watchdog_recovery_cycles\": {},\n  \"nodes\": [{}],\n  \"link_fault_steps\": {},\n  \"node_cycles\": {{\n{}\n  }},\n  \"link_fault\": {{\"dropped\": {}, \"corrupted\": {}, \"steps_without_reference\": {}, \"clock_back_after_steps\": {}}}\n}}\n",
            self.steps,
            self.mismatches,
            self.cycles_max,
            self.cycles_mean,
            json_by_mode(&self.cycles_by_mode),
            json_option(self.stack_bytes),
            self.flash_bytes,
            json_option(self.watchdog_recovery_cycles),
            names.join(", "),
            self.link_fault_steps,
            per_node.join(",\n"),
            self.link_fault.dropped,
            self.link_fault.corrupted,
            self.link_fault.steps_without_reference,
            json_option(self.link_fault.clock_back_after_steps)
        )
    }
}

/// How to reach the images.
#[derive(Clone, Debug)]
pub struct PilOptions {
    /// The reference node's flight image (ELF, `acs-reference`).
    pub elf_reference: PathBuf,
    /// The attitude node's flight image (ELF, `acs-attitude`).
    pub elf_attitude: PathBuf,
    /// The `mspdebug` program.
    pub mspdebug: String,
    /// Time allowed for one simulator command (a control period), s.
    pub timeout_s: u64,
    /// Fly the link-fault case after the scenario (see the [module docs](self)).
    pub link_faults: bool,
    /// A rehearsal's telecommand script ([`super::rehearsal`]): its packets are flown as the
    /// schedule says, and the PIL's own test telecommands (the non-finite ones,
    /// [`non_finite_uplinks`]) are left out. `None`: the PIL's own run.
    pub script: Option<Vec<ScriptPacket>>,
}

impl PilOptions {
    /// The image of `node`.
    pub fn elf(&self, node: Node) -> &Path {
        match node {
            Node::Reference => &self.elf_reference,
            Node::Attitude => &self.elf_attitude,
        }
    }
}

impl Default for PilOptions {
    fn default() -> Self {
        Self {
            elf_reference: PathBuf::from("firmware/target/msp430-none-elf/release/acs-reference"),
            elf_attitude: PathBuf::from("firmware/target/msp430-none-elf/attitude/acs-attitude"),
            mspdebug: "mspdebug".into(),
            timeout_s: 60,
            link_faults: true,
            script: None,
        }
    }
}

/// The watchdog's interval in mspdebug's simulator, MCLK cycles: 32 768 ACLK counts, its ACLK
/// being MCLK/256 (`firmware/src/rt.rs`, `WDT_KICK`).
pub const WATCHDOG_CYCLES: u64 = 32_768 * 256;

/// The `WDTCTL` word the image starts and kicks its watchdog with (`firmware/src/rt.rs`).
pub const WDT_KICK: u16 = 0x5A0C;

/// `WDTCTL`'s address.
const WDTCTL: u32 = 0x0120;

/// A node image in its simulator, stopped at a `fw_period_start`.
///
/// The run is made without mspdebug's watchdog device: its WDT+ (0.22, `simio/simio_wdt.c`)
/// never restarts its count on a kick (it masks `WDTCNTCL` off the written word before testing
/// it), so it would reset any image after 8.4 M cycles however often it is kicked. What the run
/// checks instead is the word the image last wrote to `WDTCTL` ([`Target::watchdog_word`]),
/// and, with the device added, that a halt is followed by a reset and a new start-up
/// ([`Target::halt_and_recover`]).
pub struct Target {
    dbg: Mspdebug,
    map: ImageMap,
    /// The break point at `fw_halt`.
    halt_break: u32,
    /// MCLK count at the current `fw_period_start` stop.
    cycles: u64,
    /// The stack high-water mark of the image's lives before its last power-on reset.
    stack_before_reset: Option<u32>,
    /// The telemetry packets the image handed to `fw_downlink` since the last period's
    /// outputs were taken.
    downlinked: Vec<Vec<u8>>,
}

impl Target {
    /// Loads `node`'s image of `options` into a new simulator and runs it to the first
    /// `fw_period_start`.
    pub fn start(options: &PilOptions, node: Node) -> Result<Self, PilError> {
        let elf_path = options.elf(node);
        let data = std::fs::read(elf_path).map_err(|e| {
            PilError::Input(format!(
                "{}: {e} (build it: cd firmware && cargo build --release --bin acs-{} \
                 --features fg4619-map)",
                elf_path.display(),
                node.name()
            ))
        })?;
        let elf = Elf::parse(&data)
            .map_err(|e| PilError::Input(format!("{}: {e}", elf_path.display())))?;
        let map = ImageMap::of(&elf, node)
            .map_err(|e| PilError::Input(format!("{}: {e}", elf_path.display())))?;
        let path = elf_path
            .canonicalize()
            .unwrap_or_else(|_| elf_path.to_path_buf());
        let mut dbg = Mspdebug::start(
            &options.mspdebug,
            Duration::from_secs(options.timeout_s.max(1)),
        )?;
        dbg.command(&format!("prog {}", path.display()))?;
        dbg.command("simio add tracer t")?;
        dbg.command("simio add hwmult m")?;
        dbg.set_break(map.period_start)?;
        let halt_break = dbg.set_break(map.halt)?;
        dbg.set_break(map.downlink)?;
        let mut target = Self {
            dbg,
            map,
            halt_break,
            cycles: 0,
            stack_before_reset: None,
            downlinked: Vec::new(),
        };
        target.run_to_period_start("at start-up")?;
        Ok(target)
    }

    /// The image's map.
    pub fn map(&self) -> &ImageMap {
        &self.map
    }

    fn addr(&self, name: &str) -> Result<u32, PilError> {
        self.map
            .mailbox(name)
            .ok_or_else(|| PilError::Input(format!("no mailbox `{name}`")))
    }

    fn stopped_at(&self, pc: u16, expected: u32, what: &str) -> Result<(), PilError> {
        let node = self.map.node.name();
        if u32::from(pc) == expected {
            Ok(())
        } else if u32::from(pc) == self.map.halt {
            Err(PilError::Image(format!("{node}: halted (fw_halt) {what}")))
        } else {
            Err(PilError::Image(format!(
                "{node}: stopped at 0x{pc:04x} instead of 0x{expected:04x} {what}"
            )))
        }
    }

    /// Runs to the next `fw_period_start`, taking each telemetry packet on the way (at
    /// `fw_downlink`'s entry: its address in R12, its length in R13).
    fn run_to_period_start(&mut self, what: &str) -> Result<(), PilError> {
        let mut regs = self.dbg.run()?;
        while u32::from(regs[0]) == self.map.downlink {
            let (at, len) = (u32::from(regs[12]), usize::from(regs[13]));
            if len > MAX_DOWNLINK_BYTES {
                return Err(PilError::Image(format!(
                    "{}: a telemetry packet of {len} B",
                    self.map.node.name()
                )));
            }
            let packet = if len == 0 {
                Vec::new()
            } else {
                self.dbg.read(at, len)?
            };
            self.downlinked.push(packet);
            regs = self.dbg.run()?;
        }
        self.stopped_at(regs[0], self.map.period_start, what)?;
        self.cycles = self.dbg.cycles()?;
        Ok(())
    }

    /// The word the image last wrote to `WDTCTL` (plain memory without the watchdog device).
    pub fn watchdog_word(&mut self) -> Result<u16, PilError> {
        let b = self.dbg.read(WDTCTL, 2)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    /// A power-on reset: the CPU reset (`reset`), the RAM cleared to zero (`fill`: the image's
    /// RAM from `__sdata` to `_stack_top`), and the image run through its start-up to its first
    /// period start. The stack high-water mark of the life before is kept
    /// ([`Target::stack_high_water`] reports the larger).
    pub fn power_on_reset(&mut self) -> Result<(), PilError> {
        let (bottom, top) = self
            .map
            .ram
            .ok_or_else(|| PilError::Input("the image has no `__sdata`/`_stack_top`".into()))?;
        let before = self.stack_high_water()?;
        self.stack_before_reset = before;
        self.dbg.command("reset")?;
        self.dbg.command(&format!(
            "fill 0x{bottom:04x} 0x{:x} 00",
            top.saturating_sub(bottom)
        ))?;
        self.run_to_period_start("after a power-on reset")
    }

    /// The fatal-error path, tried: adds the watchdog device, runs one period (the image's
    /// kicks set the device as the image runs it, [`WDT_KICK`]), sends the image to `fw_halt`
    /// (interrupts off, no more steps, no more kicks) and runs it: the watchdog must reset it
    /// (the reset handler entered within [`WATCHDOG_CYCLES`]) and the image start again, up to
    /// its first period start. The MCLK cycles from the halt to that period start. An image that
    /// counts its resets (`BOOTS`) must count this one: one more than before the halt, with its
    /// complement.
    pub fn halt_and_recover(&mut self) -> Result<u64, PilError> {
        let reset = self
            .map
            .reset
            .ok_or_else(|| PilError::Input("the image has no `Reset` handler symbol".into()))?;
        self.dbg.command("simio add wdt w")?;
        self.run_to_period_start("with the watchdog device")?;
        let boots_before = self.boots()?;
        self.dbg.delete_break(self.halt_break)?;
        let reset_break = self.dbg.set_break(reset)?;
        let mut regs = self.dbg.registers()?;
        regs[0] = self.map.halt as u16;
        self.dbg.set_registers(&regs)?;
        let halted = self.dbg.cycles()?;
        let at = self.dbg.run()?;
        self.stopped_at(at[0], reset, "after a halt (the watchdog's reset)")?;
        let to_reset = self.dbg.cycles()?.saturating_sub(halted);
        self.dbg.delete_break(reset_break)?;
        self.halt_break = self.dbg.set_break(self.map.halt)?;
        if to_reset > WATCHDOG_CYCLES {
            return Err(PilError::Image(format!(
                "{}: the watchdog reset the halted image after {to_reset} cycles, more than \
                 its interval ({WATCHDOG_CYCLES})",
                self.map.node.name()
            )));
        }
        self.run_to_period_start("after the watchdog's reset")?;
        if let Some((count, check)) = boots_before {
            let after = self.boots()?;
            let next = count.wrapping_add(1);
            if check != !count || after != Some((next, !next)) {
                return Err(PilError::Image(format!(
                    "{}: resets counted ({count}, {check:#06x}) before the watchdog's reset, \
                     {after:?} after it",
                    self.map.node.name()
                )));
            }
        }
        self.dbg.command("simio del w")?;
        Ok(self.cycles.saturating_sub(halted))
    }

    /// Writes `packet` to the `GROUND` mailbox's telecommand, then its length.
    fn write_telecommand(&mut self, packet: &[u8]) -> Result<(), PilError> {
        let ground = self.addr("GROUND")?;
        if packet.len() > tc_bytes(self.map.node) {
            return Err(PilError::Input(format!(
                "a telecommand of {} B does not fit the {} node's mailbox",
                packet.len(),
                self.map.node.name()
            )));
        }
        self.dbg.write(ground + 4, packet)?;
        self.dbg
            .write(ground, &(packet.len() as u16).to_le_bytes())?;
        Ok(())
    }

    /// The image's resets count and its complement (`BOOTS`), if it keeps one.
    fn boots(&mut self) -> Result<Option<(u16, u16)>, PilError> {
        let Some(addr) = self.map.boots else {
            return Ok(None);
        };
        let b = self.dbg.read(addr, 4)?;
        Ok(Some((
            u16::from_le_bytes([b[0], b[1]]),
            u16::from_le_bytes([b[2], b[3]]),
        )))
    }

    fn read_u16(&mut self, name: &str) -> Result<u16, PilError> {
        let b = self.dbg.read(self.addr(name)?, 2)?;
        Ok(u16::from_le_bytes([b[0], b[1]]))
    }

    /// The verification reports of a telecommand (command code `kind`), checking that the
    /// image took it.
    fn taken_reports(&mut self, kind: u16) -> Result<Vec<u8>, PilError> {
        let ground = self.addr("GROUND")?;
        let b = self.dbg.read(ground, 4)?;
        let (pending, len) = (
            u16::from_le_bytes([b[0], b[1]]),
            usize::from(u16::from_le_bytes([b[2], b[3]])),
        );
        if pending != 0 || len > REPORTS_LEN {
            return Err(PilError::Image(format!(
                "{}: telecommand {kind} was not taken (length {pending}), or its reports are \
                 {len} B",
                self.map.node.name()
            )));
        }
        let at = ground + 4 + tc_bytes(self.map.node) as u32;
        Ok(if len == 0 {
            Vec::new()
        } else {
            self.dbg.read(at, len)?
        })
    }

    /// One control period: writes `readings` (the attitude image's tile mailboxes), the packet
    /// `received` (if any) into `LINK_RX` and the `telecommands` (command code, packet) into
    /// `GROUND` one after the other ([module docs](self)), runs to the
    /// next `fw_period_start`; the outputs (the packet taken from `LINK_TX`, which is then
    /// emptied) and the period's cycles.
    pub fn period(
        &mut self,
        readings: Option<&Readings>,
        received: Option<&[u8]>,
        telecommands: &[(u16, Vec<u8>)],
    ) -> Result<(StepOutputs, u64), PilError> {
        if let Some(readings) = readings {
            for (name, bytes) in readings.mailboxes() {
                let addr = self.addr(name)?;
                self.dbg.write(addr, &bytes)?;
            }
        }
        if let Some(packet) = received {
            if packet.len() > LINK_BYTES {
                return Err(PilError::Input(format!(
                    "a packet of {} B does not fit the link mailbox",
                    packet.len()
                )));
            }
            self.dbg.write(self.addr("LINK_RX")?, packet)?;
            self.dbg.write(
                self.addr("LINK_RX_LEN")?,
                &(packet.len() as u16).to_le_bytes(),
            )?;
        }
        let start = self.cycles;
        let mut extra = 0u64;
        let mut reports = Vec::with_capacity(telecommands.len());
        if let Some((_, packet)) = telecommands.first() {
            self.write_telecommand(packet)?;
        }
        if telecommands.len() > 1 {
            // stop at take_telecommand's entry: its registers make the call again
            let entry = self.dbg.set_break(self.map.take_telecommand)?;
            let regs: Registers = self.dbg.run()?;
            self.stopped_at(
                regs[0],
                self.map.take_telecommand,
                "before take_telecommand",
            )?;
            self.dbg.delete_break(entry)?;
            let ret = self.dbg.read(u32::from(regs[1]), 2)?;
            let ret = u32::from(u16::from_le_bytes([ret[0], ret[1]]));
            let back = self.dbg.set_break(ret)?;
            let after = self.dbg.run()?;
            self.stopped_at(after[0], ret, "after take_telecommand")?;
            for (k, (_, packet)) in telecommands.iter().enumerate().skip(1) {
                reports.push(self.taken_reports(telecommands[k - 1].0)?);
                self.write_telecommand(packet)?;
                self.dbg.set_registers(&regs)?;
                let c0 = self.dbg.cycles()?;
                let after = self.dbg.run()?;
                self.stopped_at(after[0], ret, "after take_telecommand")?;
                extra += self.dbg.cycles()?.saturating_sub(c0);
            }
            self.dbg.delete_break(back)?;
        }
        self.run_to_period_start("after a step")?;
        if let Some((kind, _)) = telecommands.last() {
            reports.push(self.taken_reports(*kind)?);
        }
        if self.read_u16("LINK_RX_LEN")? != 0 {
            return Err(PilError::Image(format!(
                "{}: the packet in LINK_RX was not taken",
                self.map.node.name()
            )));
        }
        let commands = if self.map.node == Node::Attitude {
            let wheel = self.dbg.read(self.addr("CMD_WHEEL_NMS")?, 4 * TILES)?;
            let dipole = self.dbg.read(self.addr("CMD_DIPOLE_AM2")?, 4 * COILS)?;
            Commands::from_le_bytes(&wheel, &dipole)
                .ok_or_else(|| PilError::Image("command mailboxes unreadable".into()))?
        } else {
            Commands::default()
        };
        let len = usize::from(self.read_u16("LINK_TX_LEN")?);
        let packet = if len == 0 {
            Vec::new()
        } else if len > LINK_BYTES {
            return Err(PilError::Image(format!(
                "{}: LINK_TX_LEN {len} is longer than the mailbox",
                self.map.node.name()
            )));
        } else {
            self.dbg.read(self.addr("LINK_TX")?, len)?
        };
        self.dbg.write(self.addr("LINK_TX_LEN")?, &[0, 0])?;
        let outputs = StepOutputs {
            commands,
            packet,
            mode: self.read_u16("STEP_MODE")?,
            faults: self.read_u16("STEP_FAULTS")?,
            reports,
            telemetry: std::mem::take(&mut self.downlinked),
        };
        let cycles = self.cycles.saturating_sub(start).saturating_sub(extra);
        Ok((outputs, cycles))
    }

    /// The stack high-water mark so far, bytes: the part of `__ebss.._stack_top` no longer
    /// painted (the larger of this life's and the one before the last power-on reset).
    pub fn stack_high_water(&mut self) -> Result<Option<u32>, PilError> {
        let Some((bottom, top)) = self.map.stack else {
            return Ok(None);
        };
        let len = top.saturating_sub(bottom) as usize;
        let bytes = self.dbg.read(bottom, len)?;
        let painted = bytes
            .chunks_exact(2)
            .take_while(|w| u16::from_le_bytes([w[0], w[1]]) == STACK_PAINT)
            .count() as u32;
        let now = top - bottom - 2 * painted;
        Ok(Some(self.stack_before_reset.map_or(now, |b| b.max(now))))
    }
}

/// One step flown: (step, the attitude image's mode code after it, the attitude image's
/// cycles, the reference image's cycles for the REF of the step).
pub type StepLog = (usize, u16, u64, u64);

/// A processor-in-the-loop run.
#[derive(Clone, Debug)]
pub struct PilRun {
    /// The truth and the host composition's report of every step of the scenario flown.
    pub samples: Vec<Sample>,
    /// `pil.json`.
    pub summary: PilSummary,
    /// The first difference, if any.
    pub mismatch: Option<Mismatch>,
    /// Every step flown, the link-fault case's included.
    pub steps: Vec<StepLog>,
    /// Wall-clock steps per second of the run.
    pub steps_per_s: f64,
    /// The packets the images sent in the scenario's steps, back to back: period by period the
    /// verification reports in the order of the schedule ([`Operations`]), then the reference
    /// image's telemetry, then the attitude image's (the link-fault case's are left out).
    pub telemetry: Vec<u8>,
}

/// The periods of the link-fault case with the link damaged (30 s).
pub const LINK_FAULT_STEPS: usize = 30;

/// The periods of the link-fault case after the reference image's reset.
pub const RECOVERY_STEPS: usize = 30;

/// What the link does to a packet in period `i` of the link-fault case (0 first), going
/// `direction`: drops it (`false`) or delivers `bytes`, in some periods with one byte flipped
/// (the receiver's CRC check refuses it; a flipped header byte may be refused before the
/// CRC). Of every five periods in each direction, two drop, two corrupt (a header byte, a
/// payload or CRC byte) and one delivers intact; the directions are offset by one period.
pub fn damage(i: usize, direction: LinkDirection, bytes: &mut [u8]) -> bool {
    let offset = match direction {
        LinkDirection::Reference => 0,
        LinkDirection::Status => 1,
    };
    let n = bytes.len();
    if n == 0 {
        return false;
    }
    match (i + offset) % 5 {
        0 | 3 => false,
        1 => {
            if let Some(b) = bytes.get_mut(i % 6 % n) {
                *b ^= 0x24;
            }
            true
        }
        2 => {
            if let Some(b) = bytes.get_mut((6 + 7 * i) % n) {
                *b ^= 1 << (i % 8);
            }
            true
        }
        _ => true,
    }
}

impl LinkFaultFigures {
    /// Counts a packet `sent` that arrived as `delivered`.
    fn count(&mut self, sent: &[u8], delivered: Option<&[u8]>) {
        match delivered {
            None => self.dropped += 1,
            Some(d) if d != sent => self.corrupted += 1,
            Some(_) => {}
        }
    }
}

/// Flies `scenario` with the two node images of `options` and the host composition in
/// lockstep (see the [module docs](self)); `progress` is called after each step with the step
/// count.
pub fn run(
    scenario: &Scenario,
    options: &PilOptions,
    mut progress: impl FnMut(usize),
) -> Result<PilRun, PilError> {
    if scenario.dt_s != f64::from(CONTROL_PERIOD_S) {
        return Err(PilError::Input(format!(
            "scenario `{}`: control period {} s, the image's is {CONTROL_PERIOD_S} s",
            scenario.name, scenario.dt_s
        )));
    }
    if scenario.sim.tiles.len() != TILES {
        return Err(PilError::Input(format!(
            "scenario `{}`: {} tiles, the image flies {TILES}",
            scenario.name,
            scenario.sim.tiles.len()
        )));
    }
    let tle = crate::tle::Tle::parse(&scenario.sim.tle.0, &scenario.sim.tle.1)
        .map_err(|e| PilError::Input(format!("TLE: {e}")))?;
    let words = Sgp4::new(&tle, scenario.gravity)
        .map_err(|e| PilError::Input(format!("TLE: {e:?}")))?
        .to_words();
    let orbit =
        Sgp4::from_words(&words).map_err(|e| PilError::Input(format!("element words: {e:?}")))?;
    let mut ops = Operations::new(scenario, &words, options.script.as_deref().unwrap_or(&[]))
        .map_err(PilError::Input)?;
    let mut acs = HostLoop::new(&CONFIG, orbit.clone())
        .map_err(|e| PilError::Input(format!("flight configuration: {e}")))?;
    let mut sim = Simulator::new(scenario.sim.clone(), scenario.initial.0, scenario.initial.1)?;
    let mut reference = Target::start(options, Node::Reference)?;
    let mut attitude = Target::start(options, Node::Attitude)?;

    let steps = (scenario.duration_s / scenario.dt_s).round() as usize;
    let fault_steps = if options.link_faults {
        LINK_FAULT_STEPS + RECOVERY_STEPS
    } else {
        0
    };
    let reset_at = steps + LINK_FAULT_STEPS;
    let rehearsal = options.script.is_some();
    let mut mirror = Mirror::default();
    // the reports of the scenario's steps as the images wrote them, in the schedule's order
    let mut telemetry = Vec::new();
    let mut host_commands = Commands::default();
    let mut report = StepReport::empty(acs.mode());
    // the STATUS packet on its way to the reference image, as delivered
    let mut status_in_flight: Option<Vec<u8>> = None;
    let mut samples = Vec::with_capacity(steps);
    let mut log: Vec<StepLog> = Vec::with_capacity(steps + fault_steps);
    let mut mismatch = None;
    let mut link_fault = LinkFaultFigures::default();
    // the attitude image's mode after its last step (a reference node's mismatch names it)
    let mut image_mode = 0u16;
    let started = Instant::now();
    for k in 0..steps + fault_steps {
        let t = sim.truth().t_s;
        let faulty = (steps..reset_at).contains(&k).then(|| k - steps);
        let mut tcs = ops.due(k, t);
        if k == steps * 3 / 4 && !rehearsal {
            // to both nodes, but an element set only to the reference node: its telecommand
            // (247 B) does not fit the attitude node's mailbox
            for u in non_finite_uplinks(&words) {
                tcs.push(ops.telecommand(&u, Node::Reference));
                if !matches!(u, Uplink::Elements(_)) {
                    tcs.push(ops.telecommand(&u, Node::Attitude));
                }
            }
        }
        if k == reset_at {
            // the ground restores the element set; the clock comes back with a STATUS
            tcs.push(ops.telecommand(&Uplink::Elements(Box::new(words)), Node::Reference));
        }
        let of_node = |node: Node| -> Vec<(u16, Vec<u8>)> {
            tcs.iter()
                .filter(|tc| tc.node == node)
                .map(|tc| (tc.kind, tc.packet.clone()))
                .collect()
        };
        let (reference_encoded, attitude_encoded) =
            (of_node(Node::Reference), of_node(Node::Attitude));
        if k == reset_at {
            // a power-on reset of the reference image: the STATUS in flight is lost with its RAM
            reference.power_on_reset()?;
            acs.reset_reference(orbit.clone())
                .map_err(|e| PilError::Input(format!("flight configuration: {e}")))?;
            status_in_flight = None;
            // and so is its count of verification reports
            mirror.reset_reference();
        }
        // the host takes the period's telecommands on the composition's nodes, as the images
        let host_reports = mirror.period(&mut acs, &tcs);
        // what the reference image makes of the STATUS of step k - 1 (counted before its REF)
        let status_received = acs.received()[1];
        let node_reports = |node: Node| -> Vec<Vec<u8>> {
            tcs.iter()
                .zip(&host_reports)
                .filter(|(tc, _)| tc.node == node)
                .map(|(_, r)| r.clone())
                .collect()
        };
        let (reference_reports, attitude_reports) =
            (node_reports(Node::Reference), node_reports(Node::Attitude));
        // the reference image: its telecommands, the STATUS of step k - 1, the REF of step k
        let (reference_out, reference_cycles) =
            reference.period(None, status_in_flight.as_deref(), &reference_encoded)?;
        // the host: the step on the simulator through the recorder
        let mut recorder = Recorder::new(&mut sim, &mut host_commands);
        acs.step_over_link(&mut recorder, CONTROL_PERIOD_S, &mut report, |d, b| {
            faulty.is_none_or(|i| damage(i, d, b))
        });
        let readings = recorder.finish().map_err(PilError::Record)?;
        let [reference_telemetry, attitude_telemetry] =
            mirror.telemetry(&mut acs, &report, status_received, &tcs);
        if k >= steps {
            link_fault.steps_without_reference += usize::from(report.faults.link);
        }
        let (host_ref, host_status) = acs.packets();
        let (host_ref, host_status) = (host_ref.to_vec(), host_status.to_vec());
        if k >= reset_at && link_fault.clock_back_after_steps.is_none() {
            let valid = Reference::from_packet(&host_ref).is_ok_and(|(r, _)| r.clock_valid);
            link_fault.clock_back_after_steps = valid.then_some(k - reset_at);
        }
        let host_reference = StepOutputs {
            commands: Commands::default(),
            mode: 0,
            faults: Reference::from_packet(&host_ref).map_or(u16::MAX, |(r, _)| r.faults),
            packet: host_ref,
            reports: reference_reports,
            telemetry: reference_telemetry,
        };
        let host_attitude = StepOutputs {
            commands: host_commands,
            packet: host_status,
            mode: mode_code(report.mode),
            faults: report.faults.bits(),
            reports: attitude_reports,
            telemetry: attitude_telemetry,
        };
        let kinds = |list: &[(u16, Vec<u8>)]| list.iter().map(|(k, _)| *k).collect::<Vec<u16>>();
        let differences = compare(
            Node::Reference,
            &host_reference,
            &reference_out,
            &kinds(&reference_encoded),
        );
        if !differences.is_empty() {
            log.push((k, host_attitude.mode, 0, reference_cycles));
            progress(k + 1);
            mismatch = Some(Mismatch {
                node: Node::Reference,
                step: k,
                t_s: t,
                host_mode: host_attitude.mode,
                target_mode: image_mode,
                differences,
            });
            break;
        }
        // the attitude image: the readings, its uplinks, the REF of step k as delivered
        let mut delivered = reference_out.packet.clone();
        let delivered = faulty
            .is_none_or(|i| damage(i, LinkDirection::Reference, &mut delivered))
            .then_some(delivered);
        link_fault.count(&reference_out.packet, delivered.as_deref());
        let (image, cycles) =
            attitude.period(Some(&readings), delivered.as_deref(), &attitude_encoded)?;
        image_mode = image.mode;
        log.push((k, image.mode, cycles, reference_cycles));
        let differences = compare(
            Node::Attitude,
            &host_attitude,
            &image,
            &kinds(&attitude_encoded),
        );
        if k < steps {
            // the images' reports, back in the schedule's order
            let (mut r, mut a) = (reference_out.reports.iter(), image.reports.iter());
            for tc in &tcs {
                let next = match tc.node {
                    Node::Reference => r.next(),
                    Node::Attitude => a.next(),
                };
                telemetry.extend_from_slice(next.map_or(&[][..], Vec::as_slice));
            }
            // then the nodes' telemetry of the period, the reference node's first
            for p in reference_out.telemetry.iter().chain(&image.telemetry) {
                telemetry.extend_from_slice(p);
            }
        }
        if k < steps {
            samples.push(Sample::of_step(&sim, t, report, scenario.target));
        }
        progress(k + 1);
        if !differences.is_empty() {
            mismatch = Some(Mismatch {
                node: Node::Attitude,
                step: k,
                t_s: t,
                host_mode: host_attitude.mode,
                target_mode: image.mode,
                differences,
            });
            break;
        }
        let mut delivered = image.packet.clone();
        status_in_flight = faulty
            .is_none_or(|i| damage(i, LinkDirection::Status, &mut delivered))
            .then_some(delivered);
        link_fault.count(&image.packet, status_in_flight.as_deref());
        sim.advance(scenario.dt_s)?;
    }
    let elapsed = started.elapsed().as_secs_f64();
    let mut images = [
        (
            reference.stack_high_water()?,
            reference.map().flash_bytes,
            None,
        ),
        (
            attitude.stack_high_water()?,
            attitude.map().flash_bytes,
            None,
        ),
    ];
    if mismatch.is_none() {
        for (target, figures) in [&mut reference, &mut attitude].into_iter().zip(&mut images) {
            let word = target.watchdog_word()?;
            if word != WDT_KICK {
                return Err(PilError::Image(format!(
                    "{}: WDTCTL holds 0x{word:04x} after the run, not the kick 0x{WDT_KICK:04x}",
                    target.map().node.name()
                )));
            }
            figures.2 = Some(target.halt_and_recover()?);
        }
    }
    let mut summary = summarise(
        scenario.name,
        &log,
        steps,
        usize::from(mismatch.is_some()),
        images,
    );
    summary.link_fault = link_fault;
    Ok(PilRun {
        samples,
        summary,
        mismatch,
        steps_per_s: log.len() as f64 / elapsed.max(1e-9),
        steps: log,
        telemetry,
    })
}

/// Ground commands with non-finite arguments, each of which the reference node must refuse
/// ([`crate::uplink::UplinkError`]; the attitude node refuses them as not its own): tracking
/// and slewing to NaN and infinite quaternions, a slew within a NaN, an infinite and a negative
/// time, and the element set `words` with a NaN in a float word (its check word then fails).
pub fn non_finite_uplinks(words: &[u32; ELEMENT_WORDS]) -> Vec<Uplink> {
    let nan_q = Quaternion {
        q0: f32::NAN,
        q1: 0.0,
        q2: 0.0,
        q3: 1.0,
    };
    let inf_q = Quaternion {
        q0: 1.0,
        q1: f32::INFINITY,
        q2: 0.0,
        q3: 0.0,
    };
    let mut elements = *words;
    if let Some(w) = elements.get_mut(3) {
        *w = f32::NAN.to_bits();
    }
    vec![
        Uplink::Track { target: nan_q },
        Uplink::Track { target: inf_q },
        Uplink::Slew {
            target: nan_q,
            within_s: 100.0,
        },
        Uplink::Slew {
            target: Quaternion::IDENTITY,
            within_s: f32::NAN,
        },
        Uplink::Slew {
            target: Quaternion::IDENTITY,
            within_s: f32::INFINITY,
        },
        Uplink::Slew {
            target: Quaternion::IDENTITY,
            within_s: -f32::INFINITY,
        },
        Uplink::Elements(Box::new(elements)),
    ]
}

/// (steps, max, mean) of some cycle counts.
fn stats(cycles: impl Iterator<Item = u64>) -> (usize, u64, u64) {
    let (n, max, sum) = cycles.fold((0usize, 0u64, 0u128), |(n, m, s), c| {
        (n + 1, m.max(c), s + u128::from(c))
    });
    let mean = if n == 0 {
        0
    } else {
        ((sum + n as u128 / 2) / n as u128) as u64
    };
    (n, max, mean)
}

/// The summary of the steps flown (`log`, of which the first `scenario_steps` are the
/// scenario's and the rest the link-fault case's); `images`: per node in [`Node::ALL`]'s order,
/// (stack high-water mark, flash bytes, watchdog recovery cycles).
pub fn summarise(
    scenario: &str,
    log: &[StepLog],
    scenario_steps: usize,
    mismatches: usize,
    images: [(Option<u32>, u32, Option<u64>); 2],
) -> PilSummary {
    let nodes: Vec<NodeFigures> = Node::ALL
        .iter()
        .zip(images)
        .map(|(&node, (stack_bytes, flash_bytes, watchdog))| {
            let cycles = |s: &StepLog| match node {
                Node::Reference => s.3,
                Node::Attitude => s.2,
            };
            let (_, cycles_max, cycles_mean) = stats(log.iter().map(cycles));
            let cycles_by_mode = (0..4u16)
                .filter_map(|m| {
                    let (n, max, mean) = stats(log.iter().filter(|s| s.1 == m).map(cycles));
                    (n > 0).then_some((mode_name(m), n, max, mean))
                })
                .collect();
            NodeFigures {
                node,
                cycles_max,
                cycles_mean,
                cycles_by_mode,
                stack_bytes,
                flash_bytes,
                watchdog_recovery_cycles: watchdog,
            }
        })
        .collect();
    let attitude = nodes[1].clone();
    PilSummary {
        scenario: scenario.to_string(),
        steps: log.len().min(scenario_steps),
        link_fault_steps: log.len().saturating_sub(scenario_steps),
        mismatches,
        cycles_max: attitude.cycles_max,
        cycles_mean: attitude.cycles_mean,
        cycles_by_mode: attitude.cycles_by_mode,
        stack_bytes: attitude.stack_bytes,
        flash_bytes: attitude.flash_bytes,
        watchdog_recovery_cycles: attitude.watchdog_recovery_cycles,
        nodes,
        link_fault: LinkFaultFigures::default(),
    }
}

/// The per-step log as CSV: `step,mode,cycles,reference_cycles` (`cycles`: the attitude
/// image's).
pub fn steps_csv(log: &[StepLog]) -> String {
    let mut out = String::from("step,mode,cycles,reference_cycles\n");
    for (k, mode, cycles, reference) in log {
        out.push_str(&format!("{k},{},{cycles},{reference}\n", mode_name(*mode)));
    }
    out
}

/// Writes `pil.json` at `path` (its folder created).
pub fn write_summary(path: &Path, summary: &PilSummary) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::write(path, summary.to_json()).map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn outputs() -> StepOutputs {
        StepOutputs {
            commands: Commands {
                wheel_nms: [1e-4, -2e-4, 0.0, 3e-5, 0.0, 0.0],
                dipole_am2: [0.1, 0.0, -0.05],
            },
            packet: vec![0x08, 0x40, 0xc0, 0x00, 0x00, 0x05, 0x11, 0x22],
            mode: 2,
            faults: 0x40,
            reports: vec![
                vec![0x08, 0x50, 0xc0, 0x00],
                vec![0x08, 0x50, 0xc0, 0x01, 0x01],
            ],
            telemetry: vec![vec![0x08, 0x50, 0xc0, 0x02, 0x00]],
        }
    }

    #[test]
    fn identical_outputs_have_no_difference() {
        assert!(compare(Node::Attitude, &outputs(), &outputs(), &[4, 3]).is_empty());
    }

    #[test]
    fn every_difference_is_named_with_both_values() {
        let host = outputs();
        let mut image = outputs();
        image.commands.wheel_nms[1] = f32::from_bits((-2e-4f32).to_bits() + 1);
        image.commands.dipole_am2[2] = 0.05;
        image.packet[6] = 0x10;
        image.mode = 3;
        image.faults = 0x41;
        image.reports[1][4] = 0;
        let d = compare(Node::Attitude, &host, &image, &[4, 3]);
        assert_eq!(d.len(), 6);
        assert_eq!(
            d[0],
            Difference::Wheel {
                tile: 1,
                host: -2e-4,
                target: image.commands.wheel_nms[1]
            }
        );
        let m = Mismatch {
            node: Node::Attitude,
            step: 312,
            t_s: 312.0,
            host_mode: host.mode,
            target_mode: image.mode,
            differences: d,
        };
        let text = m.to_string();
        assert!(text.starts_with(
            "step 312 (t = 312.000 s), attitude node, mode Slew on the host, Tracking on the target:"
        ), "{text}");
        assert!(
            text.contains("wheel 1 momentum, kg·m²/s: host -1.999999949e-4 (0xb951b717), target")
        );
        assert!(text.contains("coil 2 dipole, A·m²: host -5.000000075e-2 (0xbd4ccccd), target 5.000000075e-2 (0x3d4ccccd)"));
        assert!(text.contains(
            "STATUS packet: host 8 B, target 8 B, first difference at byte 6: host 0x11, target 0x10"
        ), "{text}");
        assert!(text.contains("mode: host Slew, target Tracking"));
        assert!(text.contains("fault bits: host 0x40, target 0x41"));
        assert!(
            text.contains("telecommand 3: host reports 0850c00101, target reports 0850c00100"),
            "{text}"
        );
        // -0.0 and 0.0 differ bit for bit
        let mut zero = outputs();
        zero.commands.wheel_nms[2] = -0.0;
        assert_eq!(compare(Node::Attitude, &outputs(), &zero, &[]).len(), 1);
        // a missing packet (a dropped one) differs from any, and the reference node's is REF
        let mut none = outputs();
        none.packet.clear();
        let d = compare(Node::Reference, &outputs(), &none, &[]);
        assert_eq!(d.len(), 1);
        assert!(d[0].to_string().starts_with(
            "REF packet: host 8 B, target 0 B, first difference at byte 0: host 0x08, target (none)"
        ), "{}", d[0]);
    }

    #[test]
    fn summary_counts_cycles_per_node_and_mode_and_writes_the_json_of_the_contract() {
        // (step, mode, attitude cycles, reference cycles); the last two are the link-fault case's
        let log = [
            (0, 0, 900, 3000),
            (1, 3, 400, 2000),
            (2, 3, 501, 2100),
            (3, 2, 700, 4000),
        ];
        let s = summarise(
            "slew",
            &log,
            2,
            0,
            [
                (Some(2700), 38_000, Some(8_000_000)),
                (Some(1800), 35_000, None),
            ],
        );
        assert_eq!(s.steps, 2);
        assert_eq!(s.link_fault_steps, 2);
        assert_eq!(s.cycles_max, 900);
        assert_eq!(s.cycles_mean, 625);
        assert_eq!(
            s.cycles_by_mode,
            vec![
                ("Detumble", 1, 900, 900),
                ("Slew", 1, 700, 700),
                ("Tracking", 2, 501, 451)
            ]
        );
        assert_eq!(s.nodes[0].node, Node::Reference);
        assert_eq!(s.nodes[0].cycles_max, 4000);
        assert_eq!(s.nodes[0].cycles_mean, 2775);
        assert_eq!(s.stack_bytes, Some(1800));
        assert_eq!(s.flash_bytes, 35_000);
        let json = s.to_json();
        assert!(json.starts_with("{\n  \"scenario\": \"slew\",\n  \"steps\": 2,\n  \"mismatches\": 0,\n  \"cycles_max\": 900,\n  \"cycles_mean\": 625,\n"), "{json}");
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(v["cycles_by_mode"]["Tracking"]["cycles_mean"], 451);
        assert_eq!(v["scenario"], "slew");
        assert_eq!(v["steps"], 2);
        assert_eq!(v["mismatches"], 0);
        assert_eq!(v["cycles_max"], 900);
        assert_eq!(v["cycles_mean"], 625);
        assert_eq!(v["stack_bytes"], 1800);
        assert_eq!(v["nodes"], serde_json::json!(["reference", "attitude"]));
        assert_eq!(v["link_fault_steps"], 2);
        let r = &v["node_cycles"]["reference"];
        assert_eq!(r["max"], 4000);
        assert_eq!(r["by_mode"]["Tracking"]["cycles_max"], 2100);
        assert_eq!(r["stack_bytes"], 2700);
        assert_eq!(r["watchdog_recovery_cycles"], 8_000_000);
        assert_eq!(v["node_cycles"]["attitude"]["by_mode"]["Slew"]["steps"], 1);
        assert!(v["node_cycles"]["attitude"]["watchdog_recovery_cycles"].is_null());
        assert_eq!(v["link_fault"]["dropped"], 0);
        assert!(v["link_fault"]["clock_back_after_steps"].is_null());
        assert_eq!(
            steps_csv(&log[..1]),
            "step,mode,cycles,reference_cycles\n0,Detumble,900,3000\n"
        );
    }

    /// The symbols of a node image: its mailboxes, the functions the host stops at.
    fn image_symbols(node: Node) -> Vec<(&'static str, u32, u32)> {
        let mut symbols: Vec<(&str, u32, u32)> = mailboxes(node)
            .iter()
            .enumerate()
            .map(|(i, (n, size))| (*n, 0x1100 + 0x100 * i as u32, *size as u32))
            .collect();
        symbols.push(("fw_period_start", 0x4000, 4));
        symbols.push(("fw_halt", 0x4010, 6));
        symbols.push(("fw_downlink", 0x4020, 6));
        symbols.push((
            "_RINvNtCshTh0V548xLH_12acs_firmware6flight16take_telecommandNtNtCs5YbJjKyC2MG_3acs13attitude_node12AttitudeNodeKj6_NCNvCs5YbJjKyC2MG_12acs_attitude3run0EBZ_",
            0x4100,
            200,
        ));
        symbols
    }

    #[test]
    fn the_image_map_checks_every_mailbox_of_its_node() {
        let mut symbols = image_symbols(Node::Attitude);
        let elf = Elf::parse(&elf::tests::tiny_elf(&symbols, 0)).unwrap();
        let map = ImageMap::of(&elf, Node::Attitude).unwrap();
        assert_eq!(map.mailbox("LINK_RX"), Some(0x1600));
        assert_eq!(map.mailbox("TILE_MAG"), Some(0x1100 + 0x100 * 9));
        assert_eq!(map.take_telecommand, 0x4100);
        assert_eq!(map.downlink, 0x4020);
        // an image whose fw_downlink was folded into fw_period_start is refused
        let mut folded = symbols.clone();
        let d = folded.iter().position(|s| s.0 == "fw_downlink").unwrap();
        folded[d].1 = 0x4000;
        let elf = Elf::parse(&elf::tests::tiny_elf(&folded, 0)).unwrap();
        let e = ImageMap::of(&elf, Node::Attitude).unwrap_err().to_string();
        assert!(e.contains("folded by the linker"), "{e}");
        // each node's image has its own ground mailbox, and only the attitude image has tile
        // mailboxes
        let e = ImageMap::of(&elf, Node::Reference).unwrap_err().to_string();
        assert!(
            e.contains("`GROUND` is 90 B in the image, 302 B on the host"),
            "{e}"
        );
        let reference = image_symbols(Node::Reference);
        let elf = Elf::parse(&elf::tests::tiny_elf(&reference, 0)).unwrap();
        let map = ImageMap::of(&elf, Node::Reference).unwrap();
        assert_eq!(map.mailbox("TILE_SUN"), None);
        let e = ImageMap::of(&elf, Node::Attitude).unwrap_err().to_string();
        assert!(
            e.contains("`GROUND` is 302 B in the image, 90 B on the host"),
            "{e}"
        );
        let mut reference = reference;
        reference[0].2 = ground_bytes(Node::Attitude) as u32;
        let elf = Elf::parse(&elf::tests::tiny_elf(&reference, 0)).unwrap();
        let e = ImageMap::of(&elf, Node::Attitude).unwrap_err().to_string();
        assert!(
            e.contains("no mailbox `TILE_SUN` (not the attitude node's image?)"),
            "{e}"
        );
        // a mailbox of another size (an image of another tile count, another link) is refused
        let sun = symbols.iter().position(|s| s.0 == "TILE_SUN").unwrap();
        symbols[sun].2 = 16;
        let elf = Elf::parse(&elf::tests::tiny_elf(&symbols, 0)).unwrap();
        let e = ImageMap::of(&elf, Node::Attitude).unwrap_err().to_string();
        assert!(
            e.contains("`TILE_SUN` is 16 B in the image, 24 B on the host"),
            "{e}"
        );
        symbols[sun].2 = 24;
        let link = symbols.iter().position(|s| s.0 == "LINK_TX").unwrap();
        symbols[link].2 = 64;
        let elf = Elf::parse(&elf::tests::tiny_elf(&symbols, 0)).unwrap();
        assert!(ImageMap::of(&elf, Node::Attitude).is_err());
        symbols.remove(link);
        let elf = Elf::parse(&elf::tests::tiny_elf(&symbols, 0)).unwrap();
        assert!(ImageMap::of(&elf, Node::Reference).is_err());
    }

    #[test]
    fn the_link_faults_drop_corrupt_and_deliver_in_both_directions() {
        let packet: Vec<u8> = (0..60u8).collect();
        let mut counts = [[0usize; 3]; 2];
        for i in 0..LINK_FAULT_STEPS {
            for (d, direction) in [LinkDirection::Reference, LinkDirection::Status]
                .into_iter()
                .enumerate()
            {
                let mut bytes = packet.clone();
                let delivered = damage(i, direction, &mut bytes);
                let changed = bytes.iter().zip(&packet).filter(|(a, b)| a != b).count();
                let kind = match (delivered, changed) {
                    (false, _) => 0,
                    (true, 1) => 1,
                    (true, 0) => 2,
                    other => panic!("{other:?}"),
                };
                counts[d][kind] += 1;
                // the same packet is damaged the same way every time (both paths)
                let mut again = packet.clone();
                assert_eq!(damage(i, direction, &mut again), delivered);
                assert_eq!(again, bytes);
            }
        }
        assert_eq!(counts, [[12, 12, 6], [12, 12, 6]]);
        // a corrupted packet is refused by the receiver
        let status = crate::link::messages::Status {
            step: 7,
            boot_count: 0,
            mode: 3,
            attitude: None,
            h_wheels_body_nms: crate::linalg::Vec3::zeros(),
            guidance_id: 0,
            faults: 0,
            utc: None,
        };
        for i in 0..LINK_FAULT_STEPS {
            let mut p = status.to_packet(i as u16);
            if damage(i, LinkDirection::Status, &mut p) {
                let ok = crate::link::messages::Status::from_packet(&p).is_ok();
                assert_eq!(ok, p == status.to_packet(i as u16), "period {i}");
            }
        }
    }

    #[test]
    fn a_scenario_not_flying_the_flight_period_is_refused_before_the_simulator_starts() {
        let thesis = crate::host::sim::scenarios::thesis_slew(false).unwrap();
        let options = PilOptions {
            mspdebug: "/nonexistent/mspdebug".into(),
            ..PilOptions::default()
        };
        match run(&thesis, &options, |_| {}) {
            Err(PilError::Input(m)) => assert!(m.contains("control period 0.1 s"), "{m}"),
            other => panic!("{other:?}"),
        }
    }
}
