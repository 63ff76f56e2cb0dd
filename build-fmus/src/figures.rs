//! The chapter's figures in each FMU's documentation.
//!
//! `examples/make_figures.py` writes the figures to `docs/figures/<ModelIdentifier>_<what>.png`.
//! Each such PNG goes into the FMU as `documentation/<file name>`, and a "Figures" section with
//! an `<img>` per figure (a relative link) is added at the end of `documentation/index.html`.
//! A model without figures is packaged exactly as before.

use std::fs;
use std::path::Path;

/// One figure: its file name (also its name under `documentation/`) and its bytes.
pub type Figure = (String, Vec<u8>);

/// The figures of `identifier`: `<root>/docs/figures/<identifier>_*.png`, sorted by name.
/// No `docs/figures` folder means no figures.
pub fn find(root: &Path, identifier: &str) -> Result<Vec<Figure>, String> {
    let dir = root.join("docs").join("figures");
    let entries = match fs::read_dir(&dir) {
        Ok(entries) => entries,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(format!("could not read {}: {e}", dir.display())),
    };
    let prefix = format!("{identifier}_");
    let mut figures = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| format!("could not read {}: {e}", dir.display()))?;
        let Some(name) = entry.file_name().to_str().map(str::to_owned) else {
            continue;
        };
        if name.starts_with(&prefix) && name.ends_with(".png") {
            let bytes = fs::read(entry.path())
                .map_err(|e| format!("could not read {}: {e}", entry.path().display()))?;
            figures.push((name, bytes));
        }
    }
    figures.sort();
    Ok(figures)
}

/// `html` with a "Figures" section linking each figure (relative to `documentation/`),
/// inserted before the last `</body>` (appended when there is none). No figures: `html` as is.
pub fn with_figures(html: &str, figures: &[Figure]) -> String {
    if figures.is_empty() {
        return html.to_owned();
    }
    let mut section = String::from(
        "<h2>Figures</h2>\n<p>The chapter's figures reproduced from this FMU with fmpy \
         (<code>examples/make_figures.py</code> in the project's repository).</p>\n",
    );
    for (name, _) in figures {
        section.push_str(&format!(
            "<figure><img src=\"{name}\" alt=\"{name}\" style=\"max-width:100%\">\
             <figcaption>{name}</figcaption></figure>\n"
        ));
    }
    match html.rfind("</body>") {
        Some(i) => format!("{}{section}{}", &html[..i], &html[i..]),
        None => format!("{html}{section}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::TempDir;

    #[test]
    fn finds_only_the_models_own_pngs_sorted() {
        let tmp = TempDir::new("figures");
        let dir = tmp.path().join("docs/figures");
        fs::create_dir_all(&dir).unwrap();
        for name in [
            "MotorFan_b.png",
            "MotorFan_a.png",
            "MotorFan_table.md",
            "MotorFanSystem_x.png",
            "Fan_y.png",
        ] {
            fs::write(dir.join(name), name.as_bytes()).unwrap();
        }
        let found = find(tmp.path(), "MotorFan").unwrap();
        let names: Vec<&str> = found.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["MotorFan_a.png", "MotorFan_b.png"]);
        assert_eq!(found[0].1, b"MotorFan_a.png");
        assert_eq!(find(tmp.path(), "Fan").unwrap().len(), 1);
        assert!(find(tmp.path(), "RlcCircuit").unwrap().is_empty());
        // no docs/figures at all
        assert!(find(&tmp.path().join("nowhere"), "MotorFan")
            .unwrap()
            .is_empty());
    }

    #[test]
    fn the_section_goes_before_the_end_of_the_body() {
        let figures = vec![("M_a.png".to_owned(), vec![1u8])];
        let html = "<html><body><p>x</p></body></html>";
        let out = with_figures(html, &figures);
        assert!(
            out.starts_with("<html><body><p>x</p><h2>Figures</h2>"),
            "{out}"
        );
        assert!(out.contains("<img src=\"M_a.png\""), "{out}");
        assert!(out.ends_with("</body></html>"), "{out}");
        assert_eq!(with_figures(html, &[]), html);
        assert!(with_figures("<p>x</p>", &figures).starts_with("<p>x</p><h2>Figures</h2>"));
    }
}
