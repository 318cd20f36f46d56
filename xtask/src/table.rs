//! The comparison table: *id | quantity | paper value | pkm value | deviation | verdict*, as
//! aligned plain text for the terminal (verdict coloured on a colour terminal) and as markdown.

use pkm::papers::{Comparison, Verdict};
use std::num::FpCategory;

/// Column headers.
const HEADER: [&str; 6] = [
    "id",
    "quantity",
    "paper value",
    "pkm value",
    "deviation",
    "verdict",
];

/// Placeholder for an empty cell (no paper value, no deviation).
const NONE: &str = "—";

/// `x` rounded to `digits` significant digits, without trailing zeros; scientific notation
/// outside $[10^{-3}, 10^6)$.
pub(crate) fn significant(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    if x.classify() == FpCategory::Zero {
        return "0".to_owned();
    }
    let magnitude = x.abs();
    if !(1e-3..1e6).contains(&magnitude) {
        return format!("{:.*e}", digits.saturating_sub(1), x);
    }
    // floor(log10) of a magnitude in [1e-3, 1e6) lies in [-3, 5]: the cast is exact.
    #[allow(clippy::cast_possible_truncation)]
    let exponent = magnitude.log10().floor() as i64;
    let decimals = usize::try_from(i64::try_from(digits).unwrap_or(6) - 1 - exponent).unwrap_or(0);
    let text = format!("{x:.decimals$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        text
    }
}

/// `x` with an explicit sign.
fn signed(x: f64, digits: usize) -> String {
    let text = significant(x, digits);
    if text.starts_with('-') || x.is_nan() {
        text
    } else {
        format!("+{text}")
    }
}

/// The deviation cell: absolute deviation and, when the paper value is not zero, relative
/// deviation in percent (`+4.6 (+1.15 %)`).
pub(crate) fn deviation(row: &Comparison) -> String {
    let (Some(paper), Some(deviation)) = (row.paper_value, row.deviation()) else {
        return NONE.to_owned();
    };
    let absolute = signed(deviation, 4);
    if paper.classify() == FpCategory::Zero {
        absolute
    } else {
        format!(
            "{absolute} ({} %)",
            signed(100.0 * deviation / paper.abs(), 3)
        )
    }
}

/// The verdict as written in `results.json`.
pub(crate) fn verdict(verdict: Verdict) -> &'static str {
    match verdict {
        Verdict::Pass => "pass",
        Verdict::Fail => "fail",
        Verdict::Erratum => "erratum",
        Verdict::Info => "info",
    }
}

/// The six cells of a row.
pub(crate) fn cells(row: &Comparison) -> [String; 6] {
    let quantity = if row.unit.is_empty() {
        row.quantity.clone()
    } else {
        format!("{} [{}]", row.quantity, row.unit)
    };
    [
        row.id.clone(),
        quantity,
        row.paper_value
            .map_or_else(|| NONE.to_owned(), |p| significant(p, 6)),
        significant(row.value, 6),
        deviation(row),
        verdict(row.verdict).to_owned(),
    ]
}

/// The table as aligned plain text; with `colour`, verdicts are coloured with ANSI escapes.
pub(crate) fn plain(rows: &[Comparison], colour: bool) -> String {
    let body: Vec<[String; 6]> = rows.iter().map(cells).collect();
    let mut widths = HEADER.map(|h| h.chars().count());
    for cells in &body {
        for (width, cell) in widths.iter_mut().zip(cells) {
            *width = (*width).max(cell.chars().count());
        }
    }
    let line = |cells: [&str; 6], verdict: Option<Verdict>| {
        let mut out = String::new();
        for (column, (cell, width)) in cells.iter().zip(widths).enumerate() {
            let pad = " ".repeat(width - cell.chars().count());
            let text = match (column, verdict) {
                (5, Some(v)) if colour => paint(cell, v),
                _ => (*cell).to_owned(),
            };
            // Numbers right-aligned, text left-aligned; no trailing spaces.
            let cell = match column {
                2..=4 => format!("{pad}{text}"),
                5 => text,
                _ => format!("{text}{pad}"),
            };
            out.push_str(&cell);
            out.push_str(if column < 5 { " | " } else { "\n" });
        }
        out
    };
    let mut out = line(HEADER, None);
    let rule: Vec<String> = widths.iter().map(|w| "-".repeat(*w)).collect();
    out.push_str(&rule.join("-|-"));
    out.push('\n');
    for (cells, row) in body.iter().zip(rows) {
        out.push_str(&line(
            cells.each_ref().map(String::as_str),
            Some(row.verdict),
        ));
    }
    out
}

fn paint(text: &str, verdict: Verdict) -> String {
    let styled = console::style(text).force_styling(true);
    match verdict {
        Verdict::Pass => styled.green(),
        Verdict::Fail => styled.red().bold(),
        Verdict::Erratum => styled.yellow(),
        Verdict::Info => styled.cyan(),
    }
    .to_string()
}

/// The table in markdown.
pub(crate) fn markdown(rows: &[Comparison]) -> String {
    let escape = |cell: &str| cell.replace('|', "\\|");
    let mut out = format!("| {} |\n", HEADER.join(" | "));
    out.push_str("|---|---|--:|--:|--:|---|\n");
    for row in rows {
        let cells = cells(row).map(|c| escape(&c));
        out.push_str(&format!("| {} |\n", cells.join(" | ")));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use pkm::papers::{Paper, Source};

    fn source() -> Source {
        Source::new("wolf2006.s4_1.lambda1", Paper::WolfShoham, "§4.1")
    }

    #[test]
    fn significant_digits_trim_and_switch_to_exponent() {
        assert_eq!(significant(404.9, 6), "404.9");
        assert_eq!(significant(0.001234, 6), "0.001234");
        assert_eq!(significant(1.0 / 3.0, 4), "0.3333");
        assert_eq!(significant(-2.5e-7, 3), "-2.50e-7");
        assert_eq!(significant(1.25e8, 3), "1.25e8");
        assert_eq!(significant(0.0, 6), "0");
        assert_eq!(significant(f64::NAN, 6), "NaN");
    }

    #[test]
    fn deviation_is_absolute_and_relative() {
        let row = source().check("F", "", 400.3, 404.9, 8.0);
        assert_eq!(deviation(&row), "+4.6 (+1.15 %)");
        let below = source().check("F", "", 400.0, 396.0, 8.0);
        assert_eq!(deviation(&below), "-4 (-1 %)");
        let zero = source().check("e", "m", 0.0, 0.002, 0.01);
        assert_eq!(deviation(&zero), "+0.002");
        assert_eq!(deviation(&source().info("F", "", 1.0)), NONE);
    }

    #[test]
    fn cells_carry_unit_paper_value_and_verdict() {
        let failed = source().check("L1", "m", 1.0, 2.0, 0.1);
        assert_eq!(
            cells(&failed),
            [
                "wolf2006.s4_1.lambda1",
                "L1 [m]",
                "1",
                "2",
                "+1 (+100 %)",
                "fail"
            ]
            .map(String::from)
        );
        let erratum = failed.erratum("anchor");
        assert_eq!(cells(&erratum)[5], "erratum");
        assert_eq!(cells(&source().info("F", "", 3.5))[2], NONE);
    }

    #[test]
    fn plain_table_is_aligned_and_uncoloured_when_piped() {
        let rows = [
            source().check("F", "", 400.3, 404.9, 8.0),
            source().info("lambda", "", 1.0),
        ];
        let text = plain(&rows, false);
        assert!(
            !text.contains('\u{1b}'),
            "escape codes in plain text: {text:?}"
        );
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 4);
        assert!(lines[0].starts_with("id "));
        assert!(lines[2].ends_with("| pass"));
        assert!(lines[3].ends_with("| info"));
        let separators = |l: &str| {
            let chars = l.chars().enumerate();
            chars
                .filter(|(_, c)| *c == '|')
                .map(|(i, _)| i)
                .collect::<Vec<_>>()
        };
        assert_eq!(separators(lines[0]), separators(lines[2]));
        assert_eq!(separators(lines[2]), separators(lines[3]));
        assert!(plain(&rows, true).contains('\u{1b}'));
    }

    #[test]
    fn markdown_table_has_one_line_per_row() {
        let rows = [source().check("a|b", "", 1.0, 1.0, 0.1)];
        let text = markdown(&rows);
        assert_eq!(text.lines().count(), 3);
        assert!(text.contains("a\\|b"));
        assert!(text.lines().all(|l| l.starts_with('|') && l.ends_with('|')));
    }
}
