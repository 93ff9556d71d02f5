//! Shot-nozzle-wall contact. The nozzle is a thin-walled tube: a shot inside the
//! cylindrical bore (radius `d/2`, from the inlet plane to the exit plane) meets its
//! wall, a shot just beyond either end meets that end's lip (the circular edge of the
//! bore), as a rebounding shot flying back into the nozzle does, and a shot beside the
//! tube meets its outer surface. The nozzle's wall thickness and outer body are not
//! modelled.

use super::HertzLaw;
use crate::Vec3;

/// Shot against the nozzle tube (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallContact {
    /// Normal law of the shot-nozzle material pair.
    pub law: HertzLaw,
    /// Where the tube is.
    pub tube: Tube,
}

/// The nozzle tube's place: a thin-walled cylinder (radius `d/2`, from the inlet to the
/// exit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tube {
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
    /// [`Tube::geometry`].
    #[inline]
    pub fn geometry(&self, pos: &Vec3, radius: f64) -> Option<WallGeom> {
        self.tube.geometry(pos, radius)
    }

    /// Hertz effective radius of a sphere touching a concave cylinder from inside:
    /// `sqrt(R_axial R_hoop)` with `R_axial = R` (straight along the axis) and
    /// `R_hoop = R R_b / (R_b - R)` (conforming around the circumference). The lips and
    /// the outer surface take it too.
    #[inline]
    pub fn effective_radius(&self, radius: f64) -> f64 {
        let rb = self.tube.bore_radius;
        let hoop = radius * rb / (rb - radius);
        (radius * hoop).sqrt()
    }
}

impl Tube {
    /// Distance (m) of `pos` from the tube's axis.
    pub fn radial_distance(&self, pos: &Vec3) -> f64 {
        let rel = pos - self.exit;
        (rel - self.axis * rel.dot(&self.axis)).norm()
    }

    /// Gap and contact direction of a shot of `radius` at `pos`, or `None` when the shot
    /// can touch no part of the tube: its centre is more than `radius` beyond either end.
    /// The tube is thin-walled: a shot centred inside the bore radius meets the bore wall,
    /// one outside it the tube's outer surface (the nozzle's outer body is not modelled),
    /// and one beyond either end (the exit downstream, the inlet upstream) the lip circle
    /// of that end, from inside and outside alike. The gap is continuous wherever a shot
    /// can be without having passed through the wall.
    #[inline]
    pub fn geometry(&self, pos: &Vec3, radius: f64) -> Option<WallGeom> {
        let rel = pos - self.exit;
        let s = rel.dot(&self.axis);
        // The bore's inlet plane: a centre placed in it belongs to the bore.
        let inlet = -self.length - crate::flow::jet::INLET_TOLERANCE;
        if s < inlet - radius || s > radius {
            return None;
        }
        let radial = rel - self.axis * s;
        let rho = radial.norm();
        if s > 0.0 || s < inlet {
            // Beyond an end: the nearest wall point is on that end's lip circle. Found in
            // session 2 at the exit: without it a shot rebounding into the nozzle off-axis
            // met the bore wall only once its centre crossed the exit plane, 90 % of a
            // radius deep. Session 23 added the shots centred outside the bore radius (a
            // shot rebounding up just outside it passed the lip) and the inlet's lip.
            let out = if rho > 0.0 {
                radial / rho
            } else {
                self.axis
                    .cross(&Vec3::x())
                    .try_normalize(0.0)
                    .unwrap_or(Vec3::y())
            };
            let end = if s > 0.0 { 0.0 } else { inlet };
            let lip = self.exit + self.axis * end + out * self.bore_radius;
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
            // Beside the tube: its outer surface (session 23; before, nothing was there,
            // and a shot beside the tube that drifted inward met the bore wall a whole
            // radius deep).
            return Some(WallGeom {
                gap: rho - self.bore_radius - radius,
                outward: -radial / rho,
            });
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
            tube: Tube {
                exit: Vec3::new(0.0, 0.0, 0.1),
                axis: Vec3::new(0.0, 0.0, -1.0),
                bore_radius: 3e-3,
                length: 40e-3,
            },
        };
        let g = w.geometry(&Vec3::new(2.0e-3, 0.0, 0.12), 0.4e-3).unwrap();
        assert!((g.gap - 0.6e-3).abs() < 1e-15 && g.outward.x == 1.0);
        assert!(w.geometry(&Vec3::new(0.0, 0.0, 0.09), 0.4e-3).is_none());
        assert!(
            w.geometry(&Vec3::new(0.0, 0.0, 0.1401), 0.4e-3)
                .unwrap()
                .gap
                > 2e-3
        );
        // A shot beside the nozzle, at bore height: the tube's outer surface, pushing it
        // away from the axis.
        let g = w.geometry(&Vec3::new(0.07, 0.0, 0.12), 0.4e-3).unwrap();
        assert!((g.gap - (0.07 - 3e-3 - 0.4e-3)).abs() < 1e-15 && g.outward.x == -1.0);
        // Continuous with the lip across the exit plane, outside the bore radius.
        let [up, down] = [0.1 + 1e-12, 0.1 - 1e-12]
            .map(|z| w.geometry(&Vec3::new(3.2e-3, 0.0, z), 0.4e-3).unwrap());
        assert!((up.gap - down.gap).abs() < 1e-11 && (up.outward - down.outward).norm() < 1e-6);
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
        // Just below the exit, outside the bore radius (a shot rebounding up beside the
        // bore): the lip as well, pushing it outward and down.
        let g = w.geometry(&Vec3::new(3.1e-3, 0.0, 0.0999), 0.4e-3).unwrap();
        let d = (0.1e-3f64.powi(2) + 0.1e-3f64.powi(2)).sqrt();
        assert!((g.gap - (d - 0.4e-3)).abs() < 1e-12, "{}", g.gap);
        assert!(g.outward.x < 0.0 && g.outward.z > 0.0);
        // Continuous across the bore radius there.
        let [inside, outside] = [3e-3 - 1e-12, 3e-3 + 1e-12]
            .map(|x| w.geometry(&Vec3::new(x, 0.0, 0.0999), 0.4e-3).unwrap());
        assert!((inside.gap - outside.gap).abs() < 1e-11);
        // Above the inlet (z = 0.14): its lip, continuous with the bore wall and the
        // outer surface; on the axis, far from it; a radius above it, nothing.
        for x in [2.8e-3, 3.2e-3] {
            let [below, above] = [0.14 - 1e-12, 0.14 + 2e-9]
                .map(|z| w.geometry(&Vec3::new(x, 0.0, z), 0.4e-3).unwrap());
            assert!((below.gap - above.gap).abs() < 1e-11, "{x}");
        }
        let g = w.geometry(&Vec3::new(3.1e-3, 0.0, 0.1401), 0.4e-3).unwrap();
        assert!(g.gap < 0.0 && g.outward.x < 0.0 && g.outward.z < 0.0);
        assert!(
            w.geometry(&Vec3::new(2.8e-3, 0.0, 0.1405), 0.4e-3)
                .is_none()
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
