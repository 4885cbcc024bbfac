//! The packet dictionary (`ground/cosmos/ACS/cmd_tlm/`, `acs::host::dictionary`; issue 31
//! item 5): the committed files are what the code generates (`ACS_UPDATE_DICTIONARY=1`
//! rewrites them), and read back with COSMOS's layout rules (fields appended in order, bit
//! sizes, big-endian, ID values) every command builds the packet the nodes take (and `acs tc`
//! sends), and every report a node writes decodes field by field.

use std::collections::BTreeMap;
use std::path::PathBuf;

use acs::host::dictionary::{cosmos_commands, cosmos_telemetry, TARGET};
use acs::link::crc16::crc16;
use acs::link::messages::{ATTITUDE_TC_APID, REFERENCE_TC_APID};
use acs::link::pus::{encode_tc, AckFlags, TcHeader};
use acs::link::sequence::SequenceCounter;
use acs::time::Epoch;
use acs::uplink::telecommand::{arity, take, WordType, COMMANDS, REPORTS_LEN, SERVICE, SUBTYPE};
use acs::uplink::UplinkError;

fn dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("ground/cosmos/ACS/cmd_tlm")
}

#[test]
fn the_files_are_generated_from_the_code() {
    for (file, text) in [
        ("cmd.txt", cosmos_commands()),
        ("tlm.txt", cosmos_telemetry()),
    ] {
        let path = dir().join(file);
        if std::env::var_os("ACS_UPDATE_DICTIONARY").is_some() {
            std::fs::create_dir_all(dir()).expect("the directory");
            std::fs::write(&path, &text).expect("written");
        }
        let kept = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            kept == text,
            "{} is not what acs::host::dictionary writes: regenerate it with \
             ACS_UPDATE_DICTIONARY=1 cargo test --release --test dictionary",
            path.display()
        );
    }
}

/// One field of a packet definition: name, bits, type, the ID value or default.
#[derive(Debug, Clone)]
struct Field {
    name: String,
    bits: usize,
    ty: String,
    id: Option<u64>,
    default: String,
}

/// The packets of a COSMOS definition file: (keyword, target, name) → fields, and the states
/// of each field.
type Packets = BTreeMap<String, (Vec<Field>, BTreeMap<String, Vec<(String, u64)>>)>;

/// Reads the keywords this dictionary uses, as COSMOS lays them out (each `APPEND_*` after the
/// last; an array's size in bits is its fourth token).
fn parse(text: &str) -> Packets {
    let mut packets = Packets::new();
    let mut current = String::new();
    for line in text.lines() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        // the quoted description is last: split before it
        let head = line.split('"').next().unwrap_or("").trim();
        let t: Vec<&str> = head.split_whitespace().collect();
        match t[0] {
            "COMMAND" | "TELEMETRY" => {
                assert_eq!(t[1], TARGET);
                assert_eq!(t[3], "BIG_ENDIAN");
                current = t[2].to_string();
                assert!(packets
                    .insert(current.clone(), (vec![], BTreeMap::new()))
                    .is_none());
            }
            "APPEND_PARAMETER" | "APPEND_ID_PARAMETER" | "APPEND_ITEM" | "APPEND_ID_ITEM" => {
                let id = match t[0] {
                    "APPEND_ID_PARAMETER" => Some(t[6].parse().expect("an ID value")),
                    "APPEND_ID_ITEM" => Some(t[4].parse().expect("an ID value")),
                    _ => None,
                };
                let default = if t[0].ends_with("PARAMETER") {
                    t[6].to_string()
                } else {
                    String::new()
                };
                let (fields, _) = packets.get_mut(&current).expect("in a packet");
                fields.push(Field {
                    name: t[1].to_string(),
                    bits: t[2].parse().expect("bits"),
                    ty: t[3].to_string(),
                    id,
                    default,
                });
            }
            "APPEND_ARRAY_PARAMETER" => {
                let (fields, _) = packets.get_mut(&current).expect("in a packet");
                let item: usize = t[2].parse().expect("bits");
                let total: usize = t[4].parse().expect("array bits");
                for k in 0..total / item {
                    fields.push(Field {
                        name: format!("{}[{k}]", t[1]),
                        bits: item,
                        ty: t[3].to_string(),
                        id: None,
                        default: "0".into(),
                    });
                }
            }
            "STATE" => {
                let (fields, states) = packets.get_mut(&current).expect("in a packet");
                let field = fields.last().expect("after a field").name.clone();
                states
                    .entry(field)
                    .or_default()
                    .push((t[1].to_string(), t[2].parse().expect("a state value")));
            }
            "UNITS" => {}
            other => panic!("a keyword this test does not read: {other}"),
        }
    }
    packets
}

/// Writes `value` into `bits` bits at bit `at` of `out`, most significant first.
fn put(out: &mut [u8], at: usize, bits: usize, value: u64) {
    for i in 0..bits {
        let bit = (value >> (bits - 1 - i)) & 1;
        let pos = at + i;
        out[pos / 8] |= (bit as u8) << (7 - pos % 8);
    }
}

/// Reads `bits` bits at bit `at`.
fn get(bytes: &[u8], at: usize, bits: usize) -> u64 {
    (0..bits).fold(0, |v, i| {
        let pos = at + i;
        (v << 1) | u64::from((bytes[pos / 8] >> (7 - pos % 8)) & 1)
    })
}

/// The packet of a command definition with its defaults and `args` (by field name), its CRC
/// computed as the interface's CrcProtocol does (over every byte before it).
fn build(fields: &[Field], args: &BTreeMap<String, u64>) -> Vec<u8> {
    let total: usize = fields.iter().map(|f| f.bits).sum();
    assert_eq!(total % 8, 0);
    let mut out = vec![0u8; total / 8];
    let mut at = 0;
    for f in fields {
        let value = match (args.get(&f.name), f.id) {
            (Some(v), _) => *v,
            (None, Some(id)) => id,
            (None, None) if f.name == "CRC" => 0,
            (None, None) => f.default.parse().expect("an integer default"),
        };
        put(&mut out, at, f.bits, value);
        at += f.bits;
    }
    let n = out.len();
    let crc = crc16(&out[..n - 2]);
    out[n - 2..].copy_from_slice(&crc.to_be_bytes());
    out
}

#[test]
fn every_command_builds_the_packet_the_nodes_take() {
    let packets = parse(&cosmos_commands());
    assert_eq!(packets.len(), COMMANDS.len());
    for d in COMMANDS {
        let (fields, _) = &packets[d.name];
        // argument values: word k is 0x01020304 * (k + 1) as bits, of each type alike
        let mut args = BTreeMap::new();
        let mut words = vec![];
        for f in fields
            .iter()
            .skip_while(|f| f.name != "FUNCTION_ID")
            .skip(1)
        {
            if f.name == "CRC" {
                break;
            }
            let w = 0x0102_0304u32.wrapping_mul(words.len() as u32 + 1);
            assert_eq!(f.bits, 32, "{}", f.name);
            let ty = d
                .arguments
                .iter()
                .find(|a| f.name.split('[').next() == Some(a.name))
                .expect("an argument of the definition")
                .word;
            assert_eq!(
                f.ty,
                match ty {
                    WordType::F32 => "FLOAT",
                    WordType::I32 => "INT",
                    WordType::U32 => "UINT",
                }
            );
            args.insert(f.name.clone(), u64::from(w));
            words.push(w);
        }
        assert_eq!(Some(words.len()), arity(d.code), "{}", d.name);
        args.insert("CCSDS_SEQCNT".into(), 0x1234);
        args.insert("SOURCE_ID".into(), 0xABCD);
        let packet = build(fields, &args);
        // the same bytes as the library's encoder (what acs tc and spacepackets also write)
        let mut app = d.code.to_be_bytes().to_vec();
        app.extend(words.iter().flat_map(|w| w.to_be_bytes()));
        let mut ours = vec![0u8; packet.len()];
        let h = TcHeader {
            apid: d.apid,
            sequence_count: 0x1234,
            ack: AckFlags::ACCEPTANCE.with(AckFlags::COMPLETION),
            service: SERVICE,
            subtype: SUBTYPE,
            source_id: 0xABCD,
        };
        assert_eq!(
            encode_tc(&h, &app, &mut ours),
            Ok(packet.len()),
            "{}",
            d.name
        );
        assert_eq!(packet, ours, "{}", d.name);
        // and the node takes it: the command and its words
        let mut applied = None;
        let mut out = [0u8; REPORTS_LEN];
        let n = take(
            &packet,
            d.apid,
            None,
            &mut SequenceCounter::new(),
            &mut out,
            |k, a| {
                applied = Some((k, a[..words.len()].to_vec()));
                Ok(())
            },
        );
        assert_eq!(applied, Some((d.code, words.clone())), "{}", d.name);
        assert_eq!(n, 50, "{}: TM[1,1] and TM[1,7]", d.name);
    }
}

#[test]
fn every_report_decodes_field_by_field() {
    let packets = parse(&cosmos_telemetry());
    // 4 verification reports, a housekeeping report and 3 event reports of each node
    assert_eq!(packets.len(), 16);
    let clock = Epoch::from_parts(9_828, 23_415, 500_000_000).ok();
    for apid in [REFERENCE_TC_APID, ATTITUDE_TC_APID] {
        for outcome in [
            Ok(()),
            Err(UplinkError::InvalidArgument),
            Err(UplinkError::BadElementWord(9)),
        ] {
            let tc = {
                let mut p = vec![0u8; 15];
                let h = TcHeader {
                    apid,
                    sequence_count: 77,
                    ack: AckFlags::ACCEPTANCE.with(AckFlags::COMPLETION),
                    service: SERVICE,
                    subtype: SUBTYPE,
                    source_id: 0x00C5,
                };
                let n = encode_tc(&h, &[0, 1], &mut p).expect("sun-safe");
                p.truncate(n);
                p
            };
            let mut out = [0u8; REPORTS_LEN];
            let n = take(
                &tc,
                apid,
                clock,
                &mut SequenceCounter::new(),
                &mut out,
                |_, _| outcome,
            );
            let mut rest = &out[..n];
            while !rest.is_empty() {
                // the packet definition COSMOS identifies: every ID item matches
                let (name, fields, states) = packets
                    .iter()
                    .find(|(_, (fields, _))| {
                        let mut at = 0;
                        fields.iter().all(|f| {
                            let ok = f.id.is_none_or(|id| get(rest, at, f.bits) == id);
                            at += f.bits;
                            ok
                        })
                    })
                    .map(|(k, (f, s))| (k, f, s))
                    .expect("a definition identifies the report");
                let bits: usize = fields.iter().map(|f| f.bits).sum();
                let len = bits / 8;
                let mut at = 0;
                let mut value = BTreeMap::new();
                for f in fields {
                    value.insert(f.name.as_str(), get(rest, at, f.bits));
                    at += f.bits;
                }
                assert_eq!(value["CCSDS_LENGTH"] as usize + 7, len, "{name}");
                assert_eq!(value["CCSDS_APID"], u64::from(apid.get()));
                assert_eq!(value["DESTINATION_ID"], 0xC5);
                assert_eq!(value["TIME_STATUS"], 1);
                assert_eq!(value["TIME_SECONDS"], 9_828 * 86_400 + 23_415);
                assert_eq!(
                    value["REQUEST_PACKET_ID"],
                    u64::from(u16::from_be_bytes([tc[0], tc[1]]))
                );
                assert_eq!(
                    value["REQUEST_SEQUENCE"],
                    u64::from(u16::from_be_bytes([tc[2], tc[3]]))
                );
                assert_eq!(value["CRC"], u64::from(crc16(&rest[..len - 2])));
                let short = if apid == REFERENCE_TC_APID {
                    "REF"
                } else {
                    "ATT"
                };
                match outcome {
                    Ok(()) => assert!(
                        *name == format!("{short}_ACCEPTED")
                            || *name == format!("{short}_COMPLETED")
                    ),
                    Err(e) => {
                        assert_eq!(*name, format!("{short}_ACCEPTANCE_FAILED"));
                        let code = value["FAILURE_CODE"];
                        assert_eq!(code, 0x100 + u64::from(e.status()));
                        let state = states["FAILURE_CODE"]
                            .iter()
                            .find(|(_, v)| *v == code)
                            .map(|(s, _)| s.as_str());
                        let expected = match e {
                            UplinkError::InvalidArgument => "INVALID_ARGUMENT",
                            _ => "ELEMENT_WORD_9",
                        };
                        assert_eq!(state, Some(expected));
                    }
                }
                rest = &rest[len..];
            }
        }
    }
}

/// The states of a packet's fields.
type States = BTreeMap<String, Vec<(String, u64)>>;

/// The packet definition COSMOS identifies for `bytes` (every ID item matches) and its items'
/// values, checked for its length and CRC.
fn identify<'a>(
    packets: &'a Packets,
    bytes: &[u8],
) -> (&'a str, BTreeMap<String, u64>, &'a States) {
    let matching: Vec<_> = packets
        .iter()
        .filter(|(_, (fields, _))| {
            let mut at = 0;
            fields.iter().all(|f| {
                let ok = f.id.is_none_or(|id| {
                    at + f.bits <= bytes.len() * 8 && get(bytes, at, f.bits) == id
                });
                at += f.bits;
                ok
            })
        })
        .collect();
    assert_eq!(
        matching.len(),
        1,
        "exactly one definition identifies the packet"
    );
    let (name, (fields, states)) = matching[0];
    let bits: usize = fields.iter().map(|f| f.bits).sum();
    assert_eq!(bits / 8, bytes.len(), "{name}: the definition's length");
    let mut value = BTreeMap::new();
    let mut at = 0;
    for f in fields {
        value.insert(f.name.clone(), get(bytes, at, f.bits));
        at += f.bits;
    }
    assert_eq!(value["CCSDS_LENGTH"] as usize + 7, bytes.len(), "{name}");
    assert_eq!(
        value["CRC"],
        u64::from(crc16(&bytes[..bytes.len() - 2])),
        "{name}"
    );
    (name.as_str(), value, states)
}

/// Both nodes' housekeeping reports, from a flown two-node loop, decode item by item as
/// COSMOS lays them out: each item is the node's value (floats as their bits).
#[test]
fn the_housekeeping_reports_decode_field_by_field() {
    use acs::acs_loop::StepReport;
    use acs::flight::{FlightLoop, CONFIG};
    use acs::host::sim::scenarios;
    use acs::link::messages::Reference;
    use acs::link::pus::{CucTime, TmHeader};
    use acs::telemetry::{attitude_report, reference_report, LinkCounts};
    use acs::uplink::telecommand::cuc;
    let packets = parse(&cosmos_telemetry());
    let sc = scenarios::tracking(None).expect("scenario");
    let mut sim = sc.simulator().expect("simulator");
    let mut acs = FlightLoop::new(&CONFIG, sc.orbit().expect("orbit")).expect("loop");
    let mut report = StepReport::empty(acs.mode());
    for _ in 0..20 {
        let t = sim.truth().t_s;
        let now = sim.epoch_at(t);
        report = acs.step(&mut sim, now, 1.0);
        sim.advance(1.0).expect("advance");
    }
    assert!(report.attitude.is_some());
    let header = |apid| TmHeader {
        apid,
        sequence_count: 321,
        time_status: 1,
        message_counter: 0,
        destination_id: 0,
        time: CucTime {
            seconds: 9_828 * 86_400,
            fraction: 7,
        },
    };
    let link = LinkCounts {
        received: 18,
        refused: 1,
        missed: 1,
    };
    let f = |x: f32| u64::from(x.to_bits());
    // the attitude node
    let node = acs.attitude_node_mut();
    let mut out = [0u8; 200];
    let n = attitude_report(&header(ATTITUDE_TC_APID), node, &report, &link, &mut out)
        .expect("written");
    let (name, v, _) = identify(&packets, &out[..n]);
    assert_eq!(name, "ATT_HK");
    let q = report.attitude.expect("attitude");
    let w = report.omega_body_radps.expect("rate");
    let mut expected: Vec<(String, u64)> = vec![
        ("CCSDS_APID".into(), u64::from(ATTITUDE_TC_APID.get())),
        ("CCSDS_SEQCNT".into(), 321),
        ("SERVICE".into(), 3),
        ("SUBTYPE".into(), 25),
        ("TIME_SECONDS".into(), 9_828 * 86_400),
        ("TIME_FRACTION".into(), 7),
        ("STRUCTURE_ID".into(), 1),
        ("STEP".into(), u64::from(node.step_number())),
        ("MODE".into(), u64::from(report.mode.code())),
        ("COILS_FAILED".into(), u64::from(node.coils_failed())),
        ("FAULTS".into(), u64::from(report.faults.bits())),
        ("HK_INTERVAL".into(), 10),
        (
            "WITHOUT_REF".into(),
            u64::from(node.steps_without_reference()),
        ),
        ("LINK_RECEIVED".into(), 18),
        ("LINK_REFUSED".into(), 1),
        ("LINK_MISSED".into(), 1),
        ("Q_0".into(), f(q.q0)),
        ("Q_1".into(), f(q.q1)),
        ("Q_2".into(), f(q.q2)),
        ("Q_3".into(), f(q.q3)),
    ];
    for k in 0..3 {
        expected.push((format!("RATE_{k}"), f(w[k])));
        expected.push((format!("DIPOLE_{k}"), f(report.dipole_body_am2[k])));
    }
    for (k, x) in node.filter_variances().iter().enumerate() {
        expected.push((format!("VARIANCE_{k}"), f(*x)));
    }
    for (k, state) in node.part_states().iter().enumerate() {
        expected.push((format!("TILE_STATE_{k}"), u64::from(*state)));
        expected.push((format!("TILE_ERROR_{k}"), u64::from(node.part_errors()[k])));
        expected.push((format!("WHEEL_CMD_{k}"), f(node.wheels_commanded()[k])));
        expected.push((
            format!("WHEEL_READ_{k}"),
            u64::from(node.health().wheel_reads()[k] as u16),
        ));
    }
    for (item, value) in &expected {
        assert_eq!(v.get(item), Some(value), "ATT_HK {item}");
    }
    // every item of the definition was checked (the headers' fixed fields aside)
    let fixed = [
        "CCSDS_VERSION",
        "CCSDS_TYPE",
        "CCSDS_SHF",
        "CCSDS_SEQFLAGS",
        "CCSDS_LENGTH",
        "PUS_VERSION",
        "TIME_STATUS",
        "MESSAGE_COUNTER",
        "DESTINATION_ID",
        "CRC",
    ];
    assert_eq!(v.len(), expected.len() + fixed.len());
    // the reference node
    let (ref_packet, _) = acs.packets();
    let (reference, _) = Reference::from_packet(ref_packet).expect("the last REF");
    let node = acs.reference_node_mut();
    let n = reference_report(
        &header(REFERENCE_TC_APID),
        node,
        &reference,
        &link,
        &mut out,
    )
    .expect("written");
    let (name, v, _) = identify(&packets, &out[..n]);
    assert_eq!(name, "REF_HK");
    let (clock, _) = cuc(Some(reference.utc));
    let (epoch, _) = cuc(node.elements_epoch());
    let g = &reference.guidance;
    let expected: Vec<(&str, u64)> = vec![
        ("STRUCTURE_ID", 2),
        ("CLOCK_SECONDS", u64::from(clock.seconds)),
        ("CLOCK_FRACTION", u64::from(clock.fraction)),
        ("FLAGS", 3),
        ("SHADOW", 1),
        ("FAULTS", u64::from(reference.faults)),
        ("HK_INTERVAL", 10),
        ("LINK_RECEIVED", 18),
        ("LINK_REFUSED", 1),
        ("LINK_MISSED", 1),
        ("GUIDANCE_ID", u64::from(g.id)),
        ("GUIDANCE_KIND", 0),
        ("TARGET_0", f(g.target.q0)),
        ("TARGET_1", f(g.target.q1)),
        ("TARGET_2", f(g.target.q2)),
        ("TARGET_3", f(g.target.q3)),
        ("EPOCH_SECONDS", u64::from(epoch.seconds)),
        ("EPOCH_FRACTION", u64::from(epoch.fraction)),
    ];
    for (item, value) in &expected {
        assert_eq!(v.get(*item), Some(value), "REF_HK {item}");
    }
    assert_eq!(v.len(), expected.len() + fixed.len() + 6);
}

/// Every event report of both nodes (each fault bit raised and cleared, a mode change) decodes
/// item by item, its fault bit named by its state.
#[test]
fn the_event_reports_decode_field_by_field() {
    use acs::link::pus::{CucTime, TmHeader};
    use acs::telemetry::{write_events, State, FAULT_BITS};
    let packets = parse(&cosmos_telemetry());
    for apid in [REFERENCE_TC_APID, ATTITUDE_TC_APID] {
        let short = if apid == REFERENCE_TC_APID {
            "REF"
        } else {
            "ATT"
        };
        let header = TmHeader {
            apid,
            sequence_count: 0,
            time_status: 1,
            message_counter: 0,
            destination_id: 0,
            time: CucTime::default(),
        };
        let mut count = SequenceCounter::new();
        let mut out = [0u8; 26];
        let (n, _) = write_events(
            &header,
            &mut count,
            State { mode: 1, faults: 0 },
            State { mode: 3, faults: 0 },
            &mut out,
        );
        let (name, v, _) = identify(&packets, &out[..n]);
        assert_eq!(name, format!("{short}_MODE_CHANGED"));
        assert_eq!((v["OLD_MODE"], v["NEW_MODE"]), (1, 3));
        for (bit, bit_name) in FAULT_BITS.iter().enumerate() {
            let on = State {
                mode: 3,
                faults: 1 << bit,
            };
            let off = State { mode: 3, faults: 0 };
            for (from, to, what) in [(off, on, "RAISED"), (on, off, "CLEARED")] {
                let (n, left) = write_events(&header, &mut count, from, to, &mut out);
                assert_eq!((n, left), (25, 0));
                let (name, v, states) = identify(&packets, &out[..n]);
                assert_eq!(name, format!("{short}_FAULT_{what}"));
                assert_eq!(v["FAULT_BIT"], bit as u64);
                assert_eq!(v["FAULTS"], u64::from(to.faults));
                let state = states["FAULT_BIT"]
                    .iter()
                    .find(|(_, b)| *b == bit as u64)
                    .map(|(s, _)| s.to_lowercase());
                assert_eq!(state.as_deref(), Some(*bit_name));
            }
        }
    }
}
