//! The tables and charts of a dynamics study: the torque histories (`torques.csv`,
//! `torques.svg`) and the retrace's position error and drift (`retrace.csv`, `retrace.svg`).

use super::{RetraceSamples, Torques};
use crate::outcome::{Artifact, Cell, Table};
use pkm_draw::chart::{Chart, Colour, Series, SeriesStyle};

/// Adds the torque table (time, plate position, motor angles in degrees, both torque
/// histories) and the chart of the six histories.
pub(super) fn torques(artifacts: &mut Vec<Artifact>, torques: &Torques) {
    let mut table = Table::new([
        "t",
        "x",
        "y",
        "z",
        "theta_1_deg",
        "theta_2_deg",
        "theta_3_deg",
        "tau_hamilton_1",
        "tau_hamilton_2",
        "tau_hamilton_3",
        "tau_lagrange_1",
        "tau_lagrange_2",
        "tau_lagrange_3",
    ]);
    table.rows = (torques
        .samples
        .iter()
        .zip(&torques.hamilton)
        .zip(&torques.lagrange))
    .map(|(((t, s), h), l)| {
        let mut row: Vec<Cell> = vec![(*t).into()];
        row.extend((0..3).map(|i| Cell::from(s.q[i])));
        row.extend((3..6).map(|i| Cell::from(s.q[i].to_degrees())));
        row.extend(h.iter().chain(l.iter()).map(|v| Cell::from(*v)));
        row
    })
    .collect();
    artifacts.push(Artifact::Table {
        name: "torques.csv".into(),
        table,
    });
    let times: Vec<f64> = torques.samples.iter().map(|(t, _)| *t).collect();
    let mut series = Vec::new();
    for (name, history, style) in [
        ("Hamilton", &torques.hamilton, SeriesStyle::Line),
        ("Lagrange", &torques.lagrange, SeriesStyle::Dashed),
    ] {
        for motor in 0..3 {
            let points = times
                .iter()
                .zip(history)
                .map(|(t, v)| (*t, v[motor]))
                .collect();
            series.push(
                Series::styled(format!("{name}, motor {}", motor + 1), style, points)
                    .with_colour(Colour::Palette(motor)),
            );
        }
    }
    let chart = Chart::series("motor torques", "t (s)", "torque (N m)", series);
    artifacts.push(Artifact::Chart {
        name: "torques.svg".into(),
        chart: Box::new(chart),
    });
}

/// Adds the retrace table (time, position error per axis, drift) and the chart of the
/// position error in millimetres.
pub(super) fn retrace(artifacts: &mut Vec<Artifact>, per_sample: &RetraceSamples) {
    let mut table = Table::new(["t", "error_x", "error_y", "error_z", "drift"]);
    table.rows = per_sample
        .iter()
        .map(|(t, e, d)| vec![(*t).into(), e.x.into(), e.y.into(), e.z.into(), (*d).into()])
        .collect();
    artifacts.push(Artifact::Table {
        name: "retrace.csv".into(),
        table,
    });
    let series = ["x", "y", "z"]
        .iter()
        .enumerate()
        .map(|(i, axis)| {
            let points = per_sample
                .iter()
                .map(|(t, e, _)| (*t, e[i] * 1e3))
                .collect();
            Series::line(format!("{axis} - {axis}_commanded"), points)
        })
        .collect();
    let chart = Chart::series(
        "forward retrace with the Hamilton torques minus the commanded path",
        "t (s)",
        "position difference (mm)",
        series,
    );
    artifacts.push(Artifact::Chart {
        name: "retrace.svg".into(),
        chart: Box::new(chart),
    });
}
