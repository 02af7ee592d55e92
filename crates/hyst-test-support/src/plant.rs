//! A linear plant a_n x⁽ⁿ⁾ + … + a_1 ẋ + x = b u (the plants of Lemma 5.1) integrated with the
//! classical fourth-order Runge–Kutta method: the reference the compensator's tests drive.

/// The plant a_n x⁽ⁿ⁾ + … + a_1 ẋ + x = b u, its state [x, ẋ, …, x⁽ⁿ⁻¹⁾].
#[derive(Clone, Copy, Debug)]
pub struct LinearPlant<const N: usize> {
    /// [a_1, …, a_n] (a_n ≠ 0), in powers of the time unit.
    pub a: [f64; N],
    /// The gain b.
    pub b: f64,
}

impl<const N: usize> LinearPlant<N> {
    /// d/dt of the state `x` under the input `u`: the shifted derivatives, then
    /// x⁽ⁿ⁾ = (b u − x − Σ_{i<n} a_i x⁽ⁱ⁾) / a_n.
    pub fn rhs(&self, x: &[f64; N], u: f64) -> [f64; N] {
        std::array::from_fn(|k| {
            if k + 1 < N {
                x[k + 1]
            } else {
                let mut s = self.b * u - x[0];
                for (a, x) in self.a.iter().zip(&x[1..]) {
                    s -= a * x;
                }
                s / self.a[N - 1]
            }
        })
    }

    /// One classical RK4 step of the state `x` over `h`, the input `u` at the step's start,
    /// middle and end: k1 = f(x, u₀), k2 = f(x + h/2 k1, u½), k3 = f(x + h/2 k2, u½),
    /// k4 = f(x + h k3, u₁), x + h/6 (k1 + 2 k2 + 2 k3 + k4).
    pub fn rk4(&self, x: &[f64; N], h: f64, u: [f64; 3]) -> [f64; N] {
        let axpy = |s: f64, d: &[f64; N]| -> [f64; N] { std::array::from_fn(|i| x[i] + s * d[i]) };
        let k1 = self.rhs(x, u[0]);
        let k2 = self.rhs(&axpy(0.5 * h, &k1), u[1]);
        let k3 = self.rhs(&axpy(0.5 * h, &k2), u[1]);
        let k4 = self.rhs(&axpy(h, &k3), u[2]);
        std::array::from_fn(|i| x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
    }

    /// The output x driven by the continuous input `u(t)`, sampled every `h` for `samples`
    /// samples from rest at x = b u(0) (t = 0 at the first sample), with `substeps` RK4 steps
    /// per sample.
    pub fn response(
        &self,
        u: impl Fn(f64) -> f64,
        h: f64,
        samples: usize,
        substeps: u32,
    ) -> Vec<f64> {
        let mut x = [0.0; N];
        x[0] = self.b * u(0.0);
        let mut out = vec![x[0]];
        let dt = h / f64::from(substeps);
        for k in 1..samples {
            for j in 0..substeps {
                let t = (k - 1) as f64 * h + f64::from(j) * dt;
                x = self.rk4(&x, dt, [u(t), u(t + dt / 2.0), u(t + dt)]);
            }
            out.push(x[0]);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::LinearPlant;

    /// τ ẋ + x = sin t from rest: (sin t − τ cos t + τ e^(−t/τ)) / (1 + τ²), to RK4's accuracy.
    #[test]
    fn first_order_response_is_the_exact_one() {
        let tau = 0.1;
        let plant = LinearPlant { a: [tau], b: 1.0 };
        let x = plant.response(f64::sin, 1e-2, 301, 20);
        for (k, x) in x.iter().enumerate() {
            let t = k as f64 * 1e-2;
            let exact = (t.sin() - tau * t.cos() + tau * (-t / tau).exp()) / (1.0 + tau * tau);
            assert!((x - exact).abs() < 1e-9, "{k}: {x} against {exact}");
        }
    }

    /// ẍ + 0.9 ẋ + x = 2 u settles at 2 u.
    #[test]
    fn second_order_settles_at_its_gain() {
        let plant = LinearPlant {
            a: [0.9, 1.0],
            b: 2.0,
        };
        let x = plant.response(|_| 0.5, 0.1, 1000, 10);
        assert!((x[999] - 1.0).abs() < 1e-12, "{}", x[999]);
    }
}
