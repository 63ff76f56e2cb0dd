//! Writing an `.fmu`: a deterministic zip of the description, the binary and the docs.
//!
//! The archive holds these entries, always in this order:
//!
//! ```text
//! modelDescription.xml
//! model.png                      (the icon, drawn by `icon::png`)
//! binaries/<platform>/<modelIdentifier>.<so|dylib|dll>   (FMI 2.0 linux64, FMI 3.0 x86_64-linux)
//! documentation/index.html
//! documentation/<figure>.png     (the model's figures from docs/figures, if any)
//! ```
//!
//! Every entry is deflated, dated 1980-01-01 00:00:00 (the zip format's earliest date) and
//! marked as made on Unix with fixed permissions, so the same inputs give the same bytes.
//! The archive is written to a temporary file beside the target and renamed over it, so a
//! failed build never leaves a half-written `.fmu`.

use std::fs;
use std::io::{Cursor, Write};
use std::path::{Path, PathBuf};

use zip::write::SimpleFileOptions;
use zip::{CompressionMethod, DateTime, ZipWriter};

/// What goes into one FMU.
#[derive(Debug, Clone, Copy)]
pub struct FmuContents<'a> {
    /// The binaries folder's name, as the FMU's standard names the platform (`linux64`,
    /// `x86_64-linux`).
    pub platform: &'a str,
    /// The modelIdentifier; names the binary entry.
    pub identifier: &'a str,
    /// modelDescription.xml.
    pub model_description: &'a [u8],
    /// model.png, the FMU's icon.
    pub icon: &'a [u8],
    /// The built shared library.
    pub binary: &'a [u8],
    /// documentation/index.html.
    pub documentation: &'a [u8],
    /// documentation/<name>: the figures index.html links to (file name, bytes).
    pub figures: &'a [(String, Vec<u8>)],
}

/// The FMI 2.0 name of the platform this tool was built for (`linux64`), which is the
/// platform cargo builds the models for, and its shared-library extension; `None` where
/// FMI 2.0 names no such platform.
pub fn platform() -> Option<(&'static str, &'static str)> {
    match (std::env::consts::OS, std::env::consts::ARCH) {
        ("linux", "x86_64") => Some(("linux64", "so")),
        ("linux", "x86") => Some(("linux32", "so")),
        ("macos", "x86_64" | "aarch64") => Some(("darwin64", "dylib")),
        ("windows", "x86_64") => Some(("win64", "dll")),
        ("windows", "x86") => Some(("win32", "dll")),
        _ => None,
    }
}

/// The entry names of an FMU for `identifier` with its binary in `binaries/<platform>/`, in
/// archive order.
pub fn entry_names(identifier: &str, platform: &str) -> Result<[String; 4], String> {
    let (_, ext) = self::platform().ok_or_else(|| format!("no shared-library extension known for {}-{}", std::env::consts::OS, std::env::consts::ARCH))?;
    Ok([
        "modelDescription.xml".to_owned(),
        "model.png".to_owned(),
        format!("binaries/{platform}/{identifier}.{ext}"),
        "documentation/index.html".to_owned(),
    ])
}

/// The position of the binary among the entries (executable, 0o755).
const BINARY: usize = 2;

/// The archive's bytes.
pub fn fmu_bytes(contents: &FmuContents) -> Result<Vec<u8>, String> {
    let names = entry_names(contents.identifier, contents.platform)?;
    let data = [
        contents.model_description,
        contents.icon,
        contents.binary,
        contents.documentation,
    ];
    let base = SimpleFileOptions::default()
        .compression_method(CompressionMethod::Deflated)
        .compression_level(Some(9))
        .last_modified_time(DateTime::default())
        .system(zip::System::Unix);
    let zip_err = |e: zip::result::ZipError| format!("could not write the zip archive: {e}");
    let mut zip = ZipWriter::new(Cursor::new(Vec::new()));
    for (i, (name, bytes)) in names.iter().zip(data).enumerate() {
        let mode = if i == BINARY { 0o755 } else { 0o644 };
        zip.start_file(name.as_str(), base.unix_permissions(mode))
            .map_err(zip_err)?;
        zip.write_all(bytes)
            .map_err(|e| format!("could not write the zip archive: {e}"))?;
    }
    for (name, bytes) in contents.figures {
        zip.start_file(
            format!("documentation/{name}"),
            base.unix_permissions(0o644),
        )
        .map_err(zip_err)?;
        zip.write_all(bytes)
            .map_err(|e| format!("could not write the zip archive: {e}"))?;
    }
    Ok(zip.finish().map_err(zip_err)?.into_inner())
}

/// Writes the FMU to `path` (through a temporary file in the same directory, renamed into
/// place) and returns its size in bytes. The directory must exist.
pub fn write_fmu(path: &Path, contents: &FmuContents) -> Result<u64, String> {
    let bytes = fmu_bytes(contents)?;
    write_atomically(path, &bytes).map(|()| bytes.len() as u64)
}

/// Writes `bytes` to `path` through a temporary file in the same directory, renamed into
/// place, so that `path` is never half-written. The directory must exist.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let tmp = temp_path(path);
    let result = fs::write(&tmp, bytes)
        .and_then(|()| fs::rename(&tmp, path))
        .map_err(|e| format!("could not write {}: {e}", path.display()));
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// `dir/.<name>.tmp-<pid>`: hidden, beside the target (so the rename stays on one file
/// system), and distinct per process.
fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "fmu".to_owned());
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::TempDir;
    use std::io::Read;

    fn contents(binary: &[u8]) -> FmuContents<'_> {
        FmuContents {
            platform: "linux64",
            identifier: "RlcCircuit",
            model_description: b"<?xml version=\"1.0\"?><fmiModelDescription/>",
            icon: b"\x89PNG icon",
            binary,
            documentation: b"<!DOCTYPE html><html><body>RLC</body></html>",
            figures: &[],
        }
    }

    #[cfg(all(target_os = "linux", target_arch = "x86_64"))]
    #[test]
    fn entry_names_are_the_fmi_layout() {
        assert_eq!(
            entry_names("RlcCircuit", "linux64").unwrap(),
            [
                "modelDescription.xml",
                "model.png",
                "binaries/linux64/RlcCircuit.so",
                "documentation/index.html"
            ]
        );
        assert_eq!(entry_names("RlcCircuit", "x86_64-linux").unwrap()[2], "binaries/x86_64-linux/RlcCircuit.so");
    }

    #[test]
    fn the_archive_holds_exactly_the_four_entries_in_order() {
        let binary: Vec<u8> = (0..100_000u32).map(|i| (i * 7 % 251) as u8).collect();
        let tmp = TempDir::new("package");
        let path = tmp.path().join("RlcCircuit.fmu");
        let size = write_fmu(&path, &contents(&binary)).unwrap();
        assert_eq!(size, fs::metadata(&path).unwrap().len());

        let mut archive = zip::ZipArchive::new(fs::File::open(&path).unwrap()).unwrap();
        let names = entry_names("RlcCircuit", "linux64").unwrap();
        assert_eq!(archive.len(), 4);
        let expected: [&[u8]; 4] = [
            contents(&binary).model_description,
            contents(&binary).icon,
            &binary,
            contents(&binary).documentation,
        ];
        for (i, want) in expected.iter().enumerate() {
            let mut entry = archive.by_index(i).unwrap();
            assert_eq!(entry.name().unwrap(), names[i].as_str());
            assert_eq!(entry.compression(), CompressionMethod::Deflated);
            let t = entry.last_modified().unwrap();
            assert_eq!(
                (t.year(), t.month(), t.day(), t.hour(), t.minute()),
                (1980, 1, 1, 0, 0)
            );
            let mut got = Vec::new();
            entry.read_to_end(&mut got).unwrap();
            assert_eq!(&got, want);
        }
        assert_eq!(
            archive.by_index(BINARY).unwrap().unix_mode().map(|m| m & 0o777),
            Some(0o755)
        );
        for i in [0, 1, 3] {
            assert_eq!(
                archive.by_index(i).unwrap().unix_mode().map(|m| m & 0o777),
                Some(0o644)
            );
        }
        // Only the .fmu is left in the directory: no temporary file.
        let left: Vec<_> = fs::read_dir(tmp.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, ["RlcCircuit.fmu"]);
    }

    #[test]
    fn figures_follow_the_documentation() {
        let figures = vec![
            ("RlcCircuit_a.png".to_owned(), b"\x89PNG a".to_vec()),
            ("RlcCircuit_b.png".to_owned(), b"\x89PNG b".to_vec()),
        ];
        let contents = FmuContents {
            figures: &figures,
            ..contents(b"binary")
        };
        let bytes = fmu_bytes(&contents).unwrap();
        let mut archive = zip::ZipArchive::new(Cursor::new(bytes)).unwrap();
        let names: Vec<String> = archive
            .file_names()
            .map(|n| n.unwrap().into_owned())
            .collect();
        assert_eq!(names.len(), 6);
        assert_eq!(names[3], "documentation/index.html");
        assert_eq!(names[4], "documentation/RlcCircuit_a.png");
        assert_eq!(names[5], "documentation/RlcCircuit_b.png");
        let mut got = Vec::new();
        archive
            .by_name("documentation/RlcCircuit_b.png")
            .unwrap()
            .read_to_end(&mut got)
            .unwrap();
        assert_eq!(got, b"\x89PNG b");
    }

    #[test]
    fn the_same_inputs_give_the_same_bytes() {
        let binary = b"\x7fELF not really".repeat(1000);
        let tmp = TempDir::new("package-twice");
        let a = tmp.path().join("a.fmu");
        let b = tmp.path().join("b.fmu");
        write_fmu(&a, &contents(&binary)).unwrap();
        std::thread::sleep(std::time::Duration::from_millis(1100)); // a new second on the clock
        write_fmu(&b, &contents(&binary)).unwrap();
        assert_eq!(fs::read(&a).unwrap(), fs::read(&b).unwrap());
        // and writing over an existing file gives the same bytes again
        write_fmu(&a, &contents(&binary)).unwrap();
        assert_eq!(fs::read(&a).unwrap(), fs::read(&b).unwrap());
    }

    #[test]
    fn a_failed_write_leaves_nothing_behind() {
        let tmp = TempDir::new("package-fail");
        // The target is an existing directory: the rename fails.
        let path = tmp.path().join("Busy.fmu");
        fs::create_dir(&path).unwrap();
        let err = write_fmu(&path, &contents(b"x")).unwrap_err();
        assert!(err.contains("Busy.fmu"), "{err}");
        let left: Vec<_> = fs::read_dir(tmp.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, ["Busy.fmu"]);
        // A missing directory: nothing is created.
        let err = write_fmu(&tmp.path().join("no/such/dir/X.fmu"), &contents(b"x")).unwrap_err();
        assert!(err.contains("X.fmu"), "{err}");
    }
}
