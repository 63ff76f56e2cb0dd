//! The FMI versions this runtime exports, in one list. Everything outside an adapter's own
//! folder that depends on the version asks here: the description and documentation page
//! (`description.rs`, `exported.rs`), and, through the library's `fmu_runtime_standards`
//! symbol, build-fmus (where each version's FMU goes, and its binaries folder). A new version is
//! its adapter folder, a variant here with its match arms, and its export macro's line in
//! `export.rs`.

use crate::description::{Package, Structure};
use crate::documentation::Words;
use crate::model::Model;
use crate::variables::VariableTable;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Standard {
    Fmi2,
    Fmi3,
}

/// Every exported version, in the order the library lists them (FMI 2.0 first: build-fmus's
/// systems and the library's plain description symbols are FMI 2.0's).
pub const ALL: [Standard; 2] = [Standard::Fmi2, Standard::Fmi3];

impl Standard {
    /// Its modelDescription.xml, with the token left as `xml::TOKEN_PLACEHOLDER`.
    pub fn write_xml<M: Model>(self, table: &VariableTable, structure: &Structure, package: &Package) -> String {
        match self {
            Standard::Fmi2 => crate::fmi2::xml::write::<M>(table, structure, package),
            Standard::Fmi3 => crate::fmi3::xml::write::<M>(table, structure, package),
        }
    }

    /// What its documentation page says in its own words.
    pub fn words(self) -> &'static Words {
        match self {
            Standard::Fmi2 => &crate::fmi2::DOCUMENTATION,
            Standard::Fmi3 => &crate::fmi3::DOCUMENTATION,
        }
    }

    /// Where build-fmus puts its FMUs, inside the output directory ("" for the directory itself).
    pub fn folder(self) -> &'static str {
        match self {
            Standard::Fmi2 => "",
            Standard::Fmi3 => "fmi3",
        }
    }

    /// The name of the binaries folder of the platform this library was built for, if the
    /// standard names one (FMI 2.0, section 2.4; FMI 3.0, section 2.5.1.1).
    pub fn platform(self) -> Option<&'static str> {
        let (os, arch) = (std::env::consts::OS, std::env::consts::ARCH);
        match self {
            Standard::Fmi2 => match (os, arch) {
                ("linux", "x86_64") => Some("linux64"),
                ("linux", "x86") => Some("linux32"),
                ("macos", "x86_64" | "aarch64") => Some("darwin64"),
                ("windows", "x86_64") => Some("win64"),
                ("windows", "x86") => Some("win32"),
                _ => None,
            },
            Standard::Fmi3 => match (os, arch) {
                ("linux", "x86_64") => Some("x86_64-linux"),
                ("linux", "x86") => Some("x86-linux"),
                ("linux", "aarch64") => Some("aarch64-linux"),
                ("macos", "x86_64") => Some("x86_64-darwin"),
                ("macos", "aarch64") => Some("aarch64-darwin"),
                ("windows", "x86_64") => Some("x86_64-windows"),
                ("windows", "x86") => Some("x86-windows"),
                _ => None,
            },
        }
    }

    /// Its line in `fmu_runtime_standards`: version, output folder and binaries folder,
    /// separated by tabs ("3.0\tfmi3\tx86_64-linux"); no line where it names no platform.
    pub fn listing(self) -> Option<String> {
        Some(format!("{}\t{}\t{}", self.words().version, self.folder(), self.platform()?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(all(target_os = "linux", target_arch = "x86_64"))]
    #[test]
    fn the_listing_names_each_version_s_folders() {
        let lines: Vec<String> = ALL.iter().filter_map(|s| s.listing()).collect();
        assert_eq!(lines, ["2.0\t\tlinux64", "3.0\tfmi3\tx86_64-linux"]);
    }
}
