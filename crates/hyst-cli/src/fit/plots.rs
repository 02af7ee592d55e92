//! The plots of `hyst fit`: data and model in the input-output plane, residuals over time.

use std::path::{Path, PathBuf};

/// The plots `hyst fit --plot DIR` writes: `DIR/STEM.png` and `DIR/STEM.svg` for each stem.
pub const PLOT_STEMS: [&str; 2] = ["fit-io", "fit-residuals"];

/// Every file `--plot dir` writes, for the check that no output is an input or another output.
#[must_use]
pub fn plot_files(dir: &Path) -> Vec<PathBuf> {
    PLOT_STEMS
        .iter()
        .flat_map(|stem| ["png", "svg"].map(|ext| dir.join(format!("{stem}.{ext}"))))
        .collect()
}

use anyhow::{Context, Result};
use hyst_fit::pi_fit::PiFit;
use hyst_fit::smooth::run_records;
use hyst_fit::{Dataset, SmoothFit};
use hyst_io::Table;
use hyst_model::time::time_column as named_time_column;

use crate::plot::{Figure, Panel, Series};

/// Keeps at most `max` points, evenly spaced.
fn thin(points: Vec<(f64, f64)>, max: usize) -> Vec<(f64, f64)> {
    if points.len() <= max {
        return points;
    }
    let step = points.len().div_ceil(max);
    points.into_iter().step_by(step).collect()
}

/// Points of a plot series.
type Points = Vec<(f64, f64)>;

/// The time axis of the residual plot: `--time COL`, else a column with a conventional time name
/// (a copy: the table is dropped before the fit).
pub(super) fn time_column(table: &Table, name: Option<&str>) -> Result<Option<(String, Vec<f64>)>> {
    if let Some(name) = name {
        let column = table.column(name).context("--time")?;
        return Ok(Some((name.to_string(), column.to_vec())));
    }
    Ok(named_time_column(None, |n| table.column(n).is_ok())
        .and_then(|n| Some((n.to_string(), table.column(n).ok()?.to_vec()))))
}

/// The names and units of the input and output columns, for the axes.
pub(super) struct Axes<'a> {
    /// The input column.
    pub input: &'a str,
    /// Its unit (empty when not given).
    pub input_unit: &'a str,
    /// The output column.
    pub output: &'a str,
    /// Its unit (empty when not given).
    pub output_unit: &'a str,
}

/// Draws `fit-io` and `fit-residuals` (PNG and SVG) into `dir`; returns the files written.
pub(super) fn draw(
    dir: &Path,
    data: &Dataset,
    axes: &Axes<'_>,
    time: Option<(&str, &[f64])>,
    smooth: Option<&SmoothFit>,
    pi: Option<&PiFit>,
) -> Result<Vec<PathBuf>> {
    let xl = format!("{}{}", axes.input, unit_paren(axes.input_unit));
    let yl = format!("{}{}", axes.output, unit_paren(axes.output_unit));
    let mut measured = Vec::new();
    let mut models: Vec<(String, Points, Points)> = Vec::new();
    for r in &data.records {
        for (x, y) in r.input.iter().zip(&r.output) {
            measured.push((*x, *y));
        }
    }
    // As the fit ran them: segments of one measurement run on from each other, from the
    // estimated starts when the fit estimated them.
    let runs: Vec<(&str, Option<Vec<Vec<f64>>>)> = [
        smooth.map(|f| {
            let starts = f.starts.as_deref();
            ("smooth model", run_records(data, &f.model, starts))
        }),
        pi.map(|f| {
            (
                "Prandtl–Ishlinskii",
                data.run_histories(|x| f.model.run(x).ok()),
            )
        }),
    ]
    .into_iter()
    .flatten()
    .collect();
    for (name, outputs) in runs {
        let mut io = Vec::new();
        let mut res = Vec::new();
        let outputs = outputs.context("the fitted model cannot run the data")?;
        for (r, y) in data.records.iter().zip(&outputs) {
            for (((x, m), o), row) in r.input.iter().zip(y).zip(&r.output).zip(r.rows.iter()) {
                io.push((*x, *m));
                let at = match time {
                    Some((_, t)) => t.get(row).copied().unwrap_or(f64::NAN),
                    None => (row + 1) as f64,
                };
                res.push((at, m - o));
            }
        }
        models.push(((*name).to_string(), io, res));
    }
    let mut io_panel = Panel::new("Data and model in the input-output plane", &xl, &yl)
        .series(Series::scatter("measured", thin(measured, 20_000)).color(0));
    let (res_title, res_x) = match time {
        Some((name, _)) => ("Residuals (model − measured) over time", name.to_string()),
        None => (
            "Residuals (model − measured) over the samples",
            "sample (data row)".to_string(),
        ),
    };
    let output_unit = if axes.output_unit.is_empty() {
        format!(" (units of {})", axes.output)
    } else {
        unit_paren(axes.output_unit)
    };
    let mut res_panel = Panel::new(res_title, &res_x, &format!("residual{output_unit}"));
    for (i, (name, io, res)) in models.into_iter().enumerate() {
        let color = i + 1;
        io_panel = io_panel.series(
            Series::scatter(&name, thin(io, 20_000))
                .color(color)
                .width(1),
        );
        res_panel = res_panel.series(
            Series::scatter(&name, thin(res, 20_000))
                .color(color)
                .width(1),
        );
    }
    let [io, residuals] = PLOT_STEMS;
    let mut written = Figure::row(vec![io_panel]).save(dir, io)?;
    written.extend(Figure::row(vec![res_panel.hline("0", 0.0)]).save(dir, residuals)?);
    Ok(written)
}

fn unit_paren(u: &str) -> String {
    if u.is_empty() {
        String::new()
    } else {
        format!(" ({u})")
    }
}
