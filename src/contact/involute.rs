//! A spur gear's tooth spaces (beyond the paper): the gear that a groove's rack
//! ([`super::groove`]) cuts when it rolls on the gear's pitch circle, as a hob or a
//! rack cutter does. The rack's grooves are the cutter's teeth; the gear is what they
//! leave:
//!
//! * the **root** (zone "bottom"): an arc of the root circle `r_f = r_p - h_f`, cut by
//!   the flat tip of the cutter's tooth (the groove's bottom);
//! * the **root fillets**: the envelope of the cutter tooth's rounded corners (the
//!   groove's fillets, radius `rho_f`): a circle of `rho_f` whose centre runs along a
//!   trochoid. Its radius of curvature is `rho_f + (h_f - rho_f)^2 / (r_p + h_f - rho_f)`
//!   at the root, larger up the fillet (the textbook result; checked in the tests);
//! * the **flanks**: involutes of the base circle `r_b = r_p cos alpha`, cut by the
//!   cutter's straight flanks (pressure angle `alpha`, the groove's flank lean), from
//!   where the fillet ends up to the tip edges;
//! * the **tip edges**: arcs of `rho_e` joining the flanks to the tip circle (not cut
//!   by the rack: a turned or deburred edge), and the **tip** (zone "land"): an arc of
//!   the tip circle `r_a = r_f + depth`.
//!
//! The pitch circle `r_p = Z p / (2 pi)` (`Z` teeth, circular pitch `p`) rolls on the
//! rack's pitch line, `h_f` (the dedendum) above the groove's bottom, where the groove
//! is `p / 2` wide for a standard gear (any other `h_f` is a profile shift).
//!
//! Geometry is done on half a tooth space, in a frame turned so that the space's middle
//! is `+y` from the gear's centre and the half's flank lies at `x >= 0` ("the half
//! frame"; angles `a` from `+y` towards `+x`). A point's distance from the surface is the
//! smallest among the pieces whose normal through it has its foot on the piece, as in
//! the groove: closed forms on the circles and the involute (whose normals are the base
//! circle's tangents), a root of one equation on the fillet (its normals run through
//! the rolling's pitch point, the law of gearing).

use std::f64::consts::{FRAC_PI_2, PI};

use super::groove::{GrooveError, Zone};

/// Gauss-Legendre rule on `[-1, 1]`, 12 points: `(node, weight)` for the positive nodes
/// (the rule is symmetric).
const GAUSS12: [(f64, f64); 6] = [
    (0.125_233_408_511_468_9, 0.249_147_045_813_402_8),
    (0.367_831_498_998_180_2, 0.233_492_536_538_354_8),
    (0.587_317_954_286_617_5, 0.203_167_426_723_065_9),
    (0.769_902_674_194_304_7, 0.160_078_328_543_346_2),
    (0.904_117_256_370_474_9, 0.106_939_325_995_318_4),
    (0.981_560_634_246_719_2, 0.047_175_336_386_511_8),
];

/// Pieces the fillet is cut into for its roots' brackets and its distance's lower bound.
const FILLET_PIECES: usize = 32;

/// Consecutive pieces that share a disc holding theirs, checked before them.
const PIECES_PER_GROUP: usize = 8;
const FILLET_GROUPS: usize = FILLET_PIECES / PIECES_PER_GROUP;

/// A cross-section point in the half frame ([`Gear::fold_half`]).
#[derive(Debug, Clone, Copy)]
struct Folded {
    /// The tooth space's index.
    k: f64,
    /// `-1` if the point is left of the space's middle (mirrored), else `+1`.
    side: f64,
    /// The point, `x >= 0`.
    q: (f64, f64),
    /// Its angle from `+y`.
    a: f64,
    /// The tooth space's turn from the cross-section's `+z`, `(cos r, sin r)`.
    turn: (f64, f64),
}

/// A cross-section point's foot ([`Gear::foot`]): distance, outward normal `(s, z)`,
/// zone and curvature.
pub(super) type GearFoot = (f64, (f64, f64), Zone, f64);

/// A point's foot on the half profile.
#[derive(Debug, Clone, Copy)]
pub(super) struct HalfFoot {
    /// Distance, m (negative inside the part).
    pub distance: f64,
    /// Outward normal in the half frame.
    pub normal: (f64, f64),
    pub zone: Zone,
    /// Where on its piece the foot lies: the arc length from the space's middle, m,
    /// but on the fillet its rolling angle (the arc is an integral: [`Gear::arc_of`]).
    pub at: f64,
    /// Curvature across at the foot, 1/m, convex positive.
    pub curvature: f64,
}

/// How the fillet takes part in a foot's search ([`Gear::half_foot_with`]).
#[derive(Debug, Clone, Copy)]
enum Fillet {
    /// Its feet are solved for where a piece may hold a point nearer than the reach and
    /// than the other pieces' nearest; where no piece holds a foot, its chords tell the
    /// side ([`Gear::chord_side`]), or else its feet: the distance is exact where it is
    /// below the reach in size, and otherwise at least the reach in size, with its sign
    /// (in the air, or deep in the tooth).
    Within(f64),
    /// It offers its lower bound (zone and normal left unset) instead of being solved.
    Bound,
}

impl Fillet {
    /// Solved wherever it is the nearest piece.
    const EXACT: Fillet = Fillet::Within(f64::INFINITY);
}

/// A gear's tooth profile (see the module's documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gear {
    teeth: u32,
    /// Angular pitch `2 pi / Z`, rad.
    tau: f64,
    /// Angle of tooth space 0's middle from `+z` towards the groove's `across`, rad.
    turn: f64,
    r_p: f64,
    r_b: f64,
    r_f: f64,
    r_a: f64,
    /// The cutter's tooth corner: centre `(hb, r_p + c)` in the rack's frame, radius
    /// `rho_f` (`c = rho_f - h_f < 0`).
    hb: f64,
    c: f64,
    rho_f: f64,
    /// The rolling angles over which the corner cuts the fillet: `phi0` (at the root)
    /// down to `phi1` (at the flank).
    phi0: f64,
    phi1: f64,
    /// The involute's start angle on the base circle, and its roll angles at the
    /// fillet's end and at the edge.
    a_b: f64,
    beta_f: f64,
    beta_e: f64,
    /// The tip edge: radius, centre, the angle of its centre, and its normal's angle
    /// where it meets the flank.
    rho_e: f64,
    e: (f64, f64),
    a_e: f64,
    edge_from: f64,
    /// Arc length from the space's middle to where the fillet, the flank, the edge and
    /// the tip start; half a period.
    u_fillet: f64,
    u_flank: f64,
    u_edge: f64,
    u_land: f64,
    u_half: f64,
    /// The fillet's pieces: rolling angle at their ends (`cos`, `sin`, angle), and each
    /// piece's middle point with the arc length from it to its farther end.
    ends: [(f64, f64, f64); FILLET_PIECES + 1],
    mids: [(f64, f64, f64); FILLET_PIECES],
    /// Discs holding each group of `PIECES_PER_GROUP` pieces' discs: centre, radius.
    groups: [(f64, f64, f64); FILLET_GROUPS],
    /// A disc holding the whole fillet: centre and radius.
    hull: (f64, f64, f64),
    /// The fillet's farthest point from the gear's centre, m.
    fillet_top: f64,
    /// The fillet's chords: the pieces' ends on the fillet (half frame) and their angles
    /// from `+y`, root to flank ([`Gear::chord_side`]).
    chords: [(f64, f64); FILLET_PIECES + 1],
    chord_angles: [f64; FILLET_PIECES + 1],
    /// A bound on how far the fillet strays from its chords, m; infinite where the
    /// chords cannot tell a point's side.
    chord_gap: f64,
}

/// `sqrt(x^2 + y^2)` (libm's `hypot` guards against overflow that these lengths, all
/// within metres, cannot reach, at several times the cost).
#[inline]
fn len(x: f64, y: f64) -> f64 {
    (x * x + y * y).sqrt()
}

/// `R(-phi) (x, y)`: turns by `phi` from `+y` towards `+x`.
#[inline]
fn turn_by(p: (f64, f64), cs: (f64, f64)) -> (f64, f64) {
    let (c, s) = cs;
    (p.0 * c + p.1 * s, -p.0 * s + p.1 * c)
}

/// `R(phi) q` for `cs = (cos phi, sin phi)`: a half frame point in the rack's frame
/// at rolling angle `phi` (less the rack's travel).
#[inline]
fn to_rack(q: (f64, f64), (c, s): (f64, f64)) -> (f64, f64) {
    (q.0 * c - q.1 * s, q.0 * s + q.1 * c)
}

/// A length in mm for messages (to the nanometre, no trailing zeros).
fn mm(x: f64) -> f64 {
    (x * 1e9).round() / 1e6
}

/// Involute function `tan a - a`.
fn inv(a: f64) -> f64 {
    a.tan() - a
}

impl Gear {
    /// The gear of `teeth` cut by the rack whose tooth corner is `rho_f` at half-width
    /// `hb` of its tip, pressure angle `alpha`, circular pitch `pitch`, pitch line `hf`
    /// above its tip; tip circle `depth` above the root circle, tip edges of `rho_e`;
    /// tooth space 0 turned `offset` (m of pitch-circle arc) towards `across`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        teeth: u32,
        pitch: f64,
        alpha: f64,
        hf: f64,
        hb: f64,
        rho_f: f64,
        depth: f64,
        rho_e: f64,
        offset: f64,
    ) -> Result<Gear, GrooveError> {
        let z = teeth as f64;
        let r_p = z * pitch / (2.0 * PI);
        let tau = 2.0 * PI / z;
        let r_b = r_p * alpha.cos();
        let r_f = r_p - hf;
        let r_a = r_f + depth;
        let (sa, ca) = alpha.sin_cos();
        if r_f <= 0.0 {
            return Err(GrooveError::GearTooSmall {
                why: format!(
                    "its root circle has no radius: the dedendum ({} mm) reaches the pitch \
                     circle's radius ({} mm)",
                    mm(hf),
                    mm(r_p)
                ),
            });
        }
        let c = rho_f - hf;
        if c >= 0.0 {
            return Err(GrooveError::GearTooSmall {
                why: format!(
                    "the root fillet's radius ({} mm) reaches the pitch line ({} mm above \
                     the root)",
                    mm(rho_f),
                    mm(hf)
                ),
            });
        }
        let phi0 = hb / r_p;
        let phi1 = (hb + c * ca / sa) / r_p;
        // The flank's lowest point on the rack (where its fillet ends) lies `y` below the
        // pitch line; it cuts the involute at roll length `r_p sin a - y / sin a` (no
        // undercut while positive).
        let y = hf - rho_f * (1.0 - sa);
        let lambda_f = r_p * sa - y / sa;
        if lambda_f <= 0.0 {
            return Err(GrooveError::Undercut {
                needed_teeth: (2.0 * y / (sa * sa) / (pitch / PI)).floor() as u32 + 1,
            });
        }
        // The flank's width at the pitch line is the space's half width there.
        let x_p = hb + rho_f * ca + y * sa / ca;
        let a_b = x_p / r_p - inv(alpha);
        let beta_f = lambda_f / r_b;
        // Tip edge: centre `rho_e` inside the involute and the tip circle.
        let q = (r_a - rho_e).powi(2) - r_b * r_b;
        if q <= 0.0 {
            return Err(GrooveError::GearTooSmall {
                why: format!(
                    "its tip edges ({} mm) reach below the base circle ({} mm radius)",
                    mm(rho_e),
                    mm(r_b)
                ),
            });
        }
        let beta_e = (q.sqrt() + rho_e) / r_b;
        if beta_e <= beta_f {
            return Err(GrooveError::GearTooSmall {
                why: "its tip edges reach down to the root fillets: no flank is left".into(),
            });
        }
        let psi_e = a_b + beta_e;
        let (sp, cp) = psi_e.sin_cos();
        let e = (r_b * sp - q.sqrt() * cp, r_b * cp + q.sqrt() * sp);
        let a_e = e.0.atan2(e.1);
        if a_e > 0.5 * tau {
            return Err(GrooveError::GearTooSmall {
                why: format!(
                    "its teeth come to a point below the tip circle ({} mm radius): lower \
                     the addendum or the tip edges' radius",
                    mm(r_a)
                ),
            });
        }
        let edge_from = psi_e - FRAC_PI_2;
        let mut g = Gear {
            teeth,
            tau,
            turn: offset / r_p,
            r_p,
            r_b,
            r_f,
            r_a,
            hb,
            c,
            rho_f,
            phi0,
            phi1,
            a_b,
            beta_f,
            beta_e,
            rho_e,
            e,
            a_e,
            edge_from,
            u_fillet: 0.0,
            u_flank: 0.0,
            u_edge: 0.0,
            u_land: 0.0,
            u_half: 0.0,
            ends: [(1.0, 0.0, 0.0); FILLET_PIECES + 1],
            mids: [(0.0, 0.0, 0.0); FILLET_PIECES],
            groups: [(0.0, 0.0, 0.0); FILLET_GROUPS],
            hull: (0.0, 0.0, 0.0),
            fillet_top: 0.0,
            chords: [(0.0, 0.0); FILLET_PIECES + 1],
            chord_angles: [0.0; FILLET_PIECES + 1],
            chord_gap: f64::INFINITY,
        };
        g.u_fillet = r_f * phi0;
        g.u_flank = g.u_fillet + g.fillet_arc(phi1);
        g.u_edge = g.u_flank + 0.5 * r_b * (beta_e * beta_e - beta_f * beta_f);
        g.u_land = g.u_edge + rho_e * (a_e - edge_from);
        g.u_half = g.u_land + r_a * (0.5 * tau - a_e);
        for i in 0..=FILLET_PIECES {
            let phi = phi0 + (phi1 - phi0) * i as f64 / FILLET_PIECES as f64;
            g.ends[i] = (phi.cos(), phi.sin(), phi);
        }
        for i in 0..FILLET_PIECES {
            let (pa, pb) = (g.ends[i].2, g.ends[i + 1].2);
            let pm = 0.5 * (pa + pb);
            let (p, _) = g.fillet_point(pm);
            // Arc lengths from the middle to each end; the farther bounds the piece.
            let reach = g.arc_between(pb, pm).max(g.arc_between(pm, pa));
            g.mids[i] = (p.0, p.1, reach);
        }
        for (j, group) in g.mids.chunks(PIECES_PER_GROUP).enumerate() {
            // Centred on the middle piece's disc, as wide as the farthest piece's disc.
            let (x, y, _) = group[PIECES_PER_GROUP / 2];
            let r = group
                .iter()
                .map(|&(mx, my, mr)| len(mx - x, my - y) + mr)
                .fold(0.0, f64::max);
            g.groups[j] = (x, y, r * (1.0 + 1e-12));
        }
        let (centre, _) = g.fillet_point(0.5 * (phi0 + phi1));
        let reach = g
            .fillet_arc(0.5 * (phi0 + phi1))
            .max(g.arc_between(phi1, 0.5 * (phi0 + phi1)));
        g.hull = (centre.0, centre.1, reach);
        // The fillet's radius from the centre grows from root to flank (checked in the
        // tests), and the pieces' reach bounds it in between.
        g.fillet_top = g
            .mids
            .iter()
            .map(|&(x, y, r)| len(x, y) + r)
            .fold(0.0, f64::max);
        g.chord_gap = g.chords();
        Ok(g)
    }

    /// Sets the fillet's chords and returns the bound on their gap from the fillet
    /// ([`Gear::chord_side`]), or infinity where the chords cannot tell sides.
    fn chords(&mut self) -> f64 {
        for i in 0..=FILLET_PIECES {
            let (p, _) = self.fillet_point(self.ends[i].2);
            self.chords[i] = p;
            self.chord_angles[i] = p.0.atan2(p.1);
        }
        // The rack's corner, a disc of `rho_f`, is air and touches the fillet from the
        // air side at every point: the fillet's radius of curvature is at least `rho_f`.
        // A curve of curvature at most `1 / rho_f` strays from a chord of length at most
        // `L` (its arc length) by at most `rho_f (1 - sqrt(1 - (L / 2 rho_f)^2)) <= L^2 /
        // (4 rho_f)` while `L` is short against `rho_f` (the arc then is a graph over its
        // chord). A piece's arc length is at most twice its middle's reach.
        let longest = 2.0 * self.mids.iter().map(|m| m.2).fold(0.0, f64::max);
        let gap = longest * longest / (4.0 * self.rho_f);
        // Only the fillet's chords may lie between the angles of its ends: they turn one
        // way from the root (the bottom's end, `phi0`) to the flank (whose angle grows with
        // the radius from there), and the tip edge's disc lies beyond.
        let angles = &self.chord_angles;
        let (ex, ey) = self.e;
        let edge_lowest = ex.atan2(ey) - (self.rho_e / len(ex, ey)).min(1.0).asin();
        let one_way = angles.windows(2).all(|w| w[0] < w[1]);
        if longest <= 0.5 * self.rho_f && one_way && edge_lowest > angles[FILLET_PIECES] {
            // Twice the bound: room for the roundings of the points and their angles.
            2.0 * gap
        } else {
            f64::INFINITY
        }
    }

    /// Whether `q` (half frame, angle `a` from `+y`) is in the air, from the fillet's
    /// chord at its angle, where `q` lies farther than `reach` from the whole profile:
    /// `None` where the chords cannot tell (`reach` within their gap, or `a` outside the
    /// fillet's angles).
    ///
    /// Why it holds: between the fillet's end angles the profile is the fillet alone, one
    /// point at each angle, and so is the polygon that takes the chords for the fillet
    /// (their angles grow one way): a point there is in its air where it lies beyond the
    /// chord at its angle, seen from the gear's centre. The two regions differ only
    /// between each piece and its chord, within `chord_gap` of the fillet; a point
    /// farther than that from the profile is on the same side of both.
    #[inline]
    fn chord_side(&self, q: (f64, f64), a: f64, reach: f64) -> Option<bool> {
        let angles = &self.chord_angles;
        if !(reach > self.chord_gap && a >= angles[0] && a <= angles[FILLET_PIECES]) {
            return None;
        }
        let i = angles[1..FILLET_PIECES].partition_point(|&t| t <= a);
        let (v, w) = (self.chords[i], self.chords[i + 1]);
        let d = (w.0 - v.0, w.1 - v.1);
        // The sides of the chord's line where `q` and the gear's centre lie.
        let side = d.0 * (q.1 - v.1) - d.1 * (q.0 - v.0);
        let centre = d.1 * v.0 - d.0 * v.1;
        Some((side < 0.0) == (centre > 0.0))
    }

    /// Number of teeth.
    pub fn teeth(&self) -> u32 {
        self.teeth
    }

    /// Pitch, root, tip and base circles' radii, m.
    pub fn radii(&self) -> (f64, f64, f64, f64) {
        (self.r_p, self.r_f, self.r_a, self.r_b)
    }

    /// Arc lengths from the space's middle to where the fillet, the flank, the edge and
    /// the tip start, and half a period.
    pub(super) fn arcs(&self) -> [f64; 5] {
        [
            self.u_fillet,
            self.u_flank,
            self.u_edge,
            self.u_land,
            self.u_half,
        ]
    }

    /// The gear's centre's height below the jet's foot: the root circle's top is `z = 0`.
    #[inline]
    fn centre_depth(&self) -> f64 {
        self.r_f
    }

    /// Lowest point of the gear, m (its centre is `r_f` below `z = 0`).
    pub fn bottom_z(&self) -> f64 {
        -self.r_f - self.r_a
    }

    /// The flanks' radius of curvature where the fillets end (their sharpest), m.
    pub fn flank_radius(&self) -> f64 {
        self.r_b * self.beta_f
    }

    /// Smallest convex radius of the surface, m: the tip edges' or the flanks' at the
    /// fillet (an involute's radius of curvature is its roll length).
    pub fn smallest_convex_radius(&self) -> f64 {
        self.rho_e.min(self.r_b * self.beta_f)
    }

    // ---- the fillet ----------------------------------------------------------------

    /// The fillet's point at rolling angle `phi` and its outward normal (half frame).
    #[inline]
    fn fillet_point(&self, phi: f64) -> ((f64, f64), (f64, f64)) {
        let e = self.hb - self.r_p * phi;
        let d = len(e, self.c);
        let k = 1.0 + self.rho_f / d;
        let (sn, cn) = phi.sin_cos();
        let cs = (cn, sn);
        let p = turn_by((k * e, self.r_p + k * self.c), cs);
        (p, self.fillet_normal(e, d, cs))
    }

    /// The fillet's outward normal where the rack's corner centre is `e` across from
    /// the pitch point (`d` from it) and the gear has turned by the angle of `cs`.
    #[inline]
    fn fillet_normal(&self, e: f64, d: f64, cs: (f64, f64)) -> (f64, f64) {
        turn_by((-e / d, -self.c / d), cs)
    }

    /// `|dP/dphi|` and the fillet's radius of curvature at `phi`.
    #[inline]
    fn fillet_speed(&self, phi: f64) -> (f64, f64) {
        let e = self.hb - self.r_p * phi;
        let d2 = e * e + self.c * self.c;
        self.fillet_speed_at(e, d2, d2.sqrt())
    }

    /// [`Gear::fillet_speed`] from the corner centre's `e`, `d^2` and `d`.
    #[inline]
    fn fillet_speed_at(&self, e: f64, d2: f64, d: f64) -> (f64, f64) {
        let (r_p, c, rho) = (self.r_p, self.c, self.rho_f);
        let k = 1.0 + rho / d;
        let dk = rho * r_p * e / (d2 * d);
        let speed = len(dk * e - k * r_p + r_p + k * c, dk * c - k * e);
        // The normal turns at 1 + |c| r_p / D^2 per unit phi (backwards along the arc:
        // concave).
        (speed, speed / (1.0 - c * r_p / d2))
    }

    /// Arc length of the fillet from rolling angle `from` up to `to` (`from <= to`).
    fn arc_between(&self, from: f64, to: f64) -> f64 {
        let (mid, half) = (0.5 * (from + to), 0.5 * (to - from));
        let mut s = 0.0;
        for (x, w) in GAUSS12 {
            s += w * (self.fillet_speed(mid - half * x).0 + self.fillet_speed(mid + half * x).0);
        }
        s * half
    }

    /// Arc length of the fillet from the root to rolling angle `phi`.
    #[inline]
    fn fillet_arc(&self, phi: f64) -> f64 {
        self.arc_between(phi, self.phi0)
    }

    /// The rolling angle where the fillet's arc length from the root is `s`.
    fn fillet_phi(&self, s: f64) -> f64 {
        let (mut lo, mut hi) = (self.phi1, self.phi0);
        let len = self.u_flank - self.u_fillet;
        let mut phi = self.phi0 + (self.phi1 - self.phi0) * (s / len).clamp(0.0, 1.0);
        for _ in 0..60 {
            let f = self.fillet_arc(phi) - s;
            if f.abs() <= 1e-16 {
                break;
            }
            // The arc grows as phi falls.
            if f > 0.0 {
                lo = phi;
            } else {
                hi = phi;
            }
            let next = phi + f / self.fillet_speed(phi).0;
            phi = if next > lo && next < hi {
                next
            } else {
                0.5 * (lo + hi)
            };
            if hi - lo <= 1e-15 * self.phi0.abs().max(self.phi1.abs()) {
                break;
            }
        }
        phi
    }

    /// Whether the fillet's normal at `phi` runs through `q` (sign of the cross product
    /// of the corner's centre and `q`, both from the pitch point, in the rack's frame).
    #[inline]
    fn fillet_side(&self, q: (f64, f64), cs: (f64, f64), phi: f64) -> f64 {
        let e = self.hb - self.r_p * phi;
        let (qx, qy) = to_rack(q, cs);
        e * (qy - self.r_p) - self.c * qx
    }

    /// A lower bound on the distance of `q` from the fillet.
    #[inline]
    fn fillet_lower_bound(&self, q: (f64, f64)) -> f64 {
        self.mids
            .iter()
            .map(|&(x, y, r)| len(q.0 - x, q.1 - y) - r)
            .fold(f64::INFINITY, f64::min)
    }

    /// A coarser lower bound on the distance of `q` from the fillet (one disc).
    #[inline]
    fn fillet_far(&self, q: (f64, f64)) -> f64 {
        len(q.0 - self.hull.0, q.1 - self.hull.1) - self.hull.2
    }

    /// `d/dphi` of [`Gear::fillet_side`].
    #[inline]
    fn fillet_side_slope(&self, q: (f64, f64), cs: (f64, f64), phi: f64) -> f64 {
        let e = self.hb - self.r_p * phi;
        let (qx, qy) = to_rack(q, cs);
        // d(qx)/dphi = -qy, d(qy)/dphi = qx, de/dphi = -r_p.
        -self.r_p * (qy - self.r_p) + e * qx + self.c * qy
    }

    /// The rolling angle in `[a, b]` (where [`Gear::fillet_side`] changes sign, `fa`
    /// at `a`, `fb` at `b`) whose normal runs through `q`: Newton's steps kept in the
    /// shrinking bracket, from the chord's root. A piece is short enough (a
    /// `FILLET_PIECES`th of the fillet) for the chord to start Newton within its
    /// quadratic range, so the root is taken after a Newton step shorter than
    /// `ROOT_STEP`: the error left is about the square of that step (the tests hold it
    /// within 1e-13 rad of a bisection's root to the last bit, or within the rounding's
    /// allowance where the equation is flat).
    fn fillet_root(
        &self,
        q: (f64, f64),
        (mut a, mut fa): (f64, f64),
        (mut b, fb): (f64, f64),
    ) -> f64 {
        const ROOT_STEP: f64 = 1e-8;
        let mut x = a - fa * ((b - a) / (fb - fa));
        for _ in 0..100 {
            let (s, c) = x.sin_cos();
            let f = self.fillet_side(q, (c, s), x);
            if f == 0.0 {
                return x;
            }
            if (f < 0.0) == (fa < 0.0) {
                (a, fa) = (x, f);
            } else {
                b = x;
            }
            let step = x - f / self.fillet_side_slope(q, (c, s), x);
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            if step > lo && step < hi {
                if (step - x).abs() <= ROOT_STEP {
                    return step;
                }
                x = step;
            } else {
                x = 0.5 * (a + b);
                if hi - lo <= 1e-15 * x.abs().max(1e-3) {
                    return x;
                }
            }
        }
        x
    }

    /// The fillet's foot at rolling angle `phi` for `q`: the signed distance of `q`
    /// along the normal there, the normal ([`Gear::fillet_point`]) and the signed
    /// curvature (`-1 /` [`Gear::fillet_speed`]'s radius).
    #[inline]
    fn fillet_foot(&self, q: (f64, f64), phi: f64) -> HalfFoot {
        let (r_p, c) = (self.r_p, self.c);
        let e = self.hb - r_p * phi;
        let d2 = e * e + c * c;
        let d = d2.sqrt();
        let (sn, cn) = phi.sin_cos();
        let (qx, qy) = to_rack(q, (cn, sn));
        HalfFoot {
            distance: self.rho_f - ((qx - e) * e + (qy - r_p - c) * c) / d,
            normal: self.fillet_normal(e, d, (cn, sn)),
            zone: Zone::Fillet,
            at: phi,
            curvature: -1.0 / self.fillet_speed_at(e, d2, d).1,
        }
    }

    /// Offers the fillet's feet of `q` whose pieces may hold a point nearer than
    /// `best` and than `reach` (every rolling angle whose normal runs through `q` there).
    fn fillet_feet(&self, q: (f64, f64), best: &mut HalfFoot, reach: f64) {
        let mut ends: Option<(usize, f64)> = None;
        let side_at = |i: usize| {
            let (c, s, phi) = self.ends[i];
            self.fillet_side(q, (c, s), phi)
        };
        let near = |(x, y, r): (f64, f64, f64), best: &HalfFoot| {
            // The disc's lower bound `|q - m| - r` against the best so far, squared.
            let (dx, dy) = (q.0 - x, q.1 - y);
            let within = best.distance.abs().min(reach) + r;
            dx * dx + dy * dy < within * within
        };
        for (j, &group) in self.groups.iter().enumerate() {
            // A group's disc holds its pieces' discs: none of them is near if it is
            // not (its radius has room for the roundings).
            if !near(group, best) {
                continue;
            }
            for i in j * PIECES_PER_GROUP..(j + 1) * PIECES_PER_GROUP {
                if !near(self.mids[i], best) {
                    continue;
                }
                let h0 = match ends {
                    Some((k, h)) if k == i => h,
                    _ => side_at(i),
                };
                let h1 = side_at(i + 1);
                ends = Some((i + 1, h1));
                let phi = if h0 == 0.0 {
                    self.ends[i].2
                } else if h1 == 0.0 {
                    self.ends[i + 1].2
                } else if (h0 < 0.0) != (h1 < 0.0) {
                    self.fillet_root(q, (self.ends[i].2, h0), (self.ends[i + 1].2, h1))
                } else {
                    continue;
                };
                let f = self.fillet_foot(q, phi);
                if f.distance.abs() < best.distance.abs() {
                    *best = f;
                    if f.distance > 0.0 && f.distance < self.rho_f * (1.0 - 1e-9) {
                        // In the air nearer than the rack corner's radius: the corner's
                        // disc there (air, of `rho_f`, touching the fillet at the foot)
                        // holds `q`, and every other point of the profile lies outside
                        // it, so farther from `q`. No other foot can be nearer.
                        return;
                    }
                }
            }
        }
    }

    // ---- the half profile ------------------------------------------------------------

    /// The nearest piece's foot of `q` (half frame, `x >= 0`, within half a period), `a`
    /// the angle of `q` from `+y`. How the fillet takes part: [`Fillet`].
    fn half_foot_with(&self, q: (f64, f64), a: f64, fillet: Fillet) -> HalfFoot {
        let rho = len(q.0, q.1);
        let mut best = HalfFoot {
            distance: f64::INFINITY,
            normal: (0.0, 1.0),
            zone: Zone::Land,
            at: self.u_land,
            curvature: 0.0,
        };
        let radial = if rho > 0.0 {
            (q.0 / rho, q.1 / rho)
        } else {
            (0.0, 1.0)
        };
        fn offer(best: &mut HalfFoot, f: HalfFoot) {
            if f.distance.abs() < best.distance.abs() {
                *best = f;
            }
        }
        if a <= self.phi0 {
            offer(
                &mut best,
                HalfFoot {
                    distance: rho - self.r_f,
                    normal: radial,
                    zone: Zone::Bottom,
                    at: self.r_f * a.max(0.0),
                    curvature: 1.0 / self.r_f,
                },
            );
        }
        if rho > self.r_b {
            let lambda = (rho * rho - self.r_b * self.r_b).sqrt();
            let psi = a + (self.r_b / rho).acos();
            let beta = psi - self.a_b;
            if (self.beta_f..=self.beta_e).contains(&beta) {
                offer(
                    &mut best,
                    HalfFoot {
                        distance: lambda - self.r_b * beta,
                        // (-cos psi, sin psi), with `cos a = q_y / rho`, `cos(psi - a)
                        // = r_b / rho`.
                        normal: (
                            (q.0 * lambda - q.1 * self.r_b) / (rho * rho),
                            (q.0 * self.r_b + q.1 * lambda) / (rho * rho),
                        ),
                        zone: Zone::Flank,
                        at: self.u_flank
                            + 0.5 * self.r_b * (beta * beta - self.beta_f * self.beta_f),
                        curvature: 1.0 / (self.r_b * beta),
                    },
                );
            }
        }
        if a >= self.a_e {
            offer(
                &mut best,
                HalfFoot {
                    distance: rho - self.r_a,
                    normal: radial,
                    zone: Zone::Land,
                    at: self.u_land + self.r_a * (a - self.a_e),
                    curvature: 1.0 / self.r_a,
                },
            );
        }
        let (ex, ey) = (q.0 - self.e.0, q.1 - self.e.1);
        let l = len(ex, ey);
        let edge = |l: f64, gamma: f64| HalfFoot {
            distance: l - self.rho_e,
            normal: if l > 0.0 {
                (ex / l, ey / l)
            } else {
                (0.0, 1.0)
            },
            zone: Zone::Edge,
            at: self.u_edge + self.rho_e * (gamma.clamp(self.edge_from, self.a_e) - self.edge_from),
            curvature: 1.0 / self.rho_e,
        };
        if (l - self.rho_e).abs() < best.distance.abs() {
            let gamma = ex.atan2(ey);
            if (self.edge_from..=self.a_e).contains(&gamma) {
                offer(&mut best, edge(l, gamma));
            }
        }
        let reach = match fillet {
            Fillet::Within(reach) => reach,
            Fillet::Bound => f64::INFINITY,
        };
        let known = best.distance.abs().min(reach);
        if rho - self.fillet_top < known && self.fillet_far(q) < known {
            if let Fillet::Within(reach) = fillet {
                self.fillet_feet(q, &mut best, reach);
            } else {
                let lb = HalfFoot {
                    distance: self.fillet_lower_bound(q),
                    ..best
                };
                offer(&mut best, lb);
            }
        }
        if !best.distance.is_finite() && reach.is_finite() {
            // Only the fillet holds a foot, out of reach: in the air above it or deep in
            // the tooth under it. Its chord tells which, where it can (the distance then
            // is the reach, with its sign); else its foot does.
            match self.chord_side(q, a, reach) {
                Some(air) => best.distance = if air { reach } else { -reach },
                None => self.fillet_feet(q, &mut best, f64::INFINITY),
            }
        }
        if !best.distance.is_finite() {
            // Deep in the tooth, under no piece: the edge's distance.
            best = edge(l, ex.atan2(ey));
        }
        best
    }

    /// The surface point, outward normal and zone at arc length `s` (from the space's
    /// middle, `0 <= s <= u_half`) on the half profile.
    pub(super) fn half_at(&self, s: f64) -> ((f64, f64), (f64, f64), Zone) {
        if s < self.u_fillet {
            let a = s / self.r_f;
            let (sa, ca) = a.sin_cos();
            ((self.r_f * sa, self.r_f * ca), (sa, ca), Zone::Bottom)
        } else if s <= self.u_flank {
            let (p, n) = self.fillet_point(self.fillet_phi(s - self.u_fillet));
            (p, n, Zone::Fillet)
        } else if s <= self.u_edge {
            let beta = (self.beta_f * self.beta_f + 2.0 * (s - self.u_flank) / self.r_b).sqrt();
            let psi = self.a_b + beta;
            let (sp, cp) = psi.sin_cos();
            let l = self.r_b * beta;
            (
                (self.r_b * sp - l * cp, self.r_b * cp + l * sp),
                (-cp, sp),
                Zone::Flank,
            )
        } else if s <= self.u_land {
            let gamma = self.edge_from + (s - self.u_edge) / self.rho_e;
            let (sg, cg) = gamma.sin_cos();
            (
                (self.e.0 + self.rho_e * sg, self.e.1 + self.rho_e * cg),
                (sg, cg),
                Zone::Edge,
            )
        } else {
            let a = self.a_e + (s - self.u_land) / self.r_a;
            let (sa, ca) = a.sin_cos();
            ((self.r_a * sa, self.r_a * ca), (sa, ca), Zone::Land)
        }
    }

    // ---- the cross-section -----------------------------------------------------------

    /// A cross-section point `(s, z)` (`s` along the groove's `across`, `z` up) in the
    /// half frame.
    #[inline]
    fn fold_half(&self, s: f64, z: f64) -> Folded {
        let (x, y) = (s, z + self.centre_depth());
        let theta = x.atan2(y) - self.turn;
        let k = (theta / self.tau).round();
        let phi = theta - k * self.tau;
        let side = if phi < 0.0 { -1.0 } else { 1.0 };
        // Turned back by the tooth space's angle (`R(r)`), then mirrored onto `x >= 0`.
        let (cr, sr) = self.space_turn(k);
        Folded {
            k,
            side,
            q: ((x * cr - y * sr).abs(), x * sr + y * cr),
            a: phi.abs(),
            turn: (cr, sr),
        }
    }

    /// A half frame vector back in the cross-section (tooth space turned by `(cos r,
    /// sin r)`, `side`).
    #[inline]
    fn unfold_half(&self, (cr, sr): (f64, f64), side: f64, v: (f64, f64)) -> (f64, f64) {
        let vx = side * v.0;
        (vx * cr + v.1 * sr, -vx * sr + v.1 * cr)
    }

    /// The turn `(cos r, sin r)` of tooth space `k` from the cross-section's `+z`.
    #[inline]
    fn space_turn(&self, k: f64) -> (f64, f64) {
        let (sr, cr) = (self.turn + k * self.tau).sin_cos();
        (cr, sr)
    }

    /// The arc length from the space's middle to a foot.
    fn arc_of(&self, f: &HalfFoot) -> f64 {
        match f.zone {
            Zone::Fillet => self.u_fillet + self.fillet_arc(f.at),
            _ => f.at,
        }
    }

    /// The foot of the cross-section point `(s, z)`: distance, outward normal `(s, z)`,
    /// zone and curvature.
    pub(super) fn foot(&self, s: f64, z: f64) -> GearFoot {
        let h = self.fold_half(s, z);
        self.unfold_foot(&h, &self.half_foot_with(h.q, h.a, Fillet::EXACT))
    }

    /// A half frame foot of the folded point `h` in the cross-section.
    #[inline]
    fn unfold_foot(&self, h: &Folded, f: &HalfFoot) -> GearFoot {
        (
            f.distance,
            self.unfold_half(h.turn, h.side, f.normal),
            f.zone,
            f.curvature,
        )
    }

    /// The distance of the cross-section point `(s, z)` from the surface where it is
    /// below `reach` in size (the same as [`Gear::foot`]'s to the bit); otherwise a value
    /// at least `reach` in the air and at most `-reach` in the part. Skips solving for the
    /// fillet's feet out of reach where another piece tells the side: a shot's contact
    /// check needs no more. A point beyond the tip circle by the reach (which holds the
    /// gear) is not folded: the reach.
    pub(super) fn distance_within(&self, s: f64, z: f64, reach: f64) -> f64 {
        self.half_within(s, z, reach)
            .map_or(reach, |(_, f)| f.distance)
    }

    /// [`Gear::foot`] where the distance of `(s, z)` is below `reach` in size (to the
    /// bit), from [`Gear::distance_within`]'s search: `Ok` with it there, else `Err` with
    /// that distance.
    #[inline]
    pub(super) fn foot_within(&self, s: f64, z: f64, reach: f64) -> Result<GearFoot, f64> {
        match self.half_within(s, z, reach) {
            Some((h, f)) if f.distance.abs() < reach => Ok(self.unfold_foot(&h, &f)),
            Some((_, f)) => Err(f.distance),
            None => Err(reach),
        }
    }

    /// The folded point and its foot within `reach` ([`Fillet::Within`]); `None` beyond
    /// the tip circle by the reach.
    #[inline]
    fn half_within(&self, s: f64, z: f64, reach: f64) -> Option<(Folded, HalfFoot)> {
        let (x, y) = (s, z + self.centre_depth());
        // Room for the roundings of the distance the foot would give.
        let far = (self.r_a + reach) * (1.0 + 1e-12);
        if x * x + y * y >= far * far {
            return None;
        }
        let h = self.fold_half(s, z);
        Some((h, self.half_foot_with(h.q, h.a, Fillet::Within(reach))))
    }

    /// The unrolled arc length of the foot of `(s, z)`: from tooth space 0's middle,
    /// positive towards `across`.
    pub(super) fn unrolled(&self, s: f64, z: f64) -> f64 {
        let h = self.fold_half(s, z);
        let f = self.half_foot_with(h.q, h.a, Fillet::EXACT);
        let period = if h.k == 0.0 {
            0.0
        } else {
            2.0 * h.k * self.u_half
        };
        period + h.side * self.arc_of(&f)
    }

    /// The surface point and outward normal `(s, z)` of tooth space `k` at arc `ul`
    /// from its middle (`|ul| <= u_half`).
    pub(super) fn point_at(&self, k: f64, ul: f64) -> ((f64, f64), (f64, f64), Zone) {
        let side = if ul < 0.0 { -1.0 } else { 1.0 };
        let (p, n, zone) = self.half_at(ul.abs());
        let turn = self.space_turn(k);
        let (ps, pz) = self.unfold_half(turn, side, p);
        (
            (ps, pz - self.centre_depth()),
            self.unfold_half(turn, side, n),
            zone,
        )
    }

    /// A lower bound on the time (s) before a shot of `radius` at `(s, z)`, flying
    /// straight at `(vs, vz)` across the axis, can touch the gear: the larger of the tip
    /// circle's (a convex disc holding the gear: its distance closes no faster than
    /// now) and the surface's distance over the speed (a distance closes no faster than
    /// the speed). The fillet's distance is its lower bound there.
    pub(super) fn time_to_touch(&self, s: f64, z: f64, vs: f64, vz: f64, radius: f64) -> f64 {
        let speed = vs.hypot(vz);
        let (x, y) = (s, z + self.centre_depth());
        let rho = x.hypot(y);
        let disc = if rho - self.r_a <= radius {
            0.0
        } else {
            let rate = -(vs * x + vz * y) / rho;
            if rate > 0.0 {
                (rho - self.r_a - radius) / rate
            } else {
                return f64::INFINITY;
            }
        };
        let h = self.fold_half(s, z);
        let d = self.half_foot_with(h.q, h.a, Fillet::Bound).distance;
        let near = if d <= radius {
            0.0
        } else if speed > 0.0 {
            (d - radius) / speed
        } else {
            f64::INFINITY
        };
        disc.max(near)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A module 4 gear of `z` teeth cut by the ISO 53 profile A rack: 20 degree flanks,
    /// root fillets 0.38 m, dedendum 1.25 m, addendum 1 m, tip edges 0.2 m.
    fn gear(z: u32) -> Gear {
        let m = 4e-3;
        let alpha = 20f64.to_radians();
        let (hf, rho) = (1.25 * m, 0.38 * m);
        let pitch = PI * m;
        let hb = pitch / 4.0 - (hf - rho * (1.0 - alpha.sin())) * alpha.tan() - rho * alpha.cos();
        Gear::new(z, pitch, alpha, hf, hb, rho, 2.25 * m, 0.2 * m, 0.0).unwrap()
    }

    #[test]
    fn the_gauss_rule_integrates_polynomials_exactly() {
        let w: f64 = GAUSS12.iter().map(|&(_, w)| 2.0 * w).sum();
        assert!((w - 2.0).abs() < 1e-15);
        // x^22 over [-1, 1]: 2 / 23.
        let s: f64 = GAUSS12.iter().map(|&(x, w)| 2.0 * w * x.powi(22)).sum();
        assert!((s - 2.0 / 23.0).abs() < 1e-15, "{s}");
    }

    #[test]
    fn the_profile_is_closed_and_smooth() {
        for z in [18, 30, 80] {
            let g = gear(z);
            let at = |u: f64| g.half_at(u);
            for u in [g.u_fillet, g.u_flank, g.u_edge, g.u_land] {
                let (p0, n0, _) = at(u - 1e-12);
                let (p1, n1, _) = at(u + 1e-12);
                assert!(
                    (p0.0 - p1.0).hypot(p0.1 - p1.1) < 1e-11,
                    "z {z}: gap at {u}"
                );
                assert!(
                    (n0.0 - n1.0).hypot(n0.1 - n1.1) < 1e-8,
                    "z {z}: kink at {u}"
                );
            }
            // The half period ends on the tooth's middle line.
            let (p, _, _) = at(g.u_half);
            assert!((p.0.atan2(p.1) - 0.5 * g.tau).abs() < 1e-14);
            // Arc length and normals along the whole half.
            let n = 2000;
            for i in 1..n {
                let u = g.u_half * i as f64 / n as f64;
                let (a, _, _) = at(u - 1e-8);
                let (b, _, _) = at(u + 1e-8);
                let (_, nn, _) = at(u);
                let t = ((b.0 - a.0) / 2e-8, (b.1 - a.1) / 2e-8);
                assert!((t.0.hypot(t.1) - 1.0).abs() < 1e-6, "z {z}: arc at {u}");
                assert!(
                    (t.0 * nn.0 + t.1 * nn.1).abs() < 1e-6,
                    "z {z}: normal at {u}"
                );
                // Outward: the air lies on the left of increasing u in the half frame
                // (the profile runs from the space's middle towards +x).
                assert!(t.0 * nn.1 - t.1 * nn.0 > 0.0, "z {z}: normal side at {u}");
            }
            // The pitch circle crosses the flank at a quarter of the angular pitch.
            let beta = (g.r_p * g.r_p - g.r_b * g.r_b).sqrt() / g.r_b;
            let (p, _, _) = at(g.u_flank + 0.5 * g.r_b * (beta * beta - g.beta_f * g.beta_f));
            assert!((p.0.hypot(p.1) - g.r_p).abs() < 1e-12);
            assert!((p.0.atan2(p.1) - 0.25 * g.tau).abs() < 1e-12);
        }
    }

    #[test]
    fn the_fillet_has_the_textbook_radius_and_is_what_the_rack_cuts() {
        let m: f64 = 4e-3;
        for z in [18, 30, 80] {
            let g = gear(z);
            // Radius of curvature at the root: rho + (hf - rho)^2 / (r_p + hf - rho).
            let (rho, hf) = (0.38 * m, 1.25 * m);
            let want = rho + (hf - rho).powi(2) / (g.r_p + hf - rho);
            let (_, got) = g.fillet_speed(g.phi0);
            assert!((got - want).abs() < 1e-12 * want, "z {z}: {got} vs {want}");
            // Along the fillet: from three close points, and never below the corner's.
            for i in 1..50 {
                let u = g.u_fillet + (g.u_flank - g.u_fillet) * i as f64 / 50.0;
                let h = 1e-5;
                let (a, _, _) = g.half_at(u - h);
                let (b, _, _) = g.half_at(u);
                let (c, _, _) = g.half_at(u + h);
                let (ab, bc, ca) = (
                    (a.0 - b.0).hypot(a.1 - b.1),
                    (b.0 - c.0).hypot(b.1 - c.1),
                    (c.0 - a.0).hypot(c.1 - a.1),
                );
                let cross = ((b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)).abs();
                let circum = ab * bc * ca / (2.0 * cross);
                let phi = g.fillet_phi(u - g.u_fillet);
                let (_, radius) = g.fillet_speed(phi);
                // (Three points 10 um apart: the circle through them is off by about 1e-6.)
                assert!(
                    (circum - radius).abs() < 1e-5 * radius,
                    "z {z}: {circum} {radius}"
                );
                assert!(radius >= rho * (1.0 - 1e-12));
            }
        }
        // The gear is what the rack leaves: at every rolling position the cutter (the
        // groove's air, by the groove's own tested distance) stays out of the root,
        // fillets and flanks, and each of their points is touched at some position.
        let g = gear(30);
        let alpha = 20f64.to_radians();
        let (hf, rho) = (1.25 * m, 0.38 * m);
        let pitch = PI * m;
        let rack = super::super::groove::Groove::new(super::super::groove::GrooveSize {
            radius: rho,
            bottom: 2.0 * g.hb,
            flank: alpha,
            depth: 2.25 * m,
            edge_radius: 0.2 * m,
            pitch: Some(pitch),
            axis_angle: FRAC_PI_2,
            offset: 0.0,
            gear: None,
        })
        .unwrap();
        let rolls: Vec<f64> = (0..=40_000)
            .map(|i| -0.6 + 1.2 * i as f64 / 40_000.0)
            .collect();
        for i in 0..=300 {
            let u = g.u_edge * i as f64 / 300.0;
            let (p, _, _) = g.half_at(u);
            let mut deepest = f64::NEG_INFINITY;
            for &phi in &rolls {
                let (c, s) = (phi.cos(), phi.sin());
                let x = p.0 * c - p.1 * s + g.r_p * phi;
                let y = p.0 * s + p.1 * c - g.r_f;
                // The groove's `across` is +x for an axis along y.
                let q = crate::Vec3::new(x, 0.0, y);
                deepest = deepest.max(rack.distance(&q));
            }
            assert!(
                deepest < 1e-9,
                "u {u}: the cutter cuts {deepest:e} into the gear"
            );
            assert!(
                deepest > -2e-8,
                "u {u}: the cutter never reaches ({deepest:e})"
            );
        }
        let _ = hf;
    }

    /// The profile as a dense polyline over a period and its neighbours, in the
    /// cross-section.
    fn polyline(g: &Gear, n: usize) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        for k in [-1.0, 0.0, 1.0] {
            for i in 0..=n {
                let ul = -g.u_half + 2.0 * g.u_half * i as f64 / n as f64;
                out.push(g.point_at(k, ul).0);
            }
        }
        out
    }

    fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
        let (dx, dz) = (b.0 - a.0, b.1 - a.1);
        let t = (((p.0 - a.0) * dx + (p.1 - a.1) * dz) / (dx * dx + dz * dz)).clamp(0.0, 1.0);
        (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dz)
    }

    #[test]
    fn distances_match_a_dense_polyline() {
        for (z, turn) in [(30, 0.0), (18, 1.3e-3), (80, -2.9e-3)] {
            let mut g = gear(z);
            g.turn = turn / g.r_p;
            let line = polyline(&g, 60_000);
            let mut rng = ChaCha8Rng::seed_from_u64(2468 + z as u64);
            let mut next = || rng.random::<f64>();
            for _ in 0..400 {
                let s = (next() - 0.5) * 20e-3;
                let zz = -1e-3 + next() * 12e-3;
                let (d, n, zone, _) = g.foot(s, zz);
                let u = g.unrolled(s, zz);
                let brute = line
                    .windows(2)
                    .map(|w| segment_distance((s, zz), w[0], w[1]))
                    .fold(f64::INFINITY, f64::min);
                if d >= 0.0 {
                    assert!(
                        (d - brute).abs() < 1e-8,
                        "z {z} at ({s}, {zz}): {d} vs {brute}"
                    );
                } else if brute < 0.3e-3 {
                    assert!(
                        (d + brute).abs() < 1e-8,
                        "z {z} at ({s}, {zz}): {d} vs -{brute}"
                    );
                }
                if d.abs() < 1e-3 {
                    // The foot unrolls to its arc, its point and normal.
                    let foot = (s - n.0 * d, zz - n.1 * d);
                    let k = (u / (2.0 * g.u_half)).round();
                    let (back, nb, zb) = g.point_at(k, u - 2.0 * k * g.u_half);
                    assert!(
                        (back.0 - foot.0).hypot(back.1 - foot.1) < 1e-10,
                        "z {z} foot"
                    );
                    assert!((nb.0 - n.0).hypot(nb.1 - n.1) < 1e-8);
                    assert_eq!(zb, zone);
                }
            }
        }
    }

    #[test]
    fn feet_near_the_fillet_are_a_dense_polyline_s() {
        // Points about the fillet, in the air up to 2.5 corner radii and in the part,
        // and in the space's middle above the root, where the fillet's feet compete
        // with the root's and a point can lie on two of the fillet's normals: the
        // foot's distance is the dense polyline's. (The search stops at a foot in the
        // air nearer than the corner's radius: no other can be nearer. Taking the
        // first foot the search finds instead fails here.)
        let mut rng = ChaCha8Rng::seed_from_u64(8642);
        let mut checked = 0;
        for z in [18, 30, 80] {
            let g = gear(z);
            let line = polyline(&g, 60_000);
            for i in 0..1_500 {
                let (s, zz) = if i % 3 == 0 {
                    // The space's middle above the root, where a point can lie on two
                    // of the fillet's normals.
                    let (x, y) = (0.5 * rng.random::<f64>(), 0.5 + 1.5 * rng.random::<f64>());
                    (x * g.rho_f, y * g.rho_f)
                } else {
                    let ul = (g.u_fillet + (g.u_flank - g.u_fillet) * rng.random::<f64>())
                        * if rng.random::<bool>() { 1.0 } else { -1.0 };
                    let (p, n, _) = g.point_at(0.0, ul);
                    let t = g.rho_f * (3.0 * rng.random::<f64>() - 0.5);
                    let j = g.rho_f * (rng.random::<f64>() - 0.5);
                    (p.0 + t * n.0 - j * n.1, p.1 + t * n.1 + j * n.0)
                };
                let d = g.foot(s, zz).0;
                let brute = line
                    .windows(2)
                    .map(|w| segment_distance((s, zz), w[0], w[1]))
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    (d.abs() - brute).abs() < 1e-8,
                    "z {z} at ({s}, {zz}): {d} vs {brute}"
                );
                checked += 1;
            }
        }
        assert_eq!(checked, 4_500);
    }

    #[test]
    fn distances_within_a_reach_are_the_feet_s_own() {
        // What a shot's contact check reads (`SpecimenShape::gap_within`): the foot's
        // distance to the bit below the reach, at least the reach above it, at most
        // `-reach` below `-reach` (deep in the part: session 55 found a shot that had
        // jumped that deep in one step taken for one in the air).
        let mut rng = ChaCha8Rng::seed_from_u64(24680);
        let (mut exact, mut beyond, mut deep) = (0, 0, 0);
        for z in [18, 30, 80] {
            let g = gear(z);
            for _ in 0..20_000 {
                let (s, zz) = (
                    (rng.random::<f64>() - 0.5) * 30e-3,
                    (rng.random::<f64>() - 0.1) * 12e-3,
                );
                let reach = [0.1e-3, 0.4e-3, 1e-3][rng.random_range(0..3)];
                let d = g.foot(s, zz).0;
                let w = g.distance_within(s, zz, reach);
                if d <= -reach {
                    assert!(w <= -reach, "({s}, {zz}): {w} for {d}, reach {reach}");
                    deep += 1;
                } else if d.abs() < reach {
                    assert_eq!(w.to_bits(), d.to_bits(), "({s}, {zz}) within {reach}");
                    exact += 1;
                } else {
                    assert!(w >= reach, "({s}, {zz}): {w} for {d}, reach {reach}");
                    beyond += 1;
                }
            }
        }
        assert!(
            exact > 2_000 && beyond > 20_000 && deep > 2_000,
            "{exact} / {beyond} / {deep}"
        );
    }

    #[test]
    fn the_fillet_s_chords_tell_the_side_of_points_beyond_their_gap() {
        // `chord_side` against the exact foot's sign, for points between the fillet's end
        // angles farther than the reach from the profile, down to a reach just above
        // the chords' gap, where the side is hardest to tell.
        let mut rng = ChaCha8Rng::seed_from_u64(13579);
        let (mut air, mut part) = (0, 0);
        for z in [18, 24, 30, 80] {
            let g = gear(z);
            // The bound is microns for this 4 mm module, below the radius of the finest
            // peening media (0.1 mm): the chords serve every such shot.
            assert!(g.chord_gap < 20e-6, "z {z}: gap {}", g.chord_gap);
            let (lo, hi) = (g.chord_angles[0], g.chord_angles[FILLET_PIECES]);
            assert!(
                (lo - g.phi0).abs() < 1e-12,
                "z {z}: {lo} against {}",
                g.phi0
            );
            // The bound (half of `chord_gap`, the rest is room) holds every piece.
            for i in 0..FILLET_PIECES {
                let (v, w) = (g.chords[i], g.chords[i + 1]);
                let (dx, dy) = (w.0 - v.0, w.1 - v.1);
                for j in 1..64 {
                    let phi = g.ends[i].2 + (g.ends[i + 1].2 - g.ends[i].2) * j as f64 / 64.0;
                    let (p, _) = g.fillet_point(phi);
                    let off = ((p.0 - v.0) * dy - (p.1 - v.1) * dx).abs() / len(dx, dy);
                    assert!(off <= 0.5 * g.chord_gap, "z {z}, piece {i}: {off}");
                }
            }
            for _ in 0..20_000 {
                let a = lo + (hi - lo) * rng.random::<f64>();
                let rho = g.r_f + (rng.random::<f64>() - 0.4) * 6e-3;
                let q = (rho * a.sin(), rho * a.cos());
                let d = g.half_foot_with(q, a, Fillet::EXACT).distance;
                let reach = g.chord_gap * (1.0 + 1e-3)
                    + (d.abs() - g.chord_gap).max(0.0) * rng.random::<f64>();
                match g.chord_side(q, a, reach) {
                    Some(side) if d.abs() >= reach => {
                        assert_eq!(side, d > 0.0, "z {z}: q {q:?}, distance {d}, reach {reach}");
                        if side {
                            air += 1;
                        } else {
                            part += 1;
                        }
                    }
                    Some(_) => {}
                    None => panic!("z {z}: no side for {q:?} at {a} within {lo}..{hi}"),
                }
                assert!(g.chord_side(q, a, 0.5 * g.chord_gap).is_none());
            }
        }
        assert!(air > 20_000 && part > 20_000, "{air} / {part}");
    }

    #[test]
    fn fillet_roots_are_a_bisection_s_and_their_feet_hold_the_point() {
        // The root's early stop (`ROOT_STEP`) against a bisection to the last bit, and
        // the foot it gives: `q` lies on the normal at the fillet's point, `distance`
        // from it.
        let mut rng = ChaCha8Rng::seed_from_u64(97531);
        let (mut roots, mut loose) = (0, 0);
        let mut worst: f64 = 0.0;
        for z in [18, 30, 80] {
            let g = gear(z);
            for _ in 0..3_000 {
                let phi = g.phi1 + (g.phi0 - g.phi1) * rng.random::<f64>();
                let (p, n) = g.fillet_point(phi);
                let h = (rng.random::<f64>() - 0.3) * 3e-3;
                let q = (p.0 + h * n.0, p.1 + h * n.1);
                for i in 0..FILLET_PIECES {
                    let side = |x: f64| g.fillet_side(q, (x.cos(), x.sin()), x);
                    let (a, b) = (g.ends[i].2, g.ends[i + 1].2);
                    let (fa, fb) = (side(a), side(b));
                    if fa == 0.0 || fb == 0.0 || (fa < 0.0) == (fb < 0.0) {
                        continue;
                    }
                    let (mut lo, mut hi, flo) = (a, b, fa);
                    while (hi - lo).abs() > 2.0 * f64::EPSILON * hi.abs() {
                        let mid = 0.5 * (lo + hi);
                        let fm = side(mid);
                        if fm == 0.0 {
                            (lo, hi) = (mid, mid);
                        } else if (fm < 0.0) == (flo < 0.0) {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    let got = g.fillet_root(q, (a, fa), (b, fb));
                    // The bisection's root within 1e-13 rad (at most 1e-14 m along the
                    // fillet), or within what the side's rounding allows where that is
                    // more: the rounding of `q` turned into the rack's frame, a few
                    // epsilons of `|q| (|e| + |c|)`, over the side's slope (small near the
                    // fillet's centre of curvature).
                    let (sn, cn) = got.sin_cos();
                    let e = g.hb - g.r_p * got;
                    let rounding = len(q.0, q.1) * (e.abs() + g.c.abs());
                    let slope = g.fillet_side_slope(q, (cn, sn), got).abs();
                    let allowed = (4.0 * f64::EPSILON * rounding / slope).max(1e-13);
                    assert!(
                        (got - lo).abs() <= allowed,
                        "gear {z}, piece {i}: {got} against {lo}, {allowed:e} allowed"
                    );
                    if (got - lo).abs() > 1e-15 {
                        loose += 1;
                    }
                    worst = worst.max((got - lo).abs());
                    let f = g.fillet_foot(q, got);
                    let (pf, nf) = g.fillet_point(got);
                    assert_eq!(f.normal, nf);
                    let miss = len(
                        q.0 - pf.0 - f.distance * nf.0,
                        q.1 - pf.1 - f.distance * nf.1,
                    );
                    assert!(miss < 1e-12, "gear {z}, piece {i}: {miss} m off the normal");
                    roots += 1;
                }
            }
        }
        assert!(roots > 9_000, "{roots} roots");
        eprintln!("{roots} roots, {loose} beyond 1e-15 rad, worst {worst:e} rad");
    }

    #[test]
    fn the_time_to_touch_is_a_lower_bound() {
        let g = gear(24);
        let r = 0.3e-3;
        let mut rng = ChaCha8Rng::seed_from_u64(97531);
        let mut next = || rng.random::<f64>();
        let mut bounded = 0;
        for _ in 0..3000 {
            let (s, z) = ((next() - 0.5) * 30e-3, next() * 12e-3);
            if g.foot(s, z).0 <= r {
                continue;
            }
            let (vs, vz) = ((next() - 0.5) * 100.0, (next() - 0.5) * 100.0);
            let t = g.time_to_touch(s, z, vs, vz, r);
            let span = if t.is_finite() { t } else { 3e-4 };
            for k in 0..=400 {
                let f = span * k as f64 / 400.0;
                let d = g.foot(s + vs * f, z + vz * f).0;
                assert!(
                    d >= r * (1.0 - 1e-9),
                    "touches at {k}/400 of {t:e} from ({s}, {z})"
                );
            }
            bounded += t.is_finite() as usize;
        }
        assert!(bounded > 500, "{bounded}");
    }

    #[test]
    fn gears_that_cannot_be_cut_are_refused() {
        let m = 4e-3;
        let alpha = 20f64.to_radians();
        let (hf, rho) = (1.25 * m, 0.38 * m);
        let pitch = PI * m;
        let hb = pitch / 4.0 - (hf - rho * (1.0 - alpha.sin())) * alpha.tan() - rho * alpha.cos();
        let make = |z: u32, depth: f64, rho_e: f64| {
            Gear::new(z, pitch, alpha, hf, hb, rho, depth, rho_e, 0.0)
        };
        // Undercut below 17 teeth with this rack (the flank's foot 1.0 m below the
        // pitch line: z >= 2 (1.0) / sin^2 20 = 17.1).
        match make(17, 2.25 * m, 0.2 * m) {
            Err(GrooveError::Undercut { needed_teeth }) => assert_eq!(needed_teeth, 18),
            other => panic!("{other:?}"),
        }
        assert!(make(18, 2.25 * m, 0.2 * m).is_ok());
        // A tall addendum comes to a point.
        assert!(matches!(
            make(18, 4.0 * m, 0.2 * m),
            Err(GrooveError::GearTooSmall { .. })
        ));
    }
}
