//! `acs tm`: the nodes' telemetry packets as CSV (`docs/cli.md`, `docs/operations.md`; issue
//! 31 item 5).
//!
//! Read with the `spacepackets` crate's `PusTmReader` (CRC checked), independently of the
//! nodes' writer ([`crate::link::pus`]).
//!
//! # Use
//! ```text
//! acs tm FILE          (FILE `-`: stdin)
//! ```
//! FILE holds TM packets back to back, as bytes, or as hex digits (whitespace, line breaks and
//! `#` comment lines ignored: the file is read as hex when it holds nothing else). stdout: CSV, one line a
//! packet, with the header
//! `node,apid,sequence_count,time_status,time_utc,service,subtype,report,destination_id,request_apid,request_sequence_count,failure_code,reason,data`:
//! - `node`: `reference` (APID 0x051), `attitude` (0x050) or `unknown`;
//! - `time_utc`: the CUC time (seconds since 2000-01-01T00:00 UTC and 2⁻¹⁶ s) in ISO 8601 UTC,
//!   the fraction to the nanosecond below; empty when the time status is 0 (no clock);
//! - for a verification report (service 1): `report` (`accepted`, `acceptance failed`,
//!   `completed`, `completion failed`, …), the request's APID and sequence count, and for a
//!   failure its code (`0x105`) and reason ([`reason`]);
//! - for the other services `report` and the request's columns are empty and `data` holds the
//!   application data in hex.
//!
//! Exit 2 naming the packet and its first byte's offset for bytes that are not a valid TM
//! packet (length, CRC, type, PUS version).

use std::fmt::Write as _;
use std::io::Read;
use std::path::PathBuf;

use spacepackets::ecss::tm::{GenericPusTmSecondaryHeader, PusTmReader};
use spacepackets::ecss::PusPacket;
use spacepackets::CcsdsPacket;

use super::elements::iso_utc;
use super::CliError;
use crate::link::messages::{ATTITUDE_TC_APID, REFERENCE_TC_APID};
use crate::link::pus::{failure, TIME_LEN, TM_OVERHEAD};
use crate::telemetry::{
    Parameter, ParameterType, ATTITUDE_PARAMETERS, ATTITUDE_STRUCTURE, FAULT_BITS, FAULT_EVENT,
    MODE_CHANGED, REFERENCE_PARAMETERS, REFERENCE_STRUCTURE,
};
use crate::time::Epoch;

/// Arguments of `acs tm`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The telemetry: packets back to back, as bytes or hex digits (`-`: stdin).
    file: PathBuf,
    /// Also write the housekeeping and the events, decoded, into DIR: `attitude_hk.csv`,
    /// `reference_hk.csv` (one named column per parameter), `events.csv`, and the SVG plots
    /// of the attitude node's housekeeping (`hk_rates.svg`, `hk_wheels.svg`,
    /// `hk_attitude_sigma.svg`).
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// The CSV header.
pub const HEADER: &str = "node,apid,sequence_count,time_status,time_utc,service,subtype,report,\
                          destination_id,request_apid,request_sequence_count,failure_code,\
                          reason,data";

/// The reason of a TM\[1,2\] or TM\[1,8\] failure code (`docs/operations.md`).
pub fn reason(code: u16) -> String {
    let named = match code {
        failure::LENGTH => "length",
        failure::CRC => "CRC",
        failure::PACKET_FORMAT => "packet version or sequence flags",
        failure::APID => "another node's APID",
        failure::PACKET_TYPE => "not a telecommand, or no secondary header",
        failure::PUS_VERSION => "PUS version",
        failure::MESSAGE_TYPE => "service or subtype not served",
        0x101 => "unknown function ID",
        0x102 => "invalid argument",
        0x103 => "refused by the loop",
        0x104 => "the other node's command",
        0x105 => "wrong number of argument words",
        0x200..=0x239 => return format!("element set refused at word {}", code - 0x200),
        _ => "unknown failure code",
    };
    named.to_string()
}

/// The name of event `id` reported with subtype `subtype` (`docs/operations.md`): `mode
/// changed`, `fault raised NAME` (TM\[5,2\]), `fault cleared NAME` (TM\[5,1\]), else `event`.
pub fn event_name(subtype: u8, id: u16) -> String {
    let bit = id.wrapping_sub(FAULT_EVENT);
    match (subtype, id) {
        (1, MODE_CHANGED) => "mode changed".to_string(),
        (1 | 2, _) if 16 > bit => {
            let name = FAULT_BITS
                .get(usize::from(bit))
                .map_or(format!("bit {bit}"), |n| (*n).to_string());
            let what = if subtype == 2 { "raised" } else { "cleared" };
            format!("fault {what} {name}")
        }
        _ => "event".to_string(),
    }
}

/// The column names of a housekeeping structure's parameters (`NAME`, or `NAME_k` for element
/// k of several).
pub fn columns(table: &[Parameter]) -> Vec<String> {
    table
        .iter()
        .flat_map(|p| {
            (0..p.count).map(move |k| {
                if p.count == 1 {
                    p.name.to_string()
                } else {
                    format!("{}_{k}", p.name)
                }
            })
        })
        .collect()
}

/// The values of a structure's parameters in `data` (after the structure ID), as numbers;
/// `None` if `data` is not the structure's length.
pub fn values(table: &[Parameter], data: &[u8]) -> Option<Vec<f64>> {
    let len: usize = table.iter().map(|p| p.ty.bytes() * p.count).sum();
    if data.len() != len {
        return None;
    }
    let mut out = vec![];
    let mut at = 0;
    for p in table {
        for _ in 0..p.count {
            let b = &data[at..at + p.ty.bytes()];
            let u = b.iter().fold(0u32, |v, x| (v << 8) | u32::from(*x));
            out.push(match p.ty {
                ParameterType::U8 | ParameterType::U16 | ParameterType::U32 => f64::from(u),
                ParameterType::I16 => f64::from(u as u16 as i16),
                ParameterType::F32 => f64::from(f32::from_bits(u)),
            });
            at += b.len();
        }
    }
    Some(out)
}

/// The bytes of FILE: hex digits when it holds nothing else, else the bytes themselves.
fn read_input(path: &PathBuf) -> Result<Vec<u8>, CliError> {
    let name = path.display();
    let mut raw = Vec::new();
    let read = if path.as_os_str() == "-" {
        std::io::stdin().read_to_end(&mut raw)
    } else {
        std::fs::File::open(path).and_then(|mut f| f.read_to_end(&mut raw))
    };
    read.map_err(|e| CliError::Input(format!("{name}: {e}")))?;
    // as text: the lines that are neither blank nor `#` comments (docs/cli.md)
    let digits: Vec<u8> = raw
        .split(|b| *b == b'\n')
        .filter(|l| l.iter().find(|b| !b.is_ascii_whitespace()) != Some(&b'#'))
        .flatten()
        .copied()
        .filter(|b| !b.is_ascii_whitespace())
        .collect();
    let is_hex = !digits.is_empty() && digits.iter().all(u8::is_ascii_hexdigit);
    if !is_hex {
        return Ok(raw);
    }
    if !digits.len().is_multiple_of(2) {
        return Err(CliError::Input(format!(
            "{name}: an odd number of hex digits ({})",
            digits.len()
        )));
    }
    Ok(digits
        .chunks_exact(2)
        .map(|p| {
            let hex = |b: u8| (b as char).to_digit(16).unwrap_or(0) as u8;
            hex(p[0]) << 4 | hex(p[1])
        })
        .collect())
}

/// The CSV line of one TM packet read by `spacepackets`.
fn line(r: &PusTmReader<'_>) -> String {
    let apid = r.apid().value();
    let node = match apid {
        a if a == REFERENCE_TC_APID.get() => "reference",
        a if a == ATTITUDE_TC_APID.get() => "attitude",
        _ => "unknown",
    };
    let status = r.sc_time_ref_status().value();
    let stamp = r.timestamp();
    let time_utc = match (status, stamp) {
        (0, _) => String::new(),
        (_, &[t0, t1, t2, t3, f0, f1]) => {
            let seconds = u32::from_be_bytes([t0, t1, t2, t3]);
            let fraction = u64::from(u16::from_be_bytes([f0, f1]));
            let nano = ((fraction * 1_000_000_000) >> 16) as u32;
            Epoch::from_parts((seconds / 86_400) as i32, seconds % 86_400, nano)
                .map(|t| iso_utc(&t))
                .unwrap_or_default()
        }
        _ => String::new(),
    };
    let (service, subtype) = (
        PusPacket::service_type_id(r),
        PusPacket::message_subtype_id(r),
    );
    let data = r.source_data();
    let mut verification = [String::new(), String::new(), String::new(), String::new()];
    let report;
    let mut hex = String::new();
    match (service, data) {
        (1, [p0, p1, s0, s1, rest @ ..]) => {
            report = match subtype {
                1 => "accepted",
                2 => "acceptance failed",
                3 => "started",
                4 => "start failed",
                5 => "progress",
                6 => "progress failed",
                7 => "completed",
                8 => "completion failed",
                _ => "verification",
            }
            .to_string();
            verification[0] = format!("{}", u16::from_be_bytes([*p0, *p1]) & 0x7FF);
            verification[1] = format!("{}", u16::from_be_bytes([*s0, *s1]) & 0x3FFF);
            if let [c0, c1, ..] = rest {
                let code = u16::from_be_bytes([*c0, *c1]);
                verification[2] = format!("{code:#05x}");
                verification[3] = reason(code);
            }
        }
        _ => {
            report = match (service, subtype, data) {
                (3, 25, [s0, s1, ..]) => match u16::from_be_bytes([*s0, *s1]) {
                    ATTITUDE_STRUCTURE => "housekeeping attitude".to_string(),
                    REFERENCE_STRUCTURE => "housekeeping reference".to_string(),
                    _ => "housekeeping".to_string(),
                },
                (5, _, [e0, e1, ..]) => event_name(subtype, u16::from_be_bytes([*e0, *e1])),
                _ => String::new(),
            };
            for b in data {
                let _ = write!(hex, "{b:02x}");
            }
        }
    }
    format!(
        "{node},{apid},{},{status},{time_utc},{service},{subtype},{report},{},{},{},{},{},{hex}",
        r.seq_count().value(),
        r.dest_id(),
        verification[0],
        verification[1],
        verification[2],
        verification[3],
    )
}

/// Calls `f` with each TM packet in `bytes`, in order; an error names the first bad packet.
fn walk(bytes: &[u8], mut f: impl FnMut(&PusTmReader<'_>)) -> Result<(), CliError> {
    let mut at = 0;
    let mut k = 1;
    while at < bytes.len() {
        let bad = |why: String| {
            CliError::Input(format!(
                "packet {k} at byte {at}: not a valid TM packet ({why})"
            ))
        };
        let rest = &bytes[at..];
        // checked before the reader, which panics on a packet shorter than its headers
        // (spacepackets 0.19), and leaves the packet type and the PUS version to its caller
        if rest[0] & 0x10 != 0 {
            return Err(bad("a telecommand".into()));
        }
        if rest.len() < TM_OVERHEAD {
            return Err(bad(format!("{} bytes", rest.len())));
        }
        let len = usize::from(u16::from_be_bytes([rest[4], rest[5]])) + 7;
        if len < TM_OVERHEAD || len > rest.len() {
            return Err(bad(format!("its length field says {len} bytes")));
        }
        if rest[6] >> 4 != 2 {
            return Err(bad(format!("PUS version {}", rest[6] >> 4)));
        }
        let r = PusTmReader::new(&rest[..len], TIME_LEN).map_err(|e| bad(e.to_string()))?;
        f(&r);
        at += r.len_packed();
        k += 1;
    }
    Ok(())
}

/// The CSV of the TM packets in `bytes`, header first; an error names the first bad packet.
pub fn csv(bytes: &[u8]) -> Result<String, CliError> {
    let mut out = format!("{HEADER}\n");
    walk(bytes, |r| {
        out.push_str(&line(r));
        out.push('\n');
    })?;
    Ok(out)
}

/// The packet's CUC time, s since 2000-01-01T00:00 UTC, and its ISO 8601 form (empty without
/// a clock).
fn time_of(r: &PusTmReader<'_>) -> (f64, String) {
    match r.timestamp() {
        &[t0, t1, t2, t3, f0, f1] if r.sc_time_ref_status().value() != 0 => {
            let seconds = u32::from_be_bytes([t0, t1, t2, t3]);
            let fraction = u16::from_be_bytes([f0, f1]);
            let nano = ((u64::from(fraction) * 1_000_000_000) >> 16) as u32;
            let iso = Epoch::from_parts((seconds / 86_400) as i32, seconds % 86_400, nano)
                .map(|t| iso_utc(&t))
                .unwrap_or_default();
            (f64::from(seconds) + f64::from(fraction) / 65_536.0, iso)
        }
        _ => (f64::NAN, String::new()),
    }
}

/// A housekeeping report decoded: its time, s, and its parameters' values.
type Row = (f64, Vec<f64>);

/// The housekeeping and the events of the TM packets in `bytes`, decoded (`acs tm --out`):
/// `attitude_hk.csv`, `reference_hk.csv`, `events.csv` and the attitude node's plots, into
/// `dir`; returns the files written.
pub fn write_decoded(bytes: &[u8], dir: &std::path::Path) -> Result<Vec<String>, CliError> {
    let mut hk: [(Vec<String>, Vec<Row>); 2] = [
        (columns(ATTITUDE_PARAMETERS), vec![]),
        (columns(REFERENCE_PARAMETERS), vec![]),
    ];
    let mut hk_csv = [String::new(), String::new()];
    let mut events = String::from(
        "node,apid,sequence_count,time_utc,time_s,subtype,event_id,event,old_mode,new_mode,faults\n",
    );
    let prefix = |r: &PusTmReader<'_>| {
        let (t, iso) = time_of(r);
        let apid = r.apid().value();
        let node = match apid {
            a if a == REFERENCE_TC_APID.get() => "reference",
            a if a == ATTITUDE_TC_APID.get() => "attitude",
            _ => "unknown",
        };
        (format!("{node},{apid},{},{iso}", r.seq_count().value()), t)
    };
    walk(bytes, |r| {
        let data = r.source_data();
        match (
            PusPacket::service_type_id(r),
            PusPacket::message_subtype_id(r),
            data,
        ) {
            (3, 25, [s0, s1, rest @ ..]) => {
                let (k, table) = match u16::from_be_bytes([*s0, *s1]) {
                    ATTITUDE_STRUCTURE => (0, ATTITUDE_PARAMETERS),
                    REFERENCE_STRUCTURE => (1, REFERENCE_PARAMETERS),
                    _ => return,
                };
                if let Some(v) = values(table, rest) {
                    let (head, t) = prefix(r);
                    let cells: Vec<String> = v.iter().map(|x| format!("{x}")).collect();
                    let _ = writeln!(hk_csv[k], "{head},{t},{}", cells.join(","));
                    hk[k].1.push((t, v));
                }
            }
            (5, subtype, [e0, e1, a0, a1]) => {
                let id = u16::from_be_bytes([*e0, *e1]);
                let (head, t) = prefix(r);
                let (old, new, faults) = if id == MODE_CHANGED {
                    (a0.to_string(), a1.to_string(), String::new())
                } else {
                    let w = u16::from_be_bytes([*a0, *a1]);
                    (String::new(), String::new(), format!("{w:#06x}"))
                };
                let _ = writeln!(
                    events,
                    "{head},{t},{subtype},{id:#06x},{},{old},{new},{faults}",
                    event_name(subtype, id)
                );
            }
            _ => {}
        }
    })?;
    std::fs::create_dir_all(dir)
        .map_err(|e| CliError::Compute(format!("{}: {e}", dir.display())))?;
    let write = |name: &str, text: &str| {
        std::fs::write(dir.join(name), text)
            .map_err(|e| CliError::Compute(format!("{}: {e}", dir.join(name).display())))
    };
    let mut written = vec![];
    for (k, name) in ["attitude_hk.csv", "reference_hk.csv"]
        .into_iter()
        .enumerate()
    {
        let header = format!(
            "node,apid,sequence_count,time_utc,time_s,{}\n",
            hk[k].0.join(",")
        );
        write(name, &(header + &hk_csv[k]))?;
        written.push(name.to_string());
    }
    write("events.csv", &events)?;
    written.push("events.csv".into());
    written.extend(plot_attitude(&hk[0].0, &hk[0].1, dir)?);
    Ok(written)
}

/// The SVG plots of the attitude node's housekeeping rows `rows` (time s, values in the order
/// of `columns`): body rates, wheel momenta commanded, the filter's attitude 1σ.
fn plot_attitude(
    columns: &[String],
    rows: &[(f64, Vec<f64>)],
    dir: &std::path::Path,
) -> Result<Vec<String>, CliError> {
    use crate::host::sim::plot::{chart_spans, Series};
    use plotters::style::{RGBColor, BLUE, GREEN, RED};
    let Some(t0) = rows.iter().map(|(t, _)| *t).find(|t| t.is_finite()) else {
        return Ok(vec![]);
    };
    let t_max = rows.last().map_or(0.0, |(t, _)| (t - t0) / 60.0);
    let column = |name: &str| columns.iter().position(|c| c == name);
    let series = |name: &str, f: &dyn Fn(f64) -> f64| -> Vec<(f64, f64)> {
        let Some(i) = column(name) else {
            return vec![];
        };
        rows.iter()
            .filter_map(|(t, v)| {
                let x = f(v[i]);
                (t.is_finite() && x.is_finite()).then_some((t - t0, x))
            })
            .collect()
    };
    let colours = [
        RED,
        GREEN,
        BLUE,
        RGBColor(230, 150, 0),
        RGBColor(150, 0, 200),
        RGBColor(0, 160, 160),
    ];
    let names: Vec<String> = (0..crate::flight::TILES)
        .map(|k| format!("tile {k}"))
        .collect();
    let wheels: Vec<Series<'_>> = (0..crate::flight::TILES)
        .map(|k| {
            (
                names[k].as_str(),
                series(&format!("WHEEL_CMD_{k}"), &|x| x),
                colours[k % colours.len()],
            )
        })
        .collect();
    let charts: [(&str, &str, &str, Vec<Series<'_>>, bool); 3] = [
        (
            "hk_rates.svg",
            "Body rate (housekeeping)",
            "rate [deg/s]",
            (0..3)
                .map(|k| {
                    (
                        ["ωx", "ωy", "ωz"][k],
                        series(&format!("RATE_{k}"), &f64::to_degrees),
                        colours[k],
                    )
                })
                .collect(),
            false,
        ),
        (
            "hk_wheels.svg",
            "Wheel momentum commanded (housekeeping)",
            "h [kg·m²/s]",
            wheels,
            false,
        ),
        (
            "hk_attitude_sigma.svg",
            "Attitude 1σ of the filter (housekeeping)",
            "1σ [deg]",
            (0..3)
                .map(|k| {
                    (
                        ["x", "y", "z"][k],
                        series(&format!("VARIANCE_{k}"), &|v| v.sqrt().to_degrees()),
                        colours[k],
                    )
                })
                .collect(),
            true,
        ),
    ];
    let mut written = vec![];
    for (file, title, y, s, log) in charts {
        chart_spans(&dir.join(file), title, y, t_max, &[], &s, log)
            .map_err(|e| CliError::Compute(format!("{file}: {e}")))?;
        written.push(file.to_string());
    }
    Ok(written)
}

/// Runs `acs tm`.
pub fn run(args: &Args) -> Result<(), CliError> {
    let bytes = read_input(&args.file)?;
    let text = csv(&bytes)?;
    if let Some(dir) = &args.out {
        write_decoded(&bytes, dir)?;
    }
    std::io::Write::write_all(&mut std::io::stdout().lock(), text.as_bytes())
        .map_err(|e| CliError::Compute(format!("stdout: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_code_has_a_reason() {
        for code in [
            1, 2, 3, 4, 5, 6, 7, 0x101, 0x102, 0x103, 0x104, 0x105, 0x200, 0x239,
        ] {
            assert_ne!(reason(code), "unknown failure code", "{code:#x}");
        }
        assert_eq!(reason(0x239), "element set refused at word 57");
        assert_eq!(reason(0x23A), "unknown failure code");
    }

    /// Random bytes, and valid reports cut or changed anywhere: an error, never a panic.
    #[test]
    fn random_bytes_never_panic() {
        let mut s = 0x2545_F491_4F6C_DD1Du64;
        let mut next = || {
            s ^= s >> 12;
            s ^= s << 25;
            s ^= s >> 27;
            s.wrapping_mul(0x2545_F491_4F6C_DD1D)
        };
        for i in 0..100_000 {
            let n = (next() % 80) as usize;
            let mut b: Vec<u8> = (0..n).map(|_| next() as u8).collect();
            if i % 2 == 0 && n >= 7 {
                // a TM header with a plausible length
                b[0] = 0x08;
                b[4] = 0;
                b[5] = (next() % 40) as u8;
                b[6] = 0x20 | (b[6] & 0x0F);
            }
            let _ = csv(&b);
        }
    }
}
