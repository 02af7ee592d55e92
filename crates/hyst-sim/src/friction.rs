//! A "true" friction force for testing identification on clockwise loops: the LuGre model
//! (Canudas de Wit, Olsson, Åström and Lischinsky, IEEE TAC 40(3), 1995), whose bristle state z
//! gives pre-sliding (a stiff spring before sliding), Coulomb and Stribeck friction and viscous
//! damping:
//!
//! ż = ẋ − σ0 |ẋ| z / g(ẋ),  g(ẋ) = Fc + (Fs − Fc) e^(−(ẋ/vs)²),
//! F = σ0 z + σ1 ż + σ2 ẋ.
//!
//! It is *not* a member of any model the fit knows (Stribeck and viscous terms depend on the
//! rate, the smooth stop form does not), so it tests the fit on a structure error, as measured
//! friction does.

use crate::error::SimError;

/// LuGre parameters (force and position units of the caller's choice; times in seconds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LuGre {
    /// Bristle stiffness σ0 (force / position), > 0.
    pub sigma0: f64,
    /// Bristle damping σ1 (force · s / position), ≥ 0.
    pub sigma1: f64,
    /// Viscous coefficient σ2 (force · s / position), ≥ 0.
    pub sigma2: f64,
    /// Coulomb level Fc (force), > 0.
    pub coulomb: f64,
    /// Static (break-away) level Fs (force), ≥ Fc.
    pub stiction: f64,
    /// Stribeck velocity vs (position / s), > 0.
    pub stribeck_velocity: f64,
}

impl LuGre {
    fn check(&self) -> Result<(), SimError> {
        let checks: [(&'static str, f64, bool, &'static str); 6] = [
            ("sigma0", self.sigma0, self.sigma0 > 0.0, "finite and > 0"),
            ("sigma1", self.sigma1, self.sigma1 >= 0.0, "finite and ≥ 0"),
            ("sigma2", self.sigma2, self.sigma2 >= 0.0, "finite and ≥ 0"),
            (
                "coulomb",
                self.coulomb,
                self.coulomb > 0.0,
                "finite and > 0",
            ),
            (
                "stiction",
                self.stiction,
                self.stiction >= self.coulomb,
                "finite and ≥ coulomb",
            ),
            (
                "stribeck_velocity",
                self.stribeck_velocity,
                self.stribeck_velocity > 0.0,
                "finite and > 0",
            ),
        ];
        for (name, value, ok, expected) in checks {
            if !(ok && value.is_finite()) {
                return Err(SimError::InvalidParameter {
                    name,
                    value,
                    expected,
                });
            }
        }
        Ok(())
    }

    /// The friction force along a sampled position record (`dt` seconds apart), starting at
    /// rest with a relaxed bristle (z = 0). The velocity is constant between samples (the
    /// difference quotient), and z is advanced exactly for that constant velocity.
    ///
    /// # Errors
    /// [`SimError::InvalidParameter`] for a parameter or `dt` out of range,
    /// [`SimError::NonFinite`] for a non-finite position.
    pub fn force(&self, position: &[f64], dt: f64) -> Result<Vec<f64>, SimError> {
        self.check()?;
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(SimError::InvalidParameter {
                name: "dt",
                value: dt,
                expected: "finite and > 0",
            });
        }
        if let Some((index, &value)) = position.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(SimError::NonFinite {
                name: "position",
                index,
                value,
            });
        }
        let mut z = 0.0_f64;
        let mut out = Vec::with_capacity(position.len());
        let mut previous = position.first().copied().unwrap_or(0.0);
        for &x in position {
            let v = (x - previous) / dt;
            previous = x;
            let g = self.coulomb
                + (self.stiction - self.coulomb) * (-(v / self.stribeck_velocity).powi(2)).exp();
            // ż = v − (σ0 |v| / g) z: relaxes to z_ss = g sign(v) / σ0 at the rate σ0 |v| / g.
            let rate = self.sigma0 * v.abs() / g;
            let z_ss = if v == 0.0 {
                z
            } else {
                g * v.signum() / self.sigma0
            };
            let z_next = z_ss + (z - z_ss) * (-rate * dt).exp();
            let z_dot = v - rate * z_next;
            z = z_next;
            out.push(self.sigma0 * z + self.sigma1 * z_dot + self.sigma2 * v);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn seal() -> LuGre {
        LuGre {
            sigma0: 200.0,
            sigma1: 0.5,
            sigma2: 0.2,
            coulomb: 20.0,
            stiction: 30.0,
            stribeck_velocity: 2.0,
        }
    }

    #[test]
    fn slides_at_the_coulomb_level_plus_viscous_and_turns_with_the_motion() {
        let dt = 1e-3;
        // 10 mm/s for 1 s, then back.
        let x: Vec<f64> = (0..2000)
            .map(|k| {
                if k < 1000 {
                    0.01 * k as f64
                } else {
                    20.0 - 0.01 * k as f64
                }
            })
            .collect();
        let f = seal().force(&x, dt).unwrap();
        let sliding = 20.0 + 10.0 * (-(10.0_f64 / 2.0).powi(2)).exp() + 0.2 * 10.0;
        assert!((f[900] - sliding).abs() < 1e-6, "{}", f[900]);
        assert!((f[1900] + sliding).abs() < 1e-6, "{}", f[1900]);
        // Clockwise: the force is positive while extending.
        assert!(f[500] > 0.0 && f[1500] < 0.0);
    }

    #[test]
    fn bad_parameters_are_named() {
        let mut p = seal();
        p.stiction = 10.0;
        let e = p.force(&[0.0, 1.0], 1e-3).unwrap_err();
        assert!(e.to_string().contains("stiction"), "{e}");
        assert!(seal().force(&[0.0, f64::NAN], 1e-3).is_err());
        assert!(seal().force(&[0.0], 0.0).is_err());
    }
}
