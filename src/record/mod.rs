//! Impact recorder: the records the run produces for downstream FE analyses.
//!
//! The integrator creates an [`Impact`] at the located onset of every shot-specimen
//! contact and a [`RunEvent`] whenever a shot had to be stopped. Islands collect them in
//! their own buffers; the simulation merges them and sorts by (time, shot), so the output
//! does not depend on the thread count.

pub mod figure;
pub mod loading;

use crate::Vec3;
use crate::contact::specimen::SpecimenShape;
use serde::Serialize;

/// One shot-specimen contact, at its first instant.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Impact {
    /// Shot id.
    pub shot: u32,
    /// First-contact time, s.
    pub time_s: f64,
    /// Contact point x, m (on the specimen surface: the centre's foot on it).
    pub x_m: f64,
    /// Contact point y, m.
    pub y_m: f64,
    /// Contact point z, m (0 on the flat specimen).
    pub z_m: f64,
    /// Velocity x, m/s.
    pub vx_m_s: f64,
    /// Velocity y, m/s.
    pub vy_m_s: f64,
    /// Velocity z, m/s.
    pub vz_m_s: f64,
    /// Speed `|v|`, m/s.
    pub speed_m_s: f64,
    /// Normal speed towards the specimen `-v.n` (`n` its outward normal at the contact
    /// point), m/s.
    pub normal_speed_m_s: f64,
    /// Impact angle from the specimen normal, degrees (0 = head-on).
    pub angle_deg: f64,
    /// Shot diameter, m.
    pub diameter_m: f64,
    /// 1 for the shot's first specimen contact, 0 for a rebound hit.
    pub first_hit: u8,
    /// Tangential speed along the specimen, m/s.
    pub tangential_speed_m_s: f64,
    /// Shot centre x at first contact, m.
    pub center_x_m: f64,
    /// Shot centre y, m.
    pub center_y_m: f64,
    /// Shot centre z, m (on the flat specimen: the radius, up to the located onset's
    /// round-off).
    pub center_z_m: f64,
    /// Shot mass, kg.
    pub mass_kg: f64,
    /// Kinetic energy `m v^2 / 2`, J.
    pub kinetic_energy_j: f64,
    /// Shot-shot collisions the shot had before this impact.
    pub collisions_before: u32,
    /// Angular velocity x at first contact, rad/s (0 unless the `friction` effect is on).
    pub omega_x_rad_s: f64,
    /// Angular velocity y, rad/s.
    pub omega_y_rad_s: f64,
    /// Angular velocity z, rad/s.
    pub omega_z_rad_s: f64,
}

impl Impact {
    /// Builds the record for a shot of `radius`, `mass` at `pos`, `vel` (spinning at
    /// `omega`) touching the
    /// specimen plane (normal `+z`) at time `t`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        shot: u32,
        t: f64,
        pos: &Vec3,
        vel: &Vec3,
        omega: &Vec3,
        radius: f64,
        mass: f64,
        collisions_before: u32,
        first_hit: bool,
    ) -> Self {
        Self::on(
            &SpecimenShape::Plane,
            shot,
            t,
            pos,
            vel,
            omega,
            radius,
            mass,
            collisions_before,
            first_hit,
        )
    }

    /// [`Impact::new`] on the specimen surface `shape`: the contact point is the
    /// centre's foot on the surface, and the normal and tangential speeds and the angle
    /// are taken against the surface's outward normal there (the contact point's
    /// offset from the centre gives that normal back: `(centre - point) / radius`).
    #[allow(clippy::too_many_arguments)]
    pub fn on(
        shape: &SpecimenShape,
        shot: u32,
        t: f64,
        pos: &Vec3,
        vel: &Vec3,
        omega: &Vec3,
        radius: f64,
        mass: f64,
        collisions_before: u32,
        first_hit: bool,
    ) -> Self {
        let (point, normal, tangential) = match shape {
            SpecimenShape::Plane => (
                Vec3::new(pos.x, pos.y, 0.0),
                -vel.z,
                (vel.x * vel.x + vel.y * vel.y).sqrt(),
            ),
            _ => {
                let n = shape.normal(pos);
                let vn = vel.dot(&n);
                (pos - n * (shape.distance(pos)), -vn, (vel - n * vn).norm())
            }
        };
        let speed = vel.norm();
        Impact {
            shot,
            time_s: t,
            x_m: point.x,
            y_m: point.y,
            z_m: point.z,
            vx_m_s: vel.x,
            vy_m_s: vel.y,
            vz_m_s: vel.z,
            speed_m_s: speed,
            normal_speed_m_s: normal,
            angle_deg: tangential.atan2(normal).to_degrees(),
            diameter_m: 2.0 * radius,
            first_hit: first_hit as u8,
            tangential_speed_m_s: tangential,
            center_x_m: pos.x,
            center_y_m: pos.y,
            center_z_m: pos.z,
            mass_kg: mass,
            kinetic_energy_j: 0.5 * mass * speed * speed,
            collisions_before,
            omega_x_rad_s: omega.x,
            omega_y_rad_s: omega.y,
            omega_z_rad_s: omega.z,
        }
    }

    /// Distance of the contact point from the jet axis foot (x = y = 0), m.
    pub fn radius_m(&self) -> f64 {
        (self.x_m * self.x_m + self.y_m * self.y_m).sqrt()
    }
}

/// Something that went wrong with a shot during the run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunEvent {
    /// Shot id.
    pub shot: u32,
    /// Time, s.
    pub time_s: f64,
    /// What happened.
    pub cause: String,
    /// What the user can do about it.
    pub suggestion: String,
}
