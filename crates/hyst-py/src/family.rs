//! `hyst.Family`: the family RH(k1, Δk1, k2, Δk2) of Definition 2.8 with its guaranteed
//! error bound Δa (Proposition 3.2, eqs. 12–13 as corrected in docs/errata.md).

use hyst_core::Family as CoreFamily;
use hyst_io::number::shortest;
use pyo3::prelude::*;
use pyo3::types::PyType;

use crate::arrays::{samples_f64, to_numpy};
use crate::errors::{core, value_error};
use crate::operator::{Engine, Hysteresis, InverseHysteresis, Precision};

/// The family RH(k1, Δk1, k2, Δk2) (Definition 2.8): every operator H(k̄1, k̄2) with
/// |k̄1 − k1| ≤ Δk1 and |k̄2 − k2| ≤ Δk2. A hysteresis reproduced by the family is compensated
/// by the nominal inverse H⁻¹(k1, k2) with an error of at most `delta_a` (Propositions 3.2 and
/// 3.3), in the input units of H.
///
/// `Family(k1, dk1, k2, dk2)`: k1, k2 finite and > 0; Δk1, Δk2 finite and ≥ 0, with
/// Δk1 < k1 and Δk2 < k2 (every member valid).
#[pyclass(module = "hyst", frozen)]
#[derive(Clone, Copy, Debug)]
pub struct Family {
    inner: CoreFamily<f64>,
}

impl Family {
    /// The parameters (k1 + a Δk1, k2 + b Δk2) of the member at (a, b) ∈ [−1, 1]², for
    /// `method` (named in the error for a position outside the square).
    fn member_k(&self, method: &str, a: f64, b: f64) -> PyResult<(f64, f64)> {
        if !(-1.0..=1.0).contains(&a) || !(-1.0..=1.0).contains(&b) {
            return Err(value_error(format!(
                "{method}({a}, {b}): the position must lie in [-1, 1] x [-1, 1]"
            )));
        }
        // The member's k1 and the shift of k2 from the nominal k2 (eq. 9).
        let (k1, shift) = self.inner.member_params(a, b);
        Ok((k1, self.inner.k2() + shift))
    }
}

#[pymethods]
impl Family {
    #[new]
    fn new(k1: f64, dk1: f64, k2: f64, dk2: f64) -> PyResult<Self> {
        CoreFamily::new(k1, dk1, k2, dk2)
            .map(|inner| Self { inner })
            .map_err(|e| {
                core(
                    format!(
                        "Family({}, {}, {}, {})",
                        shortest(k1),
                        shortest(dk1),
                        shortest(k2),
                        shortest(dk2)
                    ),
                    e,
                )
            })
    }

    /// k1 of the nominal operator.
    #[getter]
    fn k1(&self) -> f64 {
        self.inner.k1()
    }

    /// Δk1.
    #[getter]
    fn dk1(&self) -> f64 {
        self.inner.dk1()
    }

    /// k2 of the nominal operator.
    #[getter]
    fn k2(&self) -> f64 {
        self.inner.k2()
    }

    /// Δk2.
    #[getter]
    fn dk2(&self) -> f64 {
        self.inner.dk2()
    }

    /// Δa (eq. 12): the largest |H⁻¹(k̄1, k̄2)[u_d] − H⁻¹(k1, k2)[u_d]| over the family, in
    /// the input units of H; also the bound on Δb (eq. 15, Proposition 3.3).
    #[getter]
    fn delta_a(&self) -> f64 {
        self.inner.bound().delta_a
    }

    /// Δx1..Δx4 of eq. (13) at the corners (k1 − Δk1, k2 − Δk2), (k1 − Δk1, k2 + Δk2),
    /// (k1 + Δk1, k2 − Δk2), (k1 + Δk1, k2 + Δk2).
    #[getter]
    fn corners(&self) -> (f64, f64, f64, f64) {
        let [a, b, c, d] = self.inner.bound().corners;
        (a, b, c, d)
    }

    /// The corner parameters (k̄1, k̄2), in the order of `corners`.
    #[getter]
    fn corner_params(&self) -> Vec<(f64, f64)> {
        self.inner.bound().corner_params.to_vec()
    }

    /// The transformed inputs max(ũ_d*, 0) at which the corner values are taken.
    #[getter]
    fn corner_points(&self) -> Vec<f64> {
        self.inner.bound().corner_points.to_vec()
    }

    /// The member H(k1 + a Δk1, k2 + b Δk2) at the position (a, b) ∈ [−1, 1]², no history.
    #[pyo3(signature = (a, b, dtype=None))]
    fn member(&self, a: f64, b: f64, dtype: Option<&Bound<'_, PyAny>>) -> PyResult<Hysteresis> {
        let (k1, k2) = self.member_k("member", a, b)?;
        Ok(Hysteresis {
            engine: Engine::new(k1, k2, Precision::from_dtype(dtype)?)?,
        })
    }

    /// The member's inverse H⁻¹(k1 + a Δk1, k2 + b Δk2) (eq. 4) at the position
    /// (a, b) ∈ [−1, 1]², no history. `inverse_member(0, 0)` is the nominal inverse, whose
    /// error on any member of the family is at most `delta_a` (Proposition 3.2).
    #[pyo3(signature = (a, b, dtype=None))]
    fn inverse_member(
        &self,
        a: f64,
        b: f64,
        dtype: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<InverseHysteresis> {
        let (k1, k2) = self.member_k("inverse_member", a, b)?;
        Ok(InverseHysteresis {
            engine: Engine::new(k1, k2, Precision::from_dtype(dtype)?)?,
        })
    }

    /// The nominal operator H(k1, k2), no history.
    #[pyo3(signature = (dtype=None))]
    fn nominal(&self, dtype: Option<&Bound<'_, PyAny>>) -> PyResult<Hysteresis> {
        self.member(0.0, 0.0, dtype)
    }

    /// The envelope of the family along the input `x` (Section 3): `(lower, upper)`, the
    /// smallest and largest output at each sample over a `grid` × `grid` lattice of members
    /// (corners included), all started without history. float64 arrays.
    #[pyo3(signature = (x, grid=3))]
    fn envelope<'py>(
        &self,
        py: Python<'py>,
        x: &Bound<'py, PyAny>,
        grid: usize,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        if !(2..=64).contains(&grid) {
            return Err(value_error(format!("grid = {grid}: expected 2 to 64")));
        }
        let input = samples_f64(x, "x")?;
        if let Some((i, v)) = input.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(value_error(format!(
                "x[{i}] = {}: not a finite number",
                shortest(*v)
            )));
        }
        let family = self.inner;
        let (lower, upper) = py
            .detach(|| {
                let mut lower = vec![0.0; input.len()];
                let mut upper = vec![0.0; input.len()];
                family
                    .envelope(&input, &mut lower, &mut upper, grid)
                    .map(|()| (lower, upper))
            })
            .map_err(|e| core("envelope", e))?;
        Ok((to_numpy(py, lower), to_numpy(py, upper)))
    }

    /// The bound as a dict: delta_a, corners, corner_params, corner_points.
    fn bound<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let d = pyo3::types::PyDict::new(py);
        d.set_item("delta_a", self.delta_a())?;
        d.set_item("corners", self.corners())?;
        d.set_item("corner_params", self.corner_params())?;
        d.set_item("corner_points", self.corner_points())?;
        Ok(d)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> (Bound<'py, PyType>, (f64, f64, f64, f64)) {
        let f = slf.get();
        (slf.get_type(), (f.k1(), f.dk1(), f.k2(), f.dk2()))
    }

    fn __repr__(&self) -> String {
        format!(
            "Family(k1={:?}, dk1={:?}, k2={:?}, dk2={:?})",
            self.k1(),
            self.dk1(),
            self.k2(),
            self.dk2()
        )
    }
}
