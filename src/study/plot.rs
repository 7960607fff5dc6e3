//! The figures of a sweep's table ([`crate::present::figures::sweep`]): the grid of values
//! over its first two axes.

use super::run::Row;
use crate::error::{Error, Result};
use crate::present::figures::sweep::{sweep_lines_figure, sweep_map_figure, SweepGrid};
use crate::present::figures::Figure;

/// The figures of a table with axes `axes` (the columns after `point`): with one axis the value
/// against it; with two or more, the value against the second axis with one line per value of
/// the first, and the heat map over both (further axes held at their smallest value). The value
/// is the objective where the table has one, else the displacement per period.
pub fn figures(axes: &[String], rows: &[Row]) -> Result<Vec<Figure>> {
    if axes.is_empty() || rows.is_empty() {
        return Err(Error::invalid(
            "sweep table",
            format!("{} rows", rows.len()),
            "the figures need at least one axis and one row",
        ));
    }
    let objective = rows.iter().any(|r| r.objective.is_some());
    let value = |r: &Row| {
        if objective {
            r.objective
        } else {
            r.displacement_per_period
        }
    };
    let distinct = |j: usize| {
        let mut v: Vec<f64> = rows.iter().map(|r| r.values[j]).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let (xj, yj) = if axes.len() == 1 {
        (0, None)
    } else {
        (1, Some(0))
    };
    let held: Vec<(usize, f64)> = (2..axes.len()).map(|j| (j, distinct(j)[0])).collect();
    let x = distinct(xj);
    let y = yj.map_or(vec![0.0], distinct);
    let mut values = vec![vec![None; x.len()]; y.len()];
    for r in rows {
        if held.iter().any(|&(j, v)| r.values[j] != v) {
            continue;
        }
        let ix = x
            .iter()
            .position(|&v| v == r.values[xj])
            .expect("a value of x");
        let iy = yj.map_or(0, |j| {
            y.iter()
                .position(|&v| v == r.values[j])
                .expect("a value of y")
        });
        values[iy][ix] = value(r).filter(|v| v.is_finite());
    }
    let grid = SweepGrid {
        x_name: axes[xj].clone(),
        x,
        y_name: yj.map_or(String::new(), |j| axes[j].clone()),
        y,
        value_name: if objective {
            "objective J"
        } else {
            "displacement per period"
        }
        .into(),
        values,
    };
    let mut figs = vec![sweep_lines_figure(&grid)?];
    if yj.is_some() {
        figs.push(sweep_map_figure(&grid)?);
    }
    Ok(figs)
}
