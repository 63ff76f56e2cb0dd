//! [`Fmu`]: an unpacked FMU with its model description and its loaded shared library.

use std::ffi::CStr;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use libloading::Library;

use crate::error::{Error, Result};
use crate::ffi::{Api, Fmi3Functions, FmiVersion, Functions, ValueReference};
use crate::model_description::{ModelDescription, ScalarVariable};
use crate::tempdir::TempDir;

/// The `binaries/<platform>` folder name of FMI 2.0 (`linux64`, ...) and the shared-library
/// extension of this host. [`platform_for`] gives FMI 3.0's.
pub fn platform() -> (&'static str, &'static str) {
    let folder = match (std::env::consts::OS, cfg!(target_pointer_width = "64")) {
        ("linux", true) => "linux64",
        ("linux", false) => "linux32",
        ("macos", _) => "darwin64",
        ("windows", true) => "win64",
        ("windows", false) => "win32",
        (other, _) => other,
    };
    (folder, std::env::consts::DLL_EXTENSION)
}

/// The `binaries/<platform>` folder name and shared-library extension of this host for an FMI
/// version: FMI 2.0's `linux64`, FMI 3.0's platform tuple `<arch>-<os>` (`x86_64-linux`).
pub fn platform_for(version: FmiVersion) -> (String, &'static str) {
    match version {
        FmiVersion::Fmi2 => (platform().0.to_string(), platform().1),
        FmiVersion::Fmi3 => {
            let arch = match std::env::consts::ARCH {
                "x86" => "x86",
                other => other,
            };
            let os = match std::env::consts::OS {
                "macos" => "darwin",
                other => other,
            };
            (format!("{arch}-{os}"), std::env::consts::DLL_EXTENSION)
        }
    }
}

/// A loaded FMI 2.0 or FMI 3.0 Co-Simulation FMU (the description's `fmiVersion` decides which
/// functions are resolved and which `binaries/` folder is loaded).
///
/// Created by [`Fmu::load`], always behind an [`Arc`]: every [`crate::Instance`] holds a clone,
/// so the library stays loaded and the unpacked files stay on disk until the last instance is
/// gone. `Fmu` is `Send + Sync`; the instances made from it can live on different threads.
pub struct Fmu {
    // Field order is drop order: the library is unloaded before its directory is removed.
    api: Api,
    /// Kept only to keep the code of `functions` mapped; unloaded on drop.
    _library: Library,
    model_description: ModelDescription,
    fmu_path: PathBuf,
    library_path: PathBuf,
    dir: TempDir,
}

impl std::fmt::Debug for Fmu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Fmu")
            .field("fmu_path", &self.fmu_path)
            .field("model_name", &self.model_description.model_name)
            .field("unpacked_to", &self.dir.path())
            .finish_non_exhaustive()
    }
}

impl Fmu {
    /// Unpacks `path` into a fresh temporary directory, parses `modelDescription.xml`, loads
    /// `binaries/<platform>/<modelIdentifier>.<ext>` and resolves every `fmi2` function (FMI 2.0)
    /// or `fmi3` function (FMI 3.0; `<platform>` is then a platform tuple, `x86_64-linux`).
    ///
    /// Each call loads its own copy of the library (from its own directory), so two `Fmu`s of
    /// the same file do not share global state.
    pub fn load(path: impl AsRef<Path>) -> Result<Arc<Fmu>> {
        let fmu_path = path.as_ref().to_owned();
        let file = File::open(&fmu_path).map_err(|source| Error::Io {
            path: fmu_path.clone(),
            source,
        })?;
        let mut archive = zip::ZipArchive::new(file).map_err(|source| Error::Zip {
            path: fmu_path.clone(),
            source,
        })?;
        let dir = TempDir::new("fmi-host").map_err(|source| Error::Io {
            path: std::env::temp_dir(),
            source,
        })?;
        archive.extract(dir.path()).map_err(|source| Error::Zip {
            path: fmu_path.clone(),
            source,
        })?;

        let md_path = dir.path().join("modelDescription.xml");
        if !md_path.is_file() {
            return Err(Error::MissingFile {
                path: "modelDescription.xml".into(),
            });
        }
        let xml = std::fs::read_to_string(&md_path).map_err(|source| Error::Io {
            path: md_path.clone(),
            source,
        })?;
        let model_description = ModelDescription::parse(&xml)?;
        let identifier = model_description
            .co_simulation
            .as_ref()
            .ok_or(Error::NotCoSimulation)?
            .model_identifier
            .clone();

        let version = model_description.version();
        let (platform, extension) = platform_for(version);
        let relative = Path::new("binaries")
            .join(platform)
            .join(format!("{identifier}.{extension}"));
        let library_path = dir.path().join(&relative);
        if !library_path.is_file() {
            return Err(Error::MissingFile { path: relative });
        }
        // SAFETY: loading a library runs its initialisers; an FMU binary is trusted code by
        // definition (a host has no other way to run it).
        let library = unsafe { Library::new(&library_path) }.map_err(|source| Error::Library {
            path: library_path.clone(),
            source,
        })?;
        // SAFETY: the symbols are the fmi2 (fmi3) functions with the signatures of the standard
        // the description names; the table is stored next to `library`, which outlives every
        // use of it.
        let api = unsafe {
            match version {
                FmiVersion::Fmi2 => Api::Fmi2(Functions::load(&library)?),
                FmiVersion::Fmi3 => Api::Fmi3(Fmi3Functions::load(&library)?),
            }
        };

        Ok(Arc::new(Fmu {
            api,
            _library: library,
            model_description,
            fmu_path,
            library_path,
            dir,
        }))
    }

    pub fn model_description(&self) -> &ModelDescription {
        &self.model_description
    }

    /// The variable called `name`; [`Error::UnknownVariable`] if there is none.
    pub fn variable(&self, name: &str) -> Result<&ScalarVariable> {
        self.model_description.variable(name)
    }

    /// The value reference of the variable called `name`.
    pub fn vr(&self, name: &str) -> Result<ValueReference> {
        Ok(self.variable(name)?.value_reference)
    }

    /// The value references of several variables, in order.
    pub fn vrs(&self, names: &[&str]) -> Result<Vec<ValueReference>> {
        names.iter().map(|n| self.vr(n)).collect()
    }

    /// FMI 2.0 or FMI 3.0.
    pub fn fmi_version(&self) -> FmiVersion {
        self.api.version()
    }

    /// The raw function table of the FMU's version. The pointers are valid as long as this
    /// `Fmu` lives.
    pub fn api(&self) -> &Api {
        &self.api
    }

    /// The raw FMI 2.0 function table. The pointers are valid as long as this `Fmu` lives.
    ///
    /// # Panics
    /// For an FMI 3.0 FMU (use [`Fmu::api`] or [`Fmu::fmi3_functions`]).
    pub fn functions(&self) -> &Functions {
        match &self.api {
            Api::Fmi2(f) => f,
            Api::Fmi3(_) => panic!("{:?} is an FMI 3.0 FMU: it has no fmi2 function table (use Fmu::api)", self.fmu_path),
        }
    }

    /// The raw FMI 3.0 function table, `None` for an FMI 2.0 FMU.
    pub fn fmi3_functions(&self) -> Option<&Fmi3Functions> {
        match &self.api {
            Api::Fmi2(_) => None,
            Api::Fmi3(f) => Some(f),
        }
    }

    /// Where the FMU was unpacked.
    pub fn unpacked_dir(&self) -> &Path {
        self.dir.path()
    }

    /// The `resources` folder of the unpacked FMU (it may not exist).
    pub fn resources_dir(&self) -> PathBuf {
        self.dir.path().join("resources")
    }

    /// `file://` URI of [`Fmu::resources_dir`], as given to `fmi2Instantiate` (FMI 3.0 takes
    /// [`Fmu::resource_path`]).
    pub fn resource_uri(&self) -> String {
        file_uri(&self.resources_dir())
    }

    /// The absolute path of [`Fmu::resources_dir`] with a trailing separator, as given to
    /// `fmi3Instantiate...` (`resourcePath`).
    pub fn resource_path(&self) -> String {
        let mut path = self.resources_dir().to_string_lossy().into_owned();
        path.push(std::path::MAIN_SEPARATOR);
        path
    }

    pub fn fmu_path(&self) -> &Path {
        &self.fmu_path
    }

    pub fn library_path(&self) -> &Path {
        &self.library_path
    }

    /// `fmi2GetVersion()` or `fmi3GetVersion()`.
    pub fn version(&self) -> String {
        let get_version = match &self.api {
            Api::Fmi2(f) => f.get_version,
            Api::Fmi3(f) => f.get_version,
        };
        // SAFETY: no arguments; the FMU returns a static NUL-terminated string (checked for NULL).
        unsafe { static_str(get_version()) }
    }

    /// `fmi2GetTypesPlatform()` (FMI 3.0 has none: [`Error::NotInVersion`]).
    pub fn types_platform(&self) -> Result<String> {
        match &self.api {
            // SAFETY: as for `version`.
            Api::Fmi2(f) => Ok(unsafe { static_str((f.get_types_platform)()) }),
            Api::Fmi3(_) => Err(Error::NotInVersion { function: "fmi2GetTypesPlatform", version: FmiVersion::Fmi3 }),
        }
    }
}

/// # Safety
/// `ptr` is NULL or a NUL-terminated string.
unsafe fn static_str(ptr: *const std::ffi::c_char) -> String {
    if ptr.is_null() {
        String::new()
    } else {
        CStr::from_ptr(ptr).to_string_lossy().into_owned()
    }
}

/// `file:///...` URI of an absolute path, percent-encoding everything but unreserved characters
/// and `/`.
pub fn file_uri(path: &Path) -> String {
    let mut uri = String::from("file://");
    let text = path.to_string_lossy();
    if !text.starts_with('/') {
        uri.push('/');
    }
    for byte in text.replace('\\', "/").bytes() {
        match byte {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'-' | b'.' | b'_' | b'~' | b'/' | b':' => {
                uri.push(byte as char)
            }
            other => uri.push_str(&format!("%{other:02X}")),
        }
    }
    uri
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_uri_encodes() {
        assert_eq!(file_uri(Path::new("/tmp/a b/res")), "file:///tmp/a%20b/res");
        assert_eq!(file_uri(Path::new("/x/%")), "file:///x/%25");
    }

    #[test]
    fn missing_fmu_is_an_io_error() {
        let err = Fmu::load("/definitely/not/here.fmu").unwrap_err();
        assert!(matches!(err, Error::Io { .. }), "{err}");
    }

    #[test]
    fn non_zip_is_a_zip_error() {
        let dir = TempDir::new("fmi-host-test").unwrap();
        let path = dir.path().join("bad.fmu");
        std::fs::write(&path, b"this is not a zip file").unwrap();
        let err = Fmu::load(&path).unwrap_err();
        assert!(matches!(err, Error::Zip { .. }), "{err}");
    }

    fn zip_with(files: &[(&str, &[u8])]) -> (TempDir, PathBuf) {
        use std::io::Write;
        let dir = TempDir::new("fmi-host-test").unwrap();
        let path = dir.path().join("test.fmu");
        let mut writer = zip::ZipWriter::new(File::create(&path).unwrap());
        for (name, content) in files {
            writer
                .start_file(*name, zip::write::SimpleFileOptions::default())
                .unwrap();
            writer.write_all(content).unwrap();
        }
        writer.finish().unwrap();
        (dir, path)
    }

    const MD: &str = r#"<fmiModelDescription fmiVersion="2.0" modelName="M" guid="g">
        <CoSimulation modelIdentifier="M"/><ModelVariables/></fmiModelDescription>"#;

    #[test]
    fn missing_model_description_and_binary_and_bad_library() {
        let (_d, path) = zip_with(&[("documentation/index.html", b"<html/>")]);
        let err = Fmu::load(&path).unwrap_err();
        assert!(
            matches!(&err, Error::MissingFile { path } if path.ends_with("modelDescription.xml")),
            "{err}"
        );

        let (_d, path) = zip_with(&[("modelDescription.xml", b"<fmiModelDescription")]);
        assert!(matches!(Fmu::load(&path).unwrap_err(), Error::Xml { .. }));

        let (_d, path) = zip_with(&[("modelDescription.xml", MD.as_bytes())]);
        let err = Fmu::load(&path).unwrap_err();
        assert!(
            matches!(&err, Error::MissingFile { path } if path.ends_with(format!("M.{}", platform().1))),
            "{err}"
        );

        let me_only = MD.replace("CoSimulation", "ModelExchange");
        let (_d, path) = zip_with(&[("modelDescription.xml", me_only.as_bytes())]);
        assert!(matches!(
            Fmu::load(&path).unwrap_err(),
            Error::NotCoSimulation
        ));

        // FMI 3.0: the binary is looked up under the platform tuple.
        let md3 = r#"<fmiModelDescription fmiVersion="3.0" modelName="M" instantiationToken="t">
            <CoSimulation modelIdentifier="M"/><ModelVariables/></fmiModelDescription>"#;
        let (_d, path) = zip_with(&[("modelDescription.xml", md3.as_bytes()), (&format!("binaries/{}/M.{}", platform().0, platform().1), b"x")]);
        let err = Fmu::load(&path).unwrap_err();
        let tuple = platform_for(FmiVersion::Fmi3).0;
        assert!(
            matches!(&err, Error::MissingFile { path } if path.ends_with(format!("{tuple}/M.{}", platform().1))),
            "{err}"
        );
        if cfg!(all(target_os = "linux", target_arch = "x86_64")) {
            assert_eq!(tuple, "x86_64-linux");
        }

        let (folder, ext) = platform();
        let lib = format!("binaries/{folder}/M.{ext}");
        let (_d, path) = zip_with(&[
            ("modelDescription.xml", MD.as_bytes()),
            (&lib, b"not an ELF file"),
        ]);
        assert!(matches!(
            Fmu::load(&path).unwrap_err(),
            Error::Library { .. }
        ));
    }
}

#[cfg(all(test, target_os = "linux"))]
mod missing_symbol_tests {
    use super::*;
    use std::io::Write;

    /// A real shared library without any fmi2 symbol: the C math library.
    fn some_system_library() -> Option<Vec<u8>> {
        [
            "/lib/x86_64-linux-gnu/libm.so.6",
            "/usr/lib/x86_64-linux-gnu/libm.so.6",
            "/lib64/libm.so.6",
            "/usr/lib64/libm.so.6",
            "/lib/aarch64-linux-gnu/libm.so.6",
        ]
        .iter()
        .find_map(|p| std::fs::read(p).ok())
    }

    #[test]
    fn library_without_fmi2_symbols_is_a_missing_symbol_error() {
        let Some(libm) = some_system_library() else {
            eprintln!("no libm found, test skipped");
            return;
        };
        let dir = TempDir::new("fmi-host-test").unwrap();
        let path = dir.path().join("nosym.fmu");
        let mut writer = zip::ZipWriter::new(File::create(&path).unwrap());
        let options = zip::write::SimpleFileOptions::default();
        writer.start_file("modelDescription.xml", options).unwrap();
        writer
            .write_all(br#"<fmiModelDescription fmiVersion="2.0" modelName="M" guid="g"><CoSimulation modelIdentifier="M"/></fmiModelDescription>"#)
            .unwrap();
        let (folder, ext) = platform();
        writer
            .start_file(format!("binaries/{folder}/M.{ext}"), options)
            .unwrap();
        writer.write_all(&libm).unwrap();
        writer.finish().unwrap();
        let err = Fmu::load(&path).unwrap_err();
        assert!(
            matches!(
                err,
                Error::MissingSymbol {
                    name: "fmi2GetTypesPlatform",
                    ..
                }
            ),
            "{err}"
        );
    }
}
