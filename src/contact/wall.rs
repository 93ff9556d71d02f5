//! Shot-nozzle-wall contact: a shot inside the cylindrical bore (radius `d/2`, from the
//! inlet plane to the exit plane), and a shot just downstream of the exit touching the
//! lip (the circular edge of the bore at the exit plane), as a rebounding shot flying
//! back into the nozzle does. The nozzle's outer body and end face are not modelled.

use super::HertzLaw;
use crate::Vec3;

/// Shot against the inside of the cylindrical bore (radius `d/2`, from the inlet to the exit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallContact {
    /// Normal law of the shot-nozzle material pair.
    pub law: HertzLaw,
    /// Centre of the exit plane, m.
    pub exit: Vec3,
    /// Unit jet axis pointing downstream.
    pub axis: Vec3,
    /// Bore radius `d/2`, m.
    pub bore_radius: f64,
    /// Bore length `l_n`, m.
    pub length: f64,
}

/// Geometry of a shot-wall contact candidate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallGeom {
    /// Gap to the wall, m (negative when overlapping).
    pub gap: f64,
    /// Unit vector from the shot's centre towards the contact point (inside the bore: the
    /// wall's outward normal, from the axis towards the wall).
    pub outward: Vec3,
}

impl WallContact {
    /// Gap and contact direction of a shot of `radius` at `pos`, or `None` when the shot
    /// can touch neither the bore (centre outside its axial extent, or farther from the
    /// axis than the wall: the nozzle's outer body is not modelled) nor the lip (centre
    /// more than `radius` downstream of the exit plane, or not closer to the axis than
    /// the bore radius).
    #[inline]
    pub fn geometry(&self, pos: &Vec3, radius: f64) -> Option<WallGeom> {
        let rel = pos - self.exit;
        let s = rel.dot(&self.axis);
        if s < -self.length - crate::flow::jet::INLET_TOLERANCE || s > radius {
            return None;
        }
        let radial = rel - self.axis * s;
        let rho = radial.norm();
        if rho >= self.bore_radius {
            // Beside the tube: its outer body is not modelled.
            return None;
        }
        if s > 0.0 {
            // Downstream of the exit: the nearest wall point is on the lip circle. Found
            // in session 2: without it a shot rebounding into the nozzle off-axis met the
            // bore wall only once its centre crossed the exit plane, 90 % of a radius deep.
            let out = if rho > 0.0 {
                radial / rho
            } else {
                self.axis
                    .cross(&Vec3::x())
                    .try_normalize(0.0)
                    .unwrap_or(Vec3::y())
            };
            let lip = self.exit + out * self.bore_radius;
            let to_lip = lip - pos;
            let d = to_lip.norm();
            if d == 0.0 {
                return None;
            }
            return Some(WallGeom {
                gap: d - radius,
                outward: to_lip / d,
            });
        }
        if rho >= self.bore_radius {
            return None;
        }
        let outward = if rho > 0.0 {
            radial / rho
        } else {
            Vec3::zeros()
        };
        Some(WallGeom {
            gap: self.bore_radius - radius - rho,
            outward,
        })
    }

    /// Hertz effective radius of a sphere touching a concave cylinder from inside:
    /// `sqrt(R_axial R_hoop)` with `R_axial = R` (straight along the axis) and
    /// `R_hoop = R R_b / (R_b - R)` (conforming around the circumference).
    #[inline]
    pub fn effective_radius(&self, radius: f64) -> f64 {
        let hoop = radius * self.bore_radius / (self.bore_radius - radius);
        (radius * hoop).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::HertzLaw;

    #[test]
    fn wall_gap_and_extent() {
        let law = HertzLaw::new(210e9, 0.3, 210e9, 0.3, 0.7);
        let w = WallContact {
            law,
            exit: Vec3::new(0.0, 0.0, 0.1),
            axis: Vec3::new(0.0, 0.0, -1.0),
            bore_radius: 3e-3,
            length: 40e-3,
        };
        let g = w.geometry(&Vec3::new(2.0e-3, 0.0, 0.12), 0.4e-3).unwrap();
        assert!((g.gap - 0.6e-3).abs() < 1e-15 && g.outward.x == 1.0);
        assert!(w.geometry(&Vec3::new(0.0, 0.0, 0.09), 0.4e-3).is_none());
        assert!(w.geometry(&Vec3::new(0.0, 0.0, 0.1401), 0.4e-3).is_none());
        // A shot beside the nozzle, at bore height but outside the tube: no wall.
        assert!(w.geometry(&Vec3::new(0.07, 0.0, 0.12), 0.4e-3).is_none());
        // Just below the exit, off-axis: the lip. Centre 0.1 mm below the exit plane and
        // 0.2 mm inside the bore radius: distance to the lip sqrt(0.1^2 + 0.2^2) mm.
        let g = w.geometry(&Vec3::new(2.8e-3, 0.0, 0.0999), 0.4e-3).unwrap();
        let d = (0.1e-3f64.powi(2) + 0.2e-3f64.powi(2)).sqrt();
        assert!((g.gap - (d - 0.4e-3)).abs() < 1e-12, "{}", g.gap);
        assert!(g.outward.x > 0.0 && g.outward.z > 0.0);
        // Continuous with the bore wall at the exit plane.
        let above = w
            .geometry(&Vec3::new(2.8e-3, 0.0, 0.1 + 1e-12), 0.4e-3)
            .unwrap();
        let below = w
            .geometry(&Vec3::new(2.8e-3, 0.0, 0.1 - 1e-12), 0.4e-3)
            .unwrap();
        assert!(
            (above.gap - below.gap).abs() < 1e-11 && (above.outward - below.outward).norm() < 1e-6
        );
        // On the axis just below the exit: far from the lip; farther down: nothing.
        assert!(
            w.geometry(&Vec3::new(0.0, 0.0, 0.0999), 0.4e-3)
                .unwrap()
                .gap
                > 2e-3
        );
        assert!(w.geometry(&Vec3::new(0.0, 0.0, 0.0995), 0.4e-3).is_none());
        // Conforming contact is softer-curved than a flat wall: larger effective radius.
        assert!(w.effective_radius(0.4e-3) > 0.4e-3);
    }
}
