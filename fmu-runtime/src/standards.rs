//! The FMI versions this runtime exports, in one list. Everything outside an adapter's own
//! folder that depends on the version asks here: the description and documentation page
//! (`description.rs`, `exported.rs`), and, through the library's `fmu_runtime_standards`
//! symbol, build-fmus (where each version's FMU goes, and its binaries folder). A new version is
//! its adapter folder, its line in `standards!` below, and its export macro's line in
//! `export.rs`.

use crate::description::{Package, Structure};
use crate::documentation::Words;
use crate::model::Model;
use crate::variables::VariableTable;

/// Declares the versions: for each, its variant and its adapter module, which provides
/// `write_xml::<M>(table, structure, package, default_floor)`, `DOCUMENTATION` (its documentation words),
/// `FOLDER` (where build-fmus puts its FMUs) and `platform()` (its binaries folder's name).
macro_rules! standards {
    ($($variant:ident => $module:ident),* $(,)?) => {
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub enum Standard {
            $($variant),*
        }

        /// Every exported version, in the order the library lists them (FMI 2.0 first:
        /// build-fmus's systems and the library's plain description symbols are FMI 2.0's).
        pub const ALL: &[Standard] = &[$(Standard::$variant),*];

        impl Standard {
            /// Its modelDescription.xml, with the token left as `xml::TOKEN_PLACEHOLDER`.
            pub fn write_xml<M: Model>(self, table: &VariableTable, structure: &Structure, package: &Package, default_floor: Option<f64>) -> String {
                match self {
                    $(Standard::$variant => crate::$module::write_xml::<M>(table, structure, package, default_floor)),*
                }
            }

            /// What its documentation page says in its own words.
            pub fn words(self) -> &'static Words {
                match self {
                    $(Standard::$variant => &crate::$module::DOCUMENTATION),*
                }
            }

            /// Where build-fmus puts its FMUs, inside the output directory ("" for the
            /// directory itself).
            pub fn folder(self) -> &'static str {
                match self {
                    $(Standard::$variant => crate::$module::FOLDER),*
                }
            }

            /// The name of the binaries folder of the platform this library was built for, if
            /// the standard names one.
            pub fn platform(self) -> Option<&'static str> {
                match self {
                    $(Standard::$variant => crate::$module::platform()),*
                }
            }
        }
    };
}

standards! {
    Fmi2 => fmi2,
    Fmi3 => fmi3,
}

impl Standard {
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
