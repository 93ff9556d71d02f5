//! Gravity: a constant body acceleration (default `-9.80665 m/s^2` along z, the specimen
//! normal). Costs nothing when off: it is simply absent from the [`super::ForceSet`].

use crate::Vec3;

/// Uniform gravitational field.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GravityModel {
    /// Gravitational acceleration, m/s^2 (default: `(0, 0, -9.80665)`).
    pub acceleration: Vec3,
}
