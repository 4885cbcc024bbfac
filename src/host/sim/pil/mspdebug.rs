//! One `mspdebug` simulator process driven through pipes, one command at a time.
//!
//! `mspdebug -q sim` with its standard input a pipe reads one command per line; before each it
//! prints its prompt `(mspdebug) ` (no newline) and echoes the command it read, and its error
//! messages go to standard error. A command is complete when the output ends with the next
//! prompt. (Its `--embedded` mode frames the output better, but it drops a command that
//! arrives before its reader thread waits for one, as its `EmbeddedMode.txt` says; that was
//! seen here at the first command. Plain commands on a pipe queue instead.) Reader threads
//! forward both streams, so that a `run` that never reaches a break point ends in a time-out
//! (the process is killed) instead of hanging the host.
//!
//! The commands used: `prog` (load an ELF), `simio add tracer t` (MCLK cycle and instruction
//! counters, read with `simio info t`), `simio add hwmult m` (the 16-bit hardware multiplier
//! the flight image uses), `setbreak`/`delbreak`, `run`, `regs`/`set`, `md`/`mw`. Numbers
//! are written in hex with a `0x` prefix (mspdebug's input radix is decimal); `mw` takes at
//! most [`MW_CHUNK`] bytes per command here (mspdebug reads lines of at most 1 024 characters:
//! a longer `mw` was measured to stop short).

use std::io::{Read, Write};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// Bytes written per `mw` command.
pub const MW_CHUNK: usize = 64;

/// mspdebug's prompt.
const PROMPT: &str = "(mspdebug) ";

/// Register names in mspdebug's dump, by register number (R3 is the constant generator).
const REGISTERS: [&str; 16] = [
    "PC", "SP", "SR", "R3", "R4", "R5", "R6", "R7", "R8", "R9", "R10", "R11", "R12", "R13", "R14",
    "R15",
];

/// What went wrong with the simulator process.
#[derive(Debug)]
pub enum MspdebugError {
    /// It could not be started (not installed?).
    Spawn(String),
    /// It exited or closed its output.
    Exited,
    /// A command printed an error.
    Command {
        /// The command.
        command: String,
        /// Its error output.
        message: String,
    },
    /// A command did not finish in time (the process was stopped).
    Timeout {
        /// The command.
        command: String,
        /// The time allowed, s.
        seconds: u64,
    },
    /// An answer could not be read.
    Parse {
        /// The command.
        command: String,
        /// What was expected.
        expected: &'static str,
    },
}

impl std::fmt::Display for MspdebugError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Spawn(m) => write!(
                f,
                "cannot start mspdebug ({m}); install it: apt-get install mspdebug"
            ),
            Self::Exited => f.write_str("mspdebug exited"),
            Self::Command { command, message } => write!(f, "mspdebug `{command}`: {message}"),
            Self::Timeout { command, seconds } => {
                write!(f, "mspdebug `{command}` did not finish within {seconds} s")
            }
            Self::Parse { command, expected } => {
                write!(
                    f,
                    "mspdebug `{command}`: cannot read {expected} in its answer"
                )
            }
        }
    }
}

/// The CPU registers R0 (PC) to R15, as 16-bit values.
pub type Registers = [u16; 16];

/// A running `mspdebug -q sim`.
pub struct Mspdebug {
    child: Child,
    stdin: ChildStdin,
    out: Receiver<Vec<u8>>,
    err: Receiver<Vec<u8>>,
    /// Output received and not yet consumed.
    pending: Vec<u8>,
    /// Time allowed for one command.
    pub timeout: Duration,
}

/// Forwards everything `stream` gives to `tx`, chunk by chunk, until it ends.
fn forward(mut stream: impl Read + Send + 'static, tx: mpsc::Sender<Vec<u8>>) {
    std::thread::spawn(move || {
        let mut buf = [0u8; 8192];
        while let Ok(n) = stream.read(&mut buf) {
            if n == 0 || tx.send(buf[..n].to_vec()).is_err() {
                break;
            }
        }
    });
}

impl Mspdebug {
    /// Starts `program` (normally `mspdebug`) on its simulator driver.
    pub fn start(program: &str, timeout: Duration) -> Result<Self, MspdebugError> {
        let mut child = Command::new(program)
            .args(["-q", "sim"])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| MspdebugError::Spawn(format!("{program}: {e}")))?;
        let (Some(stdin), Some(stdout), Some(stderr)) =
            (child.stdin.take(), child.stdout.take(), child.stderr.take())
        else {
            let _ = child.kill();
            return Err(MspdebugError::Spawn("no pipes".into()));
        };
        let (out_tx, out) = mpsc::channel();
        let (err_tx, err) = mpsc::channel();
        forward(stdout, out_tx);
        forward(stderr, err_tx);
        let mut m = Self {
            child,
            stdin,
            out,
            err,
            pending: Vec::new(),
            timeout,
        };
        m.wait_prompt("(start)")?;
        Ok(m)
    }

    /// Waits for the prompt; the output before it as lines, or the error output.
    fn wait_prompt(&mut self, command: &str) -> Result<Vec<String>, MspdebugError> {
        let deadline = Instant::now() + self.timeout;
        while !self.pending.ends_with(PROMPT.as_bytes()) {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.out.recv_timeout(left) {
                Ok(chunk) => self.pending.extend_from_slice(&chunk),
                Err(RecvTimeoutError::Timeout) => {
                    let _ = self.child.kill();
                    return Err(MspdebugError::Timeout {
                        command: command.to_string(),
                        seconds: self.timeout.as_secs(),
                    });
                }
                Err(RecvTimeoutError::Disconnected) => return Err(MspdebugError::Exited),
            }
        }
        let text = String::from_utf8_lossy(&self.pending[..self.pending.len() - PROMPT.len()])
            .into_owned();
        self.pending.clear();
        let mut errors = Vec::new();
        while let Ok(chunk) = self.err.try_recv() {
            errors.extend_from_slice(&chunk);
        }
        if !errors.is_empty() {
            return Err(MspdebugError::Command {
                command: command.to_string(),
                message: String::from_utf8_lossy(&errors).trim().replace('\n', "; "),
            });
        }
        // the echo of the command (readline) is the first line
        let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
        if lines.first().is_some_and(|l| l.trim() == command) {
            lines.remove(0);
        }
        Ok(lines)
    }

    /// Runs one command; its normal output lines.
    pub fn command(&mut self, command: &str) -> Result<Vec<String>, MspdebugError> {
        writeln!(self.stdin, "{command}").map_err(|_| MspdebugError::Exited)?;
        self.stdin.flush().map_err(|_| MspdebugError::Exited)?;
        self.wait_prompt(command)
    }

    /// Sets a break point at `addr`; its number.
    pub fn set_break(&mut self, addr: u32) -> Result<u32, MspdebugError> {
        let command = format!("setbreak 0x{addr:x}");
        let out = self.command(&command)?;
        out.iter()
            .find_map(|l| l.trim().strip_prefix("Set breakpoint "))
            .and_then(|n| n.trim().parse().ok())
            .ok_or(MspdebugError::Parse {
                command,
                expected: "the break point number",
            })
    }

    /// Deletes break point `n`.
    pub fn delete_break(&mut self, n: u32) -> Result<(), MspdebugError> {
        self.command(&format!("delbreak {n}")).map(|_| ())
    }

    /// Runs to the next break point; the registers there.
    pub fn run(&mut self) -> Result<Registers, MspdebugError> {
        let out = self.command("run")?;
        parse_registers(&out).ok_or(MspdebugError::Parse {
            command: "run".into(),
            expected: "the registers at a break point",
        })
    }

    /// The registers now.
    pub fn registers(&mut self) -> Result<Registers, MspdebugError> {
        let out = self.command("regs")?;
        parse_registers(&out).ok_or(MspdebugError::Parse {
            command: "regs".into(),
            expected: "the registers",
        })
    }

    /// Sets every register but R3 (the constant generator) to `regs`.
    pub fn set_registers(&mut self, regs: &Registers) -> Result<(), MspdebugError> {
        for (name, value) in REGISTERS.iter().zip(regs) {
            if *name != "R3" {
                self.command(&format!("set {name} 0x{value:x}"))?;
            }
        }
        Ok(())
    }

    /// Reads `len` bytes at `addr`.
    pub fn read(&mut self, addr: u32, len: usize) -> Result<Vec<u8>, MspdebugError> {
        let command = format!("md 0x{addr:x} {len}");
        let out = self.command(&command)?;
        let bytes = parse_memory(&out, addr, len);
        bytes.ok_or(MspdebugError::Parse {
            command,
            expected: "the memory dump",
        })
    }

    /// Writes `bytes` at `addr`.
    pub fn write(&mut self, addr: u32, bytes: &[u8]) -> Result<(), MspdebugError> {
        for (k, chunk) in bytes.chunks(MW_CHUNK).enumerate() {
            let mut command = format!("mw 0x{:x}", addr as usize + k * MW_CHUNK);
            for b in chunk {
                command.push_str(&format!(" 0x{b:02x}"));
            }
            self.command(&command)?;
        }
        Ok(())
    }

    /// The tracer's MCLK cycle count since it was added (`simio info t`).
    pub fn cycles(&mut self) -> Result<u64, MspdebugError> {
        let out = self.command("simio info t")?;
        out.iter()
            .find_map(|l| l.trim().strip_prefix("MCLK:"))
            .and_then(|n| n.trim().parse().ok())
            .ok_or(MspdebugError::Parse {
                command: "simio info t".into(),
                expected: "the MCLK count",
            })
    }
}

impl Drop for Mspdebug {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The registers of mspdebug's dump (`( PC: 0388a)  ( R4: 00000) ...`), if all 16 are there.
pub fn parse_registers(lines: &[String]) -> Option<Registers> {
    let mut regs = [None; 16];
    for line in lines {
        for group in line.split('(').skip(1) {
            let Some((name, rest)) = group.split_once(':') else {
                continue;
            };
            let value = rest.split(')').next().unwrap_or("").trim();
            if let (Some(i), Ok(v)) = (
                REGISTERS.iter().position(|r| *r == name.trim()),
                u32::from_str_radix(value, 16),
            ) {
                regs[i] = Some((v & 0xFFFF) as u16);
            }
        }
    }
    let mut out = [0u16; 16];
    for (o, r) in out.iter_mut().zip(regs) {
        *o = r?;
    }
    Some(out)
}

/// `len` bytes from `addr` of mspdebug's memory dump (`    00200: 01 02 ... |..|`), if all
/// are there.
pub fn parse_memory(lines: &[String], addr: u32, len: usize) -> Option<Vec<u8>> {
    let mut bytes = vec![None; len];
    for line in lines {
        let Some((at, rest)) = line.trim().split_once(':') else {
            continue;
        };
        let Ok(at) = u32::from_str_radix(at.trim(), 16) else {
            continue;
        };
        let hex = rest.split('|').next().unwrap_or("");
        for (j, token) in hex.split_whitespace().enumerate() {
            let b = u8::from_str_radix(token, 16).ok()?;
            let k = (at as usize + j).checked_sub(addr as usize);
            if let Some(slot) = k.and_then(|k| bytes.get_mut(k)) {
                *slot = Some(b);
            }
        }
    }
    bytes.into_iter().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(text: &str) -> Vec<String> {
        text.lines().map(str::to_string).collect()
    }

    #[test]
    fn reads_register_dumps() {
        let out = lines(
            "    ( PC: 0388a)  ( R4: 00000)  ( R8: 00000)  (R12: 00001)  \n\
             \x20   ( SP: 02d4e)  ( R5: 00000)  ( R9: 00000)  (R13: 03000)  \n\
             \x20   ( SR: 00001)  ( R6: 00000)  (R10: 0ffff)  (R14: 03000)  \n\
             \x20   ( R3: 00000)  ( R7: 00000)  (R11: 00000)  (R15: 00007)  \n\
             bench_mark:\n\
             \x20   0388a: 82 4c 02 02               MOV     R12,    &BENCH_ID",
        );
        let r = parse_registers(&out).unwrap();
        assert_eq!(r[0], 0x388a);
        assert_eq!(r[1], 0x2d4e);
        assert_eq!(r[10], 0xffff);
        assert_eq!(r[12], 1);
        assert_eq!(r[15], 7);
        assert_eq!(parse_registers(&out[..2]), None);
    }

    #[test]
    fn reads_memory_dumps() {
        let out = lines(
            "    01000: 00 01 02 03 04 05 06 07 08 09 0a 0b 0c 0d 0e 0f |................|\n\
             \x20   01010: 70 71 7c                                        |pq|             |",
        );
        let m = parse_memory(&out, 0x100e, 5).unwrap();
        assert_eq!(m, vec![0x0e, 0x0f, 0x70, 0x71, 0x7c]);
        assert_eq!(parse_memory(&out, 0x1010, 4), None);
    }
}
