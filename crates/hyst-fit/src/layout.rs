//! The parameterisation of a model structure ([`hyst_model::Structure`]: k2 law, shaping
//! functions, offsets, start rule): a vector θ of unconstrained numbers mapped to a
//! [`SmoothModel`].
//!
//! Gauge: H(k1, k2) commutes with shifts (H[v + b] = H[v] + b) and with scaling
//! (H(k1, k2)[s v] = s H(k1/s, k2 s)[v]), so a gain of ψ_in against a gain of ψ_out, and an
//! offset after ψ_in against an offset before ψ_out, cannot both be identified. The input is
//! therefore normalised to [−1, 1] (x̂ = (in − centre) / half-span) with a fixed gain, and the
//! overall gain and offset belong to ψ_out. k1 and k2 are then in these normalised units.

use hyst_core::{
    AffineK2, AnyK2Law, AnyShaping, Langevin, Polynomial, QuadraticExp, Real, Shaping, Tanh,
};
use serde::{Deserialize, Serialize};

use hyst_core::ScaledShaping;
use hyst_model::smooth::FitReal;
use hyst_model::{Dynamics, Form, K2Kind, Rate, ShapingKind, SmoothModel, Structure};

/// The scale of the saturating input shaping ψ_in (the model file's and the report's name).
pub const IN_SCALE: &str = "in.scale";
/// ψ_in's argument at the centre of the input range (dimensionless).
pub const IN_ARG_AT_CENTRE: &str = "in.arg_at_centre";
/// The scale of the saturating output shaping ψ_out.
pub const OUT_SCALE: &str = "out.scale";
/// ψ_out's argument at the centre of its range (dimensionless).
pub const OUT_ARG_AT_CENTRE: &str = "out.arg_at_centre";

/// How θ_j maps to the parameter's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transform {
    /// value = θ.
    Linear,
    /// value = e^θ (a positive parameter).
    Log,
}

impl Transform {
    /// The value for θ.
    #[must_use]
    pub fn value<T: Real>(self, theta: T) -> T {
        match self {
            Transform::Linear => theta,
            Transform::Log => theta.exp(),
        }
    }
    /// θ for a value.
    #[must_use]
    pub fn theta(self, value: f64) -> f64 {
        match self {
            Transform::Linear => value,
            Transform::Log => value.max(1e-300).ln(),
        }
    }
    /// d value / dθ.
    #[must_use]
    pub fn derivative(self, theta: f64) -> f64 {
        match self {
            Transform::Linear => 1.0,
            Transform::Log => theta.exp(),
        }
    }
}

/// Whether a parameter changes the operator's trajectory or only ψ_out (then the fit reuses
/// the operator output for its derivative).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Group {
    /// k1, k2, ψ_in.
    Operator,
    /// ψ_out.
    Output,
}

/// One free parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSpec {
    /// Name as in reports ("k1", "out.gain", …).
    pub name: String,
    /// Units, in words.
    pub unit: String,
    /// θ ↦ value.
    pub transform: Transform,
    /// Operator or output.
    pub group: Group,
    /// A neutral starting value.
    pub start: f64,
}

/// The normalisation of the input: x̂ = (in − centre) / half_span.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Normalisation {
    /// Centre of the input range (input units).
    pub centre: f64,
    /// Half of the input span (input units), > 0.
    pub half_span: f64,
    /// Centre of the output range (output units).
    pub output_centre: f64,
    /// Half of the output span (output units), > 0.
    pub output_half_span: f64,
}

/// A structure laid out as parameters, for data with a given normalisation.
#[derive(Clone, Debug)]
pub struct Layout {
    /// The structure.
    pub structure: Structure,
    /// The normalisation.
    pub norm: Normalisation,
    /// The free parameters, in θ order.
    pub params: Vec<ParamSpec>,
    input_offset: bool,
}

/// Margin of the polynomial and quadratic-exp domains beyond the data (normalised units).
const DOMAIN_MARGIN: f64 = 0.05;

/// The free parameters of a structure as [`Layout::new`] lays them out, in θ order: those of
/// the hysteresis, of ψ_in, of ψ_out, then the output's gain, linear term and offset.
struct Params(Vec<ParamSpec>);

impl Params {
    fn add(&mut self, name: &str, unit: &str, transform: Transform, group: Group, start: f64) {
        self.0.push(ParamSpec {
            name: name.into(),
            unit: unit.into(),
            transform,
            group,
            start,
        });
    }

    /// k1 and the k2 law.
    fn hysteresis(&mut self, structure: Structure) {
        use Group::Operator as Op;
        use Transform::{Linear, Log};
        self.add("k1", "operator units", Log, Op, 0.1);
        match structure.k2 {
            K2Kind::Constant => self.add("k2", "1/operator units", Log, Op, 5.0),
            K2Kind::Affine => {
                self.add("k2", "1/operator units", Log, Op, 5.0);
                self.add("k2.slope", "1/operator units²", Linear, Op, 0.0);
            }
        }
    }

    /// ψ_in's parameters and its offset; returns whether ψ_in has an offset.
    fn input(&mut self, structure: Structure) -> bool {
        use Group::Operator as Op;
        use Transform::{Linear, Log};
        match structure.input_shaping {
            ShapingKind::Affine => {}
            ShapingKind::Poly2 => self.add("in.p2", "1", Linear, Op, 0.0),
            ShapingKind::Poly3 => {
                self.add("in.p2", "1", Linear, Op, 0.0);
                self.add("in.p3", "1", Linear, Op, 0.0);
            }
            ShapingKind::Tanh => self.add(IN_SCALE, "normalised input", Log, Op, 1.0),
            ShapingKind::Langevin => self.add(IN_SCALE, "normalised input", Log, Op, 0.3),
            ShapingKind::QuadraticExp => {
                self.add("in.a", "1", Log, Op, 0.01);
                self.add("in.b", "1", Linear, Op, 6.0);
                self.add("in.c", "1", Log, Op, 1.0);
            }
        }
        let input_offset = structure
            .input_offset
            .unwrap_or(structure.input_shaping.saturating());
        if input_offset && structure.input_shaping.saturating() {
            // A saturating ψ_in is normalised at the input's centre (value 0, slope 1 there):
            // its offset is the argument of the shape at the centre.
            self.add(IN_ARG_AT_CENTRE, "1", Linear, Op, 0.0);
        } else if input_offset {
            self.add("in.offset", "normalised input", Linear, Op, 0.0);
        }
        input_offset
    }

    /// ψ_out's shape parameters (its gain and offset follow in [`Params::output`]).
    fn output_shaping(&mut self, structure: Structure) {
        use Group::Output as Out;
        use Transform::{Linear, Log};
        match structure.output_shaping {
            ShapingKind::Affine => {}
            ShapingKind::Poly2 => self.add("out.q2", "1", Linear, Out, 0.0),
            ShapingKind::Poly3 => {
                self.add("out.q2", "1", Linear, Out, 0.0);
                self.add("out.q3", "1", Linear, Out, 0.0);
            }
            // Saturating ψ_out: the scale and the shape's argument at the centre of the data
            // (curvature and saturation); its slope and level there follow below.
            ShapingKind::Tanh | ShapingKind::Langevin => {
                let (scale, unit) = match (structure.output_shaping, structure.form) {
                    (ShapingKind::Tanh, Form::Operator) => (2.0, "operator units"),
                    (_, Form::Operator) => (0.5, "operator units"),
                    (ShapingKind::Tanh, Form::Stop) => (2.0, "k1"),
                    (_, Form::Stop) => (0.5, "k1"),
                };
                self.add(OUT_SCALE, unit, Log, Out, scale);
                self.add(OUT_ARG_AT_CENTRE, "1", Linear, Out, 0.0);
            }
            ShapingKind::QuadraticExp => {
                self.add("out.a", "1", Log, Out, 0.01);
                self.add("out.b", "1", Linear, Out, 6.0);
                self.add("out.c", "1", Log, Out, 1.0);
            }
        }
    }

    /// The output's gain (a saturating ψ_out's slope, the stop form's level), the stop form's
    /// linear term, and the output offset, starting from the data's normalisation `norm`.
    fn output(&mut self, structure: Structure, norm: Normalisation) {
        use Group::Output as Out;
        use Transform::{Linear, Log};
        let saturating = structure.output_shaping.saturating();
        match structure.form {
            Form::Operator if saturating => self.add(
                "out.slope",
                "output units per operator unit",
                Log,
                Out,
                norm.output_half_span,
            ),
            Form::Operator => self.add("out.gain", "output units", Log, Out, norm.output_half_span),
            // The stop's output is at most k1: its level gain × k1 (the Coulomb force of a
            // friction model) stays put while k1 → 0 (the Dahl limit), where the gain does not.
            Form::Stop => self.add("out.level", "output units", Log, Out, norm.output_half_span),
        }
        if structure.form == Form::Stop {
            self.add(
                "out.linear",
                "output units per operator unit",
                Linear,
                Out,
                0.0,
            );
        }
        if structure.output_offset && saturating {
            self.add(
                "out.level_at_centre",
                "output units",
                Linear,
                Out,
                norm.output_centre,
            );
        } else if structure.output_offset {
            self.add(
                "out.offset",
                "output units",
                Linear,
                Out,
                norm.output_centre,
            );
        }
    }
}

/// The start of a plant's time constant before the fit sets it from the data (s).
const TIME_CONSTANT_START: f64 = 0.01;

/// The name of the plant coefficient a_i (i = 1…4) in reports and the model file's parameters.
#[must_use]
pub fn dynamics_name(i: usize) -> String {
    format!("dynamics.a{i}")
}

/// The coefficient a_i of the plant of order `n` with n equal time constants `tau` (s):
/// (τs + 1)ⁿ = Σ C(n, i) τ^i s^i, so a_i = C(n, i) τ^i (s^i).
#[must_use]
pub fn equal_poles(n: usize, i: usize, tau: f64) -> f64 {
    let binomial = (0..i).fold(1.0, |acc, k| acc * (n - k) as f64 / (k + 1) as f64);
    binomial * tau.powi(i as i32)
}

/// The name of the rate term's coefficient c.
pub const RATE_C: &str = "rate.c";

impl Params {
    /// The plant's a_1 … a_n (positive, as n equal time constants to start) and the rate
    /// term's c: both change the trajectory, so they belong to the operator's group.
    fn timed(&mut self, structure: Structure) {
        let n = usize::from(structure.dynamics);
        for i in 1..=n {
            let unit = if i == 1 {
                "s".to_string()
            } else {
                format!("s^{i}")
            };
            self.add(
                &dynamics_name(i),
                &unit,
                Transform::Log,
                Group::Operator,
                equal_poles(n, i, TIME_CONSTANT_START),
            );
        }
        if structure.rate.is_some() {
            self.add(
                RATE_C,
                "output units * s / input unit",
                Transform::Linear,
                Group::Operator,
                0.0,
            );
        }
    }
}

impl Layout {
    /// Lays out `structure` for data normalised by `norm`.
    #[must_use]
    pub fn new(structure: Structure, norm: Normalisation) -> Self {
        let mut params = Params(Vec::new());
        params.hysteresis(structure);
        let input_offset = params.input(structure);
        params.output_shaping(structure);
        params.output(structure, norm);
        params.timed(structure);
        Self {
            structure,
            norm,
            params: params.0,
            input_offset,
        }
    }

    /// Number of free parameters.
    #[must_use]
    pub fn len(&self) -> usize {
        self.params.len()
    }

    /// Whether there are no parameters (never: k1 is always free).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    /// θ of the neutral starting point.
    #[must_use]
    pub fn start(&self) -> Vec<f64> {
        self.params
            .iter()
            .map(|p| p.transform.theta(p.start))
            .collect()
    }

    /// Index of a parameter by name.
    #[must_use]
    pub fn index(&self, name: &str) -> Option<usize> {
        self.params.iter().position(|p| p.name == name)
    }

    /// Parameter values (natural units) for θ.
    #[must_use]
    pub fn values(&self, theta: &[f64]) -> Vec<f64> {
        self.params
            .iter()
            .zip(theta)
            .map(|(p, t)| p.transform.value(*t))
            .collect()
    }

    /// The value of the parameter `name` for θ (0 when the structure has no such parameter):
    /// generic, so the fit can evaluate the model on duals seeded in θ.
    fn get<T: Real>(&self, theta: &[T], name: &str) -> T {
        self.index(name)
            .and_then(|i| Some(self.params.get(i)?.transform.value(*theta.get(i)?)))
            .unwrap_or_else(T::zero)
    }

    /// The input shaping for θ.
    ///
    /// # Errors
    /// When the values are invalid (non-monotone polynomial, …).
    pub fn input_shaping<T: Real>(
        &self,
        theta: &[T],
    ) -> Result<ScaledShaping<T>, hyst_core::Error> {
        let c = T::from_f64;
        let get = |name: &str| self.get(theta, name);
        let saturating = self.structure.input_shaping.saturating();
        let offset = if self.input_offset && !saturating {
            get("in.offset")
        } else {
            T::zero()
        };
        let pre_gain = c(1.0 / self.norm.half_span);
        let pre_offset = c(-self.norm.centre / self.norm.half_span) + offset;
        let (lo, hi) = (
            c(-1.0 - DOMAIN_MARGIN) + offset,
            c(1.0 + DOMAIN_MARGIN) + offset,
        );
        if saturating {
            return self.saturating_input_shaping(
                get(IN_SCALE),
                get(IN_ARG_AT_CENTRE),
                pre_gain,
                pre_offset,
            );
        }
        let shape = shape(self.structure.input_shaping, IN_COEFFICIENTS, get, (lo, hi))?;
        ScaledShaping::new(pre_gain, pre_offset, shape, c(1.0), c(0.0))
    }

    /// The saturating ψ_in x̂ ↦ (σ / f'(a)) (f(x̂ / σ + a) − f(a)) (f = tanh or L, x̂ the
    /// normalised input): its value 0 and slope 1 at the input's centre keep k1 and k2 in
    /// normalised input units whatever the scale σ, so σ and the argument at the centre a
    /// carry only curvature and saturation (with ψ_in = f(x̂ / σ + a) instead, a wide σ made
    /// k1, k2 and σ nearly collinear and the fit crawled along that valley).
    fn saturating_input_shaping<T: Real>(
        &self,
        scale: T,
        arg_at_centre: T,
        pre_gain: T,
        pre_offset: T,
    ) -> Result<ScaledShaping<T>, hyst_core::Error> {
        let kind = self.structure.input_shaping;
        let shape = unit_shape(kind)?;
        let scale = natural_scale(kind, scale, arg_at_centre);
        let (value, slope) = shape.value_and_slope(arg_at_centre);
        let gain = scale / slope;
        let post_offset = -(gain * value);
        if !(gain.is_finite() && gain > T::zero() && post_offset.is_finite()) {
            return Err(hyst_core::Error::InvalidParameter {
                name: IN_ARG_AT_CENTRE,
                value: arg_at_centre.as_f64(),
                expected: "an argument where the shape is not flat",
            });
        }
        ScaledShaping::new(
            pre_gain / scale,
            pre_offset / scale + arg_at_centre,
            shape,
            gain,
            post_offset,
        )
    }

    /// The output shaping for θ, given the range of its argument on the data
    /// ([`SmoothModel::output_argument_range`]: the operator output, or the stop value
    /// v − H[v] ∈ [−k1, k1]). In the stop form the shape sees (v − H[v]) / k1 ∈ [−1, 1], and
    /// `out.level` is its gain: the output's swing at the end of a travel (the Coulomb level of
    /// a friction model), which stays put as k1 → 0 (the Dahl limit) where a gain on v − H[v]
    /// would grow without bound.
    ///
    /// A saturating ψ_out is w ↦ g f((w − w_m) / σ + a) + o (f = tanh or L, w its argument,
    /// w_m the centre of w's range on the data), parameterised by quantities the data
    /// determines well: the scale σ (`out.scale`), the argument at the centre a
    /// (`out.arg_at_centre`), the slope S at w_m (`out.slope`; in the stop form `out.level`,
    /// the slope with respect to w / k1, which is the level for an affine ψ_out) and the value L
    /// at w_m (`out.level_at_centre`), so that g = S σ / f'(a) and o = L − g f(a). With
    /// (σ, c, g, o) instead, a ψ_out that does not saturate on the data left the four nearly
    /// collinear, and the fit crawled along that valley to its iteration limit.
    ///
    /// # Errors
    /// When the values are invalid.
    pub fn output_shaping<T: Real>(
        &self,
        theta: &[T],
        arg_range: (T, T),
    ) -> Result<ScaledShaping<T>, hyst_core::Error> {
        let c = T::from_f64;
        let get = |name: &str| self.get(theta, name);
        let (gain, unit) = match self.structure.form {
            Form::Operator => (get("out.gain"), c(1.0)),
            Form::Stop => (get("out.level"), c(1.0) / get("k1")),
        };
        let v_range = (arg_range.0 * unit, arg_range.1 * unit);
        if self.structure.output_shaping.saturating() {
            let slope = match self.structure.form {
                Form::Operator => get("out.slope"),
                Form::Stop => gain,
            };
            let level = if self.structure.output_offset {
                Some(get("out.level_at_centre"))
            } else {
                None
            };
            let centre = (v_range.0 + v_range.1) * c(0.5);
            return self.saturating_output_shaping(
                get(OUT_SCALE),
                get(OUT_ARG_AT_CENTRE),
                slope,
                level,
                (unit, centre),
            );
        }
        let offset = if self.structure.output_offset {
            get("out.offset")
        } else {
            c(0.0)
        };
        let half = (v_range.1 - v_range.0) * c(0.5);
        let (lo, hi) = (v_range.0 - half * c(0.25), v_range.1 + half * c(0.25));
        let shape = shape(
            self.structure.output_shaping,
            OUT_COEFFICIENTS,
            get,
            (lo, hi),
        )?;
        ScaledShaping::new(c(1.0) * unit, c(0.0), shape, gain, offset)
    }

    /// The saturating ψ_out of [`Layout::output_shaping`] from its scale σ, argument at the
    /// centre a, slope S and level L at the centre (`None`: no output offset, o = 0), for the
    /// argument's `unit` (1, or 1/k1 in the stop form) and the centre w_m of the scaled
    /// argument's range.
    fn saturating_output_shaping<T: Real>(
        &self,
        scale: T,
        arg_at_centre: T,
        slope: T,
        level: Option<T>,
        (unit, centre): (T, T),
    ) -> Result<ScaledShaping<T>, hyst_core::Error> {
        let kind = self.structure.output_shaping;
        let shape = unit_shape(kind)?;
        let scale = natural_scale(kind, scale, arg_at_centre);
        let (value, shape_slope) = shape.value_and_slope(arg_at_centre);
        let gain = slope * scale / shape_slope;
        let offset = level.map_or_else(T::zero, |l| l - gain * value);
        if !(gain.is_finite() && gain > T::zero() && offset.is_finite()) {
            return Err(hyst_core::Error::InvalidParameter {
                name: OUT_ARG_AT_CENTRE,
                value: arg_at_centre.as_f64(),
                expected: "an argument where the shape is not flat",
            });
        }
        ScaledShaping::new(
            unit / scale,
            arg_at_centre - centre / scale,
            shape,
            gain,
            offset,
        )
    }

    /// The model for θ, for data whose input spans [in_lo, in_hi]: on `f64`, or on
    /// [`Dual`](hyst_core::Dual)s seeded in θ for the derivatives of everything the model
    /// evaluates with respect to θ (the fit's Jacobian), through the same code.
    ///
    /// # Errors
    /// When θ is outside the feasible set (the fit rejects the step).
    pub fn model<T: FitReal>(
        &self,
        theta: &[T],
        input_range: (f64, f64),
    ) -> Result<SmoothModel<T>, hyst_core::Error> {
        let c = T::from_f64;
        let get = |name: &str| self.get(theta, name);
        let input_shaping = self.input_shaping(theta)?;
        let v_lo = input_shaping.apply(c(input_range.0));
        let v_hi = input_shaping.apply(c(input_range.1));
        let k1 = get("k1");
        let k2 = match self.structure.k2 {
            K2Kind::Constant => AnyK2Law::Constant { value: get("k2") },
            K2Kind::Affine => {
                let at_zero = get("k2");
                let slope = get("k2.slope");
                let a = at_zero + slope * (v_lo - k1);
                let b = at_zero + slope * (v_hi + k1);
                let (min, max) = (a.min(b), a.max(b));
                if min.is_nan() || min <= at_zero * c(0.02) {
                    return Err(hyst_core::Error::InvalidParameter {
                        name: "k2.slope",
                        value: slope.as_f64(),
                        expected: "a k2 law that stays positive on the data",
                    });
                }
                AnyK2Law::Affine(AffineK2 {
                    at_zero,
                    slope,
                    min: min * c(0.5),
                    max: max * c(2.0),
                })
            }
        };
        let output_shaping = self.output_shaping(
            theta,
            SmoothModel::output_argument_range(self.structure.form, k1, v_lo, v_hi),
        )?;
        let m = SmoothModel {
            k1,
            k2,
            input_shaping,
            output_shaping,
            initial_state: self.structure.initial_state,
            form: self.structure.form,
            linear: match self.structure.form {
                Form::Operator => c(0.0),
                Form::Stop => get("out.linear"),
            },
            dynamics: self.dynamics(theta)?,
            rate: self.structure.rate.map(|_| Rate { c: get(RATE_C) }),
        };
        m.validate()?;
        Ok(m)
    }
}

impl Layout {
    /// The plant for θ (b = 1: ψ_in's gain scales the hysteresis input) under the structure's
    /// hold, `None` without dynamics.
    ///
    /// # Errors
    /// An unstable plant ([`Dynamics::new`]).
    pub fn dynamics<T: FitReal>(
        &self,
        theta: &[T],
    ) -> Result<Option<Dynamics<T>>, hyst_core::Error> {
        let n = usize::from(self.structure.dynamics);
        if n == 0 {
            return Ok(None);
        }
        let a: Vec<T> = (1..=n)
            .map(|i| self.get(theta, &dynamics_name(i)))
            .collect();
        Ok(Some(
            Dynamics::new(T::one(), &a)?.with_hold(self.structure.hold),
        ))
    }
}

/// The coefficients of ψ_in by name, as [`shape`] takes them.
const IN_COEFFICIENTS: [&str; 5] = ["in.p2", "in.p3", "in.a", "in.b", "in.c"];

/// The coefficients of ψ_out by name, as [`shape`] takes them.
const OUT_COEFFICIENTS: [&str; 5] = ["out.q2", "out.q3", "out.a", "out.b", "out.c"];

/// The shape of a ψ of `kind` on [lo, hi] (the polynomial's and the quadratic exponential's
/// domain), its coefficients given by `get` under their `names`: the polynomial's quadratic
/// and cubic ones, then the quadratic exponential's a, b and c. A saturating kind is its
/// [`unit_shape`]; an affine ψ, the identity.
fn shape<T: Real>(
    kind: ShapingKind,
    names: [&str; 5],
    get: impl Fn(&str) -> T,
    (lo, hi): (T, T),
) -> Result<AnyShaping<T>, hyst_core::Error> {
    let c = T::from_f64;
    let [p2, p3, a, b, qe_c] = names;
    Ok(match kind {
        ShapingKind::Affine => AnyShaping::Identity,
        ShapingKind::Poly2 => {
            AnyShaping::Polynomial(Polynomial::new([c(0.0), c(1.0), get(p2), c(0.0)], lo, hi)?)
        }
        ShapingKind::Poly3 => {
            AnyShaping::Polynomial(Polynomial::new([c(0.0), c(1.0), get(p2), get(p3)], lo, hi)?)
        }
        ShapingKind::Tanh | ShapingKind::Langevin => unit_shape(kind)?,
        ShapingKind::QuadraticExp => {
            AnyShaping::QuadraticExp(QuadraticExp::new(get(a), get(b), get(qe_c), lo, hi)?)
        }
    })
}

/// tanh or L with gain and scale 1 (the identity for the other kinds, which never ask).
fn unit_shape<T: Real>(kind: ShapingKind) -> Result<AnyShaping<T>, hyst_core::Error> {
    Ok(match kind {
        ShapingKind::Tanh => AnyShaping::Tanh(Tanh::new(T::one(), T::one())?),
        ShapingKind::Langevin => AnyShaping::Langevin(Langevin::new(T::one(), T::one())?),
        _ => AnyShaping::Identity,
    })
}

/// The scale σ of a saturating shape's argument from its parameter `scale` and the argument at
/// the centre a: σ = `scale` for tanh, σ = `scale` / √(1 + a²) for L. Far into L's tail
/// (L(x) ≈ 1 − 1/x) the curve the data sees tends to a hyperbola whose bend is set by σ a, not
/// by σ or a alone; with σ as the parameter the fit crawled along the curved valley σ a =
/// const, while with σ √(1 + a²) the bend stays put as a moves. tanh's tail tends to an
/// exponential whose bend is set by σ alone.
fn natural_scale<T: Real>(kind: ShapingKind, scale: T, arg_at_centre: T) -> T {
    match kind {
        ShapingKind::Langevin => scale / (T::one() + arg_at_centre * arg_at_centre).sqrt(),
        _ => scale,
    }
}
