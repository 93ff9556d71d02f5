//! Shot-nozzle-wall contact: a shot inside the cylindrical bore (radius `d/2`, from the
//! inlet plane to the exit plane). The nozzle's outer body and end face are not modelled.

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
    /// Unit vector from the axis towards the shot (the wall's outward normal at the contact).
    pub outward: Vec3,
}

impl WallContact {
    /// Gap and outward normal of a shot of `radius` at `pos`, or `None` when the shot's
    /// centre is not inside the bore (outside its axial extent, or farther from the axis
    /// than the wall: the nozzle's outer body is not modelled).
    #[inline]
    pub fn geometry(&self, pos: &Vec3, radius: f64) -> Option<WallGeom> {
        let rel = pos - self.exit;
        let s = rel.dot(&self.axis);
        if s < -self.length - crate::flow::jet::INLET_TOLERANCE || s > 0.0 {
            return None;
        }
        let radial = rel - self.axis * s;
        let rho = radial.norm();
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
        // Conforming contact is softer-curved than a flat wall: larger effective radius.
        assert!(w.effective_radius(0.4e-3) > 0.4e-3);
    }
}
