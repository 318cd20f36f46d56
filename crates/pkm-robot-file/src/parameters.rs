//! Named parameters of a robot file: a `[parameters]` table of scalars whose names may stand
//! for any number of the geometry, so that a design study can vary them.
//!
//! The rule (`docs/robots.md#parameters`): wherever the schema expects a number (a coordinate
//! of an `axis`, `axes` or `point`, an `offset`, a `limits` bound, the `[home]` pose, the
//! `[symmetry]` axis and point, `characteristic_length`), the file may write the bare name of a
//! parameter as a string instead (`point = ["base_radius", 0.0, 0.0]`). The name stands for
//! the parameter's value; a name ending in `_deg` is in degrees and stands for its value in
//! radians. There are no expressions: a name or a number.
//!
//! The names in scope while a file is deserialised are held by [`with_parameters`], so the
//! numbers are resolved by serde itself: every error keeps the line and column of the TOML
//! text and the key path of the value (`legs[0].joints[1].point[0]`).

use serde::de::{self, Deserializer, Visitor};
use serde::{Deserialize, Serialize};
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::fmt;

thread_local! {
    /// The parameters of the file being deserialised on this thread (values in radians for
    /// `_deg` names).
    static IN_SCOPE: RefCell<Option<BTreeMap<String, f64>>> = const { RefCell::new(None) };
}

/// Runs `deserialise` with the names of `parameters` in scope for the numbers of a robot file
/// ([`RobotFile`](crate::RobotFile) and its tables), then restores the previous scope.
pub(crate) fn with_parameters<T>(
    parameters: &BTreeMap<String, f64>,
    deserialise: impl FnOnce() -> T,
) -> T {
    let values = parameters
        .iter()
        .map(|(name, &v)| (name.clone(), value_in_radians(name, v)))
        .collect();
    let previous = IN_SCOPE.with(|scope| scope.replace(Some(values)));
    let out = deserialise();
    IN_SCOPE.with(|scope| scope.replace(previous));
    out
}

/// The value a name stands for: radians for a `_deg` name.
fn value_in_radians(name: &str, value: f64) -> f64 {
    if name.ends_with("_deg") {
        value.to_radians()
    } else {
        value
    }
}

/// The value of parameter `name` in scope, or why there is none.
fn lookup(name: &str) -> Result<f64, String> {
    IN_SCOPE.with(|scope| match scope.borrow().as_ref() {
        Some(values) => values.get(name).copied().ok_or_else(|| {
            let known = values.keys().map(String::as_str).collect::<Vec<_>>();
            if known.is_empty() {
                format!("`{name}` is not a number, and [parameters] is empty")
            } else {
                format!(
                    "`{name}` is not a number or a parameter: expected one of {}",
                    known.join(", ")
                )
            }
        }),
        None => Err(format!(
            "`{name}` is not a number (parameter names need a [parameters] table)"
        )),
    })
}

/// A number of a robot file: a float, an integer or the name of a parameter in scope.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(transparent)]
pub(crate) struct Number(pub(crate) f64);

impl<'de> Deserialize<'de> for Number {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_any(NumberVisitor)
    }
}

struct NumberVisitor;

impl Visitor<'_> for NumberVisitor {
    type Value = Number;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("a number or the name of a parameter")
    }

    fn visit_f64<E: de::Error>(self, v: f64) -> Result<Number, E> {
        Ok(Number(v))
    }

    fn visit_i64<E: de::Error>(self, v: i64) -> Result<Number, E> {
        Ok(Number(v as f64))
    }

    fn visit_u64<E: de::Error>(self, v: u64) -> Result<Number, E> {
        Ok(Number(v as f64))
    }

    fn visit_str<E: de::Error>(self, v: &str) -> Result<Number, E> {
        lookup(v).map(Number).map_err(E::custom)
    }
}

/// An array of exactly `N` elements: serde's `[T; N]` reads the first `N` entries of a longer
/// array and drops the rest, so a file's `axis = [0, 0, 1, 7]` would load as `[0, 0, 1]`.
/// Extra entries are counted (not kept, so a huge array allocates nothing more) and refused
/// with the count.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Exactly<T, const N: usize>(pub(crate) [T; N]);

impl<'de, T: Deserialize<'de> + Copy + Default, const N: usize> Deserialize<'de> for Exactly<T, N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_seq(ExactlyVisitor(std::marker::PhantomData))
    }
}

struct ExactlyVisitor<T, const N: usize>(std::marker::PhantomData<T>);

impl<'de, T: Deserialize<'de> + Copy + Default, const N: usize> Visitor<'de>
    for ExactlyVisitor<T, N>
{
    type Value = Exactly<T, N>;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "an array of exactly {N} entries")
    }

    fn visit_seq<A: de::SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
        let mut out = [T::default(); N];
        for (i, slot) in out.iter_mut().enumerate() {
            *slot = seq
                .next_element()?
                .ok_or_else(|| de::Error::invalid_length(i, &self))?;
        }
        let mut extra = 0_usize;
        while seq.next_element::<de::IgnoredAny>()?.is_some() {
            extra += 1;
        }
        if extra > 0 {
            return Err(de::Error::invalid_length(N + extra, &self));
        }
        Ok(Exactly(out))
    }
}

impl<T: Default + Copy, const N: usize> Default for Exactly<T, N> {
    fn default() -> Self {
        Self([T::default(); N])
    }
}

impl Default for Number {
    fn default() -> Self {
        Self(0.0)
    }
}

/// `deserialize_with` helpers: the fields of the schema keep their plain float types.
pub(crate) mod fields {
    use super::{Exactly, Number};
    use serde::{Deserialize, Deserializer};

    /// `N` numbers, exactly.
    type Numbers<const N: usize> = Exactly<Number, N>;

    /// A number.
    pub(crate) fn scalar<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        Number::deserialize(d).map(|n| n.0)
    }

    /// An optional number.
    pub(crate) fn optional_scalar<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<f64>, D::Error> {
        Ok(Option::<Number>::deserialize(d)?.map(|n| n.0))
    }

    /// Three numbers, exactly.
    pub(crate) fn vector<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
        Numbers::<3>::deserialize(d).map(|v| v.0.map(|n| n.0))
    }

    /// Three optional numbers, exactly.
    pub(crate) fn optional_vector<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[f64; 3]>, D::Error> {
        Ok(Option::<Numbers<3>>::deserialize(d)?.map(|v| v.0.map(|n| n.0)))
    }

    /// Two optional vectors (the axes of a U joint), exactly.
    pub(crate) fn optional_axes<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[[f64; 3]; 2]>, D::Error> {
        let axes = Option::<Exactly<Numbers<3>, 2>>::deserialize(d)?;
        Ok(axes.map(|a| a.0.map(|v| v.0.map(|n| n.0))))
    }

    /// An optional 3 × 3 matrix (an inertia tensor), rows of three, exactly.
    pub(crate) fn optional_matrix<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[[f64; 3]; 3]>, D::Error> {
        let rows = Option::<Exactly<Numbers<3>, 3>>::deserialize(d)?;
        Ok(rows.map(|m| m.0.map(|v| v.0.map(|n| n.0))))
    }

    /// An optional pair (actuator limits), exactly.
    pub(crate) fn optional_pair<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[f64; 2]>, D::Error> {
        Ok(Option::<Numbers<2>>::deserialize(d)?.map(|v| v.0.map(|n| n.0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_stand_for_values_and_degrees_for_radians() {
        let parameters = BTreeMap::from([("r".to_owned(), 0.3), ("tilt_deg".to_owned(), 90.0)]);
        #[derive(Deserialize)]
        struct Doc {
            v: [Number; 3],
        }
        let read = |text: &str| toml::from_str::<Doc>(text).map(|d| d.v.map(|n| n.0));
        let values = with_parameters(&parameters, || read(r#"v = ["r", 1, "tilt_deg"]"#));
        let expected = [0.3, 1.0, std::f64::consts::FRAC_PI_2];
        let values = values.unwrap();
        assert!(
            values
                .iter()
                .zip(expected)
                .all(|(v, e)| (v - e).abs() < 1e-15),
            "{values:?}"
        );
        let unknown = with_parameters(&parameters, || read(r#"v = ["s", 0, 0]"#));
        let unknown = unknown.unwrap_err().to_string();
        assert!(unknown.contains("expected one of r, tilt_deg"), "{unknown}");
        // Out of scope again: a name is an error.
        let none = read(r#"v = ["r", 0, 0]"#).unwrap_err().to_string();
        assert!(none.contains("[parameters]"), "{none}");
    }
}
