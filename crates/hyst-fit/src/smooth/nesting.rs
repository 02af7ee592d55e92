//! The nesting of simpler structures in richer ones: the structures one contains
//! ([`contained`], [`simpler`]), and the optimum of a contained structure placed as a point of
//! the richer one ([`embed`]), a start of its fit.

use hyst_core::Shaping;
use hyst_model::{Form, K2Kind, ShapingKind, SmoothModel, Structure};

use crate::layout::{Layout, IN_ARG_AT_CENTRE, IN_SCALE, OUT_ARG_AT_CENTRE, OUT_SCALE};
use crate::smooth::fit::SmoothFit;

/// The scale (in units of its argument's reach on the data) of a saturating shape in the
/// nested start from an affine one: linear to 1 part in 2,700 there, yet curved enough for the
/// descent to find a curvature the data calls for.
pub(super) const NESTED_SCALE: f64 = 30.0;

/// The structures `structure` contains one step down the lattice: constant k2 for affine k2,
/// the next simpler ψ_in, the next simpler ψ_out (those that exist, in this order; the first is
/// [`simpler`]'s). A structure with affine k2 and two shapings contains three; each of them is
/// also contained in others, so the fit of one structure fits each structure below it once.
#[must_use]
pub fn contained(structure: Structure) -> Vec<Structure> {
    [
        simpler_k2(structure),
        simpler_input(structure),
        simpler_output(structure),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// The simpler structure that `structure` contains, whose optimum is an exact (or, for a
/// saturating shaping, a close) point of `structure`: affine k2 ⊃ constant k2; polynomial ψ_in
/// ⊃ affine ψ_in; tanh and Langevin ψ_in ⊃ affine in the limit of a wide scale (a saturating
/// ψ_in has slope 1 at the input's centre, so k1 and k2 carry over); poly3 ψ_out ⊃ poly2 ⊃
/// affine; tanh and Langevin ψ_out ⊃ affine in the limit of a wide scale. `None` for the
/// simplest structures (and for a quadratic-exp ψ_in, whose limit rescales k1 and k2).
#[must_use]
pub fn simpler(structure: Structure) -> Option<Structure> {
    simpler_k2(structure)
        .or_else(|| simpler_input(structure))
        .or_else(|| simpler_output(structure))
}

/// `structure` with constant k2, if its k2 is affine.
fn simpler_k2(structure: Structure) -> Option<Structure> {
    (structure.k2 == K2Kind::Affine).then_some(Structure {
        k2: K2Kind::Constant,
        ..structure
    })
}

/// `structure` with the next simpler ψ_in, if there is one.
fn simpler_input(structure: Structure) -> Option<Structure> {
    let input_shaping = match structure.input_shaping {
        ShapingKind::Poly3 => ShapingKind::Poly2,
        ShapingKind::Poly2 | ShapingKind::Tanh | ShapingKind::Langevin => ShapingKind::Affine,
        ShapingKind::Affine | ShapingKind::QuadraticExp => return None,
    };
    let saturating = matches!(
        structure.input_shaping,
        ShapingKind::Tanh | ShapingKind::Langevin
    );
    Some(Structure {
        input_shaping,
        // A saturating ψ_in's offset (its argument at the centre) has no affine
        // counterpart: the affine ψ_in gets its default (none).
        input_offset: if saturating {
            None
        } else {
            structure.input_offset
        },
        ..structure
    })
}

/// `structure` with the next simpler ψ_out, if there is one.
fn simpler_output(structure: Structure) -> Option<Structure> {
    let output_shaping = match structure.output_shaping {
        ShapingKind::Poly3 => ShapingKind::Poly2,
        ShapingKind::Poly2 | ShapingKind::Tanh | ShapingKind::Langevin => ShapingKind::Affine,
        ShapingKind::Affine | ShapingKind::QuadraticExp => return None,
    };
    Some(Structure {
        output_shaping,
        ..structure
    })
}

/// The fit `simple` of a structure `layout`'s contains ([`contained`]), as θ of `layout`:
/// shared parameters keep their values, the new ones take the values that reproduce the simpler
/// model (a k2 slope and polynomial coefficients of 0; a tanh or Langevin ψ_in of scale `wide`
/// (normalised input units) with its argument 0 at the centre; a tanh or Langevin ψ_out of a
/// scale `wide` times its argument's reach, argument 0 at the centre, with the affine ψ_out's
/// slope and its level at the centre; `wide` is [`NESTED_SCALE`] for a start,
/// [`LIMIT_SCALE`](crate::smooth::limits::LIMIT_SCALE) at the limit). `None` when the point is
/// not feasible.
pub(super) fn embed(
    layout: &Layout,
    simple: &SmoothFit,
    input_range: (f64, f64),
    wide: f64,
) -> Option<Vec<f64>> {
    let value = |name: &str| {
        simple
            .estimates
            .iter()
            .find(|e| e.name == name)
            .map(|e| e.value)
    };
    let saturating = matches!(
        layout.structure.output_shaping,
        ShapingKind::Tanh | ShapingKind::Langevin
    ) && simple.layout.structure.output_shaping == ShapingKind::Affine;
    let saturating_input = matches!(
        layout.structure.input_shaping,
        ShapingKind::Tanh | ShapingKind::Langevin
    ) && simple.layout.structure.input_shaping == ShapingKind::Affine;
    let (v_lo, v_hi) = (
        simple.model.input_shaping.apply(input_range.0),
        simple.model.input_shaping.apply(input_range.1),
    );
    let (a_lo, a_hi) =
        SmoothModel::output_argument_range(simple.model.form, simple.model.k1, v_lo, v_hi);
    // In the stop form ψ_out sees (v − H[v]) / k1 ∈ [−1, 1].
    let reach = match simple.model.form {
        Form::Operator => a_lo.abs().max(a_hi.abs()),
        Form::Stop => 1.0,
    };
    let scale = wide * reach;
    // The affine ψ_out's level at the centre of its argument's range.
    let level = simple.model.output_shaping.apply(0.5 * (a_lo + a_hi));
    let mut theta = Vec::with_capacity(layout.len());
    for spec in &layout.params {
        let v = match (spec.name.as_str(), saturating, saturating_input) {
            (IN_SCALE, _, true) => wide,
            (IN_ARG_AT_CENTRE, _, true) | (OUT_ARG_AT_CENTRE, true, _) => 0.0,
            (OUT_SCALE, true, _) => scale,
            ("out.slope", true, _) => value("out.gain")?,
            ("out.level_at_centre", true, _) => level,
            (name, _, _) => value(name).unwrap_or(0.0),
        };
        theta.push(spec.transform.theta(v));
    }
    layout.model(&theta, input_range).ok()?;
    Some(theta)
}
