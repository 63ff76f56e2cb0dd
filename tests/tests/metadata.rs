//! What every FMU in dist/ says about itself beside its variables: the model crate's version,
//! authors and license (from Cargo), a copyright, a reproducible generationDateAndTime (the
//! source's date, the same in every FMU built from one source), and its icon `model.png` at the
//! archive's root.

use fmi_host::dist::every_fmu;

/// "YYYY-MM-DDThh:mm:ssZ", an xs:dateTime in UTC.
fn is_utc_date_time(s: &str) -> bool {
    let b = s.as_bytes();
    let digits = |r: std::ops::Range<usize>| r.into_iter().all(|i| b[i].is_ascii_digit());
    b.len() == 20
        && digits(0..4)
        && b[4] == b'-'
        && digits(5..7)
        && b[7] == b'-'
        && digits(8..10)
        && b[10] == b'T'
        && digits(11..13)
        && b[13] == b':'
        && digits(14..16)
        && b[16] == b':'
        && digits(17..19)
        && b[19] == b'Z'
}

#[test]
fn every_fmu_names_its_version_authors_license_and_source_date() {
    let mut dates = std::collections::BTreeSet::new();
    let fmus = every_fmu();
    for fmu in &fmus {
        let md = fmu.model_description();
        let m = &md.model_name;
        // The model crates take version, authors and license from the workspace, as this crate does.
        assert_eq!(md.version.as_deref(), Some(env!("CARGO_PKG_VERSION")), "{m}");
        let authors = env!("CARGO_PKG_AUTHORS").replace(':', ", ");
        assert_eq!(md.author.as_deref(), Some(authors.as_str()), "{m}");
        assert_eq!(md.license.as_deref(), Some(env!("CARGO_PKG_LICENSE")), "{m}");
        let date = md.generation_date_and_time.clone().unwrap_or_else(|| panic!("{m}: no generationDateAndTime"));
        assert!(is_utc_date_time(&date), "{m}: generationDateAndTime {date:?}");
        assert_eq!(md.copyright.as_deref(), Some(format!("Copyright (c) {} {authors}", &date[..4]).as_str()), "{m}");
        dates.insert(date);
        // The guid the binary recomputes at run time is the packaged one: instantiation succeeds.
        let inst = fmu.instantiate("metadata", false, false).unwrap_or_else(|e| panic!("{m}: {e:?}"));
        drop(inst);
    }
    assert_eq!(dates.len(), 1, "one source, one date: {dates:?}");
    println!("{} FMUs: version, author, license, copyright and generationDateAndTime {}", fmus.len(), dates.first().unwrap());
}

#[test]
fn every_fmu_carries_its_icon() {
    for fmu in every_fmu() {
        let m = &fmu.model_description().model_name;
        let png = std::fs::read(fmu.unpacked_dir().join("model.png")).unwrap_or_else(|e| panic!("{m}: model.png: {e}"));
        assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "{m}: model.png is no PNG");
        assert_eq!(&png[12..16], b"IHDR", "{m}");
        let (w, h) = (u32::from_be_bytes(png[16..20].try_into().unwrap()), u32::from_be_bytes(png[20..24].try_into().unwrap()));
        assert_eq!((w, h), (128, 128), "{m}");
    }
}
