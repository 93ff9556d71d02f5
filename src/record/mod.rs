//! Impact recorder: the records the run produces for downstream FE analyses.
//!
//! The integrator creates an [`Impact`] at the located onset of every shot-specimen
//! contact and a [`RunEvent`] whenever a shot had to be stopped. Islands collect them in
//! their own buffers; the simulation merges them and sorts by (time, shot), so the output
//! does not depend on the thread count.

pub mod figure;

use crate::Vec3;
use serde::Serialize;

/// One shot-specimen contact, at its first instant.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Impact {
    /// Shot id.
    pub shot: u32,
    /// First-contact time, s.
    pub time_s: f64,
    /// Contact point x, m (specimen plane).
    pub x_m: f64,
    /// Contact point y, m.
    pub y_m: f64,
    /// Contact point z, m (0: the specimen plane).
    pub z_m: f64,
    /// Velocity x, m/s.
    pub vx_m_s: f64,
    /// Velocity y, m/s.
    pub vy_m_s: f64,
    /// Velocity z, m/s.
    pub vz_m_s: f64,
    /// Speed `|v|`, m/s.
    pub speed_m_s: f64,
    /// Normal speed towards the specimen `-v.n`, m/s.
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
    /// Shot centre z, m (the radius, up to the located onset's round-off).
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
        let normal = -vel.z;
        let tangential = (vel.x * vel.x + vel.y * vel.y).sqrt();
        let speed = vel.norm();
        Impact {
            shot,
            time_s: t,
            x_m: pos.x,
            y_m: pos.y,
            z_m: 0.0,
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
