//! Every FMU in dist/ loads on every Linux with glibc 2.17 or newer (issue 19): no shared
//! library in `binaries/linux64/` asks for a symbol version newer than GLIBC_2.17.
//!
//! The versions a library needs are read from its ELF `.gnu.version_r` section (the
//! `Elf64_Verneed` / `Elf64_Vernaux` records the dynamic loader checks before it runs any code),
//! parsed here rather than with objdump, so the test needs no tool. `build-fmus --host-build`
//! links against this machine's glibc and fails this test, by design.

#![cfg(target_os = "linux")]

use std::collections::BTreeSet;
use std::io::Read;

use fmi_host::dist::every_fmu_path;

/// The newest glibc an FMU may need.
const FLOOR: (u32, u32) = (2, 17);

/// One versioned need: the library that must provide it and the version's name.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
struct Need {
    file: String,
    version: String,
}

/// A little-endian ELF64 image (what x86_64 and aarch64 Linux use).
struct Elf<'a>(&'a [u8]);

impl Elf<'_> {
    fn bytes(&self, at: usize, n: usize) -> Result<&[u8], String> {
        self.0.get(at..at + n).ok_or_else(|| format!("truncated ELF: {n} bytes at {at:#x}"))
    }
    fn u16(&self, at: usize) -> Result<usize, String> {
        Ok(u16::from_le_bytes(self.bytes(at, 2)?.try_into().unwrap()) as usize)
    }
    fn u32(&self, at: usize) -> Result<usize, String> {
        Ok(u32::from_le_bytes(self.bytes(at, 4)?.try_into().unwrap()) as usize)
    }
    fn u64(&self, at: usize) -> Result<usize, String> {
        Ok(u64::from_le_bytes(self.bytes(at, 8)?.try_into().unwrap()) as usize)
    }
    fn cstr(&self, at: usize) -> Result<String, String> {
        let tail = self.0.get(at..).ok_or("string outside the file")?;
        let end = tail.iter().position(|&b| b == 0).ok_or("unterminated string")?;
        Ok(String::from_utf8_lossy(&tail[..end]).into_owned())
    }

    /// (sh_type, sh_offset, sh_size, sh_link, sh_info) of every section.
    fn sections(&self) -> Result<Vec<(usize, usize, usize, usize, usize)>, String> {
        if self.bytes(0, 6)? != b"\x7fELF\x02\x01" {
            return Err("not a little-endian ELF64 file".into());
        }
        let (shoff, shentsize, shnum) = (self.u64(0x28)?, self.u16(0x3a)?, self.u16(0x3c)?);
        (0..shnum)
            .map(|i| {
                let h = shoff + i * shentsize;
                Ok((self.u32(h + 4)?, self.u64(h + 0x18)?, self.u64(h + 0x20)?, self.u32(h + 0x28)?, self.u32(h + 0x2c)?))
            })
            .collect()
    }

    /// The versions the image needs (SHT_GNU_verneed), each with the library to provide it.
    fn version_needs(&self) -> Result<Vec<Need>, String> {
        const SHT_GNU_VERNEED: usize = 0x6fff_fffe;
        let sections = self.sections()?;
        let mut needs = Vec::new();
        for &(kind, offset, _, link, count) in &sections {
            if kind != SHT_GNU_VERNEED {
                continue;
            }
            let strtab = sections.get(link).ok_or("verneed links to no string table")?.1;
            let mut entry = offset;
            for _ in 0..count {
                // Elf64_Verneed: vn_version u16, vn_cnt u16, vn_file u32, vn_aux u32, vn_next u32.
                let file = self.cstr(strtab + self.u32(entry + 4)?)?;
                let mut aux = entry + self.u32(entry + 8)?;
                for _ in 0..self.u16(entry + 2)? {
                    // Elf64_Vernaux: vna_hash u32, vna_flags u16, vna_other u16, vna_name u32, vna_next u32.
                    needs.push(Need { file: file.clone(), version: self.cstr(strtab + self.u32(aux + 8)?)? });
                    aux += self.u32(aux + 12)?;
                }
                entry += self.u32(entry + 12)?;
            }
        }
        Ok(needs)
    }
}

/// `GLIBC_2.17` -> (2, 17); `GLIBC_2.2.5` -> (2, 2); None for other names (GLIBC_PRIVATE,
/// GCC_3.0, ...).
fn glibc_version(name: &str) -> Option<(u32, u32)> {
    let mut parts = name.strip_prefix("GLIBC_")?.split('.');
    let major = parts.next()?.parse().ok()?;
    let minor = parts.next()?.parse().ok()?;
    Some((major, minor))
}

#[test]
fn the_parser_reads_the_needs_of_this_test_itself() {
    // This test is built by a plain cargo build for this machine: it needs some GLIBC_2.x, so
    // a parser that found nothing would not pass silently below.
    let exe = std::fs::read("/proc/self/exe").unwrap();
    let needs = Elf(&exe).version_needs().unwrap();
    assert!(needs.iter().any(|n| n.file == "libc.so.6" && glibc_version(&n.version).is_some()), "{needs:?}");
    assert_eq!(glibc_version("GLIBC_2.2.5"), Some((2, 2)));
    assert_eq!(glibc_version("GLIBC_2.35"), Some((2, 35)));
    assert_eq!(glibc_version("GLIBC_PRIVATE"), None);
}

#[test]
fn every_fmu_binary_needs_at_most_glibc_2_17() {
    let (folder, ext) = fmi_host::fmu::platform();
    let mut problems = Vec::new();
    let mut checked = 0;
    for path in every_fmu_path() {
        let mut archive = zip::ZipArchive::new(std::fs::File::open(&path).unwrap()).unwrap();
        let binaries: Vec<String> = archive
            .file_names()
            .map(|n| n.unwrap().into_owned())
            .filter(|n| n.starts_with(&format!("binaries/{folder}/")) && n.ends_with(&format!(".{ext}")))
            .collect();
        assert!(!binaries.is_empty(), "{}: no binaries/{folder}/*.{ext}", path.display());
        for name in binaries {
            let mut bytes = Vec::new();
            archive.by_name(&name).unwrap().read_to_end(&mut bytes).unwrap();
            let needs = Elf(&bytes).version_needs().unwrap_or_else(|e| panic!("{}!{name}: {e}", path.display()));
            let glibc: BTreeSet<(u32, u32)> = needs.iter().filter_map(|n| glibc_version(&n.version)).collect();
            let newest = glibc.last().copied().unwrap_or((0, 0));
            let libraries: BTreeSet<&str> = needs.iter().map(|n| n.file.as_str()).collect();
            println!(
                "{}!{name}: newest GLIBC_{}.{} ({} versioned needs from {})",
                path.file_name().unwrap().to_string_lossy(),
                newest.0,
                newest.1,
                needs.len(),
                libraries.into_iter().collect::<Vec<_>>().join(", ")
            );
            assert!(!glibc.is_empty(), "{}!{name}: no GLIBC_ version needed at all: not a glibc library?", path.display());
            for need in &needs {
                let too_new = match glibc_version(&need.version) {
                    Some(v) => v > FLOOR,
                    None => need.version.starts_with("GLIBC_"), // GLIBC_PRIVATE: no stable ABI
                };
                if too_new {
                    problems.push(format!("{}!{name}: {} from {}", path.display(), need.version, need.file));
                }
            }
            checked += 1;
        }
    }
    assert!(checked > 0);
    assert!(
        problems.is_empty(),
        "binaries that need more than glibc {}.{} (build them with `cargo run --release -p build-fmus`, \
         not --host-build):\n  {}",
        FLOOR.0,
        FLOOR.1,
        problems.join("\n  ")
    );
}
