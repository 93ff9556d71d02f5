//! The paper's empirical free-jet field (Eqs 4-7, 9-11, 25-29) and its regions.
//!
//! Given a point, the field tells which region it lies in (nozzle bore, potential core,
//! mixing layer, developed jet, still air), the air velocity and the air density there.
//! The integrator freezes a shot's region for the length of one step and locates region
//! crossings with [`JetField::margin`], because the field jumps at region borders
//! (model-notes defect 4). Coordinates: `s` is the distance downstream of the nozzle exit
//! along the jet axis (negative inside the bore), `r` the distance from the axis.

use crate::Vec3;
use crate::contact::specimen::SpecimenShape;

/// Tolerance (m) of the bore's inlet plane: a centre placed in the inlet plane belongs
/// to the bore even when `standoff + length - standoff` rounds to a hair above `length`.
pub const INLET_TOLERANCE: f64 = 1e-9;

/// One of the jet's regions (model-notes table "Jet regions").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Region {
    /// Inside the bore: `-l_n <= s < 0`, `r <= d/2`.
    Nozzle,
    /// Potential core: `0 <= s <= 5d`, `r <= (5d - s)/10`.
    Core,
    /// Mixing layer: `0 <= s <= 5d`, `(5d - s)/10 < r <= (5d + s)/10`, downstream of
    /// [`Region::Lip`].
    Mixing,
    /// The mixing layer next to the exit where the paper's Eq 5 density is capped
    /// (`0 <= s <= s_cap`, [`JetField::cap_plane`]; empty in the consistent model). The
    /// same air as the mixing layer; a region of its own because the cap puts a kink in
    /// the density at `s_cap`, and steps that straddled it were rejected (session 36).
    Lip,
    /// Developed jet: `s > 5d`, `r <= s/5`.
    Developed,
    /// Still ambient air everywhere else.
    Outside,
}

impl Region {
    /// Short lower-case name, as used in messages and outputs.
    pub fn name(self) -> &'static str {
        match self {
            Region::Nozzle => "nozzle",
            Region::Core => "core",
            Region::Mixing | Region::Lip => "mixing",
            Region::Developed => "developed",
            Region::Outside => "outside",
        }
    }
}

/// Which density laws the field uses (model-notes defects 1-3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JetModel {
    /// The paper's laws: Eq 5 in the mixing layer (capped, see [`JetField::lip_density_cap`])
    /// and Eq 7 in the developed region.
    Paper,
    /// Bounded densities relaxing from the core density to ambient: in the mixing layer
    /// `rho_ab + (rho_c - rho_ab) u/u_i`, in the developed region
    /// `rho_ab + (rho_c - rho_ab) (5d/s) exp(-94 (r/s)^2)`.
    Consistent,
}

/// Air velocity and density at a point (one flow sample).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlowSample {
    /// Air velocity, m/s (world frame).
    pub velocity: Vec3,
    /// Air density, kg/m^3.
    pub density: f64,
    /// Jet coordinates of the point.
    pub coords: JetCoords,
}

/// Position of a point in the nozzle frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JetCoords {
    /// Distance downstream of the exit plane along the axis, m (negative in the bore).
    pub s: f64,
    /// Distance from the jet axis, m.
    pub r: f64,
    /// Offset of the point from the axis, perpendicular to it (length `r`), m.
    pub offset: Vec3,
}

impl JetCoords {
    /// Unit vector from the axis towards the point, perpendicular to the axis (zero on
    /// it). Only the lateral force needs it, so it is not formed with the coordinates:
    /// that saves three divisions per flow sample where that force is zero or off.
    #[inline]
    pub fn radial(&self) -> Vec3 {
        if self.r > 0.0 {
            self.offset / self.r
        } else {
            Vec3::zeros()
        }
    }
}

/// The jet field of one nozzle. Built once per run.
#[derive(Debug, Clone, PartialEq)]
pub struct JetField {
    /// Centre of the nozzle exit plane, m (world frame).
    pub exit: Vec3,
    /// Unit vector along the jet axis, pointing downstream.
    pub axis: Vec3,
    /// Bore diameter `d`, m.
    pub bore: f64,
    /// Bore (acceleration) length `l_n`, m.
    pub length: f64,
    /// Exit air velocity `u_i`, m/s.
    pub exit_velocity: f64,
    /// Density in the bore and potential core (Eq 12 `rho*` by default, or `rho_0`), kg/m^3.
    pub rho_core: f64,
    /// Nozzle-exit density `rho*` entering Eqs 5 and 7 (`rho_as` of the paper), kg/m^3.
    pub rho_exit: f64,
    /// Ambient density `rho_ab`, kg/m^3.
    pub rho_ambient: f64,
    /// Cap on the Eq 5 mixing density in the paper model (default: `rho_0`), kg/m^3.
    /// Eq 5 diverges as `s -> 0`; no air in the jet can be denser than the stagnation air.
    pub lip_density_cap: f64,
    /// Density laws.
    pub model: JetModel,
    /// Thickness `delta` (m) of the stagnation layer above the flat specimen, or round
    /// the bar of [`JetField::layer_surface`] (beyond the paper; `None`: the free jet runs on
    /// into the part, as in the paper). Within it the air's velocity component normal to
    /// the surface is the free jet's times [`stagnation_factor`]`(h / delta)` (`h` the
    /// height above the surface, `z` over the plate), so that it vanishes at the wall;
    /// its components along the surface are the free jet's. Densities stay the free
    /// jet's.
    pub layer: Option<f64>,
    /// Whether the air the layer stops flows out along the plate (the wall jet, beyond
    /// the paper; only with a layer over the plate and a jet normal to it): a radial velocity
    /// [`stagnation_slope`]`(z / delta) / delta` times `r` [`JetField::enclosed_mean`],
    /// which is what continuity asks of the layer's slowed normal flow (within the
    /// layer the air then conserves mass as well as the free jet does, times the
    /// layer's factor).
    pub wall_jet: bool,
    /// The surface the layer lies on: the flat plate (the default), or a bar (beyond the
    /// paper; the scene refuses a layer in a groove). Over a bar the layer's height is
    /// the distance from the bar's surface and its normal the bar's, away from its axis.
    pub layer_surface: SpecimenShape,
}

/// The share of the free jet's normal air speed left at height `x` layer thicknesses
/// above the plate: `x (2 - x)` in the layer (0 at the wall, rising linearly as a
/// stagnation-point flow does, joining 1 with zero slope at its top, so the force is
/// smooth there), 1 above it.
#[inline]
pub fn stagnation_factor(x: f64) -> f64 {
    if x >= 1.0 {
        1.0
    } else if x <= 0.0 {
        0.0
    } else {
        x * (2.0 - x)
    }
}

/// The slope `f'(x)` of [`stagnation_factor`]: `2 (1 - x)` in the layer (2 at the wall),
/// 0 above it. The wall jet's radial speed is proportional to it: the normal flow the
/// layer takes away at height `x`, turned aside.
#[inline]
pub fn stagnation_slope(x: f64) -> f64 {
    if x >= 1.0 {
        0.0
    } else if x <= 0.0 {
        2.0
    } else {
        2.0 * (1.0 - x)
    }
}

/// `(1 - exp(-q)) / q`, 1 at `q = 0` (the developed jet's enclosed flow over its axis'
/// share).
#[inline]
fn expm1_ratio(q: f64) -> f64 {
    if q < 1e-3 {
        // The series to `q^4` (its next term is below 1e-17).
        1.0 - q * (0.5 - q * (1.0 / 6.0 - q * (1.0 / 24.0 - q / 120.0)))
    } else {
        -(-q).exp_m1() / q
    }
}

/// `1 - exp(-94 / 25)`: the share of the developed jet's Gaussian flow (its speed
/// `exp(-94 (r/s)^2)`) within its edge `r = s/5` (checked against `exp_m1` in the tests).
const DEVELOPED_EDGE_FLOW: f64 = 0.976716259625103;

impl JetField {
    /// Nozzle-frame coordinates of `pos`.
    #[inline]
    pub fn coords(&self, pos: &Vec3) -> JetCoords {
        let rel = pos - self.exit;
        let s = rel.dot(&self.axis);
        let offset = rel - self.axis * s;
        let r = offset.norm();
        JetCoords { s, r, offset }
    }

    /// The region containing a point. Borders belong to the upstream / inner region:
    /// the exit plane to the core, `s = 5d` to core or mixing, the core-mixing border to
    /// the core, and each region's outer edge to that region.
    pub fn region_of(&self, c: &JetCoords) -> Region {
        let d = self.bore;
        let (s, r) = (c.s, c.r);
        if s < 0.0 {
            if s >= -self.length - INLET_TOLERANCE && r <= 0.5 * d {
                Region::Nozzle
            } else {
                Region::Outside
            }
        } else if s <= 5.0 * d {
            if r <= (5.0 * d - s) / 10.0 {
                Region::Core
            } else if r <= (5.0 * d + s) / 10.0 {
                if s <= self.cap_plane() {
                    Region::Lip
                } else {
                    Region::Mixing
                }
            } else {
                Region::Outside
            }
        } else if r <= s / 5.0 {
            Region::Developed
        } else {
            Region::Outside
        }
    }

    /// Height (m) of `pos` above the surface the stagnation layer lies on: the plate's
    /// `z`, or the distance from the bar's surface.
    #[inline]
    fn layer_height(&self, pos: &Vec3) -> f64 {
        self.layer_surface.distance(pos)
    }

    /// Whether a centre at `pos` is below the stagnation layer's top (false without one).
    #[inline]
    pub fn in_layer(&self, pos: &Vec3) -> bool {
        self.layer
            .is_some_and(|delta| self.layer_height(pos) < delta)
    }

    /// Signed margin (m) of a centre at `pos` against crossing the stagnation layer's top
    /// from the side `in_layer` (below it if true): positive on that side, zero on the
    /// top; infinite without a layer. The top is smooth in the air's value but not in
    /// its slopes (the normal speed's second derivative, the wall jet's first), so the
    /// integrator locates its crossings as it does the regions' borders.
    #[inline]
    pub fn layer_margin(&self, pos: &Vec3, in_layer: bool) -> f64 {
        match self.layer {
            Some(delta) if in_layer => delta - self.layer_height(pos),
            Some(delta) => self.layer_height(pos) - delta,
            None => f64::INFINITY,
        }
    }

    /// Signed margin (m) of a point against leaving `region`: positive inside, zero on
    /// its border, negative outside. Continuous in position, so a root finder can locate
    /// the crossing. For [`Region::Outside`] it is the margin against entering any region.
    pub fn margin(&self, c: &JetCoords, region: Region) -> f64 {
        match region {
            Region::Outside => {
                let inside = [
                    Region::Nozzle,
                    Region::Core,
                    Region::Lip,
                    Region::Mixing,
                    Region::Developed,
                ]
                .iter()
                .map(|&k| self.margin(c, k))
                .fold(f64::NEG_INFINITY, f64::max);
                -inside
            }
            _ => self.inner_margin(c, region),
        }
    }

    fn inner_margin(&self, c: &JetCoords, region: Region) -> f64 {
        let d = self.bore;
        let (s, r) = (c.s, c.r);
        match region {
            // The bore's open end at the exit plane belongs to the core: margin -s.
            Region::Nozzle => (s + self.length + INLET_TOLERANCE).min(-s).min(0.5 * d - r),
            Region::Core => s.min(5.0 * d - s).min((5.0 * d - s) / 10.0 - r),
            Region::Lip => s
                .min(self.cap_plane() - s)
                .min(r - (5.0 * d - s) / 10.0)
                .min((5.0 * d + s) / 10.0 - r),
            Region::Mixing => (s - self.cap_plane())
                .min(5.0 * d - s)
                .min(r - (5.0 * d - s) / 10.0)
                .min((5.0 * d + s) / 10.0 - r),
            Region::Developed => (s - 5.0 * d).min(s / 5.0 - r),
            Region::Outside => unreachable!("BUG: outside margin handled by margin()"),
        }
    }

    /// Air velocity and density at `pos`, using the laws of `region` (the shot's frozen
    /// region for the current step; it may differ from [`Self::region_of`] by a round-off
    /// amount at a located border crossing).
    #[inline]
    pub fn sample(&self, pos: &Vec3, region: Region) -> FlowSample {
        let c = self.coords(pos);
        let (u, density) = self.speed_density(&c, region);
        let mut velocity = self.axis * u;
        if let Some(delta) = self.layer
            && (pos.z < delta || !self.layer_surface.is_plane())
        {
            self.turn_aside(&mut velocity, pos, &c, region, u, delta);
        }
        FlowSample {
            velocity,
            density,
            coords: c,
        }
    }

    /// The stagnation layer's turn of the free jet's `velocity` (axial speed `u`) at
    /// `pos`, below the plate layer's top or anywhere over a bar: within the layer (at
    /// `x` = height / `delta`) its part normal to the surface slowed, and with the wall
    /// jet (over the plate) the air it stops sent outwards. Out of line, so that
    /// [`Self::sample`] stays small enough to inline into the force models for the scenes
    /// without a layer.
    #[inline(never)]
    fn turn_aside(
        &self,
        velocity: &mut Vec3,
        pos: &Vec3,
        c: &JetCoords,
        region: Region,
        u: f64,
        delta: f64,
    ) {
        if !self.layer_surface.is_plane() {
            let (height, normal) = self.layer_surface.distance_normal(pos);
            let x = height / delta;
            if x < 1.0 {
                *velocity -= normal * (velocity.dot(&normal) * (1.0 - stagnation_factor(x)));
            }
            return;
        }
        let x = pos.z / delta;
        velocity.z *= stagnation_factor(x);
        if self.wall_jet {
            // The jet is normal to the plate: the offset from the axis lies in it.
            let mean = self.enclosed_mean(c, region, u);
            *velocity += c.offset * (stagnation_slope(x) / delta * mean);
        }
    }

    /// Axial air speed (m/s, towards the specimen) and density (kg/m^3) by region.
    pub fn speed_density(&self, c: &JetCoords, region: Region) -> (f64, f64) {
        let d = self.bore;
        let ui = self.exit_velocity;
        // Regions downstream of the exit are only evaluated at s >= 0 (up to a located
        // crossing); the floor keeps the 1/s laws finite at the lip (model-notes defect 2).
        let s = c.s.max(1e-9 * d);
        match region {
            Region::Nozzle | Region::Core => (ui, self.rho_core),
            Region::Mixing | Region::Lip => {
                // Eq 10 with |x| read as r: u_i at the core edge, 0 at the outer edge.
                let u = 5.0 * ui / s * ((5.0 * d + s) / 10.0 - c.r);
                let rho = match self.model {
                    JetModel::Paper if region == Region::Lip => self.lip_density_cap,
                    JetModel::Paper => {
                        let q = 5.0 * d / s;
                        (0.75 * self.rho_exit * (q * q - 1.0)).min(self.lip_density_cap)
                    }
                    JetModel::Consistent => {
                        self.rho_ambient
                            + (self.rho_core - self.rho_ambient) * (u / ui).clamp(0.0, 1.0)
                    }
                };
                (u, rho)
            }
            Region::Developed => {
                let q = c.r / s;
                let shape = (-94.0 * q * q).exp();
                let u = 6.0 * d * ui / s * shape; // Eq 11
                let rho = match self.model {
                    // Eq 7: rises from rho_ab at s = 5d towards rho* far downstream.
                    JetModel::Paper => {
                        self.rho_exit * (s - 5.0 * d) / s + self.rho_ambient * 5.0 * d / s
                    }
                    JetModel::Consistent => {
                        self.rho_ambient
                            + (self.rho_core - self.rho_ambient) * (5.0 * d / s) * shape
                    }
                };
                (u, rho)
            }
            Region::Outside => (0.0, self.rho_ambient),
        }
    }

    /// `J = (1/r^2) int_0^r u(r', s) r' dr'` (m/s) at the point's `s`, by the laws of
    /// `region` (the jet's axial speed `u` of Eqs 9-11): the axial flow through the disc
    /// of radius `r` across the jet, over `pi r^2`, halved. Finite on the axis (half the
    /// axial speed there); beyond the jet's edge the whole jet's flow over `r^2`, so the
    /// wall jet's radial speed `r J` falls as `1/r` there. Continuous across the radial
    /// borders (the core's edge, the mixing layer's and the developed jet's outer edges);
    /// it jumps at `s = 5d` with the paper's field (model-notes defect 4). `u` is the
    /// axial speed at the point by the same laws ([`Self::speed_density`]'s): the
    /// developed jet's Gaussian is read off it rather than computed again.
    pub fn enclosed_mean(&self, c: &JetCoords, region: Region, u: f64) -> f64 {
        let d = self.bore;
        let ui = self.exit_velocity;
        let s = c.s.max(1e-9 * d);
        let r2 = c.r * c.r;
        // `int_0^r u r' dr'` of the core and mixing layer, `r` beyond the core's edge.
        let near = |r: f64| {
            let rc = ((5.0 * d - s) / 10.0).max(0.0);
            let ro = (5.0 * d + s) / 10.0;
            0.5 * ui * rc * rc
                + 5.0 * ui / s * (ro * (r * r - rc * rc) / 2.0 - (r * r * r - rc * rc * rc) / 3.0)
        };
        // Half the developed jet's axial speed on its axis, and its Gaussian's `94 / s^2`.
        let developed = || (3.0 * d * ui / s, 94.0 / (s * s));
        match region {
            Region::Nozzle | Region::Core => 0.5 * ui,
            Region::Mixing | Region::Lip => {
                if r2 < 1e-24 {
                    0.5 * ui
                } else {
                    near(c.r) / r2
                }
            }
            Region::Developed => {
                // `(u_0 / 2) (1 - exp(-q)) / q` with `u = u_0 exp(-q)`; near the axis,
                // where the difference cancels, by its series.
                let (half, k) = developed();
                let q = k * r2;
                if q < 1e-3 {
                    half * expm1_ratio(q)
                } else {
                    (half - 0.5 * u) / q
                }
            }
            Region::Outside if c.s < 0.0 => 0.0,
            Region::Outside if s <= 5.0 * d => {
                let ro = (5.0 * d + s) / 10.0;
                near(ro) / r2.max(ro * ro)
            }
            Region::Outside => {
                let (half, k) = developed();
                let edge = 0.04 * s * s;
                half * DEVELOPED_EDGE_FLOW / (k * r2.max(edge))
            }
        }
    }

    /// The plane `s_cap` up to which the paper's Eq 5 density `0.75 rho* ((5d/s)^2 - 1)`
    /// is capped at [`JetField::lip_density_cap`] (the end of [`Region::Lip`]); 0 in the
    /// consistent model, which has no cap.
    #[inline]
    pub fn cap_plane(&self) -> f64 {
        match self.model {
            JetModel::Paper if self.rho_exit > 0.0 => {
                5.0 * self.bore / (1.0 + self.lip_density_cap / (0.75 * self.rho_exit)).sqrt()
            }
            _ => 0.0,
        }
    }

    /// Largest air speed anywhere in the field, m/s (`1.2 u_i` at the start of the
    /// developed region, Eq 11; with a wall jet, a bound on its radial speed added across:
    /// `r J <= u_i d / 2` everywhere, so the radial speed stays below `u_i d / delta`).
    /// Used for conservative reach bounds.
    pub fn max_speed(&self) -> f64 {
        let axial = 1.2 * self.exit_velocity;
        match self.layer {
            Some(delta) if self.wall_jet => axial.hypot(self.exit_velocity * self.bore / delta),
            _ => axial,
        }
    }

    /// The wall jet's fastest air at the wall (its radial speed at `z = 0`, the largest
    /// over the distance from the axis) over the free jet's axial speed on the axis at
    /// the wall: the wall jet's fastest air is not to outrun the jet that feeds it. A
    /// property of the bore, the stand-off and the layer alone (speeds scale with `u_i`);
    /// the jet is normal to the plate.
    pub fn wall_jet_peak_ratio(bore: f64, standoff: f64, delta: f64) -> f64 {
        let f = JetField {
            exit: Vec3::new(0.0, 0.0, standoff),
            axis: Vec3::new(0.0, 0.0, -1.0),
            bore,
            length: bore,
            exit_velocity: 1.0,
            rho_core: 1.0,
            rho_exit: 1.0,
            rho_ambient: 1.0,
            lip_density_cap: 1.0,
            model: JetModel::Consistent,
            layer: Some(delta),
            wall_jet: true,
            layer_surface: SpecimenShape::Plane,
        };
        let radial = |r: f64| {
            let p = Vec3::new(r, 0.0, 0.0);
            f.sample(&p, f.region_of(&f.coords(&p))).velocity.x
        };
        let foot = f.coords(&Vec3::zeros());
        let (on_axis, _) = f.speed_density(&foot, f.region_of(&foot));
        // The radial speed rises from 0 on the axis to one maximum near the jet's edge
        // and falls as 1/r beyond it: a scan, then golden sections around the best.
        let reach = standoff.max(5.0 * bore);
        let n = 2000;
        let dr = reach / n as f64;
        let best = (1..=n)
            .map(|i| i as f64 * dr)
            .max_by(|a, b| radial(*a).total_cmp(&radial(*b)))
            .unwrap_or(dr);
        let (mut lo, mut hi) = ((best - dr).max(0.0), best + dr);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..60 {
            let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if radial(a) < radial(b) {
                lo = a;
            } else {
                hi = b;
            }
        }
        radial(0.5 * (lo + hi)).max(radial(best)) / on_axis
    }

    /// Largest air density anywhere in the field, kg/m^3.
    pub fn max_density(&self) -> f64 {
        self.rho_core
            .max(self.lip_density_cap)
            .max(self.rho_exit)
            .max(self.rho_ambient)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The paper's jet (6 mm bore, 313 m/s exit), for tests elsewhere too.
    pub(crate) fn paper_field(model: JetModel) -> JetField {
        JetField {
            exit: Vec3::new(0.0, 0.0, 0.1),
            axis: Vec3::new(0.0, 0.0, -1.0),
            bore: 6e-3,
            length: 40e-3,
            exit_velocity: 313.25,
            rho_core: 5.3478,
            rho_exit: 5.3478,
            rho_ambient: 1.205,
            lip_density_cap: 8.435,
            model,
            layer: None,
            wall_jet: false,
            layer_surface: SpecimenShape::Plane,
        }
    }

    fn at(f: &JetField, s: f64, r: f64) -> JetCoords {
        f.coords(&(f.exit + f.axis * s + Vec3::new(r, 0.0, 0.0)))
    }

    #[test]
    fn regions_follow_model_notes_table() {
        let f = paper_field(JetModel::Paper);
        let d = f.bore;
        assert_eq!(f.region_of(&at(&f, -0.02, 0.0)), Region::Nozzle);
        assert_eq!(f.region_of(&at(&f, -0.02, 0.004)), Region::Outside);
        assert_eq!(f.region_of(&at(&f, -0.05, 0.0)), Region::Outside);
        // The inlet plane belongs to the bore, whatever the rounding of its height.
        let inlet = f.coords(&Vec3::new(0.0, 0.0, 0.14));
        assert_eq!(f.region_of(&inlet), Region::Nozzle);
        assert!(f.margin(&inlet, Region::Nozzle) >= 0.0);
        assert_eq!(f.region_of(&at(&f, 0.0, 0.0)), Region::Core);
        assert_eq!(f.region_of(&at(&f, 0.0, 0.5 * d)), Region::Core); // the lip
        assert_eq!(f.region_of(&at(&f, 2.0 * d, 0.25 * d)), Region::Core);
        assert_eq!(f.region_of(&at(&f, 2.0 * d, 0.4 * d)), Region::Lip);
        assert_eq!(f.region_of(&at(&f, 4.0 * d, 0.5 * d)), Region::Mixing);
        assert_eq!(f.region_of(&at(&f, 2.0 * d, 0.8 * d)), Region::Outside);
        assert_eq!(f.region_of(&at(&f, 5.0 * d, 0.0)), Region::Core);
        assert_eq!(f.region_of(&at(&f, 6.0 * d, 1.0 * d)), Region::Developed);
        assert_eq!(f.region_of(&at(&f, 6.0 * d, 1.3 * d)), Region::Outside);
    }

    /// The lip region ends where Eq 5's density reaches the cap (2.84 d with the paper
    /// scene, docs/model.md): the density is continuous across it, capped before it,
    /// Eq 5 after it; the consistent model has no cap and no lip.
    #[test]
    fn the_lip_ends_where_eq_5_reaches_the_cap() {
        let f = paper_field(JetModel::Paper);
        let d = f.bore;
        let cap = f.cap_plane();
        assert!((cap / d - 2.84).abs() < 0.005, "s_cap = {} d", cap / d);
        let rho = |s: f64, region| f.speed_density(&at(&f, s, 0.4 * d), region).1;
        let q = 5.0 * d / cap;
        let eq5 = 0.75 * f.rho_exit * (q * q - 1.0);
        assert!((eq5 / f.lip_density_cap - 1.0).abs() < 1e-12);
        assert!((rho(cap, Region::Mixing) / rho(cap, Region::Lip) - 1.0).abs() < 1e-12);
        assert_eq!(rho(0.5 * cap, Region::Lip), f.lip_density_cap);
        assert!(rho(1.5 * cap, Region::Mixing) < f.lip_density_cap);
        // The air's velocity is the mixing layer's on both sides.
        let u = |s: f64, region| f.speed_density(&at(&f, s, 0.4 * d), region).0;
        assert_eq!(u(0.5 * cap, Region::Lip), u(0.5 * cap, Region::Mixing));
        let c = paper_field(JetModel::Consistent);
        assert_eq!(c.cap_plane(), 0.0);
        assert_eq!(c.region_of(&at(&c, 0.5 * cap, 0.4 * d)), Region::Mixing);
    }

    #[test]
    fn margins_vanish_on_borders_and_change_sign_across() {
        let f = paper_field(JetModel::Paper);
        let d = f.bore;
        // Core/mixing border at s = 2d: r = 0.3 d.
        let on = at(&f, 2.0 * d, 0.3 * d);
        assert!(f.margin(&on, Region::Core).abs() < 1e-15);
        assert!(f.margin(&at(&f, 2.0 * d, 0.31 * d), Region::Core) < 0.0);
        assert!(f.margin(&at(&f, 2.0 * d, 0.31 * d), Region::Lip) > 0.0);
        // Lip/mixing border at the cap's plane.
        let cap = f.cap_plane();
        assert!(f.margin(&at(&f, cap, 0.4 * d), Region::Lip).abs() < 1e-15);
        assert!(f.margin(&at(&f, cap * 1.001, 0.4 * d), Region::Lip) < 0.0);
        assert!(f.margin(&at(&f, cap * 1.001, 0.4 * d), Region::Mixing) > 0.0);
        assert!(f.margin(&at(&f, cap * 0.999, 0.4 * d), Region::Mixing) < 0.0);
        // Outside margin is positive outside, negative once inside any region.
        assert!(f.margin(&at(&f, 2.0 * d, 0.9 * d), Region::Outside) > 0.0);
        assert!(f.margin(&at(&f, 2.0 * d, 0.6 * d), Region::Outside) < 0.0);
        // Every region's own points have a non-negative margin.
        for &(s, r) in &[(-0.01, 0.001), (0.01, 0.0), (0.02, 0.0025), (0.05, 0.003)] {
            let c = at(&f, s, r);
            assert!(f.margin(&c, f.region_of(&c)) >= 0.0, "s={s} r={r}");
        }
    }

    #[test]
    fn velocities_match_paper_equations() {
        let f = paper_field(JetModel::Paper);
        let d = f.bore;
        let ui = f.exit_velocity;
        // Mixing: u_i at the inner edge, 0 at the outer edge (Eq 10).
        let s = 3.0 * d;
        let (u_in, _) = f.speed_density(&at(&f, s, (5.0 * d - s) / 10.0), Region::Mixing);
        let (u_out, _) = f.speed_density(&at(&f, s, (5.0 * d + s) / 10.0), Region::Mixing);
        assert!((u_in - ui).abs() < 1e-9 && u_out.abs() < 1e-9);
        // Developed on axis at s = 5d: 1.2 u_i (the jump of model-notes defect 4).
        let (u_dev, rho_dev) = f.speed_density(&at(&f, 5.0 * d, 0.0), Region::Developed);
        assert!((u_dev - 1.2 * ui).abs() < 1e-9);
        // Eq 7 at s = 5d equals rho_ab.
        assert!((rho_dev - f.rho_ambient).abs() < 1e-12);
        // Eq 5 at s = 4 d: 0.75 rho* ((5/4)^2 - 1) (below the cap).
        let (_, rho_mix) = f.speed_density(&at(&f, 4.0 * d, 0.3 * d), Region::Mixing);
        assert!((rho_mix - 0.75 * f.rho_exit * (1.5625 - 1.0)).abs() < 1e-12);
        // ... and capped at the lip.
        let (_, rho_lip) = f.speed_density(&at(&f, 1e-6, 0.5 * d), Region::Mixing);
        assert_eq!(rho_lip, f.lip_density_cap);
    }

    #[test]
    fn consistent_densities_are_bounded_between_ambient_and_core() {
        let f = paper_field(JetModel::Consistent);
        let d = f.bore;
        for i in 0..200 {
            let s = 12.0 * d * (i as f64 + 0.5) / 200.0;
            for j in 0..50 {
                let r = 2.5 * d * j as f64 / 50.0;
                let c = at(&f, s, r);
                let region = f.region_of(&c);
                let (_, rho) = f.speed_density(&c, region);
                assert!(rho >= f.rho_ambient - 1e-12 && rho <= f.rho_core + 1e-12);
            }
        }
    }

    /// The stagnation layer (beyond the paper) takes the air's normal component down to
    /// zero at the wall as `x (2 - x)` of its free value (`x = z / delta`), and leaves its
    /// component along the plate, its density, and everything above the layer as the free
    /// jet's, to the bit. A tilted jet (45 degrees) shows both components.
    #[test]
    fn the_stagnation_layer_slows_only_the_air_normal_to_the_plate_within_it() {
        let mut free = paper_field(JetModel::Paper);
        free.axis = Vec3::new(1.0, 0.0, -1.0).normalize();
        let layered = JetField {
            layer: Some(0.012),
            ..free.clone()
        };
        for z in [
            0.02, 0.012, 0.0115, 0.009, 0.006, 0.003, 0.0004, 0.0, -0.0001,
        ] {
            // On the axis, `z` above the plate.
            let p = free.exit + free.axis * ((free.exit.z - z) / -free.axis.z);
            let region = free.region_of(&free.coords(&p));
            let (a, b) = (free.sample(&p, region), layered.sample(&p, region));
            assert_eq!(a.density, b.density);
            assert_eq!((a.velocity.x, a.velocity.y), (b.velocity.x, b.velocity.y));
            let x: f64 = (z / 0.012).clamp(0.0, 1.0);
            let want = a.velocity.z * (1.0 - (1.0 - x) * (1.0 - x));
            assert!(
                (b.velocity.z - want).abs() <= 1e-12 * a.velocity.z.abs(),
                "z = {z}: {} against {want}",
                b.velocity.z
            );
            if z >= 0.012 {
                assert_eq!(a.velocity, b.velocity);
            }
            assert!(
                a.velocity.z < -10.0,
                "the jet blows down here: {}",
                a.velocity
            );
        }
    }

    /// Over a bar (beyond the paper) the layer does what it does over the plate, with the
    /// bar's normal: the air's component along the normal away from the bar's axis is the
    /// free jet's times `x (2 - x)`, `x` = height above the bar / `delta`; the two
    /// components along the surface and the density are the free jet's, and above the
    /// layer everything is, to the bit. Points all round a bar of 5 mm (tilted axis, 30
    /// degrees from x) under a tilted jet; on the crest line the normal is the plate's.
    /// The layer's top is where its margin changes sign, and its side is `in_layer`'s.
    #[test]
    fn over_a_bar_the_layer_slows_only_the_air_normal_to_the_bar() {
        let (radius, delta) = (0.005, 0.004);
        let mut free = paper_field(JetModel::Paper);
        free.axis = Vec3::new(1.0, 0.5, -2.0).normalize();
        free.exit = -free.axis * 0.1;
        let axis = Vec3::new(30f64.to_radians().cos(), 30f64.to_radians().sin(), 0.0);
        let bar = SpecimenShape::Cylinder { radius, axis };
        let layered = JetField {
            layer: Some(delta),
            layer_surface: bar.clone(),
            ..free.clone()
        };
        let centre = Vec3::new(0.0, 0.0, -radius);
        let across = axis.cross(&Vec3::z());
        let mut slowed = 0;
        for along in [-0.004, 0.0, 0.0025] {
            for deg in [0.0, 10.0, 45.0, 80.0, -60.0, 120.0, 180.0] {
                let phi: f64 = f64::to_radians(deg);
                let normal = Vec3::z() * phi.cos() + across * phi.sin();
                for h in [0.0, 1e-4, 0.001, 0.002, 0.0039, 0.004, 0.0045, 0.01] {
                    let p = centre + axis * along + normal * (radius + h);
                    let region = free.region_of(&free.coords(&p));
                    let (a, b) = (free.sample(&p, region), layered.sample(&p, region));
                    assert_eq!(a.density, b.density);
                    assert!((bar.distance(&p) - h).abs() < 1e-15, "height at {p}");
                    let x: f64 = (h / delta).min(1.0);
                    let want_n = a.velocity.dot(&normal) * x * (2.0 - x);
                    let tangent = axis.cross(&normal);
                    let scale = 1e-12 * (a.velocity.norm() + 1.0);
                    assert!((b.velocity.dot(&normal) - want_n).abs() <= scale);
                    assert!((b.velocity.dot(&axis) - a.velocity.dot(&axis)).abs() <= scale);
                    assert!((b.velocity.dot(&tangent) - a.velocity.dot(&tangent)).abs() <= scale);
                    if h >= delta {
                        assert_eq!(a.velocity, b.velocity);
                    } else if a.velocity.dot(&normal).abs() > 1.0 {
                        slowed += 1;
                    }
                    if h != delta {
                        assert_eq!(layered.in_layer(&p), h < delta, "h = {h}");
                        let m = layered.layer_margin(&p, h < delta);
                        assert!(m > 0.0 && (m - (h - delta).abs()).abs() < 1e-15);
                    }
                    if deg == 0.0 && along == 0.0 {
                        // The crest line: the plate's layer, to rounding.
                        let plate = JetField {
                            layer_surface: SpecimenShape::Plane,
                            ..layered.clone()
                        };
                        let c = plate.sample(&p, region).velocity;
                        assert!(
                            (c - b.velocity).norm() <= scale,
                            "{c} against {}",
                            b.velocity
                        );
                    }
                }
            }
        }
        assert!(slowed > 30, "the test sees the jet slowed: {slowed}");
    }

    /// A jet normal to a plate at `standoff` (m), with a layer `delta` (m) and a wall jet.
    fn wall_jet_field(model: JetModel, standoff: f64, delta: f64) -> JetField {
        let mut f = paper_field(model);
        f.exit = Vec3::new(0.0, 0.0, standoff);
        f.layer = Some(delta);
        f.wall_jet = true;
        f
    }

    /// The wall jet is the layer's slowed normal flow turned aside: within the layer the
    /// air's divergence is the free jet's times the layer's factor `f(z / delta)` (the
    /// paper's axial jet is not itself divergence-free: it speeds up and slows down along
    /// its axis without drawing air in). Central differences of `sample` in x, y and z
    /// (fourth order, steps of 0.1 um) at points all over the layer, in the developed jet
    /// (a 100 mm stand-off), in the core and mixing layer (20 mm), and beyond the jet's
    /// edge; tolerance 1e-6 of the terms' sizes (`u / delta` and the three derivatives').
    #[test]
    fn the_wall_jet_conserves_the_mass_the_layer_stops() {
        for (standoff, delta) in [(0.1, 0.014), (0.1, 0.006), (0.02, 0.004), (0.02, 0.02)] {
            for model in [JetModel::Paper, JetModel::Consistent] {
                let layered = wall_jet_field(model, standoff, delta);
                let free = JetField {
                    layer: None,
                    wall_jet: false,
                    ..layered.clone()
                };
                // Fourth-order central differences, and the sum of the three terms' sizes.
                let h = 1e-7;
                let div = |f: &JetField, p: Vec3, region| {
                    let v = |dp: Vec3| f.sample(&(p + dp), region).velocity;
                    let d = |e: Vec3, k: usize| {
                        (8.0 * (v(e * h) - v(-e * h))[k] - (v(e * 2.0 * h) - v(-e * 2.0 * h))[k])
                            / (12.0 * h)
                    };
                    let terms = [d(Vec3::x(), 0), d(Vec3::y(), 1), d(Vec3::z(), 2)];
                    (
                        terms.iter().sum::<f64>(),
                        terms.iter().map(|t| t.abs()).sum::<f64>(),
                    )
                };
                let mut checked = 0;
                for i in 1..20 {
                    let z = delta * i as f64 / 20.0;
                    for j in 0..60 {
                        let r = 0.45e-3 * j as f64 + 0.1e-3;
                        let p = Vec3::new(0.6 * r, 0.8 * r, z);
                        let c = layered.coords(&p);
                        let region = layered.region_of(&c);
                        // Stencils that straddle a border or the layer's top see a jump.
                        let near_border = [-1.0, 1.0].iter().any(|&sx| {
                            [Vec3::x(), Vec3::y(), Vec3::z()].iter().any(|e| {
                                let q = layered.coords(&(p + e * (3.0 * h * sx)));
                                layered.region_of(&q) != region
                            })
                        });
                        if near_border || (z - delta).abs() < 3.0 * h {
                            continue;
                        }
                        let (u, _) = layered.speed_density(&c, region);
                        let (free_div, free_size) = div(&free, p, region);
                        let want = stagnation_factor(z / delta) * free_div;
                        let (got, size) = div(&layered, p, region);
                        let scale = (u.abs() + 1.0) / delta + size + free_size;
                        assert!(
                            (got - want).abs() < 1e-6 * scale,
                            "standoff {standoff}, delta {delta}, {region:?} at r = {r}, z = {z}: \
                             divergence {got} against {want} (scale {scale})"
                        );
                        checked += 1;
                    }
                }
                assert!(checked > 800, "{checked} points");
            }
        }
    }

    #[test]
    fn the_developed_jet_s_edge_flow_is_its_gaussian_s() {
        assert_eq!(DEVELOPED_EDGE_FLOW, -(-94.0f64 / 25.0).exp_m1());
    }

    /// The flow enclosed within `r` is the same by the laws on either side of a radial
    /// border (the core's edge, the mixing layer's and the developed jet's outer edges),
    /// so the wall jet has no jump there; and it is the integral of the axial speed
    /// (composite Simpson, 2,000 intervals between borders) in every region.
    #[test]
    fn the_enclosed_flow_is_continuous_and_is_the_integral() {
        let f = wall_jet_field(JetModel::Paper, 0.1, 0.014);
        let d = f.bore;
        let j = |s: f64, r: f64, region| {
            let c = at(&f, s, r);
            f.enclosed_mean(&c, region, f.speed_density(&c, region).0)
        };
        for s in [0.5 * d, 2.0 * d, 4.5 * d] {
            let (rc, ro) = ((5.0 * d - s) / 10.0, (5.0 * d + s) / 10.0);
            let (a, b) = (j(s, rc, Region::Core), j(s, rc, Region::Mixing));
            assert!(
                (a / b - 1.0).abs() < 1e-12,
                "core edge at s = {s}: {a} against {b}"
            );
            let (a, b) = (j(s, ro, Region::Mixing), j(s, ro, Region::Outside));
            assert!(
                (a / b - 1.0).abs() < 1e-12,
                "mixing edge at s = {s}: {a} against {b}"
            );
        }
        for s in [5.5 * d, 10.0 * d, 16.0 * d] {
            let (a, b) = (
                j(s, s / 5.0, Region::Developed),
                j(s, s / 5.0, Region::Outside),
            );
            assert!(
                (a / b - 1.0).abs() < 1e-12,
                "developed edge at s = {s}: {a} against {b}"
            );
        }
        for (s, r) in [(2.0 * d, 0.2 * d), (2.0 * d, 0.55 * d), (2.0 * d, 1.5 * d)]
            .into_iter()
            .chain([
                (10.0 * d, 1e-5 * d),
                (10.0 * d, 0.01 * d),
                (10.0 * d, 1.2 * d),
            ])
            .chain([(10.0 * d, 3.0 * d), (16.0 * d, 0.9 * d)])
        {
            let region = f.region_of(&at(&f, s, r));
            // Simpson on each piece between the radial borders (the air jumps at the
            // jet's edge and bends at the core's), none beyond the edge.
            let borders = if s <= 5.0 * d {
                vec![0.0, (5.0 * d - s) / 10.0, (5.0 * d + s) / 10.0]
            } else {
                vec![0.0, s / 5.0]
            };
            let simpson = |lo: f64, hi: f64| {
                let n = 2000;
                let h = (hi - lo) / n as f64;
                let piece = f.region_of(&at(&f, s, 0.5 * (lo + hi)));
                (0..=n)
                    .map(|i| {
                        let ri = lo + i as f64 * h;
                        let w = if i == 0 || i == n {
                            1.0
                        } else {
                            [2.0, 4.0][i % 2]
                        };
                        w * ri * f.speed_density(&at(&f, s, ri), piece).0
                    })
                    .sum::<f64>()
                    * h
                    / 3.0
            };
            let integral: f64 = borders
                .windows(2)
                .map(|w| (w[0], w[1].min(r)))
                .filter(|(lo, hi)| hi > lo)
                .map(|(lo, hi)| simpson(lo, hi))
                .sum();
            let want = integral / (r * r);
            let got = j(s, r, region);
            // Simpson across a border's jump in slope (the core's edge, the jet's edge)
            // is second order: 2,000 intervals still give 1e-6.
            assert!(
                (got / want - 1.0).abs() < 1e-6,
                "{region:?} s = {s}, r = {r}: {got} against {want}"
            );
        }
    }

    /// On the axis the wall jet has no radial speed; everywhere its air stays within
    /// `max_speed` (the reach bounds' speed); its peak at the wall is the one
    /// `wall_jet_peak_ratio` reports. The developed jet's peak is `(2 / delta) max_r
    /// int_0^r u r' dr' / r` with `u = (6 d u_i / s) exp(-94 (r/s)^2)`: `0.395 d u_i /
    /// delta` whatever `s`, found here by an independent scan of the closed form.
    #[test]
    fn the_wall_jet_s_peak_and_bound() {
        let (standoff, delta) = (0.1, 0.014);
        let f = wall_jet_field(JetModel::Paper, standoff, delta);
        let (d, ui) = (f.bore, f.exit_velocity);
        for z in [0.0, 0.003, 0.01] {
            let p = Vec3::new(0.0, 0.0, z);
            let v = f.sample(&p, f.region_of(&f.coords(&p))).velocity;
            assert_eq!((v.x, v.y), (0.0, 0.0));
        }
        let (mut fastest, mut radial): (f64, f64) = (0.0, 0.0);
        for i in 0..400 {
            for j in 0..40 {
                let p = Vec3::new(1e-4 * i as f64, 0.0, delta * j as f64 / 40.0);
                let v = f.sample(&p, f.region_of(&f.coords(&p))).velocity;
                fastest = fastest.max(v.norm());
                if j == 0 {
                    radial = radial.max(v.x);
                }
                assert!(v.x >= 0.0, "the wall jet flows out: {v} at {p}");
            }
        }
        assert!(fastest <= f.max_speed(), "{fastest} > {}", f.max_speed());
        let best = (1..200_000)
            .map(|i| {
                let q = i as f64 * 1e-6;
                (1.0 - (-94.0 * q * q).exp()) / q
            })
            .fold(0.0, f64::max);
        let peak = 2.0 / delta * 6.0 * d * ui / 188.0 * best;
        let ratio = JetField::wall_jet_peak_ratio(d, standoff, delta);
        let axis = 6.0 * d * ui / standoff;
        assert!(
            (ratio * axis / peak - 1.0).abs() < 1e-6,
            "{} against {peak}",
            ratio * axis
        );
        assert!(
            (peak / (d * ui / delta) - 0.395).abs() < 5e-4,
            "{}",
            peak / (d * ui / delta)
        );
        // The scan's fastest air along the wall (0.1 mm apart) is the peak's, a hair below.
        assert!(
            radial <= peak * (1.0 + 1e-12) && radial > peak * (1.0 - 1e-3),
            "{radial}"
        );
    }
}
