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

/// Most points of a measured dent curve.
pub const MAX_DENT_POINTS: usize = 16;

/// How dent radii are computed.
#[derive(Debug, Clone, PartialEq)]
pub enum DentModel {
    /// Dent radius over shot radius measured at a few normal speeds:
    /// `(normal speed m/s, dent radius / shot radius)`, speeds increasing.
    Measured(Vec<(f64, f64)>),
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

    /// The measured model through `points` (`(normal speed m/s, dent radius / shot
    /// radius)`), or what is wrong with them.
    pub fn measured(points: &[(f64, f64)]) -> Result<DentModel, String> {
        if points.is_empty() || points.len() > MAX_DENT_POINTS {
            return Err(format!("give 1 to {MAX_DENT_POINTS} points"));
        }
        for (i, &(v, f)) in points.iter().enumerate() {
            if !(v > 0.0 && v <= 1000.0) {
                return Err(format!("speed {v} m/s: allowed (0, 1000]"));
            }
            if i > 0 && v <= points[i - 1].0 {
                return Err(format!(
                    "speed {v} m/s after {} m/s: speeds must increase",
                    points[i - 1].0
                ));
            }
            if !(f > 0.0 && f <= 5.0) {
                return Err(format!(
                    "dent radius / shot radius {f} at {v} m/s: allowed (0, 5]"
                ));
            }
        }
        Ok(DentModel::Measured(points.to_vec()))
    }

    /// Dent radius (m) of a shot of `radius` (m) and `mass` (kg) at normal speed `v_n`.
    pub fn radius(&self, radius: f64, mass: f64, v_n: f64) -> f64 {
        if v_n <= 0.0 {
            return 0.0;
        }
        match *self {
            DentModel::Measured(ref points) => radius * measured_ratio(points, v_n),
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
            DentModel::Measured(points) => format!(
                "measured dents (--dent-curve), dent radius / shot radius {} (power law between points)",
                points
                    .iter()
                    .map(|(v, f)| format!("{f} at {v} m/s"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
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

/// `f(v)` of a measured curve: the power law of the segment holding `v` (the first or
/// last segment beyond the ends; `v^(1/2)` through a lone point).
fn measured_ratio(points: &[(f64, f64)], v: f64) -> f64 {
    if points.len() == 1 {
        let (v0, f0) = points[0];
        return f0 * (v / v0).sqrt();
    }
    let i = points
        .partition_point(|p| p.0 <= v)
        .clamp(1, points.len() - 1)
        - 1;
    crate::contact::restitution::power_law(v, points[i], points[i + 1])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A measured curve passes through its points, is a power law between them and
    /// beyond its ends (the end segments' exponents), scales with the shot radius, and
    /// refuses bad points.
    #[test]
    fn a_measured_curve_interpolates_as_power_laws() {
        let pts = [(20.0, 0.36), (70.0, 0.52), (100.0, 0.58)];
        let m = DentModel::measured(&pts).unwrap();
        let r = 0.4e-3;
        for (v, f) in pts {
            assert!((m.radius(r, 1.0, v) / (r * f) - 1.0).abs() < 1e-12);
        }
        let p0 = (0.52f64 / 0.36).ln() / 3.5f64.ln();
        assert!((m.radius(r, 1.0, 40.0) / (r * 0.36 * 2f64.powf(p0)) - 1.0).abs() < 1e-12);
        assert!((m.radius(r, 1.0, 10.0) / (r * 0.36 * 0.5f64.powf(p0)) - 1.0).abs() < 1e-12);
        let p1 = (0.58f64 / 0.52).ln() / (100.0f64 / 70.0).ln();
        assert!((m.radius(r, 1.0, 200.0) / (r * 0.58 * 2f64.powf(p1)) - 1.0).abs() < 1e-12);
        assert!((m.radius(2.0 * r, 8.0, 55.0) / m.radius(r, 1.0, 55.0) - 2.0).abs() < 1e-12);
        assert_eq!(m.radius(r, 1.0, 0.0), 0.0);
        let one = DentModel::measured(&[(50.0, 0.5)]).unwrap();
        assert!((one.radius(r, 1.0, 200.0) / (r * 1.0) - 1.0).abs() < 1e-12);
        assert!(DentModel::measured(&[]).is_err());
        assert!(
            DentModel::measured(&[(50.0, 0.5), (40.0, 0.6)])
                .unwrap_err()
                .contains("increase")
        );
        assert!(
            DentModel::measured(&[(50.0, 0.0)])
                .unwrap_err()
                .contains("(0, 5]")
        );
        assert!(
            DentModel::measured(&[(-5.0, 0.3)])
                .unwrap_err()
                .contains("(0, 1000]")
        );
    }

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
