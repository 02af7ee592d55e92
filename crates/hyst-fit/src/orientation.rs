//! Which way the data's loops run, and the model form that follows from it; and, for records
//! that move one way only (first-order reversal curves), the start rule that follows from that.
//!
//! A loop runs counterclockwise in the (input, output) plane when the output is lower while the
//! input rises than while it falls at the same input (the output lags: the operator's own
//! loops), and clockwise when it is higher (the output leads: friction against position, the
//! stop form). The input range is cut into bins; in each bin that holds both, the mean output
//! of the rising samples minus that of the falling samples is the gap between the branches, and
//! the sign of the samples-weighted mean gap gives the orientation. Unlike the signed area
//! ∮ y dx, it needs no closed loop, and a curve without loops gives a gap near 0 whatever its
//! shape.

use serde::{Deserialize, Serialize};

use hyst_model::{Choice, Form, InitialState};

use crate::data::Dataset;

/// Below this gap between its rising and falling branches (fraction of the output span), a
/// model has no loop: 0.1 %, about the resolution of a 10-bit sensor.
pub const MIN_GAP: f64 = 1e-3;

/// The direction of the data's hysteresis loops in the (input, output) plane.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Orientation {
    /// The output lags the input (piezo stacks, magnetic materials): the operator form.
    Counterclockwise,
    /// The output leads the input (friction against position): the stop form.
    Clockwise,
    /// No loop: the branches are less than [`MIN_GAP`] of the output span
    /// apart (a curve, or noise around one).
    None,
}

impl Orientation {
    /// The name printed in reports and written to JSON.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Orientation::Counterclockwise => "counterclockwise",
            Orientation::Clockwise => "clockwise",
            Orientation::None => "none",
        }
    }
}

/// The loops found in a dataset: their orientation and the gap between their branches.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Loops {
    /// The orientation of the mean gap ([`Orientation::None`] when it is below
    /// [`MIN_GAP`]).
    pub orientation: Orientation,
    /// The mean output while rising minus while falling at the same input, as a fraction of the
    /// output span: positive for clockwise, near 0 for data without loops (noise and rate
    /// effects give a few 0.1 %), up to 1 for a rectangle.
    pub gap: f64,
}

/// Input bins of the branch comparison.
const BINS: usize = 32;

/// A training sample that moves, with its direction and input bin; input and output
/// normalised to [0, 1] over their ranges.
struct Directed {
    falling: bool,
    bin: usize,
    x: f64,
    y: f64,
    weight: f64,
}

/// The input and output ranges samples are normalised over.
#[derive(Clone, Copy, Debug)]
struct Normalisation {
    /// Lowest input and the input span.
    xlo: f64,
    xs: f64,
    /// Lowest output and the output span.
    ylo: f64,
    ys: f64,
}

impl Normalisation {
    /// Over `(xlo, xhi)` and `(ylo, yhi)` (a span below the smallest positive float counts as
    /// that).
    fn new((xlo, xhi): (f64, f64), (ylo, yhi): (f64, f64)) -> Self {
        Normalisation {
            xlo,
            xs: (xhi - xlo).max(f64::MIN_POSITIVE),
            ylo,
            ys: (yhi - ylo).max(f64::MIN_POSITIVE),
        }
    }

    /// Sample `i` of a record of inputs `input`, of output `y` and weight `weight`, if its
    /// weight is positive and its input moves there (the direction by the central difference,
    /// one-sided at the ends).
    fn directed(&self, input: &[f64], i: usize, y: f64, weight: f64) -> Option<Directed> {
        let n = input.len();
        let (a, b) = (i.saturating_sub(1), (i + 1).min(n.checked_sub(1)?));
        let dx = input.get(b)? - input.get(a)?;
        if dx == 0.0 || weight <= 0.0 {
            return None;
        }
        let x = (input.get(i)? - self.xlo) / self.xs;
        Some(Directed {
            falling: dx < 0.0,
            bin: ((x * BINS as f64).floor().max(0.0) as usize).min(BINS - 1),
            x,
            y: (y - self.ylo) / self.ys,
            weight,
        })
    }
}

/// [`loops`] gathered sample by sample ([`LoopSums::add`]), normalised over given ranges: the
/// data's, or a model's outputs replayed in place of the measured ones (none of them held).
pub(crate) struct LoopSums {
    /// The ranges.
    normalisation: Normalisation,
    /// Per bin and direction (0 rising, 1 falling): n, Σx, Σy, Σx², Σxy, in normalised units.
    sums: [[[f64; 5]; 2]; BINS],
}

impl LoopSums {
    /// No samples yet, normalised over `input_range` and `output_range`.
    pub(crate) fn new(input_range: (f64, f64), output_range: (f64, f64)) -> Self {
        LoopSums {
            normalisation: Normalisation::new(input_range, output_range),
            sums: [[[0.0; 5]; 2]; BINS],
        }
    }

    /// Adds sample `i` of a record of inputs `input`, with output `y` and weight `weight`.
    pub(crate) fn add(&mut self, input: &[f64], i: usize, y: f64, weight: f64) {
        if let Some(d) = self.normalisation.directed(input, i, y, weight) {
            self.push(&d);
        }
    }

    /// Adds a directed sample.
    fn push(&mut self, d: &Directed) {
        let s = &mut self.sums[d.bin][usize::from(d.falling)];
        for (acc, v) in s.iter_mut().zip([1.0, d.x, d.y, d.x * d.x, d.x * d.y]) {
            *acc += v;
        }
    }

    /// The loops of the samples added.
    pub(crate) fn loops(&self) -> Loops {
        // In each bin, both branches as lines of one common slope: the gap is the difference
        // of their intercepts at the same input (a steep curve sampled at different inputs on
        // the way up and down has no gap).
        let (mut gap, mut weight) = (0.0, 0.0);
        for &[[nr, xr, yr, xxr, xyr], [nf, xf, yf, xxf, xyf]] in &self.sums {
            if nr < 2.0 || nf < 2.0 {
                continue;
            }
            let sxx = (xxr - xr * xr / nr) + (xxf - xf * xf / nf);
            let sxy = (xyr - xr * yr / nr) + (xyf - xf * yf / nf);
            let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
            let w = nr.min(nf);
            gap += w * ((yr / nr - yf / nf) - slope * (xr / nr - xf / nf));
            weight += w;
        }
        let gap = if weight > 0.0 { gap / weight } else { 0.0 };
        Loops {
            orientation: if gap.abs() < MIN_GAP {
                Orientation::None
            } else if gap > 0.0 {
                Orientation::Clockwise
            } else {
                Orientation::Counterclockwise
            },
            gap,
        }
    }
}

/// The training samples of `data` of positive weight whose input moves (the direction by the
/// central difference, one-sided at the ends), each in its bin of [`BINS`] over the input
/// range: what [`against_trend`] sums ([`loops`] sums the same ones, by [`LoopSums::add`]).
fn directed(data: &Dataset) -> impl Iterator<Item = Directed> + '_ {
    let normalisation = Normalisation::new(data.input_range(), data.output_range());
    data.training().flat_map(move |r| {
        (0..r.len()).filter_map(move |i| {
            normalisation.directed(&r.input, i, *r.output.get(i)?, r.weight.get(i)?)
        })
    })
}

/// The orientation of the loops in the training records of `data`.
#[must_use]
pub fn loops(data: &Dataset) -> Loops {
    let mut sums = LoopSums::new(data.input_range(), data.output_range());
    for r in data.training() {
        for (i, (y, w)) in r.output.iter().zip(&r.weight).enumerate() {
            sums.add(&r.input, i, *y, w);
        }
    }
    sums.loops()
}

/// The form the user asks for: chosen from the data, or given.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FormChoice {
    /// The stop form when the data's loops run clockwise, the operator form otherwise (also
    /// when there is no loop).
    #[default]
    Auto,
    /// Always the operator form ψ_out(H[ψ_in(in)]).
    Operator,
    /// Always the stop form ψ_out(v − H[v]) + c·v.
    Stop,
}

impl Choice for FormChoice {
    const WHAT: &'static str = "form";
    const CHOICES: &'static [(Self, &'static str, &'static str)] = &[
        (
            FormChoice::Auto,
            "auto",
            "The stop form when the data's loops run clockwise, the operator form otherwise (also \
             when there is no loop)",
        ),
        (
            FormChoice::Operator,
            "operator",
            "Always the operator form ψ_out(H[ψ_in(in)])",
        ),
        (
            FormChoice::Stop,
            "stop",
            "Always the stop form ψ_out(v − H[v]) + c·v",
        ),
    ];
}

impl FormChoice {
    /// The form for data whose loops run `orientation`.
    #[must_use]
    pub fn resolve(self, orientation: Orientation) -> Form {
        match (self, orientation) {
            (FormChoice::Operator, _) => Form::Operator,
            (FormChoice::Stop, _) => Form::Stop,
            (FormChoice::Auto, Orientation::Counterclockwise | Orientation::None) => Form::Operator,
            (FormChoice::Auto, Orientation::Clockwise) => Form::Stop,
        }
    }
}

/// How far the output goes against its own trend along the input, as a fraction of the output
/// span. For the rising and the falling samples apart (the direction by the central
/// difference, as [`loops`]), the mean output in each of [`BINS`] input bins, and the largest
/// fall of that curve below an earlier peak (for an overall rise) or rise above an earlier
/// trough (for an overall fall); the smaller of the two branches' values (bins of fewer than
/// five samples are left out, and a branch with fewer than two bins left does not count; 0 when
/// neither does). Each branch of a hysteresis
/// loop is monotone (near 0 however wide the loop); a butterfly loop (magnetostriction, whose
/// output is even in the field) or a sensor that folds gives a large value on both.
#[must_use]
pub fn against_trend(data: &Dataset) -> f64 {
    // Per direction (0 rising, 1 falling) and bin: Σw, Σw·y, samples.
    let mut sums = [[(0.0_f64, 0.0_f64, 0_usize); BINS]; 2];
    for d in directed(data) {
        if let Some(s) = sums[usize::from(d.falling)].get_mut(d.bin) {
            s.0 += d.weight;
            s.1 += d.weight * d.y;
            s.2 += 1;
        }
    }
    let branch = |sums: &[(f64, f64, usize); BINS]| -> Option<f64> {
        // Bins of fewer than MIN_BIN_SAMPLES samples are left out: one noisy sample is no
        // trend.
        let means: Vec<f64> = sums
            .iter()
            .filter(|s| s.0 > 0.0 && s.2 >= MIN_BIN_SAMPLES)
            .map(|s| s.1 / s.0)
            .collect();
        if means.len() < 2 {
            return None;
        }
        let sign = if means[means.len() - 1] >= means[0] {
            1.0
        } else {
            -1.0
        };
        let (mut peak, mut worst) = (f64::NEG_INFINITY, 0.0_f64);
        for m in &means {
            peak = peak.max(sign * m);
            worst = worst.max(peak - sign * m);
        }
        Some(worst)
    };
    match (branch(&sums[0]), branch(&sums[1])) {
        (Some(a), Some(b)) => a.min(b),
        (Some(a), None) | (None, Some(a)) => a,
        (None, None) => 0.0,
    }
}

/// Samples a bin of one branch needs to count in [`against_trend`].
const MIN_BIN_SAMPLES: usize = 5;

/// Which way every training record of `data` moves, when each moves one way only (at most 1 %
/// of its moving samples the other way) and all the same way: `Some(true)` rising, `Some(false)`
/// falling. First-order reversal curves rise only; no loop can show in such data, whatever the
/// material does.
#[must_use]
pub fn one_way(data: &Dataset) -> Option<bool> {
    let mut way = None;
    for r in data.training() {
        let (mut up, mut down) = (0usize, 0usize);
        for w in r.input.windows(2) {
            if w[1] > w[0] {
                up += 1;
            } else if w[1] < w[0] {
                down += 1;
            }
        }
        if up + down == 0 || up.min(down) * 100 > up + down {
            return None;
        }
        let rising = up > down;
        if way.is_some_and(|w| w != rising) {
            return None;
        }
        way = Some(rising);
    }
    way
}

/// How each record starts, as the user asks for it: chosen from the data, or given.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StartChoice {
    /// `falling` when every record only rises (first-order reversal curves: each starts at a
    /// reversal after a fall from saturation), `rising` when every record only falls, `rising`
    /// otherwise.
    #[default]
    Auto,
    /// As after a long rise: on the lower asymptote output = input − k1, heading up.
    Rising,
    /// As after a long fall: on the upper asymptote output = input + k1, heading down.
    Falling,
    /// No history: the first sample is a reversal point on the anhysteretic line.
    Line,
}

impl Choice for StartChoice {
    const WHAT: &'static str = "initial state";
    const CHOICES: &'static [(Self, &'static str, &'static str)] = &[
        (
            StartChoice::Auto,
            "auto",
            "`falling` when every record only rises (first-order reversal curves: each starts at \
             a reversal after a fall from saturation), `rising` when every record only falls, \
             `rising` otherwise",
        ),
        (
            StartChoice::Rising,
            "rising",
            "As after a long rise: on the lower asymptote output = input − k1, heading up",
        ),
        (
            StartChoice::Falling,
            "falling",
            "As after a long fall: on the upper asymptote output = input + k1, heading down",
        ),
        (
            StartChoice::Line,
            "line",
            "No history: the first sample is a reversal point on the anhysteretic line",
        ),
    ];
}

impl StartChoice {
    /// The start rule for `data`, and whether `Auto` chose it because the records move one way.
    #[must_use]
    pub fn resolve(self, data: &Dataset) -> (InitialState, bool) {
        match self {
            StartChoice::Rising => (InitialState::Rising, false),
            StartChoice::Falling => (InitialState::Falling, false),
            StartChoice::Line => (InitialState::Line, false),
            StartChoice::Auto => match one_way(data) {
                Some(true) => (InitialState::Falling, true),
                Some(false) => (InitialState::Rising, true),
                None => (InitialState::Rising, false),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::data::Record;

    fn circle(clockwise: bool) -> Dataset {
        let n = 400;
        let (x, y): (Vec<f64>, Vec<f64>) = (0..=n)
            .map(|k| {
                let t = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                let s = if clockwise { -t.sin() } else { t.sin() };
                (t.cos(), s)
            })
            .unzip();
        Dataset::single(&x, &y)
    }

    #[test]
    fn a_circle_has_the_mean_gap_of_its_branches_and_its_direction() {
        // x = cos t, y = ± sin t: the branches are ±√(1 − x²) (normalised to [0, 1]: gap
        // √(1 − x²)), whose mean over bins of equal sample counts is about π/4 … 1.
        let ccw = loops(&circle(false));
        assert_eq!(ccw.orientation, Orientation::Counterclockwise);
        assert!(ccw.gap < -0.5 && ccw.gap > -1.0, "{ccw:?}");
        let cw = loops(&circle(true));
        assert_eq!(cw.orientation, Orientation::Clockwise);
        assert!((cw.gap + ccw.gap).abs() < 1e-12, "{cw:?}");
    }

    #[test]
    fn a_curve_without_loops_has_no_area() {
        let x: Vec<f64> = (0..200).map(|k| (k as f64 * 0.1).sin() * 3.0).collect();
        let y: Vec<f64> = x.iter().map(|v| 1e300 * v.tanh()).collect();
        let l = loops(&Dataset::single(&x, &y));
        assert!(l.gap.abs() < 1e-3, "{l:?}");
        assert_eq!(l.orientation, Orientation::None);
    }

    #[test]
    fn auto_follows_the_orientation_and_a_given_form_does_not() {
        use Orientation::{Clockwise, Counterclockwise};
        assert_eq!(FormChoice::Auto.resolve(Orientation::None), Form::Operator);
        assert_eq!(FormChoice::Auto.resolve(Clockwise), Form::Stop);
        assert_eq!(FormChoice::Auto.resolve(Counterclockwise), Form::Operator);
        assert_eq!(FormChoice::Operator.resolve(Clockwise), Form::Operator);
        assert_eq!(FormChoice::Stop.resolve(Counterclockwise), Form::Stop);
    }

    #[test]
    fn records_that_only_rise_start_as_after_a_fall() {
        let rise: Vec<f64> = (0..50).map(|i| f64::from(i) * 0.1).collect();
        let fall: Vec<f64> = rise.iter().rev().copied().collect();
        let records = |inputs: &[&Vec<f64>]| {
            let template = Dataset::single(&[0.0], &[0.0]);
            let records = inputs
                .iter()
                .enumerate()
                .map(|(id, x)| Record {
                    id: id as i64,
                    input: (*x).clone().into(),
                    output: (*x).clone().into(),
                    weight: crate::Weights::Unit(x.len()),
                    rows: (0..x.len()).collect(),
                    validation: false,
                    continues: false,
                    period: None,
                })
                .collect();
            Dataset::from_records("d.csv", template.columns, records)
        };
        let forc = records(&[&rise, &rise]);
        assert_eq!(one_way(&forc), Some(true));
        assert_eq!(
            StartChoice::Auto.resolve(&forc),
            (InitialState::Falling, true)
        );
        assert_eq!(
            StartChoice::Auto.resolve(&records(&[&fall])),
            (InitialState::Rising, true)
        );
        // Records moving both ways, or one rising and one falling: the rising rule, as before.
        let both: Vec<f64> = rise.iter().chain(&fall).copied().collect();
        for data in [records(&[&both]), records(&[&rise, &fall])] {
            assert_eq!(one_way(&data), None);
            assert_eq!(
                StartChoice::Auto.resolve(&data),
                (InitialState::Rising, false)
            );
        }
        // A given rule is kept.
        assert_eq!(
            StartChoice::Line.resolve(&forc),
            (InitialState::Line, false)
        );
    }

    #[test]
    fn a_butterfly_goes_against_its_trend_and_a_loop_does_not() {
        // x sweeps ±1 three times; a loop's branches (x ∓ 0.3 tanh-like offset) are monotone, a
        // butterfly's (x², shifted between the branches) fall and rise again.
        let x: Vec<f64> = (0..3000)
            .map(|k| (k as f64 * 2.0 * std::f64::consts::PI / 1000.0).sin())
            .collect();
        let rising = |i: usize| i + 1 < x.len() && x[i + 1] > x[i];
        let looped: Vec<f64> = (0..x.len())
            .map(|i| x[i] + if rising(i) { -0.3 } else { 0.3 })
            .collect();
        let butterfly: Vec<f64> = (0..x.len())
            .map(|i| {
                let s = if rising(i) { 0.1 } else { -0.1 };
                (x[i] + s) * (x[i] + s)
            })
            .collect();
        assert!(against_trend(&Dataset::single(&x, &looped)) < 0.01);
        let b = against_trend(&Dataset::single(&x, &butterfly));
        assert!(b > 0.6, "{b}");
        assert_eq!(against_trend(&Dataset::single(&[1.0], &[2.0])), 0.0);
        // A short, noisy loop (120 samples, noise a tenth of the span, bins of one or two
        // samples): under the limit of 0.2.
        let mut seed = 7_u64;
        let mut noise = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.6
        };
        let (xs, ys): (Vec<f64>, Vec<f64>) = (0..120)
            .map(|i| {
                let x = (i as f64 * 2.0 * std::f64::consts::PI / 60.0).sin();
                let rising = (i as f64 * 2.0 * std::f64::consts::PI / 60.0).cos() > 0.0;
                (x, x + if rising { -0.3 } else { 0.3 } + noise())
            })
            .unzip();
        let noisy = against_trend(&Dataset::single(&xs, &ys));
        assert!(noisy < 0.2, "{noisy}");
    }
}
