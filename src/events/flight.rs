//! Free flight under uniform gravity, in closed form: positions, and the times at which a
//! shot reaches a height, a radius, or another free shot.
//!
//! Two free shots feel the same gravity, so their relative motion is a straight line and
//! their touching time is a root of a quadratic. Roots are taken in the cancellation-free
//! forms (`c / (-b + sqrt(disc))` and its relatives).

use crate::Vec3;

/// Ballistic motion with gravity `g` (m/s^2) along -z (0: none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flight {
    /// Gravitational acceleration, m/s^2, pointing down (-z).
    pub g: f64,
}

impl Flight {
    /// Position and velocity `tau` seconds after `(p, v)`.
    #[inline]
    pub fn at(&self, p: &Vec3, v: &Vec3, tau: f64) -> (Vec3, Vec3) {
        let mut q = p + v * tau;
        q.z -= 0.5 * self.g * tau * tau;
        let mut w = *v;
        w.z -= self.g * tau;
        (q, w)
    }

    /// First `tau >= 0` at which the centre height, starting at `z0` with vertical speed
    /// `vz`, passes `h` going down; `None` if it never does.
    pub fn down_through(&self, z0: f64, vz: f64, h: f64) -> Option<f64> {
        let d = z0 - h;
        if self.g > 0.0 {
            let disc = vz * vz + 2.0 * self.g * d;
            if disc < 0.0 {
                return None;
            }
            let s = disc.sqrt();
            // Larger root of g t^2 / 2 - vz t - d = 0.
            let t = if vz >= 0.0 {
                (vz + s) / self.g
            } else {
                2.0 * d / (s - vz)
            };
            Some(t.max(0.0))
        } else if vz < 0.0 {
            Some((d / -vz).max(0.0))
        } else {
            None
        }
    }

    /// First `tau >= 0` at which the centre height passes `h` going up; `None` if the
    /// shot never climbs that high.
    pub fn up_through(&self, z0: f64, vz: f64, h: f64) -> Option<f64> {
        if vz <= 0.0 {
            return None;
        }
        let d = h - z0;
        if d <= 0.0 {
            return Some(0.0);
        }
        let disc = vz * vz - 2.0 * self.g * d;
        if disc < 0.0 {
            return None;
        }
        Some(2.0 * d / (vz + disc.sqrt()))
    }

    /// First `tau >= 0` at which the horizontal distance from the z axis reaches
    /// `radius` moving outwards (horizontal motion is uniform); `None` if never.
    pub fn out_of_radius(p: &Vec3, v: &Vec3, radius: f64) -> Option<f64> {
        let a = v.x * v.x + v.y * v.y;
        let b = p.x * v.x + p.y * v.y;
        let c = p.x * p.x + p.y * p.y - radius * radius;
        if c >= 0.0 {
            return (b > 0.0).then_some(0.0);
        }
        if a == 0.0 {
            return None;
        }
        // Larger root of a t^2 + 2 b t + c = 0 (c < 0: one positive root).
        let s = (b * b - a * c).sqrt();
        Some(if b >= 0.0 { -c / (b + s) } else { (s - b) / a })
    }
}

/// First `tau >= 0` at which two free shots with relative position `dx` and relative
/// velocity `dv` (same instant) come within `sigma` of each other while closing;
/// `Some(0)` if they already overlap and close; `None` if they never touch.
#[inline]
pub fn pair_touch(dx: &Vec3, dv: &Vec3, sigma: f64) -> Option<f64> {
    let b = dx.dot(dv);
    if b >= 0.0 {
        return None;
    }
    let c = dx.norm_squared() - sigma * sigma;
    if c <= 0.0 {
        return Some(0.0);
    }
    let disc = b * b - dv.norm_squared() * c;
    if disc < 0.0 {
        return None;
    }
    Some(c / (-b + disc.sqrt()))
}

/// Smallest distance between two straight relative paths `dx + dv tau` over
/// `tau` in `[0, span]`.
#[inline]
pub fn closest_approach(dx: &Vec3, dv: &Vec3, span: f64) -> f64 {
    let vv = dv.norm_squared();
    let tau = if vv > 0.0 {
        (-dx.dot(dv) / vv).clamp(0.0, span)
    } else {
        0.0
    };
    (dx + dv * tau).norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heights_match_the_trajectory() {
        let f = Flight { g: 9.81 };
        let (p, v) = (Vec3::new(0.0, 0.0, 0.01), Vec3::new(1.0, 0.0, 2.0));
        // Up through 0.1 m: the smaller root; down through it later; down to 0.
        let up = f.up_through(p.z, v.z, 0.1).unwrap();
        let down = f.down_through(p.z, v.z, 0.1).unwrap();
        assert!(up < down);
        for tau in [up, down] {
            assert!((f.at(&p, &v, tau).0.z - 0.1).abs() < 1e-12);
        }
        let floor = f.down_through(p.z, v.z, 0.0).unwrap();
        assert!(f.at(&p, &v, floor).0.z.abs() < 1e-12);
        // Too high to reach.
        assert!(f.up_through(p.z, v.z, 1.0).is_none());
        // Falling, small distance: no cancellation.
        let t = f.down_through(1e-9, -70.0, 0.0).unwrap();
        assert!((t - 1e-9 / 70.0).abs() < 1e-22);
        // No gravity.
        let f0 = Flight { g: 0.0 };
        assert_eq!(f0.down_through(1.0, -2.0, 0.0), Some(0.5));
        assert_eq!(f0.up_through(1.0, -2.0, 2.0), None);
    }

    #[test]
    fn pair_touch_is_the_first_contact() {
        let dx = Vec3::new(1.0, 0.1, 0.0);
        let dv = Vec3::new(-2.0, 0.0, 0.0);
        let tau = pair_touch(&dx, &dv, 0.5).unwrap();
        assert!(((dx + dv * tau).norm() - 0.5).abs() < 1e-14);
        assert!((dx + dv * (0.99 * tau)).norm() > 0.5);
        // Receding or missing.
        assert!(pair_touch(&dx, &(-dv), 0.5).is_none());
        assert!(pair_touch(&Vec3::new(1.0, 0.6, 0.0), &dv, 0.5).is_none());
        assert!((closest_approach(&dx, &dv, 10.0) - 0.1).abs() < 1e-15);
        assert!((closest_approach(&dx, &dv, 0.1) - (dx + dv * 0.1).norm()).abs() < 1e-15);
    }

    #[test]
    fn radius_exit() {
        let p = Vec3::new(0.3, 0.0, 0.0);
        let v = Vec3::new(-1.0, 1.0, 5.0);
        let t = Flight::out_of_radius(&p, &v, 1.0).unwrap();
        let q = p + v * t;
        assert!(((q.x * q.x + q.y * q.y).sqrt() - 1.0).abs() < 1e-14);
        assert!(Flight::out_of_radius(&p, &Vec3::new(0.0, 0.0, 1.0), 1.0).is_none());
    }
}
