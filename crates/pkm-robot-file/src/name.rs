//! The architecture name (`3-PRS`, `6-UPS`, `RR+RRR`) checked against the expanded joints.
//!
//! A name is terms joined by `+`, each `<n>-<chain>` (n identical legs) or a chain (one leg):
//! `3-PRS`, `RR+RRR`, `2-UPR+SPR`, `3-UPS+UP`. The actuated joints may
//! be marked by an underscore before their letters (`3-_PRS`, `3-_P_PSR`) or a combining low
//! line after them (`3-P̲RS`, U+0332); when a leg's joints are marked, the marked ones must be
//! exactly its actuated ones.

use crate::chain::LegChain;
use crate::error::RobotFileError;

/// One leg of a name: its letters and the indices of the marked (actuated) letters.
#[derive(Debug, PartialEq)]
struct NamedLeg {
    letters: String,
    actuated: Vec<usize>,
}

fn parse_chain(chain: &str) -> Option<NamedLeg> {
    let mut letters = String::new();
    let mut actuated = Vec::new();
    let mut mark_next = false;
    for c in chain.chars() {
        match c {
            '_' => mark_next = true,
            '\u{332}' if !letters.is_empty() => actuated.push(letters.chars().count() - 1),
            'R' | 'P' | 'U' | 'S' | 'C' => {
                if mark_next {
                    actuated.push(letters.chars().count());
                    mark_next = false;
                }
                letters.push(c);
            }
            _ => return None,
        }
    }
    (!letters.is_empty() && !mark_next).then_some(NamedLeg { letters, actuated })
}

/// The legs of a name: terms joined by `+`, each `<n>-<chain>` (n identical legs) or a chain
/// (one leg), at most [`crate::file::MAX_LEGS`] legs in all.
fn parse_name(name: &str) -> Option<Vec<NamedLeg>> {
    let mut legs = Vec::new();
    for term in name.trim().split('+') {
        let (count, chain) = match term.split_once('-') {
            Some((count, chain)) => (count.trim().parse::<usize>().ok()?, chain),
            None => (1, term),
        };
        if count == 0 || legs.len() + count > crate::file::MAX_LEGS {
            return None;
        }
        let leg = parse_chain(chain.trim())?;
        legs.extend((0..count).map(|_| NamedLeg {
            letters: leg.letters.clone(),
            actuated: leg.actuated.clone(),
        }));
    }
    Some(legs)
}

/// The name the legs spell: runs of alike consecutive legs as `<n>-<letters>` (a single leg
/// as its letters) joined by `+`, e.g. `2-UPR+SPR`.
pub(crate) fn spelled_name(legs: &[LegChain]) -> String {
    let mut terms: Vec<(usize, &str)> = Vec::new();
    for leg in legs {
        match terms.last_mut() {
            Some((count, letters)) if *letters == leg.letters => *count += 1,
            _ => terms.push((1, &leg.letters)),
        }
    }
    terms
        .iter()
        .map(|&(count, letters)| match count {
            1 => letters.to_string(),
            n => format!("{n}-{letters}"),
        })
        .collect::<Vec<_>>()
        .join("+")
}

/// Checks `name` against `legs` (count, letters, marked actuators).
///
/// # Errors
/// [`RobotFileError::NameMismatch`] naming what the joints spell.
pub(crate) fn check_name(name: &str, legs: &[LegChain]) -> Result<(), RobotFileError> {
    let mismatch = || RobotFileError::NameMismatch {
        name: name.to_string(),
        found: spelled_name(legs),
    };
    let named = parse_name(name).ok_or_else(mismatch)?;
    if named.len() != legs.len() {
        return Err(mismatch());
    }
    for (n, leg) in named.iter().zip(legs) {
        if n.letters != leg.letters {
            return Err(mismatch());
        }
        if !n.actuated.is_empty() && n.actuated != letters_of_actuators(leg) {
            return Err(mismatch());
        }
    }
    Ok(())
}

/// Indices of the letters that hold the actuated elementary joints, in order (a U spans two
/// joints, a C two).
fn letters_of_actuators(leg: &LegChain) -> Vec<usize> {
    let mut joint = 0;
    let mut marked = Vec::new();
    for (k, c) in leg.letters.chars().enumerate() {
        let width = match c {
            'U' | 'C' => 2,
            _ => 1,
        };
        if leg
            .actuators
            .iter()
            .any(|a| (joint..joint + width).contains(&a.joint))
        {
            marked.push(k);
        }
        joint += width;
    }
    marked
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse() {
        assert_eq!(parse_name("3-PRS").map(|v| v.len()), Some(3));
        assert_eq!(
            parse_name("3-_PRS").and_then(|v| v.into_iter().next()),
            Some(NamedLeg {
                letters: "PRS".into(),
                actuated: vec![0]
            })
        );
        assert_eq!(
            parse_name("3-RP\u{332}R")
                .and_then(|v| v.into_iter().next())
                .map(|l| l.actuated),
            Some(vec![1])
        );
        assert_eq!(
            parse_name("3-_P_PSR")
                .and_then(|v| v.into_iter().next())
                .map(|l| l.actuated),
            Some(vec![0, 1])
        );
        assert_eq!(parse_name("RR+RRR").map(|v| v.len()), Some(2));
        assert_eq!(parse_name("2-UPR+SPR").map(|v| v.len()), Some(3));
        assert_eq!(parse_name("3-UPS + UP").map(|v| v.len()), Some(4));
        for bad in [
            "",
            "3-",
            "0-RRR",
            "x-RRR",
            "3-RQR",
            "3-RR_",
            "99999-R",
            "2-RR+",
            "40-R+40-R",
        ] {
            assert!(parse_name(bad).is_none(), "{bad}");
        }
    }
}
