//! SI units: every real variable names one, and `modelDescription.xml` declares each unit used
//! with its exponents of the SI base units (FMI 2.0, section 2.2.2 `UnitDefinitions`).

/// Exponents of the SI base units (and rad, which FMI lists as a base unit too),
/// plus the factor and offset to the SI unit: value_SI = factor * value + offset.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BaseUnit {
    pub kg: i32,
    pub m: i32,
    pub s: i32,
    pub a: i32,
    pub k: i32,
    pub mol: i32,
    pub cd: i32,
    pub rad: i32,
    pub factor: f64,
    pub offset: f64,
}

impl BaseUnit {
    const ONE: BaseUnit = BaseUnit { kg: 0, m: 0, s: 0, a: 0, k: 0, mol: 0, cd: 0, rad: 0, factor: 1.0, offset: 0.0 };

    const fn new(kg: i32, m: i32, s: i32, a: i32, k: i32, rad: i32) -> Self {
        BaseUnit { kg, m, s, a, k, mol: 0, cd: 0, rad, factor: 1.0, offset: 0.0 }
    }

    /// The unit of this quantity's time derivative (one more s^-1).
    pub fn per_second(self) -> Self {
        BaseUnit { s: self.s - 1, ..self }
    }
}

/// The units the runtime knows, by their FMI name. A model may only use these; adding one is a
/// one-line change here (with its exponents: kg, m, s, A, K, rad).
const KNOWN: &[(&str, BaseUnit)] = &[
    ("1", BaseUnit::ONE),
    ("%", BaseUnit { factor: 0.01, ..BaseUnit::ONE }),
    ("s", BaseUnit::new(0, 0, 1, 0, 0, 0)),
    ("Hz", BaseUnit::new(0, 0, -1, 0, 0, 0)),
    ("m", BaseUnit::new(0, 1, 0, 0, 0, 0)),
    ("m/s2", BaseUnit::new(0, 1, -2, 0, 0, 0)),
    ("kg", BaseUnit::new(1, 0, 0, 0, 0, 0)),
    ("K", BaseUnit::new(0, 0, 0, 0, 1, 0)),
    ("K/s", BaseUnit::new(0, 0, -1, 0, 1, 0)),
    ("A", BaseUnit::new(0, 0, 0, 1, 0, 0)),
    ("V", BaseUnit::new(1, 2, -3, -1, 0, 0)),
    ("Ohm", BaseUnit::new(1, 2, -3, -2, 0, 0)),
    ("H", BaseUnit::new(1, 2, -2, -2, 0, 0)),
    ("F", BaseUnit::new(-1, -2, 4, 2, 0, 0)),
    ("Wb", BaseUnit::new(1, 2, -2, -1, 0, 0)),
    ("T", BaseUnit::new(1, 0, -2, -1, 0, 0)),
    ("W", BaseUnit::new(1, 2, -3, 0, 0, 0)),
    ("J", BaseUnit::new(1, 2, -2, 0, 0, 0)),
    ("J/K", BaseUnit::new(1, 2, -2, 0, -1, 0)),
    ("W/K", BaseUnit::new(1, 2, -3, 0, -1, 0)),
    ("J/(kg.K)", BaseUnit::new(0, 2, -2, 0, -1, 0)),
    ("K/W", BaseUnit::new(-1, -2, 3, 0, 1, 0)),
    ("W/(m.K)", BaseUnit::new(1, 1, -3, 0, -1, 0)),
    ("W/(m2.K)", BaseUnit::new(1, 0, -3, 0, -1, 0)),
    ("m2", BaseUnit::new(0, 2, 0, 0, 0, 0)),
    ("K.s", BaseUnit::new(0, 0, 1, 0, 1, 0)),
    ("N", BaseUnit::new(1, 1, -2, 0, 0, 0)),
    ("Pa", BaseUnit::new(1, -1, -2, 0, 0, 0)),
    ("N/m", BaseUnit::new(1, 0, -2, 0, 0, 0)),
    ("N.s/m", BaseUnit::new(1, 0, -1, 0, 0, 0)),
    ("A.s", BaseUnit::new(0, 0, 1, 1, 0, 0)),
    ("N.m", BaseUnit::new(1, 2, -2, 0, 0, 0)),
    ("N.m/s", BaseUnit::new(1, 2, -3, 0, 0, 0)),
    ("N.m/s2", BaseUnit::new(1, 2, -4, 0, 0, 0)),
    ("rad", BaseUnit::new(0, 0, 0, 0, 0, 1)),
    ("rad/s", BaseUnit::new(0, 0, -1, 0, 0, 1)),
    ("rad/s2", BaseUnit::new(0, 0, -2, 0, 0, 1)),
    ("kg.m2", BaseUnit::new(1, 2, 0, 0, 0, 0)),
    ("N.m/rad", BaseUnit::new(1, 2, -2, 0, 0, -1)),
    ("N.m.s/rad", BaseUnit::new(1, 2, -1, 0, 0, -1)),
    ("N.m.s2/rad2", BaseUnit::new(1, 2, 0, 0, 0, -2)),
    ("V.s/rad", BaseUnit::new(1, 2, -2, -1, 0, -1)),
    ("J.s", BaseUnit::new(1, 2, -1, 0, 0, 0)),
    ("H-1", BaseUnit::new(-1, -2, 2, 2, 0, 0)),
    ("V/(N.m)", BaseUnit::new(0, 0, -1, -1, 0, 0)),
    ("m3", BaseUnit::new(0, 3, 0, 0, 0, 0)),
    ("m3/rad", BaseUnit::new(0, 3, 0, 0, 0, -1)),
    ("Pa.s/m3", BaseUnit::new(1, -4, -1, 0, 0, 0)),
    ("V/rad", BaseUnit::new(1, 2, -3, -1, 0, -1)),
];

/// The base-unit exponents of a unit name: a known unit, or a known unit followed by "/s"
/// (the unit of a state's derivative).
/// A few of the known units, for error messages.
pub fn examples() -> String {
    KNOWN.iter().map(|(n, _)| *n).filter(|n| ["1", "s", "m", "kg", "K", "A", "V", "Ohm", "W", "N.m", "rad/s", "kg.m2"].contains(n)).collect::<Vec<_>>().join(", ")
}

pub fn lookup(name: &str) -> Option<BaseUnit> {
    if let Some((_, b)) = KNOWN.iter().find(|(n, _)| *n == name) {
        return Some(*b);
    }
    name.strip_suffix("/s")
        .and_then(|base| KNOWN.iter().find(|(n, _)| *n == base))
        .map(|(_, b)| b.per_second())
}

/// The unit of the time derivative of a quantity in `unit`: "A" -> "A/s", "rad/s" -> "rad/s2".
pub fn derivative_unit(unit: &str) -> String {
    match unit {
        "1" => "Hz".to_string(),
        "rad" => "rad/s".to_string(),
        "rad/s" => "rad/s2".to_string(),
        "m/s" => "m/s2".to_string(),
        "N.m/s" => "N.m/s2".to_string(),
        "s" => "1".to_string(),
        "K.s" => "K".to_string(),
        u => format!("{u}/s"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn volt_is_watt_per_ampere() {
        let v = lookup("V").unwrap();
        let w = lookup("W").unwrap();
        assert_eq!((v.kg, v.m, v.s, v.a + 1), (w.kg, w.m, w.s, w.a));
    }

    #[test]
    fn derivative_units_are_known() {
        for (name, _) in KNOWN {
            let d = derivative_unit(name);
            let b = lookup(&d).unwrap_or_else(|| panic!("no unit for d/dt of {name}: {d}"));
            assert_eq!(b.s, lookup(name).unwrap().s - 1, "{name}");
        }
    }

    #[test]
    fn unknown_unit_is_none() {
        assert!(lookup("furlong").is_none());
    }
}
