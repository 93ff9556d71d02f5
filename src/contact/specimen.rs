//! Shot-specimen contact. The specimen is either the paper's flat plate, the plane
//! `z = 0` with normal `+z`, or (beyond the paper) a convex cylinder, a bar or a spring's
//! wire, whose crest line runs through the origin at `z = 0` along a horizontal axis
//! (the specimen frame is the world frame in both).

use std::sync::Arc;

use super::HertzLaw;
use super::restitution::SpeedLaw;
use crate::Vec3;
use crate::state::ShotState;

/// The specimen's surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpecimenShape {
    /// The plane `z = 0`, normal `+z` (the paper's specimen).
    Plane,
    /// A convex cylinder of `radius` (m) whose axis runs along the horizontal unit vector
    /// `axis` through `(0, 0, -radius)`: its crest line is `z = 0` through the origin.
    /// The outward normal at a point is its direction away from the axis.
    Cylinder {
        /// Radius, m.
        radius: f64,
        /// Axis direction, a horizontal unit vector.
        axis: Vec3,
    },
}

impl SpecimenShape {
    /// A cylinder of `radius` (m) whose axis makes `axis_angle` (rad) with `+x` in the
    /// horizontal plane.
    pub fn cylinder(radius: f64, axis_angle: f64) -> Self {
        SpecimenShape::Cylinder {
            radius,
            axis: Vec3::new(axis_angle.cos(), axis_angle.sin(), 0.0),
        }
    }

    /// Whether the surface is the flat plane.
    #[inline]
    pub fn is_plane(&self) -> bool {
        matches!(self, SpecimenShape::Plane)
    }

    /// For a cylinder: the offset of `pos` from its axis, perpendicular to the axis.
    #[inline]
    fn radial(pos: &Vec3, radius: f64, axis: &Vec3) -> Vec3 {
        let d = Vec3::new(pos.x, pos.y, pos.z + radius);
        d - axis * d.dot(axis)
    }

    /// Distance (m) of `pos` from the surface, positive outside (above the plane).
    #[inline]
    pub fn distance(&self, pos: &Vec3) -> f64 {
        match self {
            SpecimenShape::Plane => pos.z,
            SpecimenShape::Cylinder { radius, axis } => {
                Self::radial(pos, *radius, axis).norm() - radius
            }
        }
    }

    /// Outward unit normal of the surface point nearest `pos` (`+z` on the plane, and on
    /// the cylinder's axis itself).
    #[inline]
    pub fn normal(&self, pos: &Vec3) -> Vec3 {
        match self {
            SpecimenShape::Plane => Vec3::z(),
            SpecimenShape::Cylinder { radius, axis } => {
                let d = Self::radial(pos, *radius, axis);
                let l = d.norm();
                if l > 0.0 { d / l } else { Vec3::z() }
            }
        }
    }

    /// Component of `vel` along the outward normal at `pos` (negative: towards the
    /// surface). On the plane, `vel.z`.
    #[inline]
    pub fn normal_velocity(&self, pos: &Vec3, vel: &Vec3) -> f64 {
        match self {
            SpecimenShape::Plane => vel.z,
            SpecimenShape::Cylinder { .. } => vel.dot(&self.normal(pos)),
        }
    }

    /// Hertz effective radius of a sphere of `radius` on the surface. On the cylinder
    /// the contact is elliptic; its equivalent radius is `sqrt(R' R'')` with `R' = r`
    /// along the axis and `1/R'' = 1/r + 1/R_c` around it (Johnson, Contact Mechanics,
    /// Sec. 4.2; the ellipticity's correction to the load is below 1e-3 for
    /// `R_c >= r`).
    #[inline]
    pub fn effective_radius(&self, radius: f64) -> f64 {
        match self {
            SpecimenShape::Plane => radius,
            SpecimenShape::Cylinder { radius: rc, .. } => {
                (radius * (radius * rc / (radius + rc))).sqrt()
            }
        }
    }

    /// The lowest height (m) a shot of radius up to `r_max` can reach while still able
    /// to touch the specimen; a shot below it has missed it for good (`-inf` on the
    /// plane, which nothing passes).
    pub fn floor(&self, r_max: f64) -> f64 {
        match self {
            SpecimenShape::Plane => f64::NEG_INFINITY,
            SpecimenShape::Cylinder { radius, .. } => -2.0 * radius - 2.0 * r_max,
        }
    }
}

/// Shot against the specimen's surface (specimen frame = world frame).
#[derive(Debug, Clone, PartialEq)]
pub struct SpecimenContact {
    /// Normal law of the shot-specimen material pair (with a restitution curve: its
    /// stiffness; each contact takes its own damping).
    pub law: HertzLaw,
    /// Restitution against the normal impact speed (`[restitution]
    /// shot_specimen_curve`), if given: each contact then takes the damping of its
    /// speed at the touch ([`crate::contact::restitution`]).
    pub by_speed: Option<Arc<SpeedLaw>>,
    /// The surface.
    pub shape: SpecimenShape,
}

impl SpecimenContact {
    /// Gap (m) between a shot of `radius` at `pos` and the surface; negative when
    /// overlapping.
    #[inline]
    pub fn gap(&self, pos: &Vec3, radius: f64) -> f64 {
        self.shape.distance(pos) - radius
    }

    /// Outward unit normal at the surface point nearest `pos`.
    #[inline]
    pub fn normal(&self, pos: &Vec3) -> Vec3 {
        self.shape.normal(pos)
    }

    /// Component of `vel` along the outward normal at `pos` (negative: approaching).
    #[inline]
    pub fn normal_velocity(&self, pos: &Vec3, vel: &Vec3) -> f64 {
        self.shape.normal_velocity(pos, vel)
    }

    /// Hertz effective radius of a shot of `radius` on the surface.
    #[inline]
    pub fn effective_radius(&self, radius: f64) -> f64 {
        self.shape.effective_radius(radius)
    }

    /// The contact point's offset from the centre of a shot at `pos`, `lever` (m)
    /// towards the surface (on the plane exactly `(0, 0, -lever)`).
    #[inline]
    pub fn lever(&self, pos: &Vec3, lever: f64) -> Vec3 {
        match self.shape {
            SpecimenShape::Plane => Vec3::new(0.0, 0.0, -lever),
            SpecimenShape::Cylinder { .. } => self.normal(pos) * -lever,
        }
    }

    /// Adds `s` along the outward normal at `pos` to `a` (on the plane, to `a.z` alone).
    #[inline]
    pub fn add_normal(&self, pos: &Vec3, a: &mut Vec3, s: f64) {
        match self.shape {
            SpecimenShape::Plane => a.z += s,
            SpecimenShape::Cylinder { .. } => *a += self.normal(pos) * s,
        }
    }

    /// The law of a contact that starts at normal speed `speed` (m/s, towards the surface).
    #[inline]
    pub fn law_at(&self, speed: f64) -> HertzLaw {
        match &self.by_speed {
            None => self.law,
            Some(s) => self.law.with_damping(s.damping(speed)),
        }
    }

    /// The law of shot `m`'s specimen contact: the one that started at its touch
    /// (`ShotState::specimen_damping`); for a contact not yet registered (the fixed-step
    /// methods see the overlap before they record the touch), that of the normal velocity
    /// `vn` now (along the outward normal, [`SpecimenContact::normal_velocity`]).
    #[inline]
    pub fn law_of(&self, m: &ShotState, vn: f64) -> HertzLaw {
        match &self.by_speed {
            None => self.law,
            Some(_) if m.on_specimen => self.law.with_damping(m.specimen_damping),
            Some(_) => self.law_at(-vn),
        }
    }
}
