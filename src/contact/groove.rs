//! A groove in the specimen (beyond the paper): the tooth space of a rack or of a gear
//! cut straight, a keyway with rounded corners, a slot. Shot peening is asked for where
//! such parts crack: the root fillet, which the flanks shade and where the shots arrive
//! slower and more oblique than on an open face.
//!
//! The cross-section, across the groove's horizontal axis, is a C1 curve of straight
//! pieces and arcs, symmetric about the groove's middle:
//!
//! ```text
//!   land  ____          ____  land, z = depth (beyond the edges, or up to the
//!             \ edge   /          neighbouring groove with a pitch)
//!              \ flank/           flanks lean out by `flank` from the vertical
//!               \____/            fillets of `radius` (concave) join them to the
//!          fillet bottom fillet   flat bottom, `bottom` wide, at z = 0
//! ```
//!
//! The bottom's middle line runs through the origin (the jet axis' foot at
//! `z = 0`, as on the plate). With a `pitch` the grooves repeat across the axis, every
//! `pitch`, with lands between them: a rack.
//!
//! A point's distance from the surface is the distance from its nearest piece. Each
//! piece covers the points whose foot on its line or circle lies on the piece; on a C1
//! curve the nearest point of a point in the air is on a piece's interior or a joint,
//! which both neighbouring pieces cover, so the smallest distance among the covering
//! pieces is exact in the air and, for a point pressed into the surface by less than the
//! smallest radius, in the part.

use std::f64::consts::FRAC_PI_2;

use super::involute::{Gear, GearFoot};
use crate::Vec3;

/// Where on the cross-section a surface point lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Zone {
    /// The flat bottom.
    Bottom,
    /// A root fillet (concave).
    Fillet,
    /// A flank.
    Flank,
    /// A rounded edge between a flank and a land (convex).
    Edge,
    /// A land (the top face).
    Land,
}

impl Zone {
    /// All zones, from the bottom up.
    pub const ALL: [Zone; 5] = [
        Zone::Bottom,
        Zone::Fillet,
        Zone::Flank,
        Zone::Edge,
        Zone::Land,
    ];

    /// Name used in reports and files.
    pub fn name(self) -> &'static str {
        match self {
            Zone::Bottom => "bottom",
            Zone::Fillet => "fillet",
            Zone::Flank => "flank",
            Zone::Edge => "edge",
            Zone::Land => "land",
        }
    }
}

/// The groove's dimensions as a scene gives them (m, rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GrooveSize {
    /// Root fillet radius.
    pub radius: f64,
    /// Width of the flat bottom between the fillets (0: a round bottom).
    pub bottom: f64,
    /// Flanks' lean from the vertical, rad, in `[0, pi/2)`.
    pub flank: f64,
    /// Height of the lands above the bottom.
    pub depth: f64,
    /// Radius of the edges between flanks and lands.
    pub edge_radius: f64,
    /// Distance between neighbouring grooves' middles (`None`: one groove, lands to
    /// infinity).
    pub pitch: Option<f64>,
    /// Direction of the groove's axis, rad from +x in the horizontal plane.
    pub axis_angle: f64,
    /// Where the groove's middle lies across from the jet axis' foot (the origin),
    /// towards `axis x +z`, m (0: under the jet). On a gear, the arc along the pitch
    /// circle the gear is turned by.
    pub offset: f64,
    /// `Some`: the gear this rack cuts ([`super::involute`]), whose circular pitch is
    /// `pitch`; its root circle's top runs through the origin at `z = 0`.
    pub gear: Option<GearTeeth>,
}

/// A gear's teeth and where its pitch circle rolls on the rack.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GearTeeth {
    /// Number of teeth.
    pub teeth: u32,
    /// The dedendum: the rack's pitch line above its bottom (the gear's pitch circle
    /// above its root circle), m.
    pub dedendum: f64,
}

/// Why a groove's dimensions do not make one.
#[derive(Debug, Clone, PartialEq)]
pub enum GrooveError {
    /// The flanks would have a negative length: the depth is below what the fillet and
    /// the edge take (`needed`, m).
    TooShallow {
        /// The smallest depth, m.
        needed: f64,
    },
    /// The pitch is below the groove's width at the lands (`needed`, m).
    PitchTooSmall {
        /// The smallest pitch, m.
        needed: f64,
    },
    /// The rack would undercut the gear's flanks (`needed_teeth`: the fewest teeth it
    /// cuts without).
    Undercut {
        /// The fewest teeth without undercut.
        needed_teeth: u32,
    },
    /// The gear's profile does not close (`why`).
    GearTooSmall {
        /// What fails, in words.
        why: String,
    },
}

/// A groove (see the module's documentation); built by [`Groove::new`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Groove {
    size: GrooveSize,
    /// Axis direction (horizontal unit vector) and the across direction `axis x +z`.
    axis: Vec3,
    across: Vec3,
    /// `sin`, `cos` of the flank's lean.
    sa: f64,
    ca: f64,
    /// Half the bottom's width.
    hb: f64,
    /// Where the flank starts (end of the fillet), `(s, z)` on the half `s >= 0`.
    f0: (f64, f64),
    /// Flank length.
    lw: f64,
    /// Edge centre.
    ce: (f64, f64),
    /// Angle each arc sweeps: `pi/2 - flank`.
    sweep: f64,
    /// Arc length from the middle to where the fillet, the flank, the edge and the land
    /// start; arc length of half a period (infinite without a pitch).
    u_fillet: f64,
    u_flank: f64,
    u_edge: f64,
    u_land: f64,
    u_half: f64,
    /// The gear the rack cuts, if one ([`GrooveSize::gear`]): it then is the surface.
    gear: Option<Gear>,
}

/// A point's foot on the surface, on the half cross-section `s >= 0`.
#[derive(Debug, Clone, Copy)]
struct HalfFoot {
    distance: f64,
    /// Outward normal `(s, z)`.
    normal: (f64, f64),
    zone: Zone,
}

/// A point's nearest surface point (see [`Groove::foot`]).
#[derive(Debug, Clone, Copy)]
pub struct Foot {
    /// Distance from the surface, m (negative inside the part).
    pub distance: f64,
    /// Outward unit normal there.
    pub normal: Vec3,
    /// The zone it lies in.
    pub zone: Zone,
}

impl Groove {
    /// A groove of `size`; refuses dimensions that do not close the profile.
    pub fn new(size: GrooveSize) -> Result<Groove, GrooveError> {
        let (sa, ca) = size.flank.sin_cos();
        let (r, rho) = (size.radius, size.edge_radius);
        // Fillet centre (hb, r); the flank starts at its point in direction (ca, -sa),
        // climbs along (sa, ca) and meets the edge, whose centre lies rho along (ca, -sa)
        // from the flank's end, at height depth - rho.
        let hb = 0.5 * size.bottom;
        let f0 = (hb + r * ca, r * (1.0 - sa));
        let needed = (r + rho) * (1.0 - sa);
        let lw = (size.depth - needed) / ca;
        // (A gear's rack only cuts with its tooth tips and flanks: its own lands and
        // edges need not fit.)
        if lw < 0.0 && size.gear.is_none() {
            return Err(GrooveError::TooShallow { needed });
        }
        let f1 = (f0.0 + lw * sa, f0.1 + lw * ca);
        let ce = (f1.0 + rho * ca, f1.1 - rho * sa);
        let sweep = FRAC_PI_2 - size.flank;
        let u_fillet = hb;
        let u_flank = u_fillet + r * sweep;
        let u_edge = u_flank + lw;
        let u_land = u_edge + rho * sweep;
        let u_half = match size.pitch {
            None => f64::INFINITY,
            Some(p) => {
                if 0.5 * p < ce.0 && size.gear.is_none() {
                    return Err(GrooveError::PitchTooSmall { needed: 2.0 * ce.0 });
                }
                u_land + 0.5 * p - ce.0
            }
        };
        let axis = Vec3::new(size.axis_angle.cos(), size.axis_angle.sin(), 0.0);
        let gear = match size.gear {
            None => None,
            Some(t) => Some(Gear::new(
                t.teeth,
                size.pitch.unwrap_or(f64::NAN),
                size.flank,
                t.dedendum,
                hb,
                r,
                size.depth,
                rho,
                size.offset,
            )?),
        };
        let [u_fillet, u_flank, u_edge, u_land, u_half] = match &gear {
            Some(g) => g.arcs(),
            None => [u_fillet, u_flank, u_edge, u_land, u_half],
        };
        Ok(Groove {
            size,
            axis,
            across: axis.cross(&Vec3::z()),
            sa,
            ca,
            hb,
            f0,
            lw,
            ce,
            sweep,
            u_fillet,
            u_flank,
            u_edge,
            u_land,
            u_half,
            gear,
        })
    }

    /// The gear the rack cuts, if the surface is one.
    pub fn gear(&self) -> Option<&Gear> {
        self.gear.as_ref()
    }

    /// The dimensions it was built from.
    pub fn size(&self) -> &GrooveSize {
        &self.size
    }

    /// Axis direction (a horizontal unit vector).
    pub fn axis(&self) -> Vec3 {
        self.axis
    }

    /// The across direction, `axis x +z` (the cross-section's `s`).
    pub fn across(&self) -> Vec3 {
        self.across
    }

    /// Width of the groove at the lands, where the edges end, m.
    pub fn top_width(&self) -> f64 {
        2.0 * self.ce.0
    }

    /// The cross-section's `s` of `pos`: across, from the groove's middle.
    #[inline]
    fn s_of(&self, pos: &Vec3) -> f64 {
        pos.dot(&self.across) - self.size.offset
    }

    /// `s` folded into the period around the nearest groove's middle: `(period index,
    /// s from that middle)`.
    #[inline]
    fn fold(&self, s: f64) -> (f64, f64) {
        match self.size.pitch {
            None => (0.0, s),
            Some(p) => {
                let k = (s / p).round();
                (k, s - k * p)
            }
        }
    }

    /// The nearest piece's foot of `(a, z)`, `a >= 0` (see the module's documentation).
    #[inline]
    fn half_foot(&self, a: f64, z: f64) -> HalfFoot {
        let mut best = HalfFoot {
            distance: f64::INFINITY,
            normal: (0.0, 1.0),
            zone: Zone::Land,
        };
        let offer = |best: &mut HalfFoot, distance: f64, normal: (f64, f64), zone: Zone| {
            if distance.abs() < best.distance.abs() {
                *best = HalfFoot {
                    distance,
                    normal,
                    zone,
                };
            }
        };
        let (r, rho) = (self.size.radius, self.size.edge_radius);
        if a < self.hb {
            offer(&mut best, z, (0.0, 1.0), Zone::Bottom);
        }
        // Fillet: directions from its centre between straight down and (ca, -sa).
        let (dx, dz) = (a - self.hb, z - r);
        if dx >= 0.0 && self.ca * dz + self.sa * dx <= 0.0 {
            let l = dx.hypot(dz);
            if l > 0.0 {
                offer(&mut best, r - l, (-dx / l, -dz / l), Zone::Fillet);
            }
        }
        // Flank: the foot on its line between its ends.
        let (px, pz) = (a - self.f0.0, z - self.f0.1);
        let t = px * self.sa + pz * self.ca;
        if (0.0..=self.lw).contains(&t) {
            offer(
                &mut best,
                pz * self.sa - px * self.ca,
                (-self.ca, self.sa),
                Zone::Flank,
            );
        }
        if a >= self.ce.0 {
            offer(&mut best, z - self.size.depth, (0.0, 1.0), Zone::Land);
        }
        // Edge: directions from its centre between the flank's normal and straight up;
        // also the fallback for points deep under it, which no piece covers.
        let (ex, ez) = (a - self.ce.0, z - self.ce.1);
        let covered = best.distance.is_finite();
        if (ex <= 0.0 && ex * self.sa + ez * self.ca >= 0.0) || !covered {
            let l = ex.hypot(ez);
            if l > 0.0 {
                offer(&mut best, l - rho, (ex / l, ez / l), Zone::Edge);
            } else if !covered {
                best.distance = -rho;
                best.zone = Zone::Edge;
            }
        }
        best
    }

    /// The nearest surface point's distance, outward normal and zone for `pos`.
    #[inline]
    pub fn foot(&self, pos: &Vec3) -> Foot {
        if let Some(g) = &self.gear {
            return self.gear_foot(g, pos).0;
        }
        let (_, s) = self.fold(self.s_of(pos));
        let h = self.half_foot(s.abs(), pos.z);
        let sign = if s < 0.0 { -1.0 } else { 1.0 };
        Foot {
            distance: h.distance,
            normal: self.across * (sign * h.normal.0) + Vec3::z() * h.normal.1,
            zone: h.zone,
        }
    }

    /// [`Groove::distance`] where it is below `reach` in size, to the bit; otherwise a
    /// value at least `reach` in the air, at most `-reach` in the part. On a
    /// gear the fillet's feet out of reach are not solved for; a rack's foot is cheap
    /// and exact.
    #[inline]
    pub fn distance_within(&self, pos: &Vec3, reach: f64) -> f64 {
        if let Some(g) = &self.gear {
            return g.distance_within(pos.dot(&self.across), pos.z, reach);
        }
        self.distance(pos)
    }

    /// Where a shot of `radius` at `pos` overlaps the surface ([`Groove::distance_within`]
    /// of `radius`, less `radius`, below 0): its foot and effective radius
    /// ([`Groove::foot_and_radius`], to the bit); `None` where it does not. On a gear one
    /// search for the foot serves both where the overlap is below the shot's diameter.
    #[inline]
    pub fn overlapping_foot(&self, pos: &Vec3, radius: f64) -> Option<(Foot, f64)> {
        let r = radius;
        let Some(g) = &self.gear else {
            return (self.distance_within(pos, r) - r < 0.0).then(|| self.foot_and_radius(pos, r));
        };
        match g.foot_within(pos.dot(&self.across), pos.z, r) {
            Ok(f) => (f.0 - r < 0.0).then(|| {
                let (foot, k) = self.gear_foot_of(f);
                (foot, curved_effective_radius(r, k))
            }),
            Err(d) => (d - r < 0.0).then(|| self.foot_and_radius(pos, r)),
        }
    }

    /// The foot of `pos` ([`Groove::foot`]) and the effective radius of a shot of
    /// `radius` there ([`Groove::effective_radius`]), from one search for the foot.
    #[inline]
    pub fn foot_and_radius(&self, pos: &Vec3, radius: f64) -> (Foot, f64) {
        let r = radius;
        if let Some(g) = &self.gear {
            let (foot, k) = self.gear_foot(g, pos);
            return (foot, curved_effective_radius(r, k));
        }
        let foot = self.foot(pos);
        let re = self.zone_effective_radius(foot.zone, r);
        (foot, re)
    }

    /// A gear's foot of `pos`, unfolded from the gear's plane to the groove's frame,
    /// and the curvature of the piece under it.
    #[inline]
    fn gear_foot(&self, g: &Gear, pos: &Vec3) -> (Foot, f64) {
        self.gear_foot_of(g.foot(pos.dot(&self.across), pos.z))
    }

    /// A gear's cross-section foot in space, and its curvature.
    #[inline]
    fn gear_foot_of(&self, (distance, n, zone, k): GearFoot) -> (Foot, f64) {
        let foot = Foot {
            distance,
            normal: self.across * n.0 + Vec3::z() * n.1,
            zone,
        };
        (foot, k)
    }

    /// A rack's effective radius on a piece of `zone` ([`Groove::effective_radius`]).
    #[inline]
    fn zone_effective_radius(&self, zone: Zone, r: f64) -> f64 {
        match zone {
            Zone::Bottom | Zone::Flank | Zone::Land => r,
            Zone::Fillet => self.fillet_effective_radius(r),
            Zone::Edge => {
                let re = self.size.edge_radius;
                (r * (r * re / (r + re))).sqrt()
            }
        }
    }

    /// Distance (m) of `pos` from the surface, positive in the air.
    #[inline]
    pub fn distance(&self, pos: &Vec3) -> f64 {
        if let Some(g) = &self.gear {
            return g.foot(pos.dot(&self.across), pos.z).0;
        }
        let (_, s) = self.fold(self.s_of(pos));
        self.half_foot(s.abs(), pos.z).distance
    }

    /// Hertz effective radius of a sphere of `radius` touching the surface at the foot
    /// of `pos`: the plane's on the flat pieces; on the edge the convex cylinder's
    /// `sqrt(r r R_e / (r + R_e))`; in the fillet the concave cylinder's, `sqrt(r R'')`
    /// with `R'' = r R_f / (R_f - r)` (conforming around it, as the nozzle bore's,
    /// [`crate::contact::wall::WallContact::effective_radius`]).
    #[inline]
    pub fn effective_radius(&self, pos: &Vec3, radius: f64) -> f64 {
        let r = radius;
        if self.gear.is_some() {
            // Every piece of a gear is curved (convex but for the fillets).
            return curved_effective_radius(r, self.curvature_across(pos));
        }
        self.zone_effective_radius(self.foot(pos).zone, r)
    }

    /// Signed curvature (1/m, convex positive) of the piece under `pos` across the
    /// groove ([`crate::contact::specimen::SpecimenShape::curvature_across`]).
    pub fn curvature_across(&self, pos: &Vec3) -> f64 {
        if let Some(g) = &self.gear {
            return g.foot(pos.dot(&self.across), pos.z).3;
        }
        match self.foot(pos).zone {
            Zone::Bottom | Zone::Flank | Zone::Land => 0.0,
            Zone::Fillet => -1.0 / self.size.radius,
            Zone::Edge => 1.0 / self.size.edge_radius,
        }
    }

    /// The fillets' effective radius for a shot of `radius`, the largest anywhere on
    /// the groove (the stiffest contact).
    #[inline]
    pub fn fillet_effective_radius(&self, radius: f64) -> f64 {
        let (r, rf) = (radius, self.size.radius);
        (r * (r * rf / (rf - r))).sqrt()
    }

    /// Arc length along the half cross-section of the foot of `(a, z)`.
    fn half_arc(&self, a: f64, z: f64) -> f64 {
        let h = self.half_foot(a, z);
        match h.zone {
            Zone::Bottom => a,
            Zone::Fillet => {
                let (dx, dz) = (a - self.hb, z - self.size.radius);
                self.u_fillet + self.size.radius * dx.atan2(-dz).clamp(0.0, self.sweep)
            }
            Zone::Flank => {
                let t = (a - self.f0.0) * self.sa + (z - self.f0.1) * self.ca;
                self.u_flank + t.clamp(0.0, self.lw)
            }
            Zone::Edge => {
                // Angle from the flank's normal towards straight up.
                let (ex, ez) = (a - self.ce.0, z - self.ce.1);
                let from_up = (-ex).atan2(ez).clamp(0.0, self.sweep);
                self.u_edge + self.size.edge_radius * (self.sweep - from_up)
            }
            Zone::Land => self.u_land + (a - self.ce.0),
        }
    }

    /// The unrolled surface's coordinates of the foot of `pos`: the arc length across
    /// the grooves from the middle of the groove at the origin (positive towards
    /// `across`, over every groove and land on the way with a pitch) and the distance
    /// along the axis.
    pub fn unrolled(&self, pos: &Vec3) -> (f64, f64) {
        if let Some(g) = &self.gear {
            return (
                g.unrolled(pos.dot(&self.across), pos.z),
                pos.dot(&self.axis),
            );
        }
        let (k, s) = self.fold(self.s_of(pos));
        let u = self.half_arc(s.abs(), pos.z);
        let u = if s < 0.0 { -u } else { u };
        let period = if k == 0.0 { 0.0 } else { 2.0 * k * self.u_half };
        (period + u, pos.dot(&self.axis))
    }

    /// The zone of the surface at arc length `u` (as [`Groove::unrolled`] gives it).
    pub fn zone_at(&self, u: f64) -> Zone {
        let a = self.fold_arc(u).1.abs();
        if a < self.u_fillet {
            Zone::Bottom
        } else if a <= self.u_flank {
            Zone::Fillet
        } else if a <= self.u_edge {
            Zone::Flank
        } else if a <= self.u_land {
            Zone::Edge
        } else {
            Zone::Land
        }
    }

    /// `u` folded into its period: `(period index, arc from that groove's middle)`.
    fn fold_arc(&self, u: f64) -> (f64, f64) {
        if self.u_half.is_finite() {
            let k = (u / (2.0 * self.u_half)).round();
            (k, u - 2.0 * k * self.u_half)
        } else {
            (0.0, u)
        }
    }

    /// The surface point and outward normal at arc length `a >= 0` on the half
    /// cross-section: `((s, z), (n_s, n_z), zone)`.
    fn half_at(&self, a: f64) -> ((f64, f64), (f64, f64), Zone) {
        let (r, rho) = (self.size.radius, self.size.edge_radius);
        if a < self.u_fillet {
            ((a, 0.0), (0.0, 1.0), Zone::Bottom)
        } else if a <= self.u_flank {
            let phi = (a - self.u_fillet) / r;
            let (sp, cp) = phi.sin_cos();
            ((self.hb + r * sp, r - r * cp), (-sp, cp), Zone::Fillet)
        } else if a <= self.u_edge {
            let t = a - self.u_flank;
            (
                (self.f0.0 + t * self.sa, self.f0.1 + t * self.ca),
                (-self.ca, self.sa),
                Zone::Flank,
            )
        } else if a <= self.u_land {
            let from_up = self.sweep - (a - self.u_edge) / rho;
            let (sp, cp) = from_up.sin_cos();
            (
                (self.ce.0 - rho * sp, self.ce.1 + rho * cp),
                (-sp, cp),
                Zone::Edge,
            )
        } else {
            (
                (self.ce.0 + a - self.u_land, self.size.depth),
                (0.0, 1.0),
                Zone::Land,
            )
        }
    }

    /// The surface point at unrolled coordinates `(u, w)` ([`Groove::unrolled`]) and
    /// its outward normal.
    pub fn point_at(&self, u: f64, w: f64) -> (Vec3, Vec3) {
        let (k, ul) = self.fold_arc(u);
        if let Some(g) = &self.gear {
            let ((s, z), (ns, nz), _) = g.point_at(k, ul);
            return (
                self.across * s + self.axis * w + Vec3::z() * z,
                self.across * ns + Vec3::z() * nz,
            );
        }
        let ((s, z), (ns, nz), _) = self.half_at(ul.abs());
        let sign = if ul < 0.0 { -1.0 } else { 1.0 };
        let s = sign * s + k * self.size.pitch.unwrap_or(0.0) + self.size.offset;
        (
            self.across * s + self.axis * w + Vec3::z() * z,
            self.across * (sign * ns) + Vec3::z() * nz,
        )
    }

    /// A lower bound on the time (s) before a shot of `radius` at `pos`, flying straight
    /// at `vel`, can touch the surface (0 when it already does; infinite when it moves
    /// away from every face). Each piece's own distance bounds it: the flat pieces'
    /// and the edges' discs' distances are convex along a line, so they close no
    /// faster than their rate now; the fillets' (concave) close at most at the speed
    /// across the axis. With a pitch the neighbouring grooves count too.
    pub fn time_to_touch(&self, pos: &Vec3, vel: &Vec3, radius: f64) -> f64 {
        if let Some(g) = &self.gear {
            return g.time_to_touch(
                pos.dot(&self.across),
                pos.z,
                vel.dot(&self.across),
                vel.z,
                radius,
            );
        }
        let (_, s) = self.fold(self.s_of(pos));
        let (z, vs, vz) = (pos.z, vel.dot(&self.across), vel.z);
        let speed = vs.hypot(vz);
        let (rf, rho, depth) = (self.size.radius, self.size.edge_radius, self.size.depth);
        // Time for a distance `d` closing at `rate` (per second, positive: closing).
        let when = |d: f64, rate: f64| {
            if d <= radius {
                0.0
            } else if rate > 0.0 {
                (d - radius) / rate
            } else {
                f64::INFINITY
            }
        };
        // A segment from `a` to `b` (a half-line when `b` is infinitely far along x).
        let segment = |x: f64, vx: f64, a: (f64, f64), b: (f64, f64)| {
            let (dx, dz) = (b.0 - a.0, b.1 - a.1);
            let (px, pz) = (x - a.0, z - a.1);
            let u = if dx.is_infinite() {
                // Along +x from `a`.
                px.max(0.0)
            } else {
                let l2 = dx * dx + dz * dz;
                ((px * dx + pz * dz) / l2).clamp(0.0, 1.0) * l2.sqrt()
            };
            let (tx, tz) = if dx.is_infinite() {
                (1.0, 0.0)
            } else {
                let l = dx.hypot(dz);
                (dx / l, dz / l)
            };
            let (qx, qz) = (px - u * tx, pz - u * tz);
            let d = qx.hypot(qz);
            when(
                d,
                if d > 0.0 {
                    -(vx * qx + vz * qz) / d
                } else {
                    speed
                },
            )
        };
        let periods: &[f64] = match self.size.pitch {
            Some(_) => &[-1.0, 0.0, 1.0],
            None => &[0.0],
        };
        let pitch = self.size.pitch.unwrap_or(0.0);
        let land_end = match self.size.pitch {
            Some(p) => p - self.ce.0,
            None => f64::INFINITY,
        };
        let mut t = f64::INFINITY;
        for &k in periods {
            let a = s - k * pitch;
            if self.hb > 0.0 {
                t = t.min(segment(a, vs, (-self.hb, 0.0), (self.hb, 0.0)));
            }
            for side in [1.0, -1.0] {
                let (x, vx) = (side * a, side * vs);
                // Fillet: the distance to its arc, closing at most at `speed`.
                let (dx, dz) = (x - self.hb, z - rf);
                let d = if dx >= 0.0 && self.ca * dz + self.sa * dx <= 0.0 {
                    (rf - dx.hypot(dz)).abs()
                } else {
                    let e0 = (x - self.hb).hypot(z);
                    let e1 = (x - self.f0.0).hypot(z - self.f0.1);
                    e0.min(e1)
                };
                t = t.min(when(d, speed));
                // Flank.
                let f1 = (self.f0.0 + self.lw * self.sa, self.f0.1 + self.lw * self.ca);
                t = t.min(segment(x, vx, self.f0, f1));
                // Edge: the disc under it.
                let (ex, ez) = (x - self.ce.0, z - self.ce.1);
                let l = ex.hypot(ez);
                t = t.min(when(
                    l - rho,
                    if l > 0.0 {
                        -(vx * ex + vz * ez) / l
                    } else {
                        speed
                    },
                ));
                // Land, to the next groove's edge (or for ever).
                let end = if land_end.is_finite() {
                    (land_end, depth)
                } else {
                    (f64::INFINITY, depth)
                };
                t = t.min(segment(x, vx, (self.ce.0, depth), end));
            }
        }
        t
    }

    /// The zone of the surface point nearest `pos`.
    pub fn zone(&self, pos: &Vec3) -> Zone {
        self.foot(pos).zone
    }

    /// Smallest convex radius of the surface (the edges'), m: a block laid under the
    /// surface must stay shallower.
    pub fn edge_radius(&self) -> f64 {
        match &self.gear {
            Some(g) => g.smallest_convex_radius(),
            None => self.size.edge_radius,
        }
    }

    /// The zones met between arc lengths `u_lo` and `u_hi` (as [`Groove::unrolled`] gives
    /// them), in order: `(from, to, zone)`, clipped to the range.
    pub fn zone_spans(&self, u_lo: f64, u_hi: f64) -> Vec<(f64, f64, Zone)> {
        // One period's boundaries from the middle of its groove, both halves.
        let mut half: Vec<(f64, Zone)> = Zone::ALL
            .iter()
            .zip(self.zone_starts())
            .map(|(&z, u)| (u, z))
            .collect();
        half.push((self.u_half, Zone::Land));
        let mut edges: Vec<(f64, f64, Zone)> = Vec::new();
        let period = 2.0 * self.u_half;
        let (k0, k1) = if period.is_finite() {
            (
                (u_lo / period).round() as i64 - 1,
                (u_hi / period).round() as i64 + 1,
            )
        } else {
            (0, 0)
        };
        for k in k0..=k1 {
            let shift = if k == 0 { 0.0 } else { k as f64 * period };
            for w in half.windows(2) {
                let ((a, z), (b, _)) = (w[0], w[1]);
                if b > a {
                    edges.push((shift + a, shift + b, z));
                    edges.push((shift - b, shift - a, z));
                }
            }
        }
        edges.sort_by(|x, y| x.0.total_cmp(&y.0));
        // Join neighbours of one zone (the two halves of a bottom, lands across periods).
        let mut out: Vec<(f64, f64, Zone)> = Vec::new();
        for (a, b, z) in edges {
            let (a, b) = (a.max(u_lo), b.min(u_hi));
            if b <= a {
                continue;
            }
            match out.last_mut() {
                Some(last) if last.2 == z && (a - last.1).abs() <= 1e-12 => last.1 = b,
                _ => out.push((a, b, z)),
            }
        }
        out
    }

    /// The arc length of one period of the profile across a rack (a groove and a land,
    /// middle to middle: what [`Groove::unrolled`] adds per pitch); `None` for one groove.
    pub fn period_arc(&self) -> Option<f64> {
        self.u_half.is_finite().then_some(2.0 * self.u_half)
    }

    /// Arc length from the middle to where each zone starts on the half cross-section
    /// (bottom, fillet, flank, edge, land), m.
    pub fn zone_starts(&self) -> [f64; 5] {
        [0.0, self.u_fillet, self.u_flank, self.u_edge, self.u_land]
    }
}

/// The Hertz effective radius of a shot of radius `r` on a piece curved by `k` across
/// (1/m, convex positive) and straight along: the cylinder's `sqrt(r R'')` with
/// `1/R'' = 1/r + k`.
#[inline]
fn curved_effective_radius(r: f64, k: f64) -> f64 {
    (r * (r / (1.0 + r * k))).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    fn rack() -> Groove {
        // ISO 53 basic rack of module 3: 20 degree flanks, root fillet 0.38 m, 2.25 m
        // deep; a 1.2 mm bottom, 0.5 mm edges, pitch pi m.
        Groove::new(GrooveSize {
            radius: 1.14e-3,
            bottom: 1.2e-3,
            flank: 20f64.to_radians(),
            depth: 6.75e-3,
            edge_radius: 0.5e-3,
            pitch: Some(std::f64::consts::PI * 3e-3),
            axis_angle: 90f64.to_radians(),
            offset: 0.0,
            gear: None,
        })
        .unwrap()
    }

    /// The profile as a dense polyline of one period and its neighbours, from the
    /// surface points of `half_at` (checked separately to be the pieces' geometry).
    fn polyline(g: &Groove, n: usize) -> Vec<(f64, f64)> {
        let span = if g.u_half.is_finite() {
            3.0 * g.u_half
        } else {
            g.u_land + 5e-3
        };
        (0..=n)
            .map(|i| {
                let u = -span + 2.0 * span * i as f64 / n as f64;
                let (p, _) = g.point_at(u, 0.0);
                (p.dot(&g.across), p.z)
            })
            .collect()
    }

    fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
        let (dx, dz) = (b.0 - a.0, b.1 - a.1);
        let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dz) / (dx * dx + dz * dz)).clamp(0.0, 1.0);
        (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dz)
    }

    #[test]
    fn the_profile_is_closed_and_smooth() {
        let g = rack();
        // Joints: the surface point and the normal agree from both sides.
        for u in g.zone_starts().into_iter().skip(1) {
            let (p0, n0) = g.point_at(u - 1e-12, 0.0);
            let (p1, n1) = g.point_at(u + 1e-12, 0.0);
            assert!((p0 - p1).norm() < 1e-11, "gap at u = {u}");
            assert!((n0 - n1).norm() < 1e-8, "kink at u = {u}");
        }
        // The land is at the depth and the half period ends at pitch / 2.
        let (p, _) = g.point_at(g.u_half, 0.0);
        assert!((p.z - 6.75e-3).abs() < 1e-15);
        assert!((p.x - 0.5 * std::f64::consts::PI * 3e-3).abs() < 1e-15);
        // The next period continues it.
        let (q, _) = g.point_at(g.u_half + 1e-9, 0.0);
        assert!((q - p).norm() < 2e-9);
        // The normal is the curve's derivative turned: (dz/du, -ds/du) x -1.
        for i in 0..400 {
            let u = -2.0 * g.u_half + 4.0 * g.u_half * i as f64 / 400.0;
            let (a, _) = g.point_at(u - 1e-8, 0.0);
            let (b, _) = g.point_at(u + 1e-8, 0.0);
            let (_, n) = g.point_at(u, 0.0);
            let t = (b - a) / 2e-8;
            assert!((t.norm() - 1.0).abs() < 1e-6, "arc length at u = {u}");
            assert!(t.dot(&n).abs() < 1e-6, "normal at u = {u}");
            // Outward: the air is on the left of the direction of increasing u in (s, z).
            assert!(t.x * n.z - t.z * n.x > 0.0, "normal side at u = {u}");
        }
    }

    #[test]
    fn distances_match_a_dense_polyline() {
        for g in [
            rack(),
            // One round-bottomed slot with vertical walls, axis along x.
            Groove::new(GrooveSize {
                radius: 1e-3,
                bottom: 0.0,
                flank: 0.0,
                depth: 4e-3,
                edge_radius: 0.3e-3,
                pitch: None,
                axis_angle: 0.0,
                offset: 0.0,
                gear: None,
            })
            .unwrap(),
            // The rack moved 2.3 mm across, off the jet axis' foot.
            Groove::new(GrooveSize {
                offset: 2.3e-3,
                ..*rack().size()
            })
            .unwrap(),
        ] {
            let line = polyline(&g, 100_000);
            let mut rng = ChaCha8Rng::seed_from_u64(12345);
            let mut next = || rng.random::<f64>();
            let top = g.size().depth;
            for _ in 0..200 {
                let s = (next() - 0.5) * 12e-3;
                let z = -0.3e-3 + next() * (top + 2e-3);
                let pos = g.across * s + g.axis * 1e-3 + Vec3::z() * z;
                let d = g.distance(&pos);
                let brute = line
                    .windows(2)
                    .map(|w| segment_distance((s, z), w[0], w[1]))
                    .fold(f64::INFINITY, f64::min);
                // In the air the distance is exact; inside, only near the surface.
                if d >= 0.0 {
                    assert!((d - brute).abs() < 1e-8, "s {s} z {z}: {d} vs {brute}");
                } else if brute < 0.2e-3 {
                    assert!((d + brute).abs() < 1e-8, "s {s} z {z}: {d} vs -{brute}");
                }
                // The foot: `pos - n d` is on the surface, and unrolls to its arc.
                let f = g.foot(&pos);
                if d.abs() < 1e-3 {
                    let foot = pos - f.normal * d;
                    let (u, w) = g.unrolled(&foot);
                    let (back, n) = g.point_at(u, w);
                    assert!((back - foot).norm() < 1e-10, "foot at s {s} z {z}");
                    assert!((n - f.normal).norm() < 1e-9);
                    assert_eq!(g.zone_at(u), f.zone);
                }
            }
        }
    }

    #[test]
    fn the_time_to_touch_is_a_lower_bound() {
        // Straight paths from random points in the air at random velocities: the
        // surface's gap along them, sampled finely, stays positive before the bound.
        let g = rack();
        let r = 0.3e-3;
        let mut rng = ChaCha8Rng::seed_from_u64(987654321);
        let mut next = || rng.random::<f64>();
        let mut bounded = 0;
        for _ in 0..3000 {
            let p = g.across * ((next() - 0.5) * 30e-3) + Vec3::z() * (next() * 9e-3);
            if g.distance(&p) <= r {
                continue;
            }
            let v = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * 100.0;
            let t = g.time_to_touch(&p, &v, r);
            let span = if t.is_finite() { t } else { 2e-4 };
            for k in 0..=400 {
                let q = p + v * (span * k as f64 / 400.0);
                assert!(
                    g.distance(&q) >= r * (1.0 - 1e-9),
                    "touches at {} of the bound {t:e} from {p:?} at {v:?}",
                    k as f64 / 400.0
                );
            }
            bounded += t.is_finite() as usize;
        }
        assert!(bounded > 500, "{bounded}");
    }

    #[test]
    fn zone_spans_tile_the_unrolled_surface() {
        let g = rack();
        let (lo, hi) = (-1.3 * g.u_half, 2.6 * g.u_half);
        let spans = g.zone_spans(lo, hi);
        assert_eq!(spans[0].0, lo);
        assert_eq!(spans[spans.len() - 1].1, hi);
        for w in spans.windows(2) {
            assert!((w[0].1 - w[1].0).abs() < 1e-15, "{w:?}");
            assert_ne!(w[0].2, w[1].2, "{w:?}");
        }
        for (a, b, z) in &spans {
            assert_eq!(g.zone_at(0.5 * (a + b)), *z, "{a} {b}");
        }
        // Across the groove at the origin: land, edge, flank, fillet, bottom and back.
        let names: Vec<&str> = g
            .zone_spans(-g.u_land - 1e-4, g.u_land + 1e-4)
            .iter()
            .map(|s| s.2.name())
            .collect();
        assert_eq!(
            names,
            [
                "land", "edge", "flank", "fillet", "bottom", "fillet", "flank", "edge", "land"
            ]
        );
    }

    #[test]
    fn dimensions_that_do_not_close_are_refused() {
        let mut size = *rack().size();
        size.depth = 0.5e-3;
        assert!(matches!(
            Groove::new(size),
            Err(GrooveError::TooShallow { .. })
        ));
        let mut size = *rack().size();
        size.pitch = Some(3e-3);
        assert!(matches!(
            Groove::new(size),
            Err(GrooveError::PitchTooSmall { .. })
        ));
        // The effective radii: the fillet's conforms (larger), the edge's is smaller.
        let g = rack();
        let r = 0.3e-3;
        let at = |u: f64| {
            let (p, n) = g.point_at(u, 0.0);
            g.effective_radius(&(p + n * r), r)
        };
        let fillet = at(0.5 * (g.u_fillet + g.u_flank));
        let rf = 1.14e-3;
        assert!((fillet - (r * r * rf / (rf - r)).sqrt()).abs() < 1e-15);
        assert!(fillet > r);
        assert!(at(0.5 * (g.u_edge + g.u_land)) < r);
        assert_eq!(at(0.5 * (g.u_flank + g.u_edge)), r);
    }
}
