//! The truths of these tests (Example 2's plant and hysteresis, multisines) and the files they
//! write and read.

use super::*;

/// The truth's hysteresis output ψ(H[v]) along `v`, started as after a rise.
pub(crate) fn hysteresis(model: &mut impl Operator<f64>, v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| model.try_step(*x).unwrap()).collect()
}

pub(crate) fn example2_model(first: f64) -> impl Operator<f64> {
    let h = InitialState::Rising
        .start(Hysteresis::new(0.06, 5.0).unwrap(), first)
        .unwrap();
    ShapedModel::new(Identity, h, QuadraticExp::<f64>::example2().unwrap()).unwrap()
}

/// A multisine about `centre` with amplitude `amp`, phases set by `seed`.
pub(crate) fn multisine(
    centre: f64,
    amp: f64,
    freqs: &'static [f64],
    seed: f64,
) -> impl Fn(f64) -> f64 {
    move |t: f64| {
        let s: f64 = freqs
            .iter()
            .enumerate()
            .map(|(i, f)| (2.0 * std::f64::consts::PI * f * t + seed * (i as f64 + 1.0)).sin())
            .sum();
        // Start at rest: the envelope rises over the first half second.
        let ramp = (t / 0.5).min(1.0);
        centre + amp * ramp * s / freqs.len() as f64
    }
}

pub(crate) fn write_csv(path: &Path, header: &str, rows: &[Vec<f64>]) {
    let mut text = format!("{header}\n");
    for r in rows {
        let line: Vec<String> = r.iter().map(|v| format!("{v:e}")).collect();
        text.push_str(&line.join(","));
        text.push('\n');
    }
    std::fs::write(path, text).unwrap();
}

/// A static fit of `y` against `x` (columns u, y) written to `model`, given the plant
/// `[dynamics] a = A` (b = 1) by hand (format version 4).
pub(crate) fn fit_with_plant(dir: &Path, x: &[f64], y: &[f64], a: &str, model: &Path) {
    let rows: Vec<Vec<f64>> = x.iter().zip(y).map(|(&x, &y)| vec![x, y]).collect();
    let data = dir.join("s.csv");
    write_csv(&data, "u,y", &rows);
    HYST.stdout(&[
        "fit",
        data.to_str().unwrap(),
        "--input",
        "u",
        "--output",
        "y",
        "-o",
        model.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(model)
        .unwrap()
        .replace("version = 1", "version = 4")
        + &format!("\n[dynamics]\nb = 1.0\na = {a}\n");
    std::fs::write(model, text).unwrap();
}

pub(crate) fn read_column(path: &Path, name: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(at).unwrap().parse().unwrap())
        .collect()
}

pub(crate) const FREQS: &[f64] = &[0.31, 0.77, 1.6, 3.3, 6.1];
