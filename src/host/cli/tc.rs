//! `acs tc`: a ground command as the PUS-C telecommand a node takes (`docs/cli.md`,
//! `docs/operations.md`; issue 31 item 5).
//!
//! Built with the `spacepackets` crate's `PusTcCreator`, an implementation independent of the
//! one the nodes decode with ([`crate::link::pus`], [`crate::uplink::telecommand`]): the packet
//! is TC\[8,1\] on the APID of the node that owns the command, its application data the
//! function ID and the argument words of [`crate::uplink`].
//!
//! # Use
//! ```text
//! acs tc sun-safe
//! acs tc track Q0 Q1 Q2 Q3                 (scalar first, TEME → body)
//! acs tc slew Q0 Q1 Q2 Q3 SECONDS
//! acs tc elements --tle FILE [--gravity wgs72|wgs84]
//! acs tc clock UTC                         (ISO 8601, as `acs sun` reads it)
//! acs tc mark-failed tile|coil INDEX
//! acs tc restore tile|coil INDEX
//! acs tc housekeeping PERIODS --node reference|attitude   (0: none; at most 3600)
//!   [--count N] [--source ID] [--ack acceptance,completion|none] [--format hex|bin]
//! ```
//! stdout: the packet as one line of lower-case hex digits (`hex`, default) or its bytes
//! (`bin`, to append to a file). Exit 2 for an argument the node would refuse (a quaternion
//! not finite or zero, a time not positive and finite, a TLE SGP4 refuses) or out of its range.

use std::io::Write;
use std::path::PathBuf;

use arbitrary_int::{u11, u14, u4};
use spacepackets::ecss::tc::{AckFlags as SpAckFlags, PusTcCreator, PusTcSecondaryHeader};
use spacepackets::ecss::{CreatorConfig, MessageTypeId};
use spacepackets::SpHeader;

use super::propagate::{gravity, init_sgp4, read_tle};
use super::sun::parse_utc_iso;
use super::CliError;
use crate::link::messages::{ATTITUDE_TC_APID, REFERENCE_TC_APID};
use crate::link::pus::AckFlags;
use crate::link::space_packet::Apid;
use crate::uplink::kind;
use crate::uplink::telecommand::{SERVICE, SUBTYPE};

/// Arguments of `acs tc`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The command.
    #[command(subcommand)]
    command: TcCommand,
    /// The packet sequence count (0–16383).
    #[arg(long, default_value_t = 0, global = true)]
    count: u16,
    /// The source ID: who sends it (the reports' destination).
    #[arg(long, default_value_t = 1, global = true)]
    source: u16,
    /// The verification reports asked for besides failures: `acceptance`, `completion`, both
    /// (comma-separated) or `none`.
    #[arg(long, default_value = "acceptance,completion", global = true)]
    ack: String,
    /// Output: one line of hex digits, or the packet's bytes.
    #[arg(long, value_parser = ["hex", "bin"], default_value = "hex", global = true)]
    format: String,
}

/// The commands (`docs/operations.md`).
#[derive(clap::Subcommand, Debug)]
enum TcCommand {
    /// Back to sun-safe (attitude node).
    SunSafe,
    /// Track an attitude: quaternion scalar first, TEME → body (reference node).
    Track {
        /// The quaternion's four components.
        #[arg(num_args = 4, allow_negative_numbers = true)]
        q: Vec<f32>,
    },
    /// Slew to an attitude within SECONDS, then track it (reference node).
    Slew {
        /// The quaternion's four components, then the time allowed, s.
        #[arg(
            num_args = 5,
            allow_negative_numbers = true,
            value_name = "Q0 Q1 Q2 Q3 SECONDS"
        )]
        values: Vec<f32>,
    },
    /// A new element set, SGP4 initialised on the ground (reference node).
    Elements {
        /// The TLE file (two lines, or a name line and two lines).
        #[arg(long, value_name = "FILE")]
        tle: PathBuf,
        /// Gravity model of the initialisation.
        #[arg(long, value_parser = ["wgs72", "wgs84"], default_value = "wgs72")]
        gravity: String,
    },
    /// Set the clock (reference node).
    Clock {
        /// UTC, ISO 8601.
        utc: String,
    },
    /// Mark a tile (with its devices and wheel) or a coil failed (attitude node).
    MarkFailed {
        /// `tile` or `coil`.
        #[arg(value_parser = ["tile", "coil"])]
        part: String,
        /// Its index.
        index: u32,
    },
    /// Return a tile or a coil to service (attitude node).
    Restore {
        /// `tile` or `coil`.
        #[arg(value_parser = ["tile", "coil"])]
        part: String,
        /// Its index.
        index: u32,
    },
    /// Set a node's housekeeping interval: PERIODS control periods between reports, 0 none
    /// (either node, each its own; 10 at reset).
    Housekeeping {
        /// Control periods between reports (0: none; at most 3600).
        periods: u32,
        /// The node: `reference` or `attitude`.
        #[arg(long, value_parser = ["reference", "attitude"])]
        node: String,
    },
}

/// A quaternion's words, refused (exit 2) if not finite or zero, as the node would.
fn quaternion_words(q: &[f32]) -> Result<Vec<u32>, CliError> {
    let norm2: f32 = q.iter().map(|c| c * c).sum();
    if q.iter().any(|c| !c.is_finite()) || norm2 == 0.0 || !norm2.is_finite() {
        return Err(CliError::Input(format!(
            "quaternion {q:?}: not finite, or zero"
        )));
    }
    Ok(q.iter().map(|c| c.to_bits()).collect())
}

/// The APID, function ID and argument words of a command.
fn command(c: &TcCommand) -> Result<(Apid, u16, Vec<u32>), CliError> {
    let part = |p: &str| u32::from(p == "coil");
    Ok(match c {
        TcCommand::SunSafe => (ATTITUDE_TC_APID, kind::SUN_SAFE, vec![]),
        TcCommand::Track { q } => (REFERENCE_TC_APID, kind::TRACK, quaternion_words(q)?),
        TcCommand::Slew { values } => {
            let (q, within) = values.split_at(4);
            let mut words = quaternion_words(q)?;
            match within {
                [s] if s.is_finite() && *s > 0.0 => words.push(s.to_bits()),
                _ => {
                    return Err(CliError::Input(format!(
                        "time allowed {within:?} s: not positive and finite"
                    )))
                }
            }
            (REFERENCE_TC_APID, kind::SLEW, words)
        }
        TcCommand::Elements { tle, gravity: g } => {
            let sgp4 = init_sgp4(&read_tle(tle)?, gravity(g), tle)?;
            (REFERENCE_TC_APID, kind::ELEMENTS, sgp4.to_words().to_vec())
        }
        TcCommand::Clock { utc } => {
            let t = parse_utc_iso(utc).map_err(CliError::Input)?;
            let words = vec![t.day() as u32, t.second_of_day(), t.nano()];
            (REFERENCE_TC_APID, kind::CLOCK, words)
        }
        TcCommand::MarkFailed { part: p, index } => {
            (ATTITUDE_TC_APID, kind::MARK_FAILED, vec![*index, part(p)])
        }
        TcCommand::Restore { part: p, index } => {
            (ATTITUDE_TC_APID, kind::RESTORE, vec![*index, part(p)])
        }
        TcCommand::Housekeeping { periods, node } => {
            if *periods > u32::from(crate::telemetry::MAX_INTERVAL) {
                return Err(CliError::Input(format!(
                    "housekeeping interval {periods}: beyond {} periods",
                    crate::telemetry::MAX_INTERVAL
                )));
            }
            let apid = if node == "reference" {
                REFERENCE_TC_APID
            } else {
                ATTITUDE_TC_APID
            };
            (apid, kind::HOUSEKEEPING, vec![*periods])
        }
    })
}

/// The acknowledgement flags of `--ack`.
fn ack_flags(text: &str) -> Result<AckFlags, CliError> {
    let mut flags = AckFlags::NONE;
    for name in text.split(',').map(str::trim) {
        flags = flags.with(match name {
            "none" => AckFlags::NONE,
            "acceptance" => AckFlags::ACCEPTANCE,
            "completion" => AckFlags::COMPLETION,
            _ => {
                return Err(CliError::Input(format!(
                    "--ack `{name}`: expected acceptance, completion or none"
                )))
            }
        });
    }
    Ok(flags)
}

/// The telecommand packet of `args`.
pub fn packet(args: &Args) -> Result<Vec<u8>, CliError> {
    let (apid, function, words) = command(&args.command)?;
    let count = u14::try_new(args.count).map_err(|_| {
        CliError::Input(format!("--count {}: beyond 14 bits (0–16383)", args.count))
    })?;
    let ack = ack_flags(&args.ack)?;
    let mut app_data = function.to_be_bytes().to_vec();
    app_data.extend(words.iter().flat_map(|w| w.to_be_bytes()));
    let sp = SpHeader::new_for_unseg_tc(u11::new(apid.get()), count, 0);
    // the raw 4 bits: spacepackets names them in the other order (tests/pus.rs)
    let sec = PusTcSecondaryHeader::new(
        MessageTypeId::new(SERVICE, SUBTYPE),
        SpAckFlags::new_with_raw_value(u4::new(ack.bits())),
        args.source,
    );
    let creator = PusTcCreator::new(sp, sec, &app_data, CreatorConfig::default());
    let mut bytes = vec![0u8; creator.len_written()];
    creator
        .write_to_slice(&mut bytes)
        .map_err(|e| CliError::Compute(format!("spacepackets: {e}")))?;
    Ok(bytes)
}

/// Runs `acs tc`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let bytes = packet(args)?;
    let mut out = std::io::stdout().lock();
    let written = if args.format == "bin" {
        out.write_all(&bytes)
    } else {
        let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        writeln!(out, "{hex}")
    };
    written.map_err(|e| CliError::Compute(format!("stdout: {e}")))
}
