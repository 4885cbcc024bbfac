//! The symbol table and section sizes of a 32-bit little-endian ELF file (the MSP430 flight
//! image), read without a dependency.
//!
//! Only what the processor-in-the-loop host needs: the address and size of each named symbol
//! (the mailboxes, the break-point functions, the stack bounds of the linker script) and the
//! size of each section (flash and static RAM of the image). Layout from the System V ABI,
//! "Object Files" (`Elf32_Ehdr`, `Elf32_Shdr`, `Elf32_Sym`).
//!
//! | field | offset | bytes |
//! |---|---|---|
//! | `e_ident` (`\x7fELF`, class 1 = 32-bit, data 1 = little-endian) | 0 | 16 |
//! | `e_machine` (105 = MSP430) | 18 | 2 |
//! | `e_shoff` (section header table) | 32 | 4 |
//! | `e_shentsize`, `e_shnum`, `e_shstrndx` | 46, 48, 50 | 2 each |
//! | `Elf32_Shdr`: name, type, flags, addr, offset, size, link | 0, 4, 8, 12, 16, 20, 24 | 4 each |
//! | `Elf32_Sym` (16 B): name, value, size, info, other, shndx | 0, 4, 8, 12, 13, 14 | 4, 4, 4, 1, 1, 2 |

use std::collections::BTreeMap;

/// `e_machine` of the MSP430.
pub const EM_MSP430: u16 = 105;
/// `sh_type` of a symbol table.
const SHT_SYMTAB: u32 = 2;
/// Size of one `Elf32_Sym`.
const SYM_SIZE: usize = 16;

/// A named symbol: its address (`st_value`) and size in bytes (`st_size`, 0 when unknown).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Symbol {
    /// Address.
    pub addr: u32,
    /// Size, bytes.
    pub size: u32,
}

/// A section: address and size in bytes.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Section {
    /// Load address.
    pub addr: u32,
    /// Size, bytes.
    pub size: u32,
}

/// The symbols and sections of an ELF image.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Elf {
    /// `e_machine`.
    pub machine: u16,
    symbols: BTreeMap<String, Symbol>,
    sections: BTreeMap<String, Section>,
}

/// Why an ELF file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ElfError {
    /// Not a 32-bit little-endian ELF file.
    NotElf32Le,
    /// A header or table lies outside the file (what, and the offset).
    Truncated(&'static str, usize),
    /// No symbol table (a stripped image).
    NoSymbols,
}

impl std::fmt::Display for ElfError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotElf32Le => f.write_str("not a 32-bit little-endian ELF file"),
            Self::Truncated(what, at) => write!(f, "truncated ELF file: {what} at byte {at}"),
            Self::NoSymbols => f.write_str("the ELF file has no symbol table (stripped?)"),
        }
    }
}

fn u16_at(data: &[u8], at: usize, what: &'static str) -> Result<u16, ElfError> {
    data.get(at..at + 2)
        .and_then(|b| b.try_into().ok())
        .map(u16::from_le_bytes)
        .ok_or(ElfError::Truncated(what, at))
}

fn u32_at(data: &[u8], at: usize, what: &'static str) -> Result<u32, ElfError> {
    data.get(at..at + 4)
        .and_then(|b| b.try_into().ok())
        .map(u32::from_le_bytes)
        .ok_or(ElfError::Truncated(what, at))
}

/// The NUL-terminated string at `at` (empty if out of range or not UTF-8).
fn str_at(data: &[u8], at: usize) -> String {
    let tail = data.get(at..).unwrap_or(&[]);
    let end = tail.iter().position(|b| *b == 0).unwrap_or(tail.len());
    String::from_utf8_lossy(&tail[..end]).into_owned()
}

/// One section header: (name offset, type, addr, offset, size, link).
struct Shdr {
    name: u32,
    kind: u32,
    addr: u32,
    offset: u32,
    size: u32,
    link: u32,
}

impl Elf {
    /// Reads the section headers and the symbol table of `data`.
    pub fn parse(data: &[u8]) -> Result<Self, ElfError> {
        if data.get(0..6) != Some(&[0x7f, b'E', b'L', b'F', 1, 1][..]) {
            return Err(ElfError::NotElf32Le);
        }
        let machine = u16_at(data, 18, "e_machine")?;
        let shoff = u32_at(data, 32, "e_shoff")? as usize;
        let shentsize = usize::from(u16_at(data, 46, "e_shentsize")?);
        let shnum = usize::from(u16_at(data, 48, "e_shnum")?);
        let shstrndx = usize::from(u16_at(data, 50, "e_shstrndx")?);
        let mut headers = Vec::with_capacity(shnum);
        for i in 0..shnum {
            let at = shoff + i * shentsize;
            headers.push(Shdr {
                name: u32_at(data, at, "section header")?,
                kind: u32_at(data, at + 4, "section header")?,
                addr: u32_at(data, at + 12, "section header")?,
                offset: u32_at(data, at + 16, "section header")?,
                size: u32_at(data, at + 20, "section header")?,
                link: u32_at(data, at + 24, "section header")?,
            });
        }
        let names_at = headers.get(shstrndx).map_or(0, |h| h.offset as usize);
        let mut elf = Self {
            machine,
            ..Self::default()
        };
        for h in &headers {
            let name = str_at(data, names_at + h.name as usize);
            elf.sections.insert(
                name,
                Section {
                    addr: h.addr,
                    size: h.size,
                },
            );
        }
        let symtab = headers
            .iter()
            .find(|h| h.kind == SHT_SYMTAB)
            .ok_or(ElfError::NoSymbols)?;
        let strings_at = headers
            .get(symtab.link as usize)
            .map_or(0, |h| h.offset as usize);
        let start = symtab.offset as usize;
        let end = start + symtab.size as usize;
        if data.len() < end {
            return Err(ElfError::Truncated("symbol table", start));
        }
        for at in (start..end).step_by(SYM_SIZE) {
            let name = u32_at(data, at, "symbol")?;
            if name == 0 {
                continue;
            }
            let symbol = Symbol {
                addr: u32_at(data, at + 4, "symbol")?,
                size: u32_at(data, at + 8, "symbol")?,
            };
            elf.symbols
                .insert(str_at(data, strings_at + name as usize), symbol);
        }
        Ok(elf)
    }

    /// The symbol `name`, if defined.
    pub fn symbol(&self, name: &str) -> Option<Symbol> {
        self.symbols.get(name).copied()
    }

    /// The Rust function at `path` (e.g. `["acs_firmware", "flight", "take_uplink"]`), found
    /// by its mangled name whatever the crate's hash: legacy mangling
    /// `_ZN12acs_firmware6flight11take_uplink17h<hash>E`, or v0 mangling (the toolchain's
    /// default) `_RNvNtCs<hash>_12acs_firmware6flight11take_uplink`, or the v0 name of an
    /// instance of a generic function (`_RINvNtCs<hash>_12acs_firmware6flight16take_telecommand`
    /// followed by its type arguments; not an instance of another function whose type
    /// arguments name it, such as a closure passed to it). `None` if there is none or more
    /// than one (several instances of a generic function).
    pub fn rust_function(&self, path: &[&str]) -> Option<Symbol> {
        let encoded: String = path.iter().map(|p| format!("{}{p}", p.len())).collect();
        let legacy = format!("_ZN{encoded}");
        let v0_hashed = format!("_{encoded}");
        let v0_plain = format!("C{encoded}");
        // the instance's own path comes first: `_RINv`, `Nt` per module, the crate root
        // (`C` and its hash), the path; a symbol that only mentions the function further on
        // (a closure or callee instantiated with it) is another function
        let instance_of = |n: &str| {
            let Some(rest) = n.strip_prefix("_RINv") else {
                return false;
            };
            let at = |p: &str| rest.find(p).map(|i| &rest[..i]);
            let root = |head: &str, hashed: bool| {
                let mut head = head;
                while let Some(h) = head.strip_prefix("Nt") {
                    head = h;
                }
                if hashed {
                    head.strip_prefix('C')
                        .is_some_and(|h| h.chars().all(|c| c.is_ascii_alphanumeric()))
                } else {
                    head.is_empty()
                }
            };
            at(&v0_hashed).is_some_and(|h| root(h, true))
                || at(&v0_plain).is_some_and(|h| root(h, false))
        };
        let mut found = self
            .symbols
            .iter()
            .filter(|(n, _)| {
                let legacy_match = n
                    .strip_prefix(&legacy)
                    .is_some_and(|rest| rest.starts_with("17h") && rest.len() == 20);
                let v0_match =
                    n.starts_with("_R") && (n.ends_with(&v0_hashed) || n.ends_with(&v0_plain));
                let v0_instance = !n.ends_with(&v0_hashed) && instance_of(n);
                legacy_match || v0_match || v0_instance
            })
            .map(|(_, s)| *s);
        let first = found.next()?;
        found.next().is_none().then_some(first)
    }

    /// The section `name`, if present.
    pub fn section(&self, name: &str) -> Option<Section> {
        self.sections.get(name).copied()
    }

    /// Flash bytes of the image: vector table, code, constants and the `.data` image.
    pub fn flash_bytes(&self) -> u32 {
        [".vector_table", ".text", ".rodata", ".data"]
            .iter()
            .filter_map(|n| self.section(n))
            .map(|s| s.size)
            .sum()
    }

    /// Static RAM bytes of the image: `.data` and `.bss`.
    pub fn static_ram_bytes(&self) -> u32 {
        [".data", ".bss"]
            .iter()
            .filter_map(|n| self.section(n))
            .map(|s| s.size)
            .sum()
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A minimal 32-bit little-endian ELF: a null section, `.shstrtab`, `.strtab`, `.symtab`
    /// with `symbols` (name, addr, size), and a `.bss` of `bss` bytes.
    pub(crate) fn tiny_elf(symbols: &[(&str, u32, u32)], bss: u32) -> Vec<u8> {
        let shstr = b"\0.shstrtab\0.strtab\0.symtab\0.bss\0".to_vec();
        let mut strtab = vec![0u8];
        let mut symtab = vec![0u8; SYM_SIZE]; // the null symbol
        for (name, addr, size) in symbols {
            let off = strtab.len() as u32;
            strtab.extend_from_slice(name.as_bytes());
            strtab.push(0);
            symtab.extend_from_slice(&off.to_le_bytes());
            symtab.extend_from_slice(&addr.to_le_bytes());
            symtab.extend_from_slice(&size.to_le_bytes());
            symtab.extend_from_slice(&[0x11, 0, 1, 0]);
        }
        let mut data = vec![0u8; 52];
        data[0..6].copy_from_slice(&[0x7f, b'E', b'L', b'F', 1, 1]);
        data[18..20].copy_from_slice(&EM_MSP430.to_le_bytes());
        let shstr_off = data.len() as u32;
        data.extend_from_slice(&shstr);
        let str_off = data.len() as u32;
        data.extend_from_slice(&strtab);
        let sym_off = data.len() as u32;
        data.extend_from_slice(&symtab);
        let shoff = data.len() as u32;
        data[32..36].copy_from_slice(&shoff.to_le_bytes());
        data[46..48].copy_from_slice(&40u16.to_le_bytes());
        data[48..50].copy_from_slice(&5u16.to_le_bytes());
        data[50..52].copy_from_slice(&1u16.to_le_bytes());
        // (name, type, addr, offset, size, link)
        let headers: [(u32, u32, u32, u32, u32, u32); 5] = [
            (0, 0, 0, 0, 0, 0),
            (1, 3, 0, shstr_off, shstr.len() as u32, 0),
            (11, 3, 0, str_off, strtab.len() as u32, 0),
            (19, SHT_SYMTAB, 0, sym_off, symtab.len() as u32, 2),
            (27, 8, 0x200, 0, bss, 0),
        ];
        for (name, kind, addr, offset, size, link) in headers {
            for w in [name, kind, 0, addr, offset, size, link, 0, 0, 0] {
                data.extend_from_slice(&w.to_le_bytes());
            }
        }
        data
    }

    #[test]
    fn reads_symbols_sections_and_mangled_functions() {
        let data = tiny_elf(
            &[
                ("TILE_SUN", 0x0200, 24),
                ("fw_period_start", 0x4000, 4),
                (
                    "_ZN12acs_firmware6flight11take_uplink17h0123456789abcdefE",
                    0x5000,
                    300,
                ),
                (
                    "_ZN12acs_firmware6flight12take_uplinks17h0123456789abcdefE",
                    0x6000,
                    2,
                ),
                (
                    "_RNvNtCs1A0YsCYRuPp_12acs_firmware6flight7publish",
                    0x7000,
                    40,
                ),
                (
                    "_RNCNvNtCs1A0YsCYRuPp_12acs_firmware6flight7publish0",
                    0x7100,
                    4,
                ),
                (
                    "_RINvNtCshTh0V548xLH_12acs_firmware6flight16take_node_uplinkNCNvCs5YbJjKyC2MG_12acs_attitude3run0EBZ_",
                    0x7200,
                    90,
                ),
                // an instance of another function whose type arguments name take_node_uplink
                // (telecommand::take with the closure take_node_uplink passes it)
                (
                    "_RINvNtNtCsbMAO0B0id9_3acs6uplink11telecommand4takeNCINvNtCshTh0V548xLH_12acs_firmware6flight16take_node_uplinkKj24_E0EB2z_",
                    0x7300,
                    900,
                ),
            ],
            344,
        );
        let elf = Elf::parse(&data).unwrap();
        assert_eq!(elf.machine, EM_MSP430);
        assert_eq!(
            elf.symbol("TILE_SUN"),
            Some(Symbol {
                addr: 0x200,
                size: 24
            })
        );
        assert_eq!(elf.symbol("fw_period_start").unwrap().addr, 0x4000);
        assert_eq!(elf.symbol("nothing"), None);
        let take = elf
            .rust_function(&["acs_firmware", "flight", "take_uplink"])
            .unwrap();
        assert_eq!(take.addr, 0x5000);
        let publish = elf.rust_function(&["acs_firmware", "flight", "publish"]);
        assert_eq!(publish.unwrap().addr, 0x7000);
        // the one instance of a generic function
        let node_uplink = elf.rust_function(&["acs_firmware", "flight", "take_node_uplink"]);
        assert_eq!(node_uplink.unwrap().addr, 0x7200);
        assert_eq!(
            elf.rust_function(&["acs_firmware", "flight", "init_loop"]),
            None
        );
        assert_eq!(elf.section(".bss").unwrap().size, 344);
        assert_eq!(elf.static_ram_bytes(), 344);
        assert_eq!(elf.flash_bytes(), 0);
    }

    #[test]
    fn refuses_what_is_not_an_elf32_le_with_symbols() {
        assert_eq!(Elf::parse(b"not an elf"), Err(ElfError::NotElf32Le));
        let mut data = tiny_elf(&[], 0);
        data.truncate(60);
        assert!(matches!(Elf::parse(&data), Err(ElfError::Truncated(..))));
    }
}
