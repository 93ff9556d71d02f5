//! Dent-size models: the radius of the mark a shot leaves on the specimen.
//!
//! * **Plastic** (targets with a yield strength): a rigid sphere indenting a
//!   rigid-perfectly-plastic half-space at a mean contact pressure equal to the dynamic
//!   hardness `p_d = 3 Y` (Tabor). The impact's normal kinetic energy goes into the dent:
//!   `1/2 m v_n^2 = p_d V`, with the shallow spherical-cap volume `V = pi a^4 / (4 R)`,
//!   so `a = R (8 rho v_n^2 / (3 p_d))^(1/4)` (Johnson, *Contact Mechanics*, 1985,
//!   section 11.4). The dent diameter grows with the shot size and with the square root
//!   of the impact speed, as peening practice finds.
//! * **Elastic** (targets without a yield strength, e.g. the paper's Table 2 steel): the
//!   Hertz contact radius at the peak of the impact, `a = sqrt(R delta_max)`,
//!   `delta_max = (5 m v_n^2 / (4 K))^(2/5)`, `K = 4/3 E* sqrt(R)`: the footprint of the
//!   contact (an elastic target keeps no permanent dent).

use crate::scene::Material;

/// How dent radii are computed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DentModel {
    /// Perfectly plastic target at mean pressure `pressure` (Pa).
    Plastic {
        /// Dynamic hardness `3 Y`, Pa.
        pressure: f64,
    },
    /// Hertz contact radius; `effective_modulus` `E*` of the shot-target pair, Pa.
    Elastic {
        /// `E*`, Pa.
        effective_modulus: f64,
    },
}

impl DentModel {
    /// The model for `shot` on `target`: plastic when the target has a yield strength.
    pub fn for_pair(shot: &Material, target: &Material) -> DentModel {
        match target.yield_strength {
            Some(y) => DentModel::Plastic { pressure: 3.0 * y },
            None => DentModel::Elastic {
                effective_modulus: crate::contact::hertz::effective_modulus(
                    shot.youngs_modulus,
                    shot.poisson_ratio,
                    target.youngs_modulus,
                    target.poisson_ratio,
                ),
            },
        }
    }

    /// Dent radius (m) of a shot of `radius` (m) and `mass` (kg) at normal speed `v_n`.
    pub fn radius(&self, radius: f64, mass: f64, v_n: f64) -> f64 {
        if v_n <= 0.0 {
            return 0.0;
        }
        match *self {
            DentModel::Plastic { pressure } => {
                let rho = mass / (4.0 / 3.0 * std::f64::consts::PI * radius.powi(3));
                radius * (8.0 * rho * v_n * v_n / (3.0 * pressure)).powf(0.25)
            }
            DentModel::Elastic { effective_modulus } => {
                let k = 4.0 / 3.0 * effective_modulus * radius.sqrt();
                let delta = (5.0 * mass * v_n * v_n / (4.0 * k)).powf(0.4);
                (radius * delta).sqrt()
            }
        }
    }

    /// One line for reports.
    pub fn describe(&self) -> String {
        match self {
            DentModel::Plastic { pressure } => format!(
                "plastic dent, a = R (8 rho v_n^2 / (3 p_d))^(1/4), dynamic hardness p_d = 3 Y = {:.0} MPa",
                pressure * 1e-6
            ),
            DentModel::Elastic { effective_modulus } => format!(
                "elastic target (no yield strength): Hertz contact radius at peak load, E* = {:.1} GPa",
                effective_modulus * 1e-9
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plastic_dent_conserves_energy_and_grows_with_sqrt_speed() {
        let (r, rho, p): (f64, f64, f64) = (0.4e-3, 7850.0, 585e6);
        let m = rho * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        let model = DentModel::Plastic { pressure: p };
        let a = model.radius(r, m, 60.0);
        // Energy balance: 1/2 m v^2 = p V, V = pi a^4 / (4 R).
        let v = std::f64::consts::PI * a.powi(4) / (4.0 * r);
        assert!((p * v / (0.5 * m * 3600.0) - 1.0).abs() < 1e-12);
        // Square root of the speed; proportional to the shot radius.
        assert!((model.radius(r, m, 240.0) / a - 2.0).abs() < 1e-12);
        assert!((model.radius(2.0 * r, 8.0 * m, 60.0) / a - 2.0).abs() < 1e-12);
    }

    #[test]
    fn elastic_dent_is_the_hertz_contact_radius() {
        // Peak force F = K delta^(3/2); Hertz a = (3 F R / (4 E*))^(1/3) must agree.
        let (r, e) = (0.4e-3, 115e9);
        let m = 2.1e-6;
        let model = DentModel::Elastic {
            effective_modulus: e,
        };
        let a = model.radius(r, m, 60.0);
        let k = 4.0 / 3.0 * e * r.sqrt();
        let delta = a * a / r;
        let f = k * delta.powf(1.5);
        let a_hertz = (3.0 * f * r / (4.0 * e)).cbrt();
        assert!((a / a_hertz - 1.0).abs() < 1e-12);
    }
}
