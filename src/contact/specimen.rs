//! Shot-specimen contact. The specimen is either the paper's flat plate, the plane
//! `z = 0` with normal `+z`, or (beyond the paper) a convex cylinder, a bar or a spring's
//! wire, whose crest line runs through the origin at `z = 0` along a horizontal axis,
//! or a groove (a gear's or a rack's tooth space, a slot: [`super::groove`]) whose
//! bottom's middle line runs there (the specimen frame is the world frame in all).

use std::sync::Arc;

use super::HertzLaw;
use super::groove::{Foot, Groove};
use super::restitution::SpeedLaw;
use crate::Vec3;
use crate::state::ShotState;

/// The specimen's surface. (The groove is behind an `Arc`: its profile is 30 numbers, and
/// the plate's and the bar's contact data stay as small as before it: measured, the
/// groove held inline made the 10,000-shot pack 5 % slower with the same instructions.)
#[derive(Debug, Clone, PartialEq, Default)]
pub enum SpecimenShape {
    /// The plane `z = 0`, normal `+z` (the paper's specimen).
    #[default]
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
    /// A groove, or a rack of them ([`Groove`]).
    Groove(Arc<Groove>),
}

/// The surface under a shot: what its contact's force needs, from one search for the
/// foot (on a gear each of [`SpecimenShape::distance`], [`SpecimenShape::normal`] and
/// [`SpecimenShape::effective_radius`] solves for it; the same numbers to the bit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Touch {
    /// The shot's gap, m (negative when overlapping): [`SpecimenContact::gap`].
    pub gap: f64,
    /// Outward unit normal at the foot: [`SpecimenShape::normal`].
    pub normal: Vec3,
    /// Hertz effective radius: [`SpecimenShape::effective_radius`].
    pub effective_radius: f64,
}

impl Touch {
    /// A shot of `radius` on a groove's foot with its effective radius.
    #[inline]
    fn on_groove((foot, effective_radius): (Foot, f64), radius: f64) -> Touch {
        Touch {
            gap: foot.distance - radius,
            normal: foot.normal,
            effective_radius,
        }
    }
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

    /// The speed (m/s) at which a shot of `radius` at `pos`, flying straight at `vel`,
    /// may close its gap to the surface: on the plate and the bar (convex parts, whose
    /// distance is convex along a line) its speed towards the nearest surface point,
    /// `-v . n`; in a groove, where a shot moving along the bottom closes on a flank,
    /// its gap (`gap`, the shot's, as [`SpecimenContact::gap`] gives it) over the lower
    /// bound on the time to touch any face ([`Groove::time_to_touch`]).
    #[inline]
    pub fn closing_speed(&self, pos: &Vec3, vel: &Vec3, radius: f64, gap: f64) -> f64 {
        match self {
            SpecimenShape::Groove(g) => {
                let t = g.time_to_touch(pos, vel, radius);
                if gap <= 0.0 || t <= 0.0 {
                    vel.norm()
                } else {
                    gap / t
                }
            }
            _ => -self.normal_velocity(pos, vel),
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

    /// For a cylinder: the length of the radial offset `d` and the outward unit normal
    /// along it (`+z` on the axis itself).
    #[inline]
    fn radial_normal(d: &Vec3) -> (f64, Vec3) {
        let l = d.norm();
        (l, if l > 0.0 { d / l } else { Vec3::z() })
    }

    /// A cylinder's effective radius for a shot of `radius` ([`Self::effective_radius`]).
    #[inline]
    fn cylinder_effective_radius(radius: f64, rc: f64) -> f64 {
        (radius * (radius * rc / (radius + rc))).sqrt()
    }

    /// Distance (m) of `pos` from the surface, positive outside (above the plane).
    #[inline]
    pub fn distance(&self, pos: &Vec3) -> f64 {
        match self {
            SpecimenShape::Plane => pos.z,
            SpecimenShape::Cylinder { radius, axis } => {
                Self::radial(pos, *radius, axis).norm() - radius
            }
            SpecimenShape::Groove(g) => g.distance(pos),
        }
    }

    /// [`SpecimenShape::distance`] where it is below `reach` in size, to the bit;
    /// otherwise a value at least `reach` in the air, at most `-reach` in the part.
    /// Cheaper on a gear, whose fillet's feet out of reach are not solved for where
    /// another piece tells the side.
    #[inline]
    pub fn distance_within(&self, pos: &Vec3, reach: f64) -> f64 {
        match self {
            SpecimenShape::Groove(g) => g.distance_within(pos, reach),
            _ => self.distance(pos),
        }
    }

    /// The surface under a shot of `radius` at `pos` ([`Touch`]).
    #[inline]
    pub fn touch(&self, pos: &Vec3, radius: f64) -> Touch {
        match self {
            SpecimenShape::Plane => Touch {
                gap: pos.z - radius,
                normal: Vec3::z(),
                effective_radius: radius,
            },
            SpecimenShape::Cylinder { radius: rc, axis } => {
                let (l, normal) = Self::radial_normal(&Self::radial(pos, *rc, axis));
                Touch {
                    gap: (l - rc) - radius,
                    normal,
                    effective_radius: Self::cylinder_effective_radius(radius, *rc),
                }
            }
            SpecimenShape::Groove(g) => Touch::on_groove(g.foot_and_radius(pos, radius), radius),
        }
    }

    /// [`SpecimenShape::touch`] where a shot of `radius` at `pos` overlaps the surface
    /// ([`SpecimenShape::distance_within`] of `radius`, less `radius`, below 0), to the
    /// bit; `None` where it does not. On a gear from one search for the foot where the
    /// overlap is below the shot's diameter.
    #[inline]
    pub fn overlap_touch(&self, pos: &Vec3, radius: f64) -> Option<Touch> {
        match self {
            SpecimenShape::Groove(g) => g
                .overlapping_foot(pos, radius)
                .map(|f| Touch::on_groove(f, radius)),
            _ => {
                (self.distance_within(pos, radius) - radius < 0.0).then(|| self.touch(pos, radius))
            }
        }
    }

    /// [`SpecimenShape::distance`] and [`SpecimenShape::normal`] at `pos`, the same
    /// numbers to the bit, from one radial offset on the bar.
    #[inline]
    pub fn distance_normal(&self, pos: &Vec3) -> (f64, Vec3) {
        match self {
            SpecimenShape::Plane => (pos.z, Vec3::z()),
            SpecimenShape::Cylinder { radius, axis } => {
                let (l, normal) = Self::radial_normal(&Self::radial(pos, *radius, axis));
                (l - radius, normal)
            }
            SpecimenShape::Groove(g) => {
                let foot = g.foot(pos);
                (foot.distance, foot.normal)
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
                Self::radial_normal(&Self::radial(pos, *radius, axis)).1
            }
            SpecimenShape::Groove(g) => g.foot(pos).normal,
        }
    }

    /// Component of `vel` along the outward normal at `pos` (negative: towards the
    /// surface). On the plane, `vel.z`.
    #[inline]
    pub fn normal_velocity(&self, pos: &Vec3, vel: &Vec3) -> f64 {
        match self {
            SpecimenShape::Plane => vel.z,
            _ => vel.dot(&self.normal(pos)),
        }
    }

    /// Hertz effective radius of a sphere of `radius` at `pos` on the surface. On the
    /// cylinder the contact is elliptic; its equivalent radius is `sqrt(R' R'')` with
    /// `R' = r` along the axis and `1/R'' = 1/r + 1/R_c` around it (Johnson, Contact
    /// Mechanics, Sec. 4.2; the ellipticity's correction to the load is below 1e-3 for
    /// `R_c >= r`). In a groove, that of the piece under the shot
    /// ([`Groove::effective_radius`]).
    #[inline]
    pub fn effective_radius(&self, pos: &Vec3, radius: f64) -> f64 {
        match self {
            SpecimenShape::Plane => radius,
            SpecimenShape::Cylinder { radius: rc, .. } => {
                Self::cylinder_effective_radius(radius, *rc)
            }
            SpecimenShape::Groove(g) => g.effective_radius(pos, radius),
        }
    }

    /// Curvature (1/m) of the surface across, at the foot of `pos`, positive where it
    /// is convex: 0 on the plane, `1/R_c` around the bar, in a groove `-1/R_f` in the
    /// fillets, `1/R_e` on the edges and 0 on the flat pieces. Along the bar's or the
    /// groove's axis the surface is straight. Dents are shaped by it
    /// ([`crate::coverage::dent::DentModel::footprint`]).
    pub fn curvature_across(&self, pos: &Vec3) -> f64 {
        match self {
            SpecimenShape::Plane => 0.0,
            SpecimenShape::Cylinder { radius, .. } => 1.0 / radius,
            SpecimenShape::Groove(g) => g.curvature_across(pos),
        }
    }

    /// The largest effective radius (the stiffest contact) a shot of `radius` meets
    /// anywhere on the surface.
    pub fn stiffest_radius(&self, radius: f64) -> f64 {
        match self {
            SpecimenShape::Groove(g) => g.fillet_effective_radius(radius),
            _ => self.effective_radius(&Vec3::zeros(), radius),
        }
    }

    /// Coordinates of the surface point `point` on the unrolled surface, m: on the plane
    /// `(x, y)`; on the cylinder the arc length from the crest line around the axis
    /// (positive towards `axis x +z`, i.e. towards +x for an axis along y) and the
    /// distance along the axis from the origin. Maps of dents and coverage are drawn in
    /// these.
    pub fn unrolled(&self, point: &Vec3) -> (f64, f64) {
        match self {
            SpecimenShape::Plane => (point.x, point.y),
            SpecimenShape::Cylinder { radius, axis } => {
                let across = axis.cross(&Vec3::z());
                let d = Self::radial(point, *radius, axis);
                (radius * d.dot(&across).atan2(d.z), point.dot(axis))
            }
            SpecimenShape::Groove(g) => g.unrolled(point),
        }
    }

    /// Where the jet axis (through `exit`, along the unit vector `axis`) first meets the
    /// surface, on the unrolled surface (m): the origin on the plate and on the bar's
    /// crest; in a groove moved off the jet (`offset_mm`), found by marching along the
    /// axis by the distance to the surface (a lower bound on the way to it). `None` if
    /// the axis misses the surface within 1,000 times the exit's distance.
    pub fn axis_foot(&self, exit: &Vec3, axis: &Vec3) -> Option<(f64, f64)> {
        let SpecimenShape::Groove(g) = self else {
            return Some((0.0, 0.0));
        };
        if g.size().offset == 0.0 {
            return Some((0.0, 0.0));
        }
        let (mut t, reach) = (0.0, 1e3 * exit.norm());
        for _ in 0..10_000 {
            let p = exit + axis * t;
            let d = g.distance(&p);
            if d <= 1e-12 {
                return Some(g.unrolled(&p));
            }
            t += d;
            if t > reach {
                return None;
            }
        }
        None
    }

    /// Names of the unrolled coordinates ([`SpecimenShape::unrolled`]), for axes.
    pub fn unrolled_names(&self) -> (&'static str, &'static str) {
        match self {
            SpecimenShape::Plane => ("x", "y"),
            SpecimenShape::Cylinder { .. } => ("around the bar", "along its axis"),
            SpecimenShape::Groove(g) if g.gear().is_some() => {
                ("across the teeth", "along the axis")
            }
            SpecimenShape::Groove(_) => ("across the groove", "along it"),
        }
    }

    /// The lowest height (m) a shot of radius up to `r_max` can reach while still able
    /// to touch the specimen; a shot below it has missed it for good (`-inf` on the
    /// plane, which nothing passes).
    pub fn floor(&self, r_max: f64) -> f64 {
        match self {
            SpecimenShape::Plane => f64::NEG_INFINITY,
            SpecimenShape::Cylinder { radius, .. } => -2.0 * radius - 2.0 * r_max,
            // A gear's lowest point; a groove's lands run on for ever: nothing passes it.
            SpecimenShape::Groove(g) => match g.gear() {
                Some(gear) => gear.bottom_z() - 2.0 * r_max,
                None => f64::NEG_INFINITY,
            },
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

    /// [`SpecimenContact::gap`] where the shot overlaps the surface by less than its
    /// diameter, to the bit; some value of at least 0 where it does not overlap, and at
    /// most `-2 radius` where it overlaps by more (cheaper on a gear:
    /// [`SpecimenShape::distance_within`]).
    #[inline]
    pub fn overlap_gap(&self, pos: &Vec3, radius: f64) -> f64 {
        self.shape.distance_within(pos, radius) - radius
    }

    /// A value whose minimum with `cap` is `cap.min(self.gap(pos, radius))` to the bit
    /// wherever the shot's centre is less than `cap + radius` inside the part: the gap
    /// where it is below `cap`, some value of at least `cap` otherwise; deeper, a value
    /// below `cap` still, so that a margin sees the shot in the part (cheaper on a gear:
    /// [`SpecimenShape::distance_within`]). For a margin that is a minimum.
    #[inline]
    pub fn gap_below(&self, pos: &Vec3, radius: f64, cap: f64) -> f64 {
        // Four roundings' room, so that a value of at least `reach` less `radius` is at
        // least `cap`.
        let reach = (cap + radius) * (1.0 + 4.0 * f64::EPSILON);
        if reach > 0.0 {
            self.shape.distance_within(pos, reach) - radius
        } else {
            self.gap(pos, radius)
        }
    }

    /// The surface under a shot of `radius` at `pos` ([`Touch`]).
    #[inline]
    pub fn touch(&self, pos: &Vec3, radius: f64) -> Touch {
        self.shape.touch(pos, radius)
    }

    /// [`SpecimenContact::touch`] where [`SpecimenContact::overlap_gap`] is below 0,
    /// `None` elsewhere: the same numbers, from one search for the foot on a gear.
    #[inline]
    pub fn overlap_touch(&self, pos: &Vec3, radius: f64) -> Option<Touch> {
        self.shape.overlap_touch(pos, radius)
    }

    /// [`SpecimenContact::normal_velocity`] under `touch`.
    #[inline]
    pub fn normal_velocity_at(&self, touch: &Touch, vel: &Vec3) -> f64 {
        match self.shape {
            SpecimenShape::Plane => vel.z,
            _ => vel.dot(&touch.normal),
        }
    }

    /// [`SpecimenContact::lever`] under `touch`.
    #[inline]
    pub fn lever_at(&self, touch: &Touch, lever: f64) -> Vec3 {
        match self.shape {
            SpecimenShape::Plane => Vec3::new(0.0, 0.0, -lever),
            _ => touch.normal * -lever,
        }
    }

    /// [`SpecimenContact::add_normal`] under `touch`.
    #[inline]
    pub fn add_normal_at(&self, touch: &Touch, a: &mut Vec3, s: f64) {
        match self.shape {
            SpecimenShape::Plane => a.z += s,
            _ => *a += touch.normal * s,
        }
    }

    /// Component of `vel` along the outward normal at `pos` (negative: approaching).
    #[inline]
    pub fn normal_velocity(&self, pos: &Vec3, vel: &Vec3) -> f64 {
        self.shape.normal_velocity(pos, vel)
    }

    /// Hertz effective radius of a shot of `radius` at `pos` on the surface.
    #[inline]
    pub fn effective_radius(&self, pos: &Vec3, radius: f64) -> f64 {
        self.shape.effective_radius(pos, radius)
    }

    /// The contact point's offset from the centre of a shot at `pos`, `lever` (m)
    /// towards the surface (on the plane exactly `(0, 0, -lever)`).
    #[inline]
    pub fn lever(&self, pos: &Vec3, lever: f64) -> Vec3 {
        match self.shape {
            SpecimenShape::Plane => Vec3::new(0.0, 0.0, -lever),
            _ => self.normal(pos) * -lever,
        }
    }

    /// Adds `s` along the outward normal at `pos` to `a` (on the plane, to `a.z` alone).
    #[inline]
    pub fn add_normal(&self, pos: &Vec3, a: &mut Vec3, s: f64) {
        match self.shape {
            SpecimenShape::Plane => a.z += s,
            _ => *a += self.normal(pos) * s,
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

#[cfg(test)]
mod tests {
    use super::*;

    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The module 4 rack of 20 degrees (ISO 53 proportions) as a rack of grooves, or
    /// wrapped into the 30-tooth gear it cuts.
    fn rack_or_gear(gear: bool) -> SpecimenShape {
        use crate::contact::groove::{GearTeeth, GrooveSize};
        let (m, a) = (4e-3, 20f64.to_radians());
        let (hf, rho, pitch) = (1.25 * m, 0.38 * m, std::f64::consts::PI * m);
        let hb = pitch / 4.0 - (hf - rho * (1.0 - a.sin())) * a.tan() - rho * a.cos();
        let size = GrooveSize {
            radius: rho,
            bottom: 2.0 * hb,
            flank: a,
            depth: 2.25 * m,
            edge_radius: 0.2 * m,
            pitch: Some(pitch),
            axis_angle: 90f64.to_radians(),
            offset: 1.3e-3,
            gear: gear.then_some(GearTeeth {
                teeth: 30,
                dedendum: hf,
            }),
        };
        SpecimenShape::Groove(Arc::new(Groove::new(size).unwrap()))
    }

    #[test]
    fn one_foot_gives_what_a_contact_reads_to_the_bit() {
        // `touch`, `overlap_gap` and `gap_below` stand for `gap`, `normal`,
        // `effective_radius` in the integrator's contacts and margins (and
        // `distance_normal` for `distance` and `normal` in the bar's layer): the same
        // numbers, whatever the shape.
        let law = HertzLaw::new(2.1e11, 0.3, 2.1e11, 0.3, 0.7);
        let r = 0.4e-3;
        for shape in [
            SpecimenShape::Plane,
            SpecimenShape::cylinder(5e-3, 30f64.to_radians()),
            rack_or_gear(false),
            rack_or_gear(true),
        ] {
            let sp = SpecimenContact {
                law,
                by_speed: None,
                shape: shape.clone(),
            };
            let (mut touching, mut clear, mut deep) = (0, 0, 0);
            let mut rng = ChaCha8Rng::seed_from_u64(1357);
            for _ in 0..10_000 {
                let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
                let p = Vec3::new(u(-12e-3, 12e-3), u(-5e-3, 5e-3), u(-1e-3, 10e-3));
                let v = Vec3::new(u(-5.0, 5.0), u(-5.0, 5.0), u(-20.0, 5.0));
                let gap = sp.gap(&p, r);
                let t = sp.touch(&p, r);
                assert_eq!(t.gap.to_bits(), gap.to_bits());
                assert_eq!(t.normal, sp.normal(&p));
                let (d, n) = shape.distance_normal(&p);
                assert_eq!(d.to_bits(), shape.distance(&p).to_bits());
                assert_eq!(n, shape.normal(&p));
                assert_eq!(
                    t.effective_radius.to_bits(),
                    sp.effective_radius(&p, r).to_bits()
                );
                assert_eq!(
                    sp.normal_velocity_at(&t, &v).to_bits(),
                    sp.normal_velocity(&p, &v).to_bits()
                );
                assert_eq!(sp.lever_at(&t, 0.7 * r), sp.lever(&p, 0.7 * r));
                let (mut a, mut b) = (v, v);
                sp.add_normal_at(&t, &mut a, 2.5);
                sp.add_normal(&p, &mut b, 2.5);
                assert_eq!(a, b);
                for cap in [
                    f64::INFINITY,
                    1e-3,
                    0.2e-3,
                    1e-5,
                    0.0,
                    -0.1e-3,
                    -r,
                    -2.0 * r,
                ] {
                    let below = sp.gap_below(&p, r, cap);
                    if cap + r <= 0.0 || gap + r > -(cap + r) {
                        assert_eq!(cap.min(below).to_bits(), cap.min(gap).to_bits());
                    } else {
                        // Deeper in the part than the margin's reach: still below it.
                        assert!(below < cap, "{shape:?} at {p:?}: {below} for {gap}, {cap}");
                    }
                }
                let o = sp.overlap_gap(&p, r);
                match sp.overlap_touch(&p, r) {
                    Some(ot) => {
                        assert!(o < 0.0, "{shape:?} at {p:?}: a touch for {o}");
                        assert_eq!(ot.gap.to_bits(), t.gap.to_bits());
                        assert_eq!(ot.normal, t.normal);
                        assert_eq!(ot.effective_radius.to_bits(), t.effective_radius.to_bits());
                    }
                    None => assert!(o >= 0.0, "{shape:?} at {p:?}: no touch for {o}"),
                }
                if gap <= -2.0 * r {
                    assert!(o <= -2.0 * r, "{shape:?} at {p:?}: {o} for {gap}");
                    deep += 1;
                } else if gap < 0.0 {
                    assert_eq!(o.to_bits(), gap.to_bits());
                    touching += 1;
                } else {
                    assert!(o >= 0.0, "{shape:?} at {p:?}: {o} for {gap}");
                    clear += 1;
                }
            }
            assert!(
                touching > 100 && clear > 2_000 && deep > 100,
                "{touching} / {clear} / {deep}"
            );
        }
    }

    #[test]
    fn a_cylinders_geometry_and_unrolled_surface() {
        // A 5 mm bar along y (axis 90 degrees); a point 40 degrees around it towards +x,
        // 2 mm out from the surface and 3 mm along the axis.
        let bar = SpecimenShape::cylinder(5e-3, 90f64.to_radians());
        let th = 40f64.to_radians();
        let p = Vec3::new(7e-3 * th.sin(), 3e-3, 7e-3 * th.cos() - 5e-3);
        assert!((bar.distance(&p) - 2e-3).abs() < 1e-15);
        let n = bar.normal(&p);
        assert!((n - Vec3::new(th.sin(), 0.0, th.cos())).norm() < 1e-15);
        let v = Vec3::new(1.0, 2.0, -3.0);
        assert!((bar.normal_velocity(&p, &v) - v.dot(&n)).abs() < 1e-15);
        let foot = p - n * 2e-3;
        let (u, w) = bar.unrolled(&foot);
        assert!((u - 5e-3 * th).abs() < 1e-15 && (w - 3e-3).abs() < 1e-15);
        // The other side is negative; along x the axis turns the frame with it.
        let q = Vec3::new(-foot.x, foot.y, foot.z);
        assert!((bar.unrolled(&q).0 + 5e-3 * th).abs() < 1e-15);
        let along_x = SpecimenShape::cylinder(5e-3, 0.0);
        let (u, w) = along_x.unrolled(&Vec3::new(3e-3, -foot.x, foot.z));
        assert!((u - 5e-3 * th).abs() < 1e-15 && (w - 3e-3).abs() < 1e-15);
        // The plane: as before.
        let plate = SpecimenShape::Plane;
        assert_eq!(plate.distance(&p), p.z);
        assert_eq!(plate.normal(&p), Vec3::z());
        assert_eq!(plate.unrolled(&p), (p.x, p.y));
        assert_eq!(plate.floor(1e-3), f64::NEG_INFINITY);
    }

    #[test]
    fn the_elliptic_contacts_radius_lies_between_the_shot_and_its_half() {
        let r = 4e-4;
        let o = Vec3::zeros();
        assert_eq!(SpecimenShape::Plane.effective_radius(&o, r), r);
        // A bar as thin as the shot: sqrt(r r/2); a wide one: the plate's r.
        let thin = SpecimenShape::cylinder(r, 0.0).effective_radius(&o, r);
        assert!((thin - r / 2f64.sqrt()).abs() < 1e-18);
        let wide = SpecimenShape::cylinder(1.0, 0.0).effective_radius(&o, r);
        assert!((wide / r - 1.0).abs() < 3e-4);
    }
}
