//! Shot-nozzle-wall contact. The nozzle is a tube: a shot inside the cylindrical bore
//! (radius `d/2`, from the inlet plane to the exit plane) meets its wall, a shot beside
//! the tube meets its outer surface, and a shot just beyond either end meets that end:
//! the lip (the circular edge of the bore), as a rebounding shot flying back into the
//! nozzle does, the flat annular face of a thick-walled tube (`nozzle.outer_diameter_mm`),
//! or the outer edge. Without an outer diameter the tube is thin-walled: its outer
//! surface is at the bore radius and each end is the lip circle alone.

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

/// The nozzle tube's place: a hollow cylinder (bore radius `d/2`, outer radius at least
/// that, from the inlet to the exit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tube {
    /// Centre of the exit plane, m.
    pub exit: Vec3,
    /// Unit jet axis pointing downstream.
    pub axis: Vec3,
    /// Bore radius `d/2`, m.
    pub bore_radius: f64,
    /// Outer radius of the tube's wall, m (`bore_radius`: thin-walled).
    pub outer_radius: f64,
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
    /// `R_hoop = R R_b / (R_b - R)` (conforming around the circumference). The lips, the
    /// end faces and the outer surface take it too.
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
    /// In the plane through the axis the wall is the rectangle from the bore radius to the
    /// outer radius and from the inlet to the exit; the gap is the distance from the
    /// centre to it less the shot's radius. A shot centred inside the bore radius meets the
    /// bore wall, one outside the outer radius the outer surface, and one beyond either end
    /// (the exit downstream, the inlet upstream) that end: the lip circle from inside the
    /// bore radius, the outer edge from outside the outer radius, the flat annular face in
    /// between (thin-walled: the lip alone, from inside and outside alike). The gap is
    /// continuous wherever a shot can be without having passed through the wall.
    #[inline]
    pub fn geometry(&self, pos: &Vec3, radius: f64) -> Option<WallGeom> {
        let rel = pos - self.exit;
        let s = rel.dot(&self.axis);
        // The bore's inlet plane: a centre placed in it belongs to the bore.
        let inlet = -self.length - crate::flow::jet::INLET_TOLERANCE;
        if s < inlet - radius || s > radius {
            return None;
        }
        self.section(pos, rel, s, inlet, radius)
    }

    /// The gap from a shot of `radius` at `pos` to the tube, however far it is (where
    /// [`Tube::geometry`] says `None`, the distance to the nearest end): for bounds on
    /// when a shot can reach the tube. Negative when overlapping.
    pub fn clearance(&self, pos: &Vec3, radius: f64) -> f64 {
        self.nearest(pos, radius).map_or(-radius, |g| g.gap)
    }

    /// The speed of `vel` across the axis: the fastest a shot's distance from the axis
    /// can change. No part of the tube is nearer the axis than the bore radius, so a shot
    /// nearer the axis than `bore radius - radius` touches nothing before that distance
    /// has grown that far.
    pub fn speed_across_axis(&self, vel: &Vec3) -> f64 {
        (vel - self.axis * vel.dot(&self.axis)).norm()
    }

    /// How far `pos` lies beyond the nearer end of the tube along its axis (m; zero
    /// between the inlet and exit planes), and the unit vector back towards that end's
    /// plane. No part of the tube is nearer than that distance.
    pub fn beyond_end(&self, pos: &Vec3) -> (f64, Vec3) {
        let s = (pos - self.exit).dot(&self.axis);
        let inlet = -self.length - crate::flow::jet::INLET_TOLERANCE;
        if s > 0.0 {
            (s, -self.axis)
        } else if s < inlet {
            (inlet - s, self.axis)
        } else {
            (0.0, Vec3::zeros())
        }
    }

    /// [`Tube::geometry`] however far the shot is: the gap to the nearest point of the
    /// tube and the direction to it (`None` only for a centre exactly on a lip or edge
    /// circle).
    pub fn nearest(&self, pos: &Vec3, radius: f64) -> Option<WallGeom> {
        let rel = pos - self.exit;
        let s = rel.dot(&self.axis);
        let inlet = -self.length - crate::flow::jet::INLET_TOLERANCE;
        self.section(pos, rel, s, inlet, radius)
    }

    /// [`Tube::geometry`] without the cut-off beyond the ends: `rel` is the shot's centre
    /// `pos` from the exit's, `s` its coordinate along the axis, `inlet` the inlet
    /// plane's.
    #[inline]
    fn section(&self, pos: &Vec3, rel: Vec3, s: f64, inlet: f64, radius: f64) -> Option<WallGeom> {
        let radial = rel - self.axis * s;
        let rho = radial.norm();
        if s > 0.0 || s < inlet {
            // Beyond an end: the nearest wall point is on that end's lip circle, its outer
            // edge, or its face. Found in session 2 at the exit: without the lip a shot
            // rebounding into the nozzle off-axis met the bore wall only once its centre
            // crossed the exit plane, 90 % of a radius deep. Session 23 added the shots
            // centred outside the bore radius (a shot rebounding up just outside it passed
            // the lip) and the inlet's lip; session 27 the thick wall's faces and edges.
            let end = if s > 0.0 { 0.0 } else { inlet };
            let edge = if rho <= self.bore_radius {
                self.bore_radius
            } else if rho >= self.outer_radius {
                self.outer_radius
            } else {
                // On the flat face: straight along the axis.
                let ds = end - s;
                return Some(WallGeom {
                    gap: ds.abs() - radius,
                    outward: self.axis * ds.signum(),
                });
            };
            let out = if rho > 0.0 {
                radial / rho
            } else {
                self.axis
                    .cross(&Vec3::x())
                    .try_normalize(0.0)
                    .unwrap_or(Vec3::y())
            };
            let lip = self.exit + self.axis * end + out * edge;
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
        if rho >= self.outer_radius {
            // Beside the tube: its outer surface (session 23; before, nothing was there,
            // and a shot beside the tube that drifted inward met the bore wall a whole
            // radius deep).
            return Some(WallGeom {
                gap: rho - self.outer_radius - radius,
                outward: -radial / rho,
            });
        }
        if rho > self.bore_radius {
            // The centre inside the thick wall itself (an overlap deeper than a radius:
            // the run stops it as "Hertz contact does not hold"). The gap goes on
            // continuously from the nearest face, pushing back out through it.
            let faces = [
                (rho - self.bore_radius, radial / rho),
                (self.outer_radius - rho, -radial / rho),
                (-s, -self.axis),
                (s - inlet, self.axis),
            ];
            let (depth, outward) = faces
                .into_iter()
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .expect("four faces");
            return Some(WallGeom {
                gap: -depth - radius,
                outward,
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
                outer_radius: 3e-3,
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

    #[test]
    fn thick_wall_gap_is_the_distance_to_the_wall_section() {
        // Independent computation: in the plane through the axis the wall is the rectangle
        // rho in [3, 8] mm, s in [-40, 0] mm (s along the axis from the exit, downstream
        // positive); a centre outside it is at the clamped distance, and the contact
        // direction points at the nearest point of the rectangle.
        use rand::{Rng, SeedableRng};
        let tube = Tube {
            exit: Vec3::new(0.0, 0.0, 0.1),
            axis: Vec3::new(0.0, 0.0, -1.0),
            bore_radius: 3e-3,
            outer_radius: 8e-3,
            length: 40e-3,
        };
        let inlet = -tube.length - crate::flow::jet::INLET_TOLERANCE;
        let r = 0.4e-3;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(27);
        let mut seen = [0usize; 3];
        for _ in 0..20_000 {
            let (rho, s, phi) = (
                rng.random_range(0.0..9e-3),
                rng.random_range(-41e-3..1e-3),
                rng.random_range(0.0..std::f64::consts::TAU),
            );
            let pos = tube.exit + Vec3::new(rho * phi.cos(), rho * phi.sin(), 0.0) - tube.axis * -s;
            let dr = (tube.bore_radius - rho)
                .max(rho - tube.outer_radius)
                .max(0.0);
            let ds = (inlet - s).max(s).max(0.0);
            let dist = dr.hypot(ds);
            let g = tube.geometry(&pos, r);
            if dist == 0.0 {
                // Centre inside the wall: overlapping by more than a radius.
                assert!(g.unwrap().gap < -r);
                seen[0] += 1;
                continue;
            }
            if ds > r {
                assert!(g.is_none(), "rho {rho}, s {s}");
                continue;
            }
            let g = g.unwrap();
            assert!(
                (g.gap - (dist - r)).abs() < 1e-15,
                "rho {rho}, s {s}: {}",
                g.gap - (dist - r)
            );
            // The nearest point, from the centre.
            let near_rho = rho.clamp(tube.bore_radius, tube.outer_radius);
            let near_s = s.clamp(inlet, 0.0);
            let near = tube.exit
                + Vec3::new(near_rho * phi.cos(), near_rho * phi.sin(), 0.0)
                + tube.axis * near_s;
            assert!(
                (g.outward - (near - pos) / dist).norm() < 1e-9,
                "rho {rho}, s {s}"
            );
            seen[if ds > 0.0 { 1 } else { 2 }] += 1;
        }
        assert!(seen.iter().all(|&n| n > 100), "{seen:?}");
    }
}
