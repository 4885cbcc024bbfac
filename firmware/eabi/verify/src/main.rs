//! Host driver for the `msp430-eabi` verification and cycle counts.
//!
//! ```text
//! msp430-eabi-verify [--elf NAME=PATH]... [--ops a,b,..] [--scale F] [--seed S] [--bench]
//! ```
//! Verify mode (default): for each firmware variant and each operation, the test firmware runs
//! `nblocks` blocks of 256 generated cases in `mspdebug -n sim` and leaves one hash per block;
//! the host generates the same cases (same source, `../tests-fw/src/cases.rs`), computes them
//! natively and compares hashes. A mismatching block is re-run in dump mode and the failing
//! cases are printed (inputs, expected, got). Ends with `N passed, M failed`.
//!
//! Bench mode: MCLK cycles per operation on typical operands, read from the simulator's tracer.

#[path = "../../tests-fw/src/bench_ops.rs"]
#[allow(dead_code)]
mod bench_ops;
#[path = "../../tests-fw/src/cases.rs"]
#[allow(dead_code)]
mod cases;

use std::process::Command;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

const IO: u32 = 0x0200;
const RES: u32 = 0x0400;

struct Variant {
    name: String,
    elf: String,
}

fn mspdebug(
    v: &Variant,
    params: &[u16],
    extra: &[String],
    timeout_s: u64,
) -> Result<String, String> {
    let mut mw = format!("mw 0x{IO:04x}");
    for p in params {
        mw.push_str(&format!(" {:02x} {:02x}", p & 0xff, p >> 8));
    }
    let mut args = vec![
        "-q".to_string(),
        "-n".to_string(),
        "sim".to_string(),
        format!("prog {}", v.elf),
        mw,
    ];
    if v.name.contains("hw") {
        args.push("simio add hwmult mpy".to_string());
    }
    args.extend(extra.iter().cloned());
    // Output goes to a file (no pipe to fill); a run that does not stop in time is killed.
    static SEQ: AtomicUsize = AtomicUsize::new(0);
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../../target/eabi/runs");
    std::fs::create_dir_all(dir).map_err(|e| e.to_string())?;
    let path = format!(
        "{dir}/run-{}-{}.txt",
        std::process::id(),
        SEQ.fetch_add(1, Ordering::SeqCst)
    );
    let file = std::fs::File::create(&path).map_err(|e| e.to_string())?;
    let err = file.try_clone().map_err(|e| e.to_string())?;
    let mut child = Command::new("mspdebug")
        .args(&args)
        .stdin(std::process::Stdio::null())
        .stdout(file)
        .stderr(err)
        .spawn()
        .map_err(|e| format!("cannot run mspdebug: {e} (apt-get install mspdebug)"))?;
    let t0 = Instant::now();
    let status = loop {
        if let Some(st) = child.try_wait().map_err(|e| e.to_string())? {
            break st;
        }
        if t0.elapsed().as_secs() > timeout_s {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "mspdebug did not stop within {timeout_s} s (a helper that loops?): {args:?}"
            ));
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    let text = std::fs::read_to_string(&path).unwrap_or_default();
    let _ = std::fs::remove_file(&path);
    if !status.success() {
        return Err(format!("mspdebug failed: {text}"));
    }
    Ok(text)
}

/// Parse `md` output lines (`    00400: xx xx ... |...|`) into a byte map for [lo, lo+len).
fn parse_md(text: &str, lo: u32, len: u32) -> Vec<u8> {
    let mut mem = vec![0u8; len as usize];
    for line in text.lines() {
        let t = line.trim_start();
        let Some((addr, rest)) = t.split_once(": ") else {
            continue;
        };
        let Ok(addr) = u32::from_str_radix(addr, 16) else {
            continue;
        };
        let hex = rest.split('|').next().unwrap_or("");
        for (i, b) in hex.split_whitespace().enumerate() {
            let Ok(b) = u8::from_str_radix(b, 16) else {
                break;
            };
            if i >= 16 {
                break;
            }
            let a = addr + i as u32;
            if a >= lo && a < lo + len {
                mem[(a - lo) as usize] = b;
            }
        }
    }
    mem
}

fn words(mem: &[u8]) -> Vec<u32> {
    mem.chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

fn run_firmware(v: &Variant, params: &[u16], nwords: u32) -> Result<Vec<u32>, String> {
    let extra = vec![
        "setbreak tf_done".to_string(),
        "run".to_string(),
        format!("md 0x{IO:04x} 16"),
        format!("md 0x{RES:04x} {}", nwords * 4),
    ];
    let text = mspdebug(v, params, &extra, 120 + 4 * nwords as u64)?;
    let io = parse_md(&text, IO, 16);
    let status = u16::from_le_bytes([io[14], io[15]]);
    if status != 0xd00e {
        return Err(format!(
            "firmware did not finish (status {status:#06x}):\n{text}"
        ));
    }
    Ok(words(&parse_md(&text, RES, nwords * 4)))
}

/// Blocks of 256 cases per operation at scale 1.
fn default_blocks(op: &str) -> u16 {
    match op {
        "addd" | "subd" | "mpyd" | "divd" | "cmpd" => 32,
        "fixdli" | "fixdul" | "fixdlli" | "fixdull" | "fltlid" | "fltuld" | "fltllid"
        | "fltulld" | "cvtfd" | "cvtdf" | "fixflli" | "fixfull" | "fltllif" | "fltullf" => 64,
        "mpyll" | "mpyll32" | "divlli" | "remlli" | "divull" | "remull" => 64,
        _ => 1024,
    }
}

fn host_hashes(seed: u32, op: u16, nblocks: u16) -> Vec<u32> {
    (0..nblocks)
        .map(|b| {
            let mut r = cases::Rng::new(seed, op, b);
            let mut h = 0u32;
            for _ in 0..cases::BLOCK {
                let (_, (x, y)) = cases::case(op, &mut r);
                h = cases::mix(cases::mix(h, x), y);
            }
            h
        })
        .collect()
}

fn verify_op(v: &Variant, seed: u32, op: u16, nblocks: u16) -> Result<String, String> {
    let name = cases::OPS[op as usize];
    let t0 = Instant::now();
    let got = run_firmware(
        v,
        &[0, 1, op, nblocks, seed as u16, (seed >> 16) as u16, 0, 0, 0],
        nblocks as u32,
    )?;
    let want = host_hashes(seed, op, nblocks);
    let bad: Vec<u16> = (0..nblocks)
        .filter(|&b| got[b as usize] != want[b as usize])
        .collect();
    let ncases = nblocks as u32 * cases::BLOCK as u32;
    if bad.is_empty() {
        return Ok(format!(
            "{:<6} {:<8} {:>7} cases bit-exact ({:.1} s)",
            v.name,
            name,
            ncases,
            t0.elapsed().as_secs_f64()
        ));
    }
    let mut msg = format!(
        "{:<6} {:<8} {} of {} blocks differ",
        v.name,
        name,
        bad.len(),
        nblocks
    );
    // Dump the first bad block and print its failing cases.
    let b = bad[0];
    let dump = run_firmware(
        v,
        &[0, 2, op, 0, seed as u16, (seed >> 16) as u16, b, 0, 0],
        2 * cases::BLOCK as u32,
    )?;
    let mut r = cases::Rng::new(seed, op, b);
    let mut shown = 0;
    let mut nfail = 0;
    for i in 0..cases::BLOCK as usize {
        let (inp, (x, y)) = cases::case(op, &mut r);
        let (gx, gy) = (dump[2 * i], dump[2 * i + 1]);
        if (gx, gy) != (x, y) {
            nfail += 1;
            if shown < 12 {
                msg.push_str(&format!(
                    "\n    in {:08x} {:08x} {:08x} {:08x}  want {:08x} {:08x}  got {:08x} {:08x}",
                    inp[0], inp[1], inp[2], inp[3], x, y, gx, gy
                ));
                shown += 1;
            }
        }
    }
    msg.push_str(&format!(
        "\n    block {b}: {nfail} of {} cases differ",
        cases::BLOCK
    ));
    Err(msg)
}

fn bench(variants: &[Variant], ops: &[String]) -> Result<(), String> {
    let mut rows = Vec::new();
    for v in variants {
        let mut col = Vec::new();
        for (k, &name) in bench_ops::BENCH.iter().enumerate() {
            if !ops.is_empty() && !ops.iter().any(|o| o == name) && name != "empty" {
                continue;
            }
            let extra = vec![
                "simio add tracer t".to_string(),
                "setbreak tf_mark".to_string(),
                "run".to_string(),
                "simio info t".to_string(),
                "run".to_string(),
                "simio info t".to_string(),
            ];
            let reps = bench_ops::REPS;
            let text = mspdebug(v, &[0, 3, k as u16, 0, 0, 0, 0, 0, reps], &extra, 600)?;
            let mut c = Vec::new();
            let mut n = Vec::new();
            for line in text.lines() {
                if let Some(x) = line.trim().strip_prefix("MCLK:") {
                    c.push(x.trim().parse::<u64>().map_err(|e| e.to_string())?);
                }
                if let Some(x) = line.trim().strip_prefix("Instruction count:") {
                    n.push(x.trim().parse::<u64>().map_err(|e| e.to_string())?);
                }
            }
            if c.len() != 2 || n.len() != 2 {
                return Err(format!("bench {name}: cannot read the tracer:\n{text}"));
            }
            col.push((name, c[1] - c[0], n[1] - n[0]));
        }
        rows.push((v.name.clone(), col));
    }
    // Per-call figures: (total - empty loop) / (reps * sets).
    let calls = bench_ops::REPS as f64 * bench_ops::SETS as f64;
    let mut json = String::from("{");
    println!(
        "{:<10} {}",
        "op",
        rows.iter()
            .map(|(n, _)| format!("{:>14}", format!("{n} cycles")))
            .collect::<String>()
    );
    let names: Vec<&str> = rows[0].1.iter().map(|r| r.0).collect();
    for (i, name) in names.iter().enumerate() {
        if *name == "empty" {
            continue;
        }
        let mut line = format!("{name:<10}");
        for (vn, col) in &rows {
            let empty = col
                .iter()
                .find(|r| r.0 == "empty")
                .map(|r| (r.1, r.2))
                .unwrap_or((0, 0));
            let cyc = (col[i].1 as f64 - empty.0 as f64) / calls;
            let ins = (col[i].2 as f64 - empty.1 as f64) / calls;
            line.push_str(&format!("{cyc:>14.0}"));
            json.push_str(&format!(
                "{}\"{name}/{vn}\": {{\"cycles\": {:.0}, \"instructions\": {:.0}}}",
                if json.len() > 1 { ", " } else { "" },
                cyc,
                ins
            ));
        }
        println!("{line}");
    }
    json.push('}');
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../../..");
    let path = format!("{root}/target/eabi/cycles.json");
    std::fs::write(&path, json + "\n").map_err(|e| e.to_string())?;
    println!("(MCLK cycles per call, typical operands, call overhead included; written to target/eabi/cycles.json)");
    Ok(())
}

fn main() {
    let mut variants = Vec::new();
    let mut ops: Vec<String> = Vec::new();
    let mut scale = 1.0f64;
    let mut seed = 0x2545_f491u32;
    let mut do_bench = false;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--elf" => {
                let s = args.next().expect("--elf NAME=PATH");
                let (n, p) = s.split_once('=').expect("--elf NAME=PATH");
                variants.push(Variant {
                    name: n.to_string(),
                    elf: p.to_string(),
                });
            }
            "--ops" => {
                ops = args
                    .next()
                    .expect("--ops a,b")
                    .split(',')
                    .map(str::to_string)
                    .collect()
            }
            "--scale" => scale = args.next().expect("--scale F").parse().expect("--scale F"),
            "--seed" => {
                seed = u32::from_str_radix(
                    args.next().expect("--seed HEX").trim_start_matches("0x"),
                    16,
                )
                .expect("hex seed")
            }
            "--bench" => do_bench = true,
            _ => {
                eprintln!("usage: msp430-eabi-verify [--elf NAME=PATH]... [--ops a,b] [--scale F] [--seed HEX] [--bench]");
                std::process::exit(2);
            }
        }
    }
    if do_bench {
        if let Err(e) = bench(&variants, &ops) {
            eprintln!("{e}");
            std::process::exit(1);
        }
        return;
    }
    let mut jobs = Vec::new();
    for vi in 0..variants.len() {
        for (op, &name) in cases::OPS.iter().enumerate() {
            if !ops.is_empty() && !ops.iter().any(|o| o == name) {
                continue;
            }
            let nb = ((default_blocks(name) as f64 * scale).round() as u16).clamp(1, 1024);
            jobs.push((vi, op as u16, nb));
        }
    }
    let next = AtomicUsize::new(0);
    let failed = Mutex::new(Vec::new());
    let passed = AtomicUsize::new(0);
    let threads = std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(2)
        .min(4);
    let t0 = Instant::now();
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                let Some(&(vi, op, nb)) = jobs.get(i) else {
                    break;
                };
                match verify_op(&variants[vi], seed, op, nb) {
                    Ok(m) => {
                        println!("ok   {m}");
                        passed.fetch_add(1, Ordering::SeqCst);
                    }
                    Err(m) => {
                        println!("FAIL {m}");
                        failed.lock().unwrap().push(m);
                    }
                }
            });
        }
    });
    let failed = failed.into_inner().unwrap();
    println!(
        "verification took {:.0} s, seed {seed:#010x}",
        t0.elapsed().as_secs_f64()
    );
    println!(
        "{} passed, {} failed",
        passed.load(Ordering::SeqCst),
        failed.len()
    );
    if !failed.is_empty() {
        std::process::exit(1);
    }
}
