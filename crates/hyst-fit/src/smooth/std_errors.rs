//! The standard errors of a smooth fit's parameters, from the covariance at the optimum: the
//! larger, parameter by parameter, of the white-noise estimate cov θ = s² (JᵀJ)⁻¹,
//! s² = Σ r² / (n − p), and the block sandwich (JᵀJ)⁻¹ M (JᵀJ)⁻¹ · G/(G − 1) with M the
//! score's outer product over G blocks ([`Correlation`](crate::smooth::fit::Correlation)),
//! which stays valid when the residuals are correlated; value = f(θ), its standard error
//! |f′(θ)| σ_θ.

use hyst_model::{Estimate, SmoothModel};

use crate::layout::Layout;
use crate::linalg::spd_inverse;
use crate::lm::Solution;
use crate::smooth::limits::{linear_limit_parameters, ParameterLimit};

/// The parameters of `layout` with their values and standard errors at the optimum `best` of a
/// fit to `n` residuals (`model` is the model at `best.theta`), with the block sandwich's
/// middle `meat` (p × p) over its number of blocks when there is one.
///
/// In a parameter limit (the stop form's Dahl limit, the backlash limit) the unidentified
/// parameter carries no information (its column of J vanishes): the covariance of the others is
/// taken without it, and its standard error is NaN.
pub(super) fn estimates(
    layout: &Layout,
    model: &SmoothModel,
    best: &Solution,
    n: usize,
    meat: Option<(&[f64], usize)>,
) -> Vec<Estimate> {
    let p = layout.len();
    let dof = (n - p).max(1) as f64;
    let s2 = best.cost / dof * layout.norm.output_half_span.powi(2);
    let unidentified = unidentified(layout, model, &best.theta);
    let (kept, inv) = covariance(layout, &best.jtj, &unidentified);
    let q = kept.len();
    // The sandwich's diagonal on the kept parameters (θ units; the residuals are scaled).
    let sandwich: Option<Vec<f64>> = match (meat, inv.as_ref()) {
        (Some((m, blocks)), Some(inv)) if blocks > 1 => {
            let correction = blocks as f64 / (blocks - 1) as f64;
            Some(
                (0..q)
                    .map(|a| {
                        let mut v = 0.0;
                        for (x, &i) in kept.iter().enumerate() {
                            for (y, &j) in kept.iter().enumerate() {
                                v += inv[a * q + x] * m[i * p + j] * inv[y * q + a];
                            }
                        }
                        correction * v
                    })
                    .collect(),
            )
        }
        _ => None,
    };
    let scale2 = layout.norm.output_half_span.powi(2);
    layout
        .params
        .iter()
        .enumerate()
        .map(|(j, spec)| {
            let value = spec.transform.value(best.theta[j]);
            // NaN (not identifiable) propagates: NaN.max(0.0) would hide it.
            let var = match (kept.iter().position(|&k| k == j), inv.as_ref()) {
                (Some(a), Some(inv)) => {
                    let white = inv[a * q + a] * s2 / scale2;
                    let robust = sandwich.as_ref().map_or(0.0, |d| d[a]);
                    // NaN (not identifiable) stays NaN: NaN.max(x) would hide it.
                    if white.is_nan() || robust.is_nan() {
                        f64::NAN
                    } else {
                        white.max(robust)
                    }
                }
                _ => f64::NAN,
            };
            let var = if var < 0.0 { 0.0 } else { var };
            Estimate {
                name: spec.name.clone(),
                value,
                std_error: spec.transform.derivative(best.theta[j]).abs() * var.sqrt(),
                unit: spec.unit.clone(),
            }
        })
        .collect()
}

/// The parameters the data cannot identify at θ (`model` is the model there): those a parameter
/// limit leaves unidentified ([`ParameterLimit::unidentified`]), and those of a saturating shape
/// at its linear limit.
fn unidentified(layout: &Layout, model: &SmoothModel, theta: &[f64]) -> Vec<&'static str> {
    let mut unidentified: Vec<&str> = ParameterLimit::of(model)
        .map_or(&[][..], ParameterLimit::unidentified)
        .to_vec();
    // A saturating shape at its linear limit (the fallback of the fit, or a start from a
    // contained fit that ended there) is a line on the data: its scale and its argument at the
    // centre have no effect there (their columns of J vanish).
    unidentified.extend(linear_limit_parameters(layout, theta));
    unidentified
}

/// The parameters that get a standard error (indices into θ, in order) and the inverse of the
/// p × p matrix `jtj` (JᵀJ) on their rows and columns; the inverse is `None` when no such set
/// makes it invertible. The parameters named `unidentified` are left out; when the rest is
/// singular, so are the parameters whose removal makes it invertible.
fn covariance(
    layout: &Layout,
    jtj: &[f64],
    unidentified: &[&str],
) -> (Vec<usize>, Option<Vec<f64>>) {
    let p = layout.len();
    let mut kept: Vec<usize> = (0..p)
        .filter(|&j| !unidentified.contains(&layout.params[j].name.as_str()))
        .collect();
    let mut inv = reduced_inverse(jtj, p, &kept);
    if inv.is_none() {
        // Singular: the parameters whose removal makes it invertible span the direction the
        // data does not see; they get NaN, the others their standard errors without them.
        let lost: Vec<usize> = kept
            .iter()
            .copied()
            .filter(|&j| {
                let without: Vec<usize> = kept.iter().copied().filter(|&k| k != j).collect();
                reduced_inverse(jtj, p, &without).is_some()
            })
            .collect();
        if let Some(&first) = lost.first() {
            let without: Vec<usize> = kept.iter().copied().filter(|&k| k != first).collect();
            inv = reduced_inverse(jtj, p, &without);
            kept = without.into_iter().filter(|k| !lost.contains(k)).collect();
            // Standard errors of the kept ones come from the matrix without `first` only.
            let with_first_removed: Vec<usize> = (0..p)
                .filter(|&j| j != first && !unidentified.contains(&layout.params[j].name.as_str()))
                .collect();
            inv = inv.map(|full| restrict(&full, &with_first_removed, &kept));
        }
    }
    (kept, inv)
}

/// The rows and columns `kept` (indices into θ) of the matrix `full`, whose rows and columns
/// are the parameters `rows` (indices into θ, in order); NaN where a kept one is not among
/// them.
fn restrict(full: &[f64], rows: &[usize], kept: &[usize]) -> Vec<f64> {
    let q = rows.len();
    let mut out = vec![f64::NAN; kept.len() * kept.len()];
    for (a, &i) in kept.iter().enumerate() {
        for (b, &j) in kept.iter().enumerate() {
            let (Some(x), Some(y)) = (
                rows.iter().position(|&k| k == i),
                rows.iter().position(|&k| k == j),
            ) else {
                continue;
            };
            out[a * kept.len() + b] = full[x * q + y];
        }
    }
    out
}

/// The inverse of the rows and columns `kept` of the p × p matrix `a`.
fn reduced_inverse(a: &[f64], p: usize, kept: &[usize]) -> Option<Vec<f64>> {
    let q = kept.len();
    let mut reduced = vec![0.0; q * q];
    for (x, &i) in kept.iter().enumerate() {
        for (y, &j) in kept.iter().enumerate() {
            reduced[x * q + y] = a[i * p + j];
        }
    }
    spd_inverse(&reduced, q)
}
