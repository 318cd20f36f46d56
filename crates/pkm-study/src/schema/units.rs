//! Numbers with a unit and a range, checked while the study file is read: a wrong type, a NaN or
//! a negative length is an error at the value's line that names the expected unit.
//!
//! Lengths are in metres and angles, where a key ends in `_deg`, in degrees; everything else is
//! dimensionless. The library receives SI units and radians.

use serde::de::{self, Deserializer, Unexpected, Visitor};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Reads any TOML number (integer or float) as `f64`.
struct NumberVisitor(&'static str);

impl Visitor<'_> for NumberVisitor {
    type Value = f64;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<f64, E> {
        Ok(v)
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<f64, E> {
        Ok(v as f64)
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<f64, E> {
        Ok(v as f64)
    }
}

/// Declares a checked quantity: a newtype over `f64` whose deserialisation rejects values
/// outside `$check` with the message `$expect`.
macro_rules! quantity {
    ($(#[$doc:meta])* $name:ident, $expect:literal, |$v:ident| $check:expr) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Serialize)]
        #[serde(transparent)]
        pub struct $name(pub f64);

        impl $name {
            /// What a value must be (with its unit).
            pub const EXPECTED: &'static str = $expect;

            /// Whether `v` is an allowed value.
            pub fn accepts($v: f64) -> bool {
                $check
            }
        }

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let v = d.deserialize_any(NumberVisitor($expect))?;
                if Self::accepts(v) {
                    Ok(Self(v))
                } else {
                    Err(de::Error::invalid_value(Unexpected::Float(v), &$expect))
                }
            }
        }
    };
}

quantity!(
    /// A position or signed length in metres.
    Metres,
    "a length in metres (a finite number)",
    |v| v.is_finite()
);
quantity!(
    /// A length in metres, > 0.
    PositiveMetres,
    "a length in metres (a finite number > 0)",
    |v| v.is_finite() && v > 0.0
);
quantity!(
    /// A length in metres, ≥ 0.
    NonNegativeMetres,
    "a length in metres (a finite number >= 0)",
    |v| v.is_finite() && v >= 0.0
);
quantity!(
    /// An angle in degrees.
    Degrees,
    "an angle in degrees (a finite number)",
    |v| v.is_finite()
);
quantity!(
    /// A cone half-angle in degrees, in (0, 180].
    ConeDegrees,
    "a cone half-angle in degrees (0 < angle <= 180)",
    |v| v > 0.0 && v <= 180.0
);
quantity!(
    /// A dimensionless finite number.
    Real,
    "a finite number (dimensionless)",
    |v| v.is_finite()
);

impl Degrees {
    /// The angle in radians.
    pub fn radians(self) -> f64 {
        self.0.to_radians()
    }
}

/// Declares a closed interval `[lower, upper]` of a quantity, `lower <= upper`.
macro_rules! interval {
    ($(#[$doc:meta])* $name:ident, $of:ident, $unit:literal) => {
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Serialize)]
        pub struct $name {
            /// Lower end.
            pub lower: f64,
            /// Upper end.
            pub upper: f64,
        }

        impl<'de> Deserialize<'de> for $name {
            fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                let [lower, upper] = <[$of; 2]>::deserialize(d)?;
                if lower.0 <= upper.0 {
                    Ok(Self {
                        lower: lower.0,
                        upper: upper.0,
                    })
                } else {
                    Err(de::Error::custom(concat!(
                        "expected [lower, upper] in ",
                        $unit,
                        " with lower <= upper"
                    )))
                }
            }
        }
    };
}

interval!(
    /// An interval of angles, `[lower, upper]` in degrees.
    DegreeRange,
    Degrees,
    "degrees"
);
interval!(
    /// An interval of positions, `[lower, upper]` in metres.
    MetreRange,
    Metres,
    "metres"
);

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[derive(Debug, Deserialize)]
    struct Probe {
        length: PositiveMetres,
        range: Option<DegreeRange>,
    }

    #[test]
    fn integers_are_numbers_and_bad_values_name_the_unit() {
        let ok: Probe = toml::from_str("length = 2\nrange = [-40, 90.5]").unwrap();
        assert!((ok.length.0 - 2.0).abs() < f64::EPSILON);
        assert!(ok.range.is_some_and(|r| r.lower < r.upper));
        for bad in [
            "length = -1",
            "length = nan",
            "length = \"a\"",
            "length = inf",
        ] {
            let e = toml::from_str::<Probe>(bad).unwrap_err().to_string();
            assert!(e.contains("metres"), "{bad}: {e}");
        }
        let e = toml::from_str::<Probe>("length = 1\nrange = [90, -40]")
            .unwrap_err()
            .to_string();
        assert!(e.contains("lower <= upper"), "{e}");
    }
}
