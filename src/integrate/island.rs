//! Island integrator: advances a group of shots that may touch each other ("island")
//! over one synchronisation window `[t0, t1]` on a common clock.
//!
//! * Error control: Dormand-Prince 5(4); each shot's position error is scaled by
//!   `tolerance x diameter`, its velocity error by `tolerance x (|v| + 1 m/s)`.
//! * Jet regions: each shot's region is frozen for a step (the field jumps at borders,
//!   model-notes defect 4). A step that ends outside the frozen region is cut back to the
//!   crossing, located by a safeguarded Illinois root search on the region margin, started
//!   from the root of the step's dense output (`first_crossing_guided`); the shot then
//!   switches region.
//! * Contacts: a step that ends with a new overlap is cut back to the located onset
//!   (so the impact record carries the exact first-contact time and velocity). While in
//!   contact steps are capped at `t_c / contact_steps` (Hertz duration `t_c`), and on
//!   approach at `gap / closing speed + t_c / contact_steps`, so no contact is skipped or
//!   entered deeply. Free flight is limited by the error controller alone.
//! * Touches: the force starts as `s^(1/4)` (the dashpot) and `s^(3/2)` (the spring),
//!   which no Runge-Kutta step integrates to its order and whose error its estimate
//!   misses. Without friction, the steps within a contact step of a touch get what
//!   their quadrature missed of that start added (`HertzLaw::onset_correction`), and
//!   the first is as long as the tolerance allows (`first_contact_step`: `t_c / 24` at
//!   1e-4, `t_c / 126` at 1e-6); with friction the first is 1 % of a contact step. The
//!   next steps are at most four times the time since the touch.
//!
//! Reads shot states, writes them back, and appends impacts and run events.

use crate::Vec3;
use crate::contact::friction::{self, INERTIA_FACTOR};
use crate::contact::hertz::HertzLaw;
use crate::contact::specimen::SpecimenShape;
use crate::contact::{ContactSet, PairContact, effective_mass, hertz};
use crate::counters::WorkCounters;
use crate::forces::{ForceSet, ShotBody, Turbulence};
use crate::integrate::dopri::{DenseStep, Dopri5, KINK_MISS, step_factor};
use crate::integrate::{add_at, vec_at};
use crate::record::{Impact, RunEvent};
use crate::state::{Domain, ShotState, ShotStatus};
use std::ops::Range;

/// Time-integration method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// Error-controlled Dormand-Prince 5(4) with located events (the default).
    Adaptive,
    /// Fixed-step velocity Verlet, as classic DEM codes (LIGGGHTS' `nve/sphere`)
    /// integrate: every shot takes the same step `step` (s) on one time grid (the window
    /// scheduler ends its windows on it and carries each shot's last force evaluation
    /// across them, `ShotState::verlet_acc`); contacts are detected at step ends; the jet
    /// region is re-evaluated at every force evaluation; with friction, spins are kicked
    /// by the torques. Its accuracy is the step's, not a tolerance's: the contrast in
    /// `peenflow accuracy`, and the fast way through contact-dominated scenes (an agitated
    /// pile, where every shot is always in or near a contact; docs/performance.md).
    Verlet {
        /// The fixed step, s.
        step: f64,
    },
    /// The adaptive method in flight, fixed-step velocity Verlet inside contacts: an
    /// island flies under error control (kept steps, located region crossings and
    /// onsets) until a contact begins; from the located touch its members take the fixed
    /// `step` until no contact is left, then fly adaptively again (`advance_hybrid`).
    /// The tolerance holds in flight, the step's accuracy in contacts. What carries the
    /// history tangential law (a per-contact state the adaptive integrators do not hold)
    /// onto scenes with air, where every shot in flight would otherwise take the fixed
    /// step (docs/accuracy.md).
    Hybrid {
        /// The fixed step inside contacts, s.
        step: f64,
    },
}

impl Method {
    /// The name used in scene files and summaries.
    pub fn name(self) -> &'static str {
        match self {
            Method::Adaptive => "adaptive",
            Method::Verlet { .. } => "verlet",
            Method::Hybrid { .. } => "hybrid",
        }
    }

    /// Whether shots fly under error control (kept steps, sleepers, split islands).
    pub fn adaptive_flight(self) -> bool {
        !matches!(self, Method::Verlet { .. })
    }

    /// The fixed step, s, of the methods that have one.
    pub fn fixed_step(self) -> Option<f64> {
        match self {
            Method::Adaptive => None,
            Method::Verlet { step } | Method::Hybrid { step } => Some(step),
        }
    }
}

/// Everything the integrator needs that does not change during a run.
#[derive(Debug, Clone)]
pub struct Physics {
    /// Enabled body forces (and the jet field they sample).
    pub forces: ForceSet,
    /// Enabled contacts.
    pub contacts: ContactSet,
    /// Relative error tolerance per step (default: `1e-6`).
    pub tolerance: f64,
    /// Minimum number of steps per Hertz contact duration (default: `10`).
    pub contact_steps: f64,
    /// Box outside which shots are dropped.
    pub domain: Domain,
    /// Largest step, s.
    pub max_step: f64,
    /// Integration method.
    pub method: Method,
    /// Whether a lone shot whose specimen contact has settled slides (with friction:
    /// rolls) on the specimen (`ShotState::sliding`) instead of stepping through the pressed
    /// contact's oscillation (default `true`; `false` for comparisons).
    pub sliding: bool,
    /// Members from which an island's right-hand side, event margins, error norm and
    /// step-end passes are split over the threads, a block of at least this many per
    /// thread (default [`BLOCKS_MIN`]; the results are the same to the bit either way).
    pub blocks_min: usize,
    /// Whether a lone shot's fixed steps away from every contact skip the contact passes
    /// (`advance_verlet`: its forces are the body forces, and the onset, overlap and
    /// separation passes find nothing) (default `true`; the results are the same to the
    /// bit either way; `false` for comparisons).
    pub free_steps: bool,
}

/// Scale (m/s^2) of a sliding shot's lift-off margin (its load per mass, `-a_z`).
const STANDARD_GRAVITY: f64 = 9.80665;

/// Largest normal speed (m/s) of a settled specimen contact that may turn into sliding.
const SLIDE_SPEED: f64 = 1e-3;

/// Largest relative difference between a settled contact's overlap and the static
/// overlap under its load for it to turn into sliding.
const SLIDE_OVERLAP: f64 = 1e-2;

/// A shot-shot pair that may touch during the window (local member indices).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct IslandPair {
    /// First member (local index).
    pub a: u32,
    /// Second member (local index).
    pub b: u32,
    /// Whether the pair is in contact.
    pub touching: bool,
    /// Hertz duration estimate of the current contact, s.
    pub contact_time: f64,
    /// Onset time of the current contact, s.
    pub onset: f64,
    /// Tangential displacement of the current contact (member `a`'s contact point
    /// relative to `b`'s), m: the `history` tangential law's; zero otherwise.
    pub xi: Vec3,
}

/// What an island produced during a window.
#[derive(Debug, Default, Clone)]
pub struct IslandOutput {
    /// Located shot-specimen contact onsets.
    pub impacts: Vec<Impact>,
    /// Shots that had to be stopped.
    pub events: Vec<RunEvent>,
    /// Work counters.
    pub work: WorkCounters,
}

/// Per-thread buffers reused across islands and windows (no allocation per step).
#[derive(Debug, Clone)]
pub struct Scratch {
    dopri: Dopri5,
    y: Vec<f64>,
    y_new: Vec<f64>,
    err: Vec<f64>,
    pushing: Pushing,
    /// Event location: the step's dense output and a state read off it.
    dense: DenseStep,
    probe: Vec<f64>,
    /// The island's pairs' Hertz constants ([`pair_laws`]).
    laws: Vec<PairLaw>,
}

impl Default for Scratch {
    fn default() -> Self {
        Scratch {
            dopri: Dopri5::new(0),
            y: Vec::new(),
            y_new: Vec::new(),
            err: Vec::new(),
            pushing: Pushing::default(),
            dense: DenseStep::default(),
            probe: Vec::new(),
            laws: Vec::new(),
        }
    }
}

/// Smallest step (s) the error controller may ask for before the run declares the
/// shot's integration failed.
pub(crate) const MIN_STEP: f64 = 1e-15;
/// Floor (m/s) of the closing speed used to estimate a contact's duration.
pub(crate) const MIN_CONTACT_SPEED: f64 = 0.01;

#[inline]
fn pos(y: &[f64], i: usize) -> Vec3 {
    vec_at(y, 6 * i)
}

#[inline]
fn vel(y: &[f64], i: usize) -> Vec3 {
    vec_at(y, 6 * i + 3)
}

/// Angular velocity of member `i` of `n` (stored after all positions and velocities,
/// only when the `friction` effect is on).
#[inline]
fn omega(y: &[f64], n: usize, i: usize) -> Vec3 {
    vec_at(y, 6 * n + 3 * i)
}

/// Writes the members' positions and velocities (then, with `spin`, their angular
/// velocities) into the flat state `y`: `[x0 v0 x1 v1 ... | w0 w1 ...]`.
pub(crate) fn load_state(members: &[ShotState], y: &mut Vec<f64>, spin: bool) {
    y.clear();
    for m in members {
        y.extend_from_slice(m.pos.as_slice());
        y.extend_from_slice(m.vel.as_slice());
    }
    if spin {
        for m in members {
            y.extend_from_slice(m.omega.as_slice());
        }
    }
}

/// Copies the flat state back into the members that are still integrated.
fn store_state(members: &mut [ShotState], y: &[f64]) {
    let n = members.len();
    let spin = y.len() == 9 * n;
    for (i, m) in members.iter_mut().enumerate() {
        if m.is_active() {
            m.pos = pos(y, i);
            m.vel = vel(y, i);
            if spin {
                m.omega = omega(y, n, i);
            }
        }
    }
}

/// Angular velocity of member `i` at the fraction `s` of a step from `y0` to `y1`
/// (linear; zero when spin is not integrated).
#[inline]
fn spin_at(y0: &[f64], y1: &[f64], n: usize, i: usize, s: f64) -> Vec3 {
    if y0.len() < 9 * n {
        return Vec3::zeros();
    }
    omega(y0, n, i) * (1.0 - s) + omega(y1, n, i) * s
}

/// Adds an angular acceleration to member `i` of `n`.
#[inline]
fn add_alpha(dy: &mut [f64], n: usize, i: usize, a: &Vec3) {
    add_at(dy, 6 * n + 3 * i, a);
}

/// Cubic Hermite interpolation of member `i` between `y0` and `y1` (a step of `h`) at
/// the fraction `s` of the step: (position, velocity).
#[inline]
fn hermite(y0: &[f64], y1: &[f64], h: f64, i: usize, s: f64) -> (Vec3, Vec3) {
    let (p0, v0, p1, v1) = (pos(y0, i), vel(y0, i), pos(y1, i), vel(y1, i));
    let (s2, s3) = (s * s, s * s * s);
    let p = p0 * (2.0 * s3 - 3.0 * s2 + 1.0)
        + v0 * (h * (s3 - 2.0 * s2 + s))
        + p1 * (3.0 * s2 - 2.0 * s3)
        + v1 * (h * (s3 - s2));
    let v = (p0 * (6.0 * s2 - 6.0 * s)
        + v0 * (h * (3.0 * s2 - 4.0 * s + 1.0))
        + p1 * (6.0 * s - 6.0 * s2)
        + v1 * (h * (3.0 * s2 - 2.0 * s)))
        / h;
    (p, v)
}

#[inline]
fn add_acc(dy: &mut [f64], i: usize, a: &Vec3) {
    add_at(dy, 6 * i + 3, a);
}

/// Members `lo..hi` of an island and their parts of a derivative `dy` (see
/// [`load_state`] for the layout): `lin` their `(v, a)` rows, `ang` their angular
/// accelerations (empty without spin).
struct Part<'a> {
    lo: usize,
    hi: usize,
    lin: &'a mut [f64],
    ang: &'a mut [f64],
}

impl<'a> Part<'a> {
    /// `dy` of `n` members cut at `bounds` (ascending, from 0 to `n`).
    fn split(dy: &'a mut [f64], n: usize, bounds: &[usize]) -> Vec<Part<'a>> {
        let (lin, ang) = dy.split_at_mut(6 * n);
        let spin = if ang.is_empty() { 0 } else { 3 };
        cut(lin, bounds, 6)
            .into_iter()
            .zip(cut(ang, bounds, spin))
            .zip(bounds.windows(2))
            .map(|((lin, ang), w)| Part {
                lo: w[0],
                hi: w[1],
                lin,
                ang,
            })
            .collect()
    }
}

/// `v` cut into the consecutive parts `width * (bounds[b + 1] - bounds[b])` long.
fn cut<'a, T>(mut v: &'a mut [T], bounds: &[usize], width: usize) -> Vec<&'a mut [T]> {
    bounds
        .windows(2)
        .map(|w| {
            let (part, rest) = std::mem::take(&mut v).split_at_mut(width * (w[1] - w[0]));
            v = rest;
            part
        })
        .collect()
}

/// Touching pairs of `pairs` whose shots are apart at `y` (`radius`: a member's) stop
/// touching.
fn pair_separations(pairs: &mut [IslandPair], radius: impl Fn(usize) -> f64, y: &[f64]) {
    for pr in pairs.iter_mut() {
        let (i, j) = (pr.a as usize, pr.b as usize);
        pair_separation(pr, (radius(i), radius(j)), y);
    }
}

/// [`pair_separations`] of pair `pr`, its shots' radii `ri` and `rj`.
#[inline(always)]
fn pair_separation(pr: &mut IslandPair, (ri, rj): (f64, f64), y: &[f64]) {
    if pr.touching {
        let (i, j) = (pr.a as usize, pr.b as usize);
        let gap = (pos(y, j) - pos(y, i)).norm() - ri - rj;
        if gap > 0.0 {
            pr.touching = false;
        }
    }
}

/// The overlap guard ([`Ctx::overlap_violation`]) of pair `pr`, both of whose shots move
/// (radii `ri` and `rj`).
#[inline(always)]
fn pair_overlap_of(
    members: &[ShotState],
    pr: &IslandPair,
    (ri, rj): (f64, f64),
    y: &[f64],
) -> Option<String> {
    let (i, j) = (pr.a as usize, pr.b as usize);
    let r_eff = PairContact::effective_radius(ri, rj);
    let d = pos(y, j) - pos(y, i);
    if surely_apart(&d, ri + rj - r_eff) {
        return None;
    }
    let overlap = ri + rj - d.norm();
    (overlap > r_eff).then(|| {
        format!(
            "shots {} and {} overlap by {:.4} mm, {:.0} % of their effective radius",
            members[i].id.0,
            members[j].id.0,
            overlap * 1e3,
            100.0 * overlap / r_eff
        )
    })
}

/// Default of [`Physics::blocks_min`].
pub const BLOCKS_MIN: usize = 2048;

/// How many blocks the right-hand side of an island of `n` members takes on the current
/// thread pool: one per thread, each of at least [`Physics::blocks_min`] members (one
/// block: a single pass on this thread).
pub fn blocks(phys: &Physics, n: usize) -> usize {
    rayon::current_num_threads()
        .min(n / phys.blocks_min.max(1))
        .max(1)
}

/// A large island's members cut into consecutive blocks, one per thread, for its
/// right-hand side ([`Ctx::rhs`]); each block takes the pairs with a member in it, in
/// the island's order (a pair across two blocks is evaluated in both, each adding its
/// terms to its own member).
struct Blocks {
    /// Members `bounds[b]..bounds[b + 1]` form block `b`.
    bounds: Vec<usize>,
    /// Block `b`'s pairs for the right-hand side (ascending).
    pairs: Vec<Vec<u32>>,
    /// The pairs cut into as many consecutive ranges, for the passes whose results are
    /// per pair or a minimum (any cut gives the same).
    pair_bounds: Vec<usize>,
}

impl Blocks {
    /// Blocks of at least `phys.blocks_min` members, as many as there are threads; none
    /// (one pass) on one thread or for a smaller island.
    fn plan(phys: &Physics, members: &[ShotState], pairs: &[IslandPair]) -> Option<Self> {
        let n = members.len();
        let k = blocks(phys, n);
        if k < 2 {
            return None;
        }
        let bounds: Vec<usize> = (0..=k).map(|b| b * n / k).collect();
        let block = |i: u32| bounds.partition_point(|&x| x <= i as usize) - 1;
        let mut lists = vec![Vec::new(); k];
        for (q, p) in pairs.iter().enumerate() {
            let (a, b) = (block(p.a), block(p.b));
            lists[a].push(q as u32);
            if b != a {
                lists[b].push(q as u32);
            }
        }
        let pair_bounds = (0..=k).map(|b| b * pairs.len() / k).collect();
        Some(Blocks {
            bounds,
            pairs: lists,
            pair_bounds,
        })
    }

    /// `f(b, item b)` for every block `b` and its item, the first on this thread and the
    /// others on the pool's (a calling thread outside the pool, as a library user's or a
    /// test's may be, would otherwise wait idle); the results in block order.
    fn run<P: Send, T: Send>(&self, items: Vec<P>, f: impl Fn(usize, P) -> T + Sync) -> Vec<T> {
        let mut out: Vec<Option<T>> = items.iter().map(|_| None).collect();
        let mut items = items.into_iter();
        let first = items.next().expect("two blocks or more");
        let (o0, rest) = out.split_first_mut().expect("two blocks or more");
        let f = &f;
        rayon::in_place_scope(|s| {
            for (b, (item, o)) in items.zip(rest).enumerate() {
                s.spawn(move |_| *o = Some(f(b + 1, item)));
            }
            *o0 = Some(f(0, first));
        });
        out.into_iter()
            .map(|o| o.expect("BUG: a block did not run"))
            .collect()
    }

    /// `f(members, pairs)` for each block's members and its range of pairs, folded by
    /// `op` from `init` in block order (callers fold by `min` or `max`: exact in any order
    /// but for the sign of a zero, which no caller reads).
    fn fold(
        &self,
        init: f64,
        op: fn(f64, f64) -> f64,
        f: impl Fn(Range<usize>, Range<usize>) -> f64 + Sync,
    ) -> f64 {
        self.each(f).into_iter().fold(init, op)
    }

    /// `f(members, pairs)` for each block's members and its range of pairs, in block
    /// order.
    fn each<T: Send>(&self, f: impl Fn(Range<usize>, Range<usize>) -> T + Sync) -> Vec<T> {
        let k = self.bounds.len() - 1;
        self.run(vec![(); k], |b, ()| {
            f(
                self.bounds[b]..self.bounds[b + 1],
                self.pair_bounds[b]..self.pair_bounds[b + 1],
            )
        })
    }
}

/// Impacts (frictionless) whose start a step's quadrature misses, so that
/// [`Ctx::correct_onsets`] corrects the step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Onsets {
    /// None within a contact step of the step's start.
    None,
    /// Some touched within a contact step before the step's start.
    Recent,
    /// One touched at the step's start (within `AT_ONSET`): the step is
    /// `first_contact_step` long, and its last stage, taken before the correction, cannot
    /// start the next step.
    AtStart,
}

/// A touching pair's lever arms from members `i` and `j` (radii given) to their contact
/// point, the middle of the overlap (`R - delta/2`, as LIGGGHTS: the pair's angular
/// momentum is conserved), and the slip of `i`'s contact point against `j`'s, for the
/// normal `nrm` from `i` to `j` in state `y` (`n` members).
fn pair_slip(
    y: &[f64],
    n: usize,
    (i, r_i): (usize, f64),
    (j, r_j): (usize, f64),
    nrm: &Vec3,
    overlap: f64,
) -> (Vec3, Vec3, Vec3) {
    let (ri, rj) = (nrm * (r_i - 0.5 * overlap), nrm * (0.5 * overlap - r_j));
    let vi = vel(y, i) + omega(y, n, i).cross(&ri);
    let vj = vel(y, j) + omega(y, n, j).cross(&rj);
    (ri, rj, friction::tangential_part(&(vi - vj), nrm))
}

/// A touching pair's contact in state `y`: the unit normal from member `i` to `j`, the
/// overlap, its rate, the Hertz stiffness and the effective mass.
struct PairGeom {
    nrm: Vec3,
    overlap: f64,
    rate: f64,
    k: f64,
    m_eff: f64,
    /// `sqrt(m_eff k)`, the dashpot's factor ([`HertzLaw::force_unclamped_with`]).
    root_mk: f64,
}

/// A pair's Hertz constants, fixed while an island runs (its shots' radii and masses):
/// found once per island run ([`pair_laws`]) instead of at every force evaluation, the
/// same numbers.
#[derive(Debug, Clone, Copy, Default)]
struct PairLaw {
    /// Stiffness `K`, N/m^1.5.
    k: f64,
    /// Effective mass, kg.
    m_eff: f64,
    /// `sqrt(m_eff K)`.
    root_mk: f64,
}

/// Each pair's [`PairLaw`] (none without shot-shot contact), into `laws`.
fn pair_laws(phys: &Physics, members: &[ShotState], pairs: &[IslandPair], laws: &mut Vec<PairLaw>) {
    laws.clear();
    let Some(pc) = &phys.contacts.pair else {
        return;
    };
    laws.extend(pairs.iter().map(|pr| {
        let (mi, mj) = (&members[pr.a as usize].body, &members[pr.b as usize].body);
        let k = pc
            .law
            .stiffness(PairContact::effective_radius(mi.radius, mj.radius));
        let m_eff = effective_mass(mi.mass, mj.mass);
        PairLaw {
            k,
            m_eff,
            root_mk: (m_eff * k).sqrt(),
        }
    }));
}

/// [`PairGeom`] of members `i` and `j` (their bodies given, their pair's law `law`) in
/// state `y`; `None` when they do not overlap.
#[inline(always)]
fn pair_geometry(
    law: &PairLaw,
    (i, mi): (usize, &ShotBody),
    (j, mj): (usize, &ShotBody),
    y: &[f64],
) -> Option<PairGeom> {
    let dpos = pos(y, j) - pos(y, i);
    if surely_apart(&dpos, mi.radius + mj.radius) {
        return None;
    }
    let dist = dpos.norm();
    let overlap = mi.radius + mj.radius - dist;
    if overlap <= 0.0 || dist == 0.0 {
        return None;
    }
    let nrm = dpos / dist;
    Some(PairGeom {
        nrm,
        overlap,
        rate: -(vel(y, j) - vel(y, i)).dot(&nrm),
        k: law.k,
        m_eff: law.m_eff,
        root_mk: law.root_mk,
    })
}

/// The lever arm (m) from a shot's centre (radius `r`) to its contact point on the
/// specimen or the wall at `overlap`: `r` for the viscous law; for the history law
/// (`tangent` set) `r - overlap / 2`, as LIGGGHTS takes it (the contact plane of a sphere
/// pressed into a half-space of the same material lies half the overlap inside the
/// sphere's undeformed surface; the pairs' is `r - overlap / 2` for both laws).
#[inline]
fn history_lever(r: f64, overlap: f64, tangent: Option<&[Vec3]>) -> f64 {
    if tangent.is_some() {
        r - 0.5 * overlap
    } else {
        r
    }
}

/// Adds the start of a touch's tangential force `-(d1 s^(1/4) + d2 s^(3/2)) slip / |slip|`
/// (`friction::onset_terms`) that a step of `h` starting `at` after the touch missed:
/// on the first of `bodies` (member, state, lever arm to the contact point) as it acts,
/// on the second (a pair's other shot) the opposite, to positions, velocities and spins.
fn tangential_start(
    y1: &mut [f64],
    n: usize,
    slip: &Vec3,
    d_t: (f64, f64),
    at: f64,
    h: f64,
    bodies: &[(usize, &ShotState, Vec3)],
) {
    let sn = slip.norm();
    if sn == 0.0 || d_t.0 + d_t.1 <= 0.0 {
        return;
    }
    let (dx, dv) = hertz::start_correction(d_t, at, h);
    for (q, (i, m, r_c)) in bodies.iter().enumerate() {
        let sign = if q == 0 { -1.0 } else { 1.0 };
        let (jx, jv) = (slip * (sign * dx / sn), slip * (sign * dv / sn));
        let b = &m.body;
        add_at(y1, 6 * i, &(jx / b.mass));
        add_acc(y1, *i, &(jv / b.mass));
        add_alpha(
            y1,
            n,
            *i,
            &(r_c.cross(&jv) / (INERTIA_FACTOR * b.mass * b.radius * b.radius)),
        );
    }
}

/// The friction force that keeps a shot rolling on the specimen (normal `+z`) under the
/// acceleration `a` of its other forces, `F_t = -m_t a_t` (`m_t = 2/7 m`: the contact
/// point then does not accelerate, see [`friction::sphere_on_wall_mass`]), and its ratio
/// to the most the contact holds, `mu F` with the load `F = -m a_z` (infinite without
/// load): rolling needs a ratio of at most 1.
fn rolling_friction(mass: f64, a: &Vec3, mu: f64) -> (Vec3, f64) {
    let ft = Vec3::new(a.x, a.y, 0.0) * -friction::sphere_on_wall_mass(mass);
    let load = -a.z * mass;
    let ratio = if load > 0.0 {
        ft.norm() / (mu * load)
    } else {
        f64::INFINITY
    };
    (ft, ratio)
}

/// Whether member `m` moves at time `t`.
#[inline]
fn moving(m: &ShotState, t: f64) -> bool {
    m.status == ShotStatus::Active && t >= m.t_start
}

/// Whether the centres `d` apart are surely farther apart than `s` (> 0), without a
/// square root: most of an island's pairs are not in contact at a given step. The margin
/// leaves every case a rounding could decide to the exact test (`d.norm()` against `s`),
/// so results are unchanged.
#[inline]
fn surely_apart(d: &Vec3, s: f64) -> bool {
    d.norm_squared() > s * s * (1.0 + 1e-12)
}

struct Ctx<'a> {
    phys: &'a Physics,
    /// Specimen onsets are located (adaptive method) rather than seen at step ends.
    onsets_located: bool,
    /// Every step's end set each moving member's jet region and side of the layer's top
    /// from its position (the fixed step's `set_regions`) before [`Ctx::apply_events`]
    /// reads them: their margins there are never negative, so they are not computed.
    regions_set: bool,
    /// A large island's blocks for its right-hand side on several threads.
    blocks: Option<Blocks>,
    /// Each pair's Hertz constants ([`pair_laws`]; empty without shot-shot contact).
    laws: &'a [PairLaw],
}

impl Ctx<'_> {
    /// Sliding on the specimen for a lone shot (`y` its state): it starts once the shot's
    /// specimen contact is persistent (older than three Hertz durations) and has
    /// settled (normal speed below [`SLIDE_SPEED`], overlap within [`SLIDE_OVERLAP`] of
    /// the static overlap `(F / K)^(2/3)` under the load `F` its forces press it with);
    /// it ends when they no longer press it onto the specimen (the overlap then pushes
    /// it off as the contact would). While it lasts, the overlap follows the load, set
    /// here after every step. Returns whether the state or the right-hand side changed.
    ///
    /// With friction on the specimen the shot rolls (see [`rolling_friction`]): it
    /// starts only from a sticking contact (the regularised law's viscous branch, slip
    /// below `mu F / gamma_t`), whose residual slip it removes with the impulse at the
    /// contact point that stops it (`-m_t s`, a change of `2/7 s` in velocity); it ends
    /// when rolling would take more friction than `mu F` (located, see
    /// [`Ctx::event_margin`]): the shot then slips, stepped through its contact again.
    fn slide(&self, m: &mut ShotState, t: f64, y: &mut [f64], work: &mut WorkCounters) -> bool {
        let Some(sp) = &self.phys.contacts.specimen else {
            return false;
        };
        if !m.on_specimen || !moving(m, t) || !sp.shape.is_plane() {
            let was = m.sliding;
            m.sliding = false;
            return was;
        }
        let (p, v) = (pos(y, 0), vel(y, 0));
        if !m.sliding
            && (t - m.specimen_onset <= 3.0 * m.specimen_contact_time || v.z.abs() > SLIDE_SPEED)
        {
            return false;
        }
        let a = self
            .phys
            .forces
            .acceleration(&m.body, &p, &v, m.region, &m.gust, work);
        let load = -a.z * m.body.mass;
        if load <= 0.0 {
            let was = m.sliding;
            m.sliding = false;
            return was;
        }
        let k = sp.law.stiffness(sp.effective_radius(&p, m.body.radius));
        let delta = (load / k).powf(2.0 / 3.0);
        if !m.sliding && (-sp.gap(&p, m.body.radius) - delta).abs() > SLIDE_OVERLAP * delta {
            return false;
        }
        if let Some(mu) = self.specimen_friction() {
            let (_, ratio) = rolling_friction(m.body.mass, &a, mu);
            if ratio > 1.0 {
                let was = m.sliding;
                m.sliding = false;
                return was;
            }
            if !m.sliding {
                // Only a sticking contact rolls; its residual slip is stopped.
                let r_c = Vec3::new(0.0, 0.0, -m.body.radius);
                let w = omega(y, 1, 0);
                let slip = friction::tangential_part(&(v + w.cross(&r_c)), &Vec3::z());
                let m_t = friction::sphere_on_wall_mass(m.body.mass);
                if friction::stick_damping(m_t, k, delta) * slip.norm() >= mu * load {
                    return false;
                }
                let j = slip * -m_t;
                let inertia = INERTIA_FACTOR * m.body.mass * m.body.radius * m.body.radius;
                add_at(y, 3, &(j / m.body.mass));
                add_at(y, 6, &(r_c.cross(&j) / inertia));
            }
        }
        y[2] += -delta - sp.gap(&p, m.body.radius);
        y[5] = 0.0;
        if !m.sliding {
            work.slides += 1;
        }
        m.sliding = true;
        true
    }

    /// The specimen's friction coefficient, if friction acts there.
    fn specimen_friction(&self) -> Option<f64> {
        self.phys
            .contacts
            .friction
            .map(|fr| fr.specimen)
            .filter(|&mu| mu > 0.0)
    }

    /// Whether a contact of Hertz time `tc` that touched at `onset` is an impact still
    /// within a contact step of its touch at `t` (closing speed at least
    /// `RAMP_MIN_SPEED` at the onset, read back from `tc ~ v^(-1/5)`).
    fn fresh_impact(&self, t: f64, tc: f64, onset: f64, m_eff: f64, k: f64) -> bool {
        t - onset < tc / self.phys.contact_steps
            && hertz::contact_time(m_eff, k, RAMP_MIN_SPEED) > tc
    }

    /// Right-hand side: `dy = (v, a)` for every member. A large island's members are
    /// split into blocks, one per thread ([`Blocks`]): each block's derivatives receive
    /// the same terms in the same order as in one pass over every member and pair, so
    /// `dy` is the same to the bit for any thread count.
    #[allow(clippy::too_many_arguments)]
    fn rhs(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        pushing: Option<&Pushing>,
        tangent: Option<&[Vec3]>,
        t: f64,
        y: &[f64],
        dy: &mut [f64],
        work: &mut WorkCounters,
    ) {
        work.rhs_evaluations += 1;
        let n = members.len();
        let with = (pushing, tangent);
        let Some(blocks) = &self.blocks else {
            let (lin, ang) = dy.split_at_mut(6 * n);
            let part = Part {
                lo: 0,
                hi: n,
                lin,
                ang,
            };
            self.rhs_part::<true>(members, pairs, 0..pairs.len(), with, t, y, part, work);
            return;
        };
        let parts = Part::split(dy, n, &blocks.bounds);
        let works = blocks.run(parts, |b, part| {
            let mut w = WorkCounters::default();
            let list = blocks.pairs[b].iter().map(|&q| q as usize);
            self.rhs_part::<false>(members, pairs, list, with, t, y, part, &mut w);
            w
        });
        for w in &works {
            work.add(w);
        }
    }

    /// Whether the lone member `m` at `p` (moving) is away from every contact: not
    /// sliding, not on the specimen or the nozzle wall, and clear of both (their gaps
    /// above 0: no force, no onset, no overlap). The caller has checked that there is no
    /// pair.
    fn clear_of_contacts(&self, m: &ShotState, p: &Vec3) -> bool {
        let c = &self.phys.contacts;
        let r = m.body.radius;
        !m.sliding
            && !m.on_specimen
            && !m.on_wall
            && c.specimen
                .as_ref()
                .is_none_or(|sp| sp.overlap_gap(p, r) > 0.0)
            && c.wall
                .as_ref()
                .is_none_or(|w| w.geometry(p, r).is_none_or(|g| g.gap > 0.0))
    }

    /// The free steps of a lone member `m` (the `lone` case of [`advance_verlet`]) from
    /// `*t`, one after another while each ends clear of contacts
    /// ([`Ctx::clear_of_contacts`]): the general step's arithmetic and counts to the bit,
    /// without its passes over members and pairs. Stops before a step that would not end
    /// clear (the caller takes it), at `t1`, or when the shot stops. Returns whether the
    /// caller's step loop ends: the state stopped being finite (the island failed), or
    /// `apart_after` was reached (no contact is in progress in a free step).
    ///
    /// The state is carried in locals and only written to `y` (and the forces to `acc`),
    /// never read back within a step: reading an entry just written as part of a wider
    /// load stalls the processor's store forwarding, and that was most of such a step's
    /// time when it ran through `y` (session 68).
    #[allow(clippy::too_many_arguments)]
    fn free_steps(
        &self,
        m: &mut ShotState,
        (t, t1, step, apart_after): (&mut f64, f64, f64, Option<f64>),
        spin: bool,
        (y, acc, prev): (&mut [f64], &mut Vec<f64>, &mut Vec<f64>),
        out: &mut IslandOutput,
        work: &mut WorkCounters,
        observer: &mut dyn FnMut(f64, &[f64]),
    ) -> bool {
        let (mut x, mut v, mut a) = (pos(y, 0), vel(y, 0), vel(acc, 0));
        let (mut w, mut alpha) = if spin {
            (omega(y, 1, 0), omega(acc, 1, 0))
        } else {
            (Vec3::zeros(), Vec3::zeros())
        };
        let specimen = self.phys.contacts.specimen.is_some();
        let wall = self.phys.contacts.wall.is_some();
        let field = self.phys.forces.field.as_ref();
        while *t < t1 && moving(m, *t) {
            let h = if t1 - *t <= step * (1.0 + 1e-9) {
                t1 - *t
            } else {
                step
            };
            // Kick and drift, tried aside: kept only if the step ends clear.
            let half = 0.5 * h;
            let v_half = kicked(&v, &a, half);
            let x_new = kicked(&x, &v_half, h);
            let t_new = if h == t1 - *t { t1 } else { *t + h };
            if !(moving(m, t_new) && self.clear_of_contacts(m, &x_new)) {
                return false;
            }
            (x, v) = (x_new, v_half);
            if spin {
                w = kicked(&w, &alpha, half);
            }
            // (A free step is not on the specimen: no first contact's step to count.)
            m.steps += 1;
            work.shot_steps += 1;
            *t = t_new;
            // The forces at the step's end, `Ctx::rhs`'s numbers and counts where there is
            // no contact: body forces (in the jet region the step's end is in, as
            // `set_regions` locates it), no torque. The step's starting forces move to
            // `prev`.
            if let Some(field) = field {
                m.locate_at(field, &x);
            }
            work.free_steps += 1;
            work.rhs_evaluations += 1;
            a = self
                .phys
                .forces
                .acceleration(&m.body, &x, &v, m.region, &m.gust, work);
            if specimen {
                work.specimen_contact_checks += 1;
            }
            if wall {
                work.wall_contact_checks += 1;
            }
            std::mem::swap(acc, prev);
            acc[..6].copy_from_slice(&[v.x, v.y, v.z, a.x, a.y, a.z]);
            v = kicked(&v, &a, half);
            y[..6].copy_from_slice(&[x.x, x.y, x.z, v.x, v.y, v.z]);
            if spin {
                // No torque; the kick by it is still made, as the general step makes it
                // (it turns a spin component of -0 into +0).
                alpha = Vec3::zeros();
                acc[6..9].copy_from_slice(&[0.0; 3]);
                w = kicked(&w, &alpha, half);
                y[6..9].copy_from_slice(w.as_slice());
            }
            work.steps_accepted += 1;
            let state = [x.x, x.y, x.z, v.x, v.y, v.z, w.x, w.y, w.z];
            if !all_finite(&state) {
                fail_island(
                    std::slice::from_mut(m),
                    *t,
                    y,
                    out,
                    "the state stopped being finite",
                    "use a smaller fixed step",
                );
                return true;
            }
            observer(*t, y);
            // (No overlap to guard, no contact to end.)
            if !self.phys.domain.contains(&x) {
                self.leave_domain(std::slice::from_mut(m), *t, y);
            }
            if apart_after.is_some_and(|ta| *t >= ta) {
                return true;
            }
        }
        false
    }

    /// [`Ctx::rhs`] for the members of `dy` and the pairs `list` (ascending, every pair
    /// with a member in `dy`): a pair adds its terms to its members in `dy` and is counted
    /// by the part that holds its first member. `ALL`: `dy` holds every member.
    /// `tangent`: the contacts' tangential forces when the history law set them
    /// ([`Ctx::history`]), in place of the viscous law's.
    #[allow(clippy::too_many_arguments)]
    fn rhs_part<const ALL: bool>(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        list: impl Iterator<Item = usize>,
        (pushing, tangent): (Option<&Pushing>, Option<&[Vec3]>),
        t: f64,
        y: &[f64],
        dy: Part<'_>,
        work: &mut WorkCounters,
    ) {
        let c = &self.phys.contacts;
        let n = members.len();
        let fr = c.friction;
        let Part { lo, hi, lin, ang } = dy;
        ang.fill(0.0);
        let owns = |i: usize| ALL || (lo..hi).contains(&i);
        // Whether every member moves (known after the members' pass when it covers them
        // all): the pairs' pass then need not ask, member by member.
        let mut all_moving = ALL;
        for i in lo..hi {
            let m = &members[i];
            if !moving(m, t) {
                all_moving = false;
                lin[6 * (i - lo)..6 * (i - lo) + 6].fill(0.0);
                continue;
            }
            let p = pos(y, i);
            let v = vel(y, i);
            let inertia = INERTIA_FACTOR * m.body.mass * m.body.radius * m.body.radius;
            let mut a = self
                .phys
                .forces
                .acceleration(&m.body, &p, &v, m.region, &m.gust, work);
            if m.sliding {
                // In the specimen's plane; the contact carries the normal load, and with
                // friction holds the contact point still (rolling).
                if let Some(mu) = self.specimen_friction() {
                    work.friction_calls += 1;
                    let (ft, _) = rolling_friction(m.body.mass, &a, mu);
                    a += ft / m.body.mass;
                    let r_c = Vec3::new(0.0, 0.0, -m.body.radius);
                    add_at(ang, 3 * (i - lo), &(r_c.cross(&ft) / inertia));
                }
                lin[6 * (i - lo)..6 * (i - lo) + 6]
                    .copy_from_slice(&[v.x, v.y, 0.0, a.x, a.y, 0.0]);
                continue;
            }
            if let Some(sp) = &c.specimen {
                work.specimen_contact_checks += 1;
                // With located onsets, a specimen contact pushes from the end of the step
                // that located it: the trial steps that locate it see free flight, so the
                // recorded impact velocity is not polluted by the damping term's
                // delta^(1/4) jump weighted over the whole step (measured: 7.6e-5 of the
                // normal speed at 10 m/s). The contact then misses at most the
                // `1e-9 R` of overlap the location leaves, i.e. ~1e-14 s of force.
                // One search for the foot serves the overlap, the gap, the normal and the
                // radius.
                if (m.on_specimen || !self.onsets_located)
                    && let Some(touch) = sp.overlap_touch(&p, m.body.radius)
                {
                    let gap = touch.gap;
                    let k = sp.law.stiffness(touch.effective_radius);
                    // A contact pushing at the step's start: its force unclamped, so the
                    // stages of a step that runs past its kink see a smooth force (and the
                    // error estimate an error of the step's order, not of a kink's), and
                    // the step is then cut at the kink (`Ctx::event_margin`). Clamped, a
                    // step across the kink was rejected until it stopped short of it: on
                    // the 10,000-shot stream, a quarter of the rejected trials
                    // (docs/performance-history.md, "Contacts unclamped up to their kink, session
                    // 35"). Friction takes the clamped load.
                    let vn = sp.normal_velocity_at(&touch, &v);
                    let law = sp.law_of(m, vn);
                    let f = if pushing.is_some_and(|p| p.specimen[i]) {
                        law.force_unclamped(k, m.body.mass, -gap, -vn)
                    } else {
                        law.force(k, m.body.mass, -gap, -vn)
                    };
                    sp.add_normal_at(&touch, &mut a, f / m.body.mass);
                    let f = f.max(0.0);
                    if let Some(fr) = &fr {
                        work.friction_calls += 1;
                        // Contact point on the surface side of the centre, along the
                        // normal (on the plane, below it). The history law acts where
                        // LIGGGHTS' does (`Ctx::history`).
                        let r_c = sp.lever_at(&touch, history_lever(m.body.radius, -gap, tangent));
                        let ft = if let Some(tf) = tangent {
                            tf[pairs.len() + i]
                        } else {
                            let nz = touch.normal;
                            let slip =
                                friction::tangential_part(&(v + omega(y, n, i).cross(&r_c)), &nz);
                            let gamma = friction::stick_damping(
                                friction::sphere_on_wall_mass(m.body.mass),
                                k,
                                -gap,
                            );
                            friction::tangential_force(fr.specimen, f, &slip, gamma)
                        };
                        a += ft / m.body.mass;
                        add_at(ang, 3 * (i - lo), &(r_c.cross(&ft) / inertia));
                    }
                }
            }
            if let Some(w) = &c.wall {
                work.wall_contact_checks += 1;
                if let Some(g) = w.geometry(&p, m.body.radius)
                    && g.gap < 0.0
                {
                    let k = w.law.stiffness(w.effective_radius(m.body.radius));
                    let rate = v.dot(&g.outward);
                    let f = w.law.force(k, m.body.mass, -g.gap, rate);
                    a -= g.outward * (f / m.body.mass);
                    if let Some(fr) = &fr {
                        work.friction_calls += 1;
                        // Contact point towards the wall.
                        let r_c = g.outward * history_lever(m.body.radius, -g.gap, tangent);
                        let ft = if let Some(tf) = tangent {
                            tf[pairs.len() + n + i]
                        } else {
                            let slip = friction::tangential_part(
                                &(v + omega(y, n, i).cross(&r_c)),
                                &g.outward,
                            );
                            let gamma = friction::stick_damping(
                                friction::sphere_on_wall_mass(m.body.mass),
                                k,
                                -g.gap,
                            );
                            friction::tangential_force(fr.wall, f, &slip, gamma)
                        };
                        a += ft / m.body.mass;
                        add_at(ang, 3 * (i - lo), &(r_c.cross(&ft) / inertia));
                    }
                }
            }
            lin[6 * (i - lo)..6 * (i - lo) + 6].copy_from_slice(&[v.x, v.y, v.z, a.x, a.y, a.z]);
        }
        if let Some(pc) = &c.pair {
            for q in list {
                let pr = &pairs[q];
                let (i, j) = (pr.a as usize, pr.b as usize);
                if !all_moving && (!moving(&members[i], t) || !moving(&members[j], t)) {
                    continue;
                }
                let (own_i, own_j) = (owns(i), owns(j));
                if own_i {
                    work.pair_contact_checks += 1;
                }
                let (mi, mj) = (&members[i].body, &members[j].body);
                let Some(PairGeom {
                    nrm,
                    overlap,
                    rate,
                    k,
                    root_mk,
                    ..
                }) = pair_geometry(&self.laws[q], (i, mi), (j, mj), y)
                else {
                    continue;
                };
                // Unclamped while pushing at the step's start, as the specimen's above.
                let f = if pushing.is_some_and(|p| p.pairs[q]) {
                    pc.law.force_unclamped_with(k, root_mk, overlap, rate)
                } else {
                    pc.law.force_with(k, root_mk, overlap, rate)
                };
                if own_i {
                    add_at(lin, 6 * (i - lo) + 3, &(nrm * (-f / mi.mass)));
                }
                if own_j {
                    add_at(lin, 6 * (j - lo) + 3, &(nrm * (f / mj.mass)));
                }
                let f = f.max(0.0);
                if let Some(fr) = &fr {
                    if own_i {
                        work.friction_calls += 1;
                    }
                    let (ri, rj, slip) =
                        pair_slip(y, n, (i, mi.radius), (j, mj.radius), &nrm, overlap);
                    let ft = if let Some(tf) = tangent {
                        tf[q]
                    } else {
                        let gamma = friction::stick_damping(
                            friction::sphere_pair_mass(mi.mass, mj.mass),
                            k,
                            overlap,
                        );
                        friction::tangential_force(fr.shot, f, &slip, gamma)
                    };
                    if own_i {
                        add_at(lin, 6 * (i - lo) + 3, &(ft / mi.mass));
                        let ii = INERTIA_FACTOR * mi.mass * mi.radius * mi.radius;
                        add_at(ang, 3 * (i - lo), &(ri.cross(&ft) / ii));
                    }
                    if own_j {
                        add_at(lin, 6 * (j - lo) + 3, &(ft / -mj.mass));
                        let ij = INERTIA_FACTOR * mj.mass * mj.radius * mj.radius;
                        add_at(ang, 3 * (j - lo), &(rj.cross(&(-ft)) / ij));
                    }
                }
            }
        }
    }

    /// The history law's step ([`friction::history_step`]) of every contact of the
    /// members in state `y` at `t`, over `dt` (velocities at the step's half, as
    /// [`advance_verlet`] holds them when it evaluates the forces): each contact's
    /// tangential displacement (`IslandPair::xi`, `ShotState::specimen_xi`, `wall_xi`)
    /// grows by its slip and is cut to Coulomb's cone, and `out` receives the tangential
    /// forces for [`Ctx::rhs`], laid out as its `tangent` (the pairs', then each member's
    /// on the specimen, then on the wall). A contact that has ended loses its history.
    /// With `keep`, the displacements are read and left as they are (`dt` is then 0: the
    /// forces at a window's start).
    #[allow(clippy::too_many_arguments)]
    fn history(
        &self,
        members: &mut [ShotState],
        pairs: &mut [IslandPair],
        t: f64,
        y: &[f64],
        dt: f64,
        keep: bool,
        out: &mut Vec<Vec3>,
    ) {
        let c = &self.phys.contacts;
        let Some(fr) = &c.friction else {
            return;
        };
        let friction::Tangential::History {
            specimen: g_s,
            shot: g_p,
            wall: g_w,
        } = fr.law
        else {
            return;
        };
        let n = members.len();
        out.clear();
        out.resize(pairs.len() + 2 * n, Vec3::zeros());
        let step =
            |xi: &mut Vec3, n: &Vec3, slip: &Vec3, k_t: f64, gamma_t: f64, mu: f64, f_n: f64| {
                if keep {
                    let mut x = *xi;
                    friction::history_step(&mut x, n, slip, 0.0, k_t, gamma_t, mu, f_n)
                } else {
                    friction::history_step(xi, n, slip, dt, k_t, gamma_t, mu, f_n)
                }
            };
        for (i, m) in members.iter_mut().enumerate() {
            let moves = moving(m, t);
            let (p, v) = (pos(y, i), vel(y, i));
            let mass = m.body.mass;
            let mut on_specimen = false;
            if moves
                && let Some(sp) = &c.specimen
                && let Some(touch) = sp.overlap_touch(&p, m.body.radius)
            {
                on_specimen = true;
                let gap = touch.gap;
                let k = sp.law.stiffness(touch.effective_radius);
                let vn = sp.normal_velocity_at(&touch, &v);
                let law = sp.law_of(m, vn);
                let f_n = law.force(k, mass, -gap, -vn);
                let r_c = sp.lever_at(&touch, m.body.radius + 0.5 * gap);
                let nz = touch.normal;
                let slip = friction::tangential_part(&(v + omega(y, n, i).cross(&r_c)), &nz);
                let k_t = friction::history_stiffness(g_s, k, -gap);
                let gamma = friction::history_damping(g_s, law.damping, mass, k, -gap);
                out[pairs.len() + i] =
                    step(&mut m.specimen_xi, &nz, &slip, k_t, gamma, fr.specimen, f_n);
            }
            if !on_specimen && !keep {
                m.specimen_xi = Vec3::zeros();
            }
            let mut on_wall = false;
            if moves
                && let Some(w) = &c.wall
                && let Some(g) = w.geometry(&p, m.body.radius)
                && g.gap < 0.0
            {
                on_wall = true;
                let k = w.law.stiffness(w.effective_radius(m.body.radius));
                let f_n = w.law.force(k, mass, -g.gap, v.dot(&g.outward));
                let r_c = g.outward * (m.body.radius + 0.5 * g.gap);
                let slip = friction::tangential_part(&(v + omega(y, n, i).cross(&r_c)), &g.outward);
                let k_t = friction::history_stiffness(g_w, k, -g.gap);
                let gamma = friction::history_damping(g_w, w.law.damping, mass, k, -g.gap);
                out[pairs.len() + n + i] =
                    step(&mut m.wall_xi, &g.outward, &slip, k_t, gamma, fr.wall, f_n);
            }
            if !on_wall && !keep {
                m.wall_xi = Vec3::zeros();
            }
        }
        let Some(pc) = &c.pair else {
            return;
        };
        for (q, pr) in pairs.iter_mut().enumerate() {
            let (i, j) = (pr.a as usize, pr.b as usize);
            let (mi, mj) = (&members[i].body, &members[j].body);
            let geometry = (moving(&members[i], t) && moving(&members[j], t))
                .then(|| pair_geometry(&self.laws[q], (i, mi), (j, mj), y))
                .flatten();
            let Some(PairGeom {
                nrm,
                overlap,
                rate,
                k,
                m_eff,
                root_mk,
            }) = geometry
            else {
                if !keep {
                    pr.xi = Vec3::zeros();
                }
                continue;
            };
            let f_n = pc.law.force_with(k, root_mk, overlap, rate);
            let (_, _, slip) = pair_slip(y, n, (i, mi.radius), (j, mj.radius), &nrm, overlap);
            let k_t = friction::history_stiffness(g_p, k, overlap);
            let gamma = friction::history_damping(g_p, pc.law.damping, m_eff, k, overlap);
            out[q] = step(&mut pr.xi, &nrm, &slip, k_t, gamma, fr.shot, f_n);
        }
    }

    /// Smallest margin (m) over the events that cut a step: a moving member leaving its
    /// frozen jet region (the field jumps at region borders), a shot touching the
    /// specimen (located exactly: the impact record is the product), and an impact's
    /// force reaching zero before the bodies part (the clamp's kink; for the contacts
    /// `pushing` at the step start, weighted by `KINK_SCALE`), and two shots touching at
    /// an impact's closing speed (the dashpot's `delta^(1/4)` makes the force's slope
    /// infinite at the touch, which a step straddling it integrates badly and its error
    /// estimate underrates: measured, a rebound error of 1.7e-5 at tolerance 1e-6), and
    /// the same two events of the nozzle wall (its touch at an impact's speed, its kink).
    /// Positive: none. Slower shot-shot and wall onsets (a resting pile's contacts) do not
    /// cut steps (see [`Ctx::record_onsets`]).
    fn event_margin(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        pushing: &Pushing,
        t: f64,
        y: &[f64],
    ) -> f64 {
        self.margin_of(members, pairs, pushing, t, y, true)
    }

    /// [`Ctx::event_margin`] without the jet's region boundaries (`regions` false): the
    /// margin of the events that change more than which formula the air takes.
    #[inline]
    fn margin_of(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        pushing: &Pushing,
        t: f64,
        y: &[f64],
        regions: bool,
    ) -> f64 {
        let part = |ms: Range<usize>, ps: Range<usize>| {
            self.margin_part(members, pairs, (ms, ps), pushing, t, y, regions)
        };
        match &self.blocks {
            None => part(0..members.len(), 0..pairs.len()),
            Some(blocks) => blocks.fold(f64::INFINITY, f64::min, part),
        }
    }

    /// [`Ctx::margin_of`] over the members and pairs in `ranges`.
    #[allow(clippy::too_many_arguments)]
    fn margin_part(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        (ms, ps): (Range<usize>, Range<usize>),
        pushing: &Pushing,
        t: f64,
        y: &[f64],
        regions: bool,
    ) -> f64 {
        let field = self.phys.forces.field.as_ref().filter(|_| regions);
        let specimen = self.phys.contacts.specimen.as_ref();
        let mut g = f64::INFINITY;
        for i in ms {
            let m = &members[i];
            if !moving(m, t) {
                continue;
            }
            let p = pos(y, i);
            if let Some(field) = field {
                g = g.min(REGION_SCALE * field.margin(&field.coords(&p), m.region));
                if field.layer.is_some() {
                    g = g.min(REGION_SCALE * field.layer_margin(&p, m.in_layer));
                }
            }
            if m.sliding {
                // A sliding shot's steps are not capped (`advance_adaptive`): its events are
                // located. It leaves the domain; its load lifts it off; rolling, it slips
                // where rolling would take more than `mu F`. (The forces here are not
                // counted among the work: they only locate events.)
                let a = self.phys.forces.acceleration(
                    &m.body,
                    &p,
                    &vel(y, i),
                    m.region,
                    &m.gust,
                    &mut WorkCounters::default(),
                );
                g = g.min(self.phys.domain.radius - p.x.hypot(p.y));
                g = g.min(m.body.radius * -a.z / (a.z.abs() + STANDARD_GRAVITY));
                if let Some(mu) = self.specimen_friction() {
                    let (_, ratio) = rolling_friction(m.body.mass, &a, mu);
                    g = g.min(m.body.radius * (1.0 - ratio));
                }
            } else if let Some(sp) = specimen {
                if !m.on_specimen {
                    g = g.min(sp.gap_below(&p, m.body.radius, g));
                } else if pushing.specimen[i] {
                    g = g.min(KINK_SCALE * self.specimen_unloading(m, i, y));
                }
            }
            if pushing.wall[i] != WallEvent::None {
                g = g.min(KINK_SCALE * self.wall_margin(m, i, y, pushing.wall[i]));
            }
        }
        for q in ps {
            let pr = &pairs[q];
            if pushing.pairs[q] {
                g = g.min(KINK_SCALE * self.pair_unloading(members, pairs, q, y));
            }
            if pushing.approaching[q] {
                g = g.min(KINK_SCALE * pair_gap(members, pr, y));
            }
        }
        g
    }

    /// [`HertzLaw::unloading_margin`] of member `i`'s specimen contact.
    fn specimen_unloading(&self, m: &ShotState, i: usize, y: &[f64]) -> f64 {
        let sp = self
            .phys
            .contacts
            .specimen
            .as_ref()
            .expect("BUG: specimen contact without specimen");
        let touch = sp.touch(&pos(y, i), m.body.radius);
        let k = sp.law.stiffness(touch.effective_radius);
        let overlap = -touch.gap;
        let vn = sp.normal_velocity_at(&touch, &vel(y, i));
        sp.law_of(m, vn)
            .unloading_margin(k, m.body.mass, overlap, -vn)
    }

    /// Member `i`'s nozzle-wall margin for `what`: the gap while approaching, the
    /// [`HertzLaw::unloading_margin`] while pushing (no event where the shot is out of
    /// the wall's reach).
    fn wall_margin(&self, m: &ShotState, i: usize, y: &[f64], what: WallEvent) -> f64 {
        let Some(w) = &self.phys.contacts.wall else {
            return f64::INFINITY;
        };
        let p = pos(y, i);
        if what == WallEvent::Touch {
            // Continuous beyond the ends too (`Tube::clearance`): a touch is located
            // wherever the step started.
            return w.tube.clearance(&p, m.body.radius);
        }
        let Some(geo) = w.geometry(&p, m.body.radius) else {
            return f64::INFINITY;
        };
        match what {
            WallEvent::Touch => geo.gap,
            WallEvent::Kink => {
                let k = w.law.stiffness(w.effective_radius(m.body.radius));
                w.law
                    .unloading_margin(k, m.body.mass, -geo.gap, vel(y, i).dot(&geo.outward))
            }
            WallEvent::None => f64::INFINITY,
        }
    }

    /// A touching pair's contact now (`None` at zero distance), `law` its constants.
    fn pair_now(
        &self,
        members: &[ShotState],
        (pr, law): (&IslandPair, &PairLaw),
        y: &[f64],
    ) -> Option<PairNow<'_>> {
        let pc = self
            .phys
            .contacts
            .pair
            .as_ref()
            .expect("BUG: touching pair without pair contact");
        let (i, j) = (pr.a as usize, pr.b as usize);
        let (bi, bj) = (members[i].body, members[j].body);
        let d = pos(y, j) - pos(y, i);
        let dist = d.norm();
        if dist == 0.0 {
            return None;
        }
        let closing = -(vel(y, j) - vel(y, i)).dot(&(d / dist));
        Some(PairNow {
            law: &pc.law,
            k: law.k,
            m_eff: law.m_eff,
            overlap: bi.radius + bj.radius - dist,
            closing,
            size: 2.0 * bi.radius.min(bj.radius),
        })
    }

    /// [`HertzLaw::unloading_margin`] of touching pair `q`.
    fn pair_unloading(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        q: usize,
        y: &[f64],
    ) -> f64 {
        let pair = (&pairs[q], &self.laws[q]);
        self.pair_now(members, pair, y).map_or(f64::INFINITY, |c| {
            c.law.unloading_margin(c.k, c.m_eff, c.overlap, c.closing)
        })
    }

    /// Whether a touching pair pushes ([`HertzLaw::unloading_margin`] positive) with a
    /// kink that matters to a step of `h` ([`kink_matters`]).
    fn pair_pushes(
        &self,
        members: &[ShotState],
        pair: (&IslandPair, &PairLaw),
        y: &[f64],
        h: f64,
    ) -> bool {
        let Some(c) = self.pair_now(members, pair, y) else {
            return false;
        };
        let mu = self.phys.contacts.friction.map_or(0.0, |f| f.shot);
        let (tol, state) = (self.phys.tolerance, (c.overlap, c.closing));
        c.law.unloading_margin(c.k, c.m_eff, c.overlap, c.closing) > 0.0
            && kink_matters(tol, c.k, c.m_eff, state, h, mu, c.size)
    }

    /// The contacts still pushing at the start of a step of `h` (unloading margin
    /// positive) whose kink matters to it ([`kink_matters`]): the step is cut where
    /// one stops. Contacts past that kink (force clamped at zero until they separate)
    /// are left out, and come back if they load again; so are the contacts whose kink a
    /// step of `h` may run over (their force clamped: the error estimate sees the rest).
    fn pushing(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        t: f64,
        y: &[f64],
        h: f64,
        out: &mut Pushing,
    ) {
        let fr = self.phys.contacts.friction;
        out.specimen.clear();
        out.specimen
            .extend(members.iter().enumerate().map(|(i, m)| {
                let Some(sp) = self.phys.contacts.specimen.as_ref() else {
                    return false;
                };
                moving(m, t)
                    && m.on_specimen
                    && t - m.specimen_onset <= 3.0 * m.specimen_contact_time
                    && self.specimen_unloading(m, i, y) > 0.0
                    && {
                        let touch = sp.touch(&pos(y, i), m.body.radius);
                        let k = sp.law.stiffness(touch.effective_radius);
                        let overlap = -touch.gap;
                        let vn = sp.normal_velocity_at(&touch, &vel(y, i));
                        let mu = fr.map_or(0.0, |f| f.specimen);
                        let size = 2.0 * m.body.radius;
                        let tol = self.phys.tolerance;
                        kink_matters(tol, k, m.body.mass, (overlap, -vn), h, mu, size)
                    }
            }));
        // Per pair: pushing, and approaching at an impact's speed.
        let flags = |ps: Range<usize>, push: &mut [bool], close: &mut [bool]| {
            let laws = &self.laws[ps.clone()];
            for (k, (pr, law)) in pairs[ps].iter().zip(laws).enumerate() {
                let (i, j) = (pr.a as usize, pr.b as usize);
                let both = moving(&members[i], t) && moving(&members[j], t);
                push[k] = pr.touching
                    && t - pr.onset <= 3.0 * pr.contact_time
                    && both
                    && self.pair_pushes(members, (pr, law), y, h);
                close[k] = !pr.touching && both && pair_gap(members, pr, y) > 0.0 && {
                    let d = pos(y, j) - pos(y, i);
                    -(vel(y, j) - vel(y, i)).dot(&d) >= RAMP_MIN_SPEED * d.norm()
                };
            }
        };
        for v in [&mut out.pairs, &mut out.approaching] {
            v.clear();
            v.resize(pairs.len(), false);
        }
        match &self.blocks {
            None => flags(0..pairs.len(), &mut out.pairs, &mut out.approaching),
            Some(blocks) => {
                let b = &blocks.pair_bounds;
                let parts = cut(&mut out.pairs, b, 1).into_iter();
                let parts = parts.zip(cut(&mut out.approaching, b, 1)).collect();
                blocks.run(parts, |k, (push, close)| flags(b[k]..b[k + 1], push, close));
            }
        }
        out.wall.clear();
        out.wall.extend(members.iter().enumerate().map(|(i, m)| {
            if !moving(m, t) || self.phys.contacts.wall.is_none() {
                return WallEvent::None;
            }
            let (p, v) = (pos(y, i), vel(y, i));
            let Some(w) = self.phys.contacts.wall.as_ref() else {
                return WallEvent::None;
            };
            let Some(geo) = w.geometry(&p, m.body.radius) else {
                // Beyond an end: a touch is still an event if the shot approaches the
                // nearest part of the tube (`contact_cap` keeps its steps short enough);
                // moving away from the end's plane, it cannot touch it in this step.
                if v.dot(&w.tube.beyond_end(&p).1) <= 0.0 {
                    return WallEvent::None;
                }
                return match w.tube.nearest(&p, m.body.radius) {
                    Some(g) if g.gap > 0.0 && v.dot(&g.outward) >= RAMP_MIN_SPEED => {
                        WallEvent::Touch
                    }
                    _ => WallEvent::None,
                };
            };
            if m.on_wall {
                let young = t - m.wall_onset <= 3.0 * m.wall_contact_time;
                if young && self.wall_margin(m, i, y, WallEvent::Kink) > 0.0 {
                    WallEvent::Kink
                } else {
                    WallEvent::None
                }
            } else if geo.gap > 0.0 && v.dot(&geo.outward) >= RAMP_MIN_SPEED {
                WallEvent::Touch
            } else {
                WallEvent::None
            }
        }));
    }

    /// Shot-shot and wall contact onsets inside the accepted step `[t0, t0 + h]` (start
    /// `y0`, end `y1`): contacts open at the start that overlap at the end. The onset
    /// time, position and velocity come from the cubic Hermite interpolant of the step,
    /// whose gap root is found by bisection. A shot-shot or wall touch at an impact's
    /// speed was located before (it ends the step, so its onset is the step's end);
    /// slower ones (a resting pile's) let the step stand, their force being continuous at
    /// the onset. Specimen onsets were located exactly before (they end the step), and
    /// are only caught here if a shot entered the run overlapping the specimen.
    #[allow(clippy::too_many_arguments)]
    fn record_onsets(
        &self,
        members: &mut [ShotState],
        pairs: &mut [IslandPair],
        t0: f64,
        h: f64,
        y0: &[f64],
        y1: &[f64],
        out: &mut IslandOutput,
    ) {
        let c = &self.phys.contacts;
        let tol = 1e-12
            * members
                .iter()
                .map(|m| m.body.radius)
                .fold(f64::INFINITY, f64::min);
        let root = |gap: &dyn Fn(f64) -> f64| onset_fraction(gap, tol);
        let n = members.len();
        for (i, m) in members.iter_mut().enumerate() {
            if !moving(m, t0) {
                continue;
            }
            let r = m.body.radius;
            if let Some(sp) = &c.specimen
                && !m.on_specimen
                && sp.overlap_gap(&pos(y1, i), r) < 0.0
            {
                let g = |s: f64| sp.gap(&hermite(y0, y1, h, i, s).0, r);
                let s = if g(0.0) < 0.0 { 0.0 } else { root(&g) };
                let (p, v) = hermite(y0, y1, h, i, s);
                let w = spin_at(y0, y1, n, i, s);
                self.specimen_onset(m, t0 + s * h, &p, &v, &w, out);
            }
            if let Some(w) = &c.wall
                && !m.on_wall
                && w.geometry(&pos(y1, i), r).is_some_and(|g| g.gap < 0.0)
            {
                let g = |s: f64| {
                    w.geometry(&hermite(y0, y1, h, i, s).0, r)
                        .map_or(1.0, |g| g.gap)
                };
                let s = if g(0.0) < 0.0 { 0.0 } else { root(&g) };
                let (p, v) = hermite(y0, y1, h, i, s);
                self.wall_onset(m, t0 + s * h, &p, &v, out);
            }
        }
        if c.pair.is_some() {
            for pr in pairs.iter_mut() {
                let (i, j) = (pr.a as usize, pr.b as usize);
                if pr.touching || !moving(&members[i], t0) || !moving(&members[j], t0) {
                    continue;
                }
                let rr = members[i].body.radius + members[j].body.radius;
                if (pos(y1, j) - pos(y1, i)).norm() >= rr {
                    continue;
                }
                let g =
                    |s: f64| (hermite(y0, y1, h, j, s).0 - hermite(y0, y1, h, i, s).0).norm() - rr;
                let s = if g(0.0) < 0.0 { 0.0 } else { root(&g) };
                let (pi, vi) = hermite(y0, y1, h, i, s);
                let (pj, vj) = hermite(y0, y1, h, j, s);
                self.pair_onset(pr, members, t0 + s * h, (&pi, &vi), (&pj, &vj), out);
            }
        }
    }

    fn specimen_onset(
        &self,
        m: &mut ShotState,
        t: f64,
        p: &Vec3,
        v: &Vec3,
        w: &Vec3,
        out: &mut IslandOutput,
    ) {
        let sp = self
            .phys
            .contacts
            .specimen
            .as_ref()
            .expect("BUG: specimen onset without specimen");
        let touch = sp.touch(p, m.body.radius);
        let vn = sp.normal_velocity_at(&touch, v);
        m.specimen_damping = sp.law_at(-vn).damping;
        m.on_specimen = true;
        let k = sp.law.stiffness(touch.effective_radius);
        m.specimen_contact_time = hertz::contact_time(m.body.mass, k, (-vn).max(MIN_CONTACT_SPEED));
        m.specimen_onset = t;
        m.hits += 1;
        if m.hits == 1 {
            m.steps_to_first_contact = Some(m.steps);
        }
        out.impacts.push(Impact::on(
            &sp.shape,
            m.id.0,
            t,
            p,
            v,
            w,
            m.body.radius,
            m.body.mass,
            m.collisions,
            m.hits == 1,
        ));
        out.work.contact_onsets += 1;
    }

    fn wall_onset(&self, m: &mut ShotState, t: f64, p: &Vec3, v: &Vec3, out: &mut IslandOutput) {
        let w = self
            .phys
            .contacts
            .wall
            .as_ref()
            .expect("BUG: wall onset without wall");
        let outward = w
            .geometry(p, m.body.radius)
            .map_or(Vec3::zeros(), |g| g.outward);
        m.on_wall = true;
        let k = w.law.stiffness(w.effective_radius(m.body.radius));
        m.wall_contact_time =
            hertz::contact_time(m.body.mass, k, v.dot(&outward).max(MIN_CONTACT_SPEED));
        m.wall_onset = t;
        m.wall_contacts += 1;
        out.work.contact_onsets += 1;
    }

    fn pair_onset(
        &self,
        pr: &mut IslandPair,
        members: &mut [ShotState],
        t: f64,
        (pi, vi): (&Vec3, &Vec3),
        (pj, vj): (&Vec3, &Vec3),
        out: &mut IslandOutput,
    ) {
        let pc = self
            .phys
            .contacts
            .pair
            .as_ref()
            .expect("BUG: pair onset without pair contact");
        let (i, j) = (pr.a as usize, pr.b as usize);
        let (bi, bj) = (members[i].body, members[j].body);
        let d = pj - pi;
        let n = if d.norm() > 0.0 {
            d / d.norm()
        } else {
            Vec3::z()
        };
        let closing = -(vj - vi).dot(&n);
        let k = pc
            .law
            .stiffness(PairContact::effective_radius(bi.radius, bj.radius));
        pr.touching = true;
        pr.onset = t;
        pr.contact_time = hertz::contact_time(
            effective_mass(bi.mass, bj.mass),
            k,
            closing.max(MIN_CONTACT_SPEED),
        );
        members[i].collisions += 1;
        members[j].collisions += 1;
        out.work.contact_onsets += 1;
    }

    /// Applies what holds at `(t, y)` at the start of a step: region switches (after a
    /// located crossing, or a shot placed on a border) and contacts that already overlap
    /// (a shot entering the run in contact). Returns whether anything changed.
    fn apply_events(
        &self,
        members: &mut [ShotState],
        pairs: &mut [IslandPair],
        t: f64,
        y: &[f64],
        out: &mut IslandOutput,
    ) -> bool {
        let mut changed = false;
        let n = members.len();
        for (i, m) in members.iter_mut().enumerate() {
            if moving(m, t) {
                changed |= self.member_events(m, (i, n), t, y, out);
            }
        }
        if self.phys.contacts.pair.is_some() {
            for pr in pairs.iter_mut() {
                let (i, j) = (pr.a as usize, pr.b as usize);
                if pr.touching || !moving(&members[i], t) || !moving(&members[j], t) {
                    continue;
                }
                let radii = (members[i].body.radius, members[j].body.radius);
                changed |= self.pair_events(pr, radii, members, t, y, out);
            }
        }
        changed
    }

    /// [`Ctx::apply_events`] of moving member `i` of `n`, `m`: its regions, its eddy, its
    /// onsets on the specimen and the wall. Whether anything changed.
    #[inline(always)]
    fn member_events(
        &self,
        m: &mut ShotState,
        (i, n): (usize, usize),
        t: f64,
        y: &[f64],
        out: &mut IslandOutput,
    ) -> bool {
        let c = &self.phys.contacts;
        let mut changed = false;
        let (p, v) = (pos(y, i), vel(y, i));
        let r = m.body.radius;
        if let Some(field) = &self.phys.forces.field
            && (!self.regions_set || self.phys.forces.turbulence.is_some())
        {
            let co = field.coords(&p);
            if !self.regions_set {
                if field.margin(&co, m.region) < 0.0 {
                    let next = field.region_of(&co);
                    if next != m.region {
                        m.region = next;
                        out.work.region_crossings += 1;
                        changed = true;
                    }
                }
                if field.layer_margin(&p, m.in_layer) < 0.0 {
                    m.in_layer = !m.in_layer;
                    out.work.region_crossings += 1;
                    changed = true;
                }
            }
            // Turbulent eddies: a new one when the last has lived its lifetime; none
            // outside the mixing layer and the developed jet.
            if let Some(turb) = &self.phys.forces.turbulence {
                if !Turbulence::turbulent(m.region) {
                    if m.gust_until > f64::NEG_INFINITY {
                        m.gust = Vec3::zeros();
                        m.gust_until = f64::NEG_INFINITY;
                        changed = true;
                    }
                } else if t >= m.gust_until {
                    let (u, _) = field.speed_density(&co, m.region);
                    match turb.eddy(m.id.0, m.gusts, &co, m.region, u) {
                        Some((g, life)) => {
                            m.gust = g;
                            m.gust_until = t + life;
                            m.gusts += 1;
                            out.work.eddies += 1;
                        }
                        None => {
                            m.gust = Vec3::zeros();
                            m.gust_until = f64::NEG_INFINITY;
                        }
                    }
                    changed = true;
                }
            }
        }
        if let Some(sp) = &c.specimen
            && !m.on_specimen
            && sp.overlap_gap(&p, r) < 0.0
        {
            let w = spin_at(y, y, n, i, 0.0);
            self.specimen_onset(m, t, &p, &v, &w, out);
            changed = true;
        }
        if let Some(w) = &c.wall
            && !m.on_wall
            && w.geometry(&p, r).is_some_and(|g| g.gap < 0.0)
        {
            self.wall_onset(m, t, &p, &v, out);
            changed = true;
        }
        changed
    }

    /// [`Ctx::apply_events`] of a pair not touching whose members both move (radii `ri`
    /// and `rj`): its onset if they overlap. Whether it touched.
    #[inline(always)]
    fn pair_events(
        &self,
        pr: &mut IslandPair,
        (ri, rj): (f64, f64),
        members: &mut [ShotState],
        t: f64,
        y: &[f64],
        out: &mut IslandOutput,
    ) -> bool {
        let (i, j) = (pr.a as usize, pr.b as usize);
        let (pi, pj) = (pos(y, i), pos(y, j));
        let (d, reach) = (pj - pi, ri + rj);
        if !surely_apart(&d, reach) && d.norm() < reach {
            let (vi, vj) = (vel(y, i), vel(y, j));
            self.pair_onset(pr, members, t, (&pi, &vi), (&pj, &vj), out);
            return true;
        }
        false
    }

    /// Step cap (s) from contacts in progress and contacts being approached, and the
    /// impacts that touched within a contact step before `t` or at `t`
    /// (the step's result is then corrected by [`Ctx::correct_onsets`]).
    ///
    /// An impact is resolved with `contact_steps` steps per Hertz duration. A contact that
    /// has lasted more than three Hertz durations is persistent (a shot resting or
    /// rolling): it is capped at a tenth of its current linearised oscillation period
    /// `2 pi sqrt(m* / (1.5 K delta^(1/2)))` instead, leaving accuracy to the error
    /// controller, so resting shots do not pay impact-sized steps forever.
    fn contact_cap(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        t: f64,
        y: &[f64],
    ) -> (f64, Onsets) {
        let c = &self.phys.contacts;
        let n = self.phys.contact_steps;
        let mut cap = f64::INFINITY;
        let onsets = std::cell::Cell::new(Onsets::None);
        // How long a step a slow touch may fall in (`HertzLaw::touch_span`), within one
        // contact step, and no shorter than before such spans (an onset step).
        let span = |law: &HertzLaw, tc: f64, m_eff: f64, k: f64, v: f64| -> f64 {
            let dv = UNSEEN_SHARE * self.phys.tolerance;
            law.touch_span(k, m_eff, v, dv)
                .clamp(ONSET_STEP * tc / n, tc / n)
        };
        let in_contact =
            |law: &HertzLaw, tc: f64, onset: f64, overlap: f64, m_eff: f64, k: f64| -> f64 {
                // Right after an onset: the dashpot's delta^(1/4) makes the force's slope
                // infinite there, which a Runge-Kutta step only resolves when it is short,
                // and the error estimate underrates it. The steps within a contact step of
                // the touch are corrected for that (`HertzLaw::onset_correction`, and the
                // tangential force's start with friction), and the step that starts on
                // the touch (located: the usual case) is `first_contact_step` long; an
                // onset found inside a step (none located) steps from 1 % of a contact
                // step. The steps grow from there
                // at most five-fold per step (a step cut by a cap does not restrain the
                // controller's next proposal, so without this the second step jumped to a
                // whole contact step: measured, a rebound error of 5e-4 at any tolerance
                // above 1e-5). Only for impacts (a closing speed of at least
                // `RAMP_MIN_SPEED` at the onset, read back from the contact's Hertz time
                // `tc ~ v^(-1/5)`): the contacts of a resting pile open and close at
                // millimetres per second, where a ramp would cost every member of its
                // island steps. Their touch (found inside a step) is bounded instead: the
                // step after it is at most its span (`HertzLaw::touch_span`: a tenth of
                // the tolerance's velocity error from the force's start). Until session
                // 39 it was 0.1 % of a contact time, and the slow touches of a 10,240-shot
                // bed cut half of its steps.
                if self.fresh_impact(t, tc, onset, m_eff, k) {
                    onsets.set(onsets.get().max(Onsets::Recent));
                    if t - onset <= AT_ONSET * tc {
                        onsets.set(Onsets::AtStart);
                        return first_contact_step(tc, n, self.phys.tolerance);
                    }
                    let early = (ONSET_STEP * tc / n).max(4.0 * (t - onset));
                    if early < tc / n {
                        return early;
                    }
                } else if t - onset < tc / n {
                    let span = span(law, tc, m_eff, k, hertz::impact_speed(m_eff, k, tc));
                    if t - onset < span {
                        return span;
                    }
                }
                if t - onset <= 3.0 * tc {
                    return tc / n;
                }
                let k_lin = 1.5 * k * overlap.max(0.0).sqrt();
                if k_lin > 0.0 {
                    0.1 * std::f64::consts::TAU * (m_eff / k_lin).sqrt()
                } else {
                    tc / n
                }
            };
        // Approach: the step may end at most one contact-resolving step past the
        // ballistic touching time, so a contact is neither skipped nor entered deeply:
        // an impact's onset step, a slow touch's span (see `in_contact`).
        // (`cap` so far: a touch no sooner than that cannot lower it, and its Hertz time
        // costs a power.)
        let approach = |law: &HertzLaw, gap: f64, closing: f64, m_eff: f64, k: f64, cap: f64| {
            if closing <= 0.0 {
                return f64::INFINITY;
            }
            let free = gap.max(0.0) / closing;
            if free >= cap {
                return free;
            }
            let tc = hertz::contact_time(m_eff, k, closing);
            if closing < RAMP_MIN_SPEED {
                free + span(law, tc, m_eff, k, closing)
            } else {
                free + ONSET_STEP * tc / n
            }
        };
        for (i, m) in members.iter().enumerate() {
            if !moving(m, t) {
                continue;
            }
            let p = pos(y, i);
            let v = vel(y, i);
            if let Some(sp) = &c.specimen
                && !m.sliding
            {
                if m.on_specimen {
                    let touch = sp.touch(&p, m.body.radius);
                    let k = sp.law.stiffness(touch.effective_radius);
                    let overlap = -touch.gap;
                    cap = cap.min(in_contact(
                        &sp.law_of(m, sp.normal_velocity_at(&touch, &v)),
                        m.specimen_contact_time,
                        m.specimen_onset,
                        overlap,
                        m.body.mass,
                        k,
                    ));
                } else {
                    let touch = sp.touch(&p, m.body.radius);
                    let k = sp.law.stiffness(touch.effective_radius);
                    let vn = sp.normal_velocity_at(&touch, &v);
                    // Towards a convex part the gap closes no faster than `-vn`; in a
                    // groove a shot may close on another face than the nearest (along
                    // the bottom towards a flank: `SpecimenShape::closing_speed`; found
                    // by bench/random_scenes.py --groove, where such a step crossed a
                    // tooth's edge unseen).
                    let gap = touch.gap;
                    let closing = if sp.shape.is_plane() {
                        -vn
                    } else {
                        sp.shape.closing_speed(&p, &v, m.body.radius, gap)
                    };
                    cap = cap.min(approach(&sp.law_at(-vn), gap, closing, m.body.mass, k, cap));
                }
            }
            if let Some(w) = &c.wall {
                if m.on_wall {
                    let k = w.law.stiffness(w.effective_radius(m.body.radius));
                    let overlap = w.geometry(&p, m.body.radius).map_or(0.0, |g| -g.gap);
                    cap = cap.min(in_contact(
                        &w.law,
                        m.wall_contact_time,
                        m.wall_onset,
                        overlap,
                        m.body.mass,
                        k,
                    ));
                } else if let Some(geo) = w.geometry(&p, m.body.radius) {
                    let k = w.law.stiffness(w.effective_radius(m.body.radius));
                    // Inside the bore the wall is concave: a shot moving across the
                    // axis closes on it faster than its speed towards the nearest wall
                    // point says (at first not at all, moving along a chord), and a shot
                    // just beyond an end, inside the lip, may enter the bore and cross
                    // it within the step. A shot nearer the axis than `R_b - R` touches
                    // nothing before its distance from the axis has grown that far, at
                    // most at its speed across the axis; one nearer the axis than `R_b`
                    // but not than that (passing a lip) nothing before it has covered
                    // its gap, at most at its speed. Beside the tube or past a face the
                    // tube lies inside a convex set (the solid cylinder of the outer
                    // radius, cut at the end's plane) whose nearest point is the tube's,
                    // and the speed towards that point bounds the approach.
                    let (rho, rb) = (w.tube.radial_distance(&p), w.tube.bore_radius);
                    let (gap, closing) = if rho < rb - m.body.radius {
                        (rb - m.body.radius - rho, w.tube.speed_across_axis(&v))
                    } else if rho < rb {
                        (geo.gap, v.norm())
                    } else {
                        (geo.gap, v.dot(&geo.outward))
                    };
                    cap = cap.min(approach(&w.law, gap, closing, m.body.mass, k, cap));
                } else {
                    // More than a radius beyond an end: the shot can touch the tube only
                    // once it is within a radius of that end's plane. The tube is not
                    // convex, so a step that starts and ends clear of it can still cross
                    // a corner (the lip, or a body's face edge) on its way: until session
                    // 28 such steps were not capped, and a shot crossed a corner unseen.
                    let (beyond, towards) = w.tube.beyond_end(&p);
                    let closing = v.dot(&towards);
                    if closing > 0.0 {
                        let k = w.law.stiffness(w.effective_radius(m.body.radius));
                        let gap = beyond - m.body.radius;
                        cap = cap.min(approach(&w.law, gap, closing, m.body.mass, k, cap));
                    }
                }
            }
        }
        if let Some(pc) = &c.pair {
            for (pr, law) in pairs.iter().zip(self.laws) {
                let (i, j) = (pr.a as usize, pr.b as usize);
                if !moving(&members[i], t) || !moving(&members[j], t) {
                    continue;
                }
                let (bi, bj) = (members[i].body, members[j].body);
                let dpos = pos(y, j) - pos(y, i);
                let dist = dpos.norm();
                if pr.touching {
                    let overlap = bi.radius + bj.radius - dist;
                    cap = cap.min(in_contact(
                        &pc.law,
                        pr.contact_time,
                        pr.onset,
                        overlap,
                        law.m_eff,
                        law.k,
                    ));
                    continue;
                }
                if dist == 0.0 {
                    continue;
                }
                let nrm = dpos / dist;
                let closing = -(vel(y, j) - vel(y, i)).dot(&nrm);
                cap = cap.min(approach(
                    &pc.law,
                    dist - bi.radius - bj.radius,
                    closing,
                    law.m_eff,
                    law.k,
                    cap,
                ));
            }
        }
        (cap, onsets.get())
    }

    /// Adds to the step `(t, y0) -> (t + h, y1)` what its quadrature missed of the start
    /// of the impacts that touched within a contact step before `t`
    /// (`HertzLaw::onset_correction`): the normal force's along each contact's normal at
    /// `t`, and with friction the tangential force's along the contact point's slip
    /// there (`friction::onset_terms`); the contacts `contact_cap` reports in its
    /// [`Onsets`].
    #[allow(clippy::too_many_arguments)]
    fn correct_onsets(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        t: f64,
        h: f64,
        y0: &[f64],
        y1: &mut [f64],
    ) {
        let c = &self.phys.contacts;
        let n = members.len();
        let fr = c.friction;
        let fresh = |tc, onset, m_eff, k| self.fresh_impact(t, tc, onset, m_eff, k);
        let push = |y1: &mut [f64], i: usize, dir: &Vec3, mass: f64, (dx, dv): (f64, f64)| {
            add_at(y1, 6 * i, &(dir * (dx / mass)));
            add_acc(y1, i, &(dir * (dv / mass)));
        };
        for (i, m) in members.iter().enumerate() {
            if !moving(m, t) {
                continue;
            }
            let mass = m.body.mass;
            let (p, v, r) = (pos(y0, i), vel(y0, i), m.body.radius);
            // A contact with the specimen (`up`: +z) or the wall (`up`: inward).
            let one = |y1: &mut [f64], law: &hertz::HertzLaw, k, tc, onset, up: Vec3, mu| {
                let v0 = hertz::impact_speed(mass, k, tc);
                let terms = law.onset_terms(k, mass, v0);
                push(
                    y1,
                    i,
                    &up,
                    mass,
                    hertz::start_correction(terms, t - onset, h),
                );
                if mu > 0.0 {
                    let r_c = up * -r;
                    let slip = friction::tangential_part(&(v + omega(y0, n, i).cross(&r_c)), &up);
                    let m_t = friction::sphere_on_wall_mass(mass);
                    let d_t = friction::onset_terms(mu, terms, m_t, k, v0, slip.norm());
                    tangential_start(y1, n, &slip, d_t, t - onset, h, &[(i, m, r_c)]);
                }
            };
            if let Some(sp) = &c.specimen
                && m.on_specimen
            {
                let touch = sp.touch(&p, r);
                let k = sp.law.stiffness(touch.effective_radius);
                if fresh(m.specimen_contact_time, m.specimen_onset, mass, k) {
                    let mu = fr.map_or(0.0, |f| f.specimen);
                    let (tc, on) = (m.specimen_contact_time, m.specimen_onset);
                    let law = sp.law_of(m, sp.normal_velocity_at(&touch, &v));
                    one(y1, &law, k, tc, on, touch.normal, mu);
                }
            }
            if let Some(w) = &c.wall {
                let k = w.law.stiffness(w.effective_radius(r));
                if m.on_wall
                    && fresh(m.wall_contact_time, m.wall_onset, mass, k)
                    && let Some(g) = w.geometry(&p, r)
                {
                    let mu = fr.map_or(0.0, |f| f.wall);
                    let (tc, on) = (m.wall_contact_time, m.wall_onset);
                    one(y1, &w.law, k, tc, on, -g.outward, mu);
                }
            }
        }
        if let Some(pc) = &c.pair {
            let mu = fr.map_or(0.0, |f| f.shot);
            for pr in pairs {
                let (i, j) = (pr.a as usize, pr.b as usize);
                if !pr.touching || !moving(&members[i], t) || !moving(&members[j], t) {
                    continue;
                }
                let (bi, bj) = (members[i].body, members[j].body);
                let k = pc
                    .law
                    .stiffness(PairContact::effective_radius(bi.radius, bj.radius));
                let m_eff = effective_mass(bi.mass, bj.mass);
                if !fresh(pr.contact_time, pr.onset, m_eff, k) {
                    continue;
                }
                let d = pos(y0, j) - pos(y0, i);
                let dist = d.norm();
                if dist == 0.0 {
                    continue;
                }
                let nrm = d / dist;
                let v0 = hertz::impact_speed(m_eff, k, pr.contact_time);
                let terms = pc.law.onset_terms(k, m_eff, v0);
                let corr = hertz::start_correction(terms, t - pr.onset, h);
                push(y1, j, &nrm, bj.mass, corr);
                push(y1, i, &(-nrm), bi.mass, corr);
                if mu > 0.0 {
                    let overlap = bi.radius + bj.radius - dist;
                    let (ri, rj, slip) =
                        pair_slip(y0, n, (i, bi.radius), (j, bj.radius), &nrm, overlap);
                    let m_t = friction::sphere_pair_mass(bi.mass, bj.mass);
                    let d_t = friction::onset_terms(mu, terms, m_t, k, v0, slip.norm());
                    let at = [(i, &members[i], ri), (j, &members[j], rj)];
                    tangential_start(y1, n, &slip, d_t, t - pr.onset, h, &at);
                }
            }
        }
    }

    /// The first contact whose overlap exceeds half of the effective radius: Hertz contact
    /// means nothing there (and a shot about to tunnel would get there first).
    fn overlap_violation(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        t: f64,
        y: &[f64],
    ) -> Option<String> {
        let part = |ms: Range<usize>, ps: Range<usize>| {
            (
                self.member_overlap(members, ms, t, y),
                self.pair_overlap(members, &pairs[ps], t, y),
            )
        };
        let Some(blocks) = &self.blocks else {
            let (m, p) = part(0..members.len(), 0..pairs.len());
            return m.or(p);
        };
        // The first violation of the one pass: the members', then the pairs'.
        let found = blocks.each(part);
        let (ms, ps): (Vec<_>, Vec<_>) = found.into_iter().unzip();
        ms.into_iter().chain(ps).flatten().next()
    }

    /// [`Ctx::overlap_violation`] of the members `ms` with the specimen and the wall.
    fn member_overlap(
        &self,
        members: &[ShotState],
        ms: Range<usize>,
        t: f64,
        y: &[f64],
    ) -> Option<String> {
        ms.filter(|&i| moving(&members[i], t))
            .find_map(|i| self.member_overlap_of(&members[i], &pos(y, i)))
    }

    /// [`Ctx::overlap_violation`] of a moving member `m` at `p`.
    #[inline(always)]
    fn member_overlap_of(&self, m: &ShotState, p: &Vec3) -> Option<String> {
        let c = &self.phys.contacts;
        let r = m.body.radius;
        // The cheaper gap first (exact up to an overlap of a diameter, an overlap of
        // at least a diameter beyond), the exact one for the message.
        if let Some(sp) = c
            .specimen
            .as_ref()
            .filter(|sp| sp.overlap_gap(p, r) < -0.5 * r)
        {
            let overlap = -sp.gap(p, r);
            if overlap > 0.5 * r {
                return Some(format!(
                    "shot {} overlaps the specimen by {:.4} mm, {:.0} % of its radius",
                    m.id.0,
                    overlap * 1e3,
                    100.0 * overlap / r
                ));
            }
        }
        if let Some(w) = &c.wall
            && let Some(g) = w.geometry(p, r)
            && -g.gap > 0.5 * r
        {
            return Some(format!(
                "shot {} overlaps the nozzle wall by {:.4} mm, {:.0} % of its radius",
                m.id.0,
                -g.gap * 1e3,
                -100.0 * g.gap / r
            ));
        }
        None
    }

    /// [`Ctx::overlap_violation`] of the pairs `pairs`.
    fn pair_overlap(
        &self,
        members: &[ShotState],
        pairs: &[IslandPair],
        t: f64,
        y: &[f64],
    ) -> Option<String> {
        self.phys.contacts.pair.as_ref()?;
        pairs
            .iter()
            .filter(|pr| moving(&members[pr.a as usize], t) && moving(&members[pr.b as usize], t))
            .find_map(|pr| {
                let radii = (
                    members[pr.a as usize].body.radius,
                    members[pr.b as usize].body.radius,
                );
                pair_overlap_of(members, pr, radii, y)
            })
    }

    /// A fixed step's end at `(t, y)` in one pass over the members and one over the pairs
    /// (an island without blocks): [`Ctx::apply_events`], then the overlap guard and the
    /// separations of [`Ctx::end_of_step`], each member and each pair taken through all
    /// three at once. The same as the three passes: an onset changes only its own member
    /// or pair (and the members' collision counts, which the guard does not read), and
    /// when the guard finds a violation the island fails, so the separations made beside
    /// it are never read. Returns the guard's first violation, the members' before the
    /// pairs' (the caller stops the island on one), and whether a moving member is outside
    /// the domain (the caller then takes the shots that left: [`Ctx::leave_domain`]).
    fn fixed_step_end(
        &self,
        members: &mut [ShotState],
        pairs: &mut [IslandPair],
        t: f64,
        y: &[f64],
        out: &mut IslandOutput,
    ) -> (Option<String>, bool) {
        let n = members.len();
        let (mut violation, mut outside) = (None, false);
        // Whether every member moves: the pairs' pass then need not ask, pair by pair.
        let mut all_moving = true;
        for (i, m) in members.iter_mut().enumerate() {
            let p = pos(y, i);
            if moving(m, t) {
                self.member_events(m, (i, n), t, y, out);
                if violation.is_none() {
                    violation = self.member_overlap_of(m, &p);
                }
                outside |= !self.phys.domain.contains(&p);
            } else {
                all_moving = false;
            }
            self.member_separation(m, &p);
        }
        if self.phys.contacts.pair.is_some() {
            let mut pair_violation = None;
            for pr in pairs.iter_mut() {
                let (i, j) = (pr.a as usize, pr.b as usize);
                let r = (members[i].body.radius, members[j].body.radius);
                if all_moving || (moving(&members[i], t) && moving(&members[j], t)) {
                    if !pr.touching {
                        self.pair_events(pr, r, members, t, y, out);
                    }
                    if violation.is_none() && pair_violation.is_none() {
                        pair_violation = pair_overlap_of(members, pr, r, y);
                    }
                }
                pair_separation(pr, r, y);
            }
            violation = violation.or(pair_violation);
        }
        (violation, outside)
    }

    /// Bookkeeping after an accepted step at `(t, y)`: the overlap guard (stops the
    /// island with `suggestion`), separations, and shots leaving the domain. Returns
    /// `None` when the island was stopped, else whether a shot left.
    fn end_of_step(
        &self,
        members: &mut [ShotState],
        pairs: &mut [IslandPair],
        t: f64,
        y: &[f64],
        out: &mut IslandOutput,
        suggestion: &str,
    ) -> Option<bool> {
        if let Some(cause) = self.overlap_violation(members, pairs, t, y) {
            fail_island(members, t, y, out, &overlap_cause(&cause), suggestion);
            return None;
        }
        self.update_separations(members, pairs, y);
        Some(self.leave_domain(members, t, y))
    }

    /// Stops the members whose centre is outside the domain at `(t, y)`; whether any was.
    fn leave_domain(&self, members: &mut [ShotState], t: f64, y: &[f64]) -> bool {
        let mut left = false;
        for (i, m) in members.iter_mut().enumerate() {
            if m.is_active() && t >= m.t_start && !self.phys.domain.contains(&pos(y, i)) {
                m.status = ShotStatus::LeftDomain;
                m.t_stop = Some(t);
                m.pos = pos(y, i);
                m.vel = vel(y, i);
                left = true;
            }
        }
        left
    }

    /// Separations: contacts whose overlap ended during the last step.
    fn update_separations(&self, members: &mut [ShotState], pairs: &mut [IslandPair], y: &[f64]) {
        let Some(blocks) = &self.blocks else {
            self.separations_of(members, 0, y);
            let radius = |i: usize| members[i].body.radius;
            return pair_separations(pairs, radius, y);
        };
        let (b, pb) = (&blocks.bounds, &blocks.pair_bounds);
        blocks.run(cut(members, b, 1), |k, ms| self.separations_of(ms, b[k], y));
        let members = &*members;
        let radius = |i: usize| members[i].body.radius;
        blocks.run(cut(pairs, pb, 1), |_, ps| pair_separations(ps, radius, y));
    }

    /// [`Ctx::update_separations`] of the members `ms`, the first of them member `lo`.
    fn separations_of(&self, ms: &mut [ShotState], lo: usize, y: &[f64]) {
        for (k, m) in ms.iter_mut().enumerate() {
            self.member_separation(m, &pos(y, lo + k));
        }
    }

    /// [`Ctx::update_separations`] of member `m` at `p`.
    #[inline(always)]
    fn member_separation(&self, m: &mut ShotState, p: &Vec3) {
        let c = &self.phys.contacts;
        // The cheaper gap has the gap's sign, but may be 0 for a positive gap.
        if m.on_specimen
            && let Some(sp) = &c.specimen
            && let g = sp.overlap_gap(p, m.body.radius)
            && (g > 0.0 || (g == 0.0 && sp.gap(p, m.body.radius) > 0.0))
        {
            m.on_specimen = false;
        }
        if m.on_wall {
            let apart = c
                .wall
                .and_then(|w| w.geometry(p, m.body.radius))
                .is_none_or(|g| g.gap > 0.0);
            if apart {
                m.on_wall = false;
            }
        }
    }

    /// Scaled error norm (max over moving members and components); `<= 1` is acceptable.
    fn error_norm(&self, members: &[ShotState], t: f64, y: &[f64], err: &[f64]) -> f64 {
        let part = |ms: Range<usize>, _| self.error_part(members, ms, t, y, err);
        match &self.blocks {
            None => part(0..members.len(), 0..0),
            // The largest of numbers `>= +0` (NaN ignored by `f64::max`): exact in any
            // order.
            Some(blocks) => blocks.fold(0.0, f64::max, part),
        }
    }

    /// [`Ctx::error_norm`] over the members `ms`.
    fn error_part(
        &self,
        members: &[ShotState],
        ms: Range<usize>,
        t: f64,
        y: &[f64],
        err: &[f64],
    ) -> f64 {
        let tol = self.phys.tolerance;
        let mut e: f64 = 0.0;
        for i in ms {
            let m = &members[i];
            if !moving(m, t) {
                continue;
            }
            let sx = tol * 2.0 * m.body.radius;
            let sv = tol * (vel(y, i).norm() + 1.0);
            for k in 0..3 {
                e = e.max(err[6 * i + k].abs() / sx);
                e = e.max(err[6 * i + 3 + k].abs() / sv);
            }
            if self.phys.contacts.friction.is_some() {
                // Spin: the contact-point speed omega R, on the velocity's scale.
                let n = members.len();
                let r = m.body.radius;
                let sw = tol * (vel(y, i).norm() + omega(y, n, i).norm() * r + 1.0) / r;
                let o = 6 * n + 3 * i;
                for k in 0..3 {
                    e = e.max(err[o + k].abs() / sw);
                }
            }
        }
        e
    }
}

/// One Dormand-Prince trial step of length `h` from `(t, y)` into `y_new` / `err`.
#[allow(clippy::too_many_arguments)]
fn trial(
    ctx: &Ctx<'_>,
    dopri: &mut Dopri5,
    members: &[ShotState],
    pairs: &[IslandPair],
    pushing: &Pushing,
    (t, onsets): (f64, Onsets),
    y: &[f64],
    h: f64,
    y_new: &mut [f64],
    err: &mut [f64],
    work: &mut WorkCounters,
) {
    // Who moves is decided at the step's start for all its stages: steps are cut at entry
    // times, and a shot entering at the step's end must not act on its last stages (it
    // may still be held back there, `hold_entries`).
    dopri.step(
        &mut |_, yy: &[f64], dd: &mut [f64]| {
            ctx.rhs(members, pairs, Some(pushing), None, t, yy, dd, work)
        },
        t,
        y,
        h,
        y_new,
        err,
    );
    if onsets != Onsets::None {
        ctx.correct_onsets(members, pairs, t, h, y, y_new);
    }
}

/// Cuts the trial step of length `h` from `t`, whose event margin goes from `g0` to
/// `g1 < 0`, back to the margin's first root (within `tol_g` past it), guessed from the
/// step's dense output and confirmed by trial steps (`first_crossing_guided`). Returns
/// the cut length `b` and its error norm; the cut step's state is in `y_new`.
#[allow(clippy::too_many_arguments)]
fn cut_at_event(
    ctx: &Ctx<'_>,
    scratch: (&mut Dopri5, &mut DenseStep, &mut Vec<f64>),
    members: &[ShotState],
    pairs: &[IslandPair],
    pushing: &Pushing,
    at: (f64, Onsets),
    y: &[f64],
    (h, g0, g1, tol_g): (f64, f64, f64, f64),
    y_new: &mut [f64],
    err: &mut [f64],
    work: &mut WorkCounters,
) -> (f64, f64) {
    let (dopri, dense, probe) = scratch;
    let t = at.0;
    dopri.dense_into(t, y, y_new, h, dense);
    probe.clear();
    probe.extend_from_slice(y);
    let mut guess = |c: f64| {
        dense.at(t + c, probe);
        ctx.event_margin(members, pairs, pushing, t + c, probe)
    };
    let (b, held) = first_crossing_guided((0.0, g0), (h, g1), tol_g, &mut guess, &mut |c| {
        trial(
            ctx, dopri, members, pairs, pushing, at, y, c, y_new, err, work,
        );
        work.steps_rejected += 1;
        ctx.event_margin(members, pairs, pushing, t + c, y_new)
    });
    if held {
        // The last trial step ended at `b`: it is the step taken.
        work.steps_rejected -= 1;
    } else if b != h {
        trial(
            ctx, dopri, members, pairs, pushing, at, y, b, y_new, err, work,
        );
    }
    let e = if y_new.iter().all(|v| v.is_finite()) {
        ctx.error_norm(members, t, y, err)
    } else {
        f64::INFINITY
    };
    (b, e)
}

/// Holds back a shot fed into the run at `t` (its entry time) that would appear
/// overlapping a shot already moving there (one that came back up the bore to the inlet,
/// or lingers there in a tilted nozzle; the feed only keeps the shots it places apart,
/// `feed::StreamFeed`): its entry moves on by the time the two need to cover a contact
/// distance at their speeds, and it is tried again then, as LIGGGHTS' insertion waits
/// for a free place. Counted in `WorkCounters::entries_held`. The fixed-step method,
/// whose steps are not cut at entries, passes the previous step's start as `since`: a
/// shot entering in `(since, t]` starts moving at `t` and is checked there (the adaptive
/// method passes `t`).
fn hold_entries(
    members: &mut [ShotState],
    pairs: &[IslandPair],
    (since, t): (f64, f64),
    y: &[f64],
    work: &mut WorkCounters,
) {
    let entering =
        |m: &ShotState| m.is_active() && (m.t_start == t || (m.t_start > since && m.t_start <= t));
    // (Shots placed at the start, a bed's, may touch there on purpose.)
    if t <= 0.0 || !members.iter().any(entering) {
        return;
    }
    for pr in pairs {
        for (i, j) in [
            (pr.a as usize, pr.b as usize),
            (pr.b as usize, pr.a as usize),
        ] {
            let (mi, mj) = (&members[i], &members[j]);
            if !(entering(mi) && moving(mj, t)) {
                continue;
            }
            let reach = mi.body.radius + mj.body.radius;
            if (pos(y, j) - pos(y, i)).norm() < reach {
                let speed = vel(y, i).norm() + vel(y, j).norm();
                members[i].t_start = t + reach / speed.max(1e-3);
                work.entries_held += 1;
            }
        }
    }
}

/// Gap (m) between the shots of pair `pr` in state `y`; negative when they overlap.
fn pair_gap(members: &[ShotState], pr: &IslandPair, y: &[f64]) -> f64 {
    let (i, j) = (pr.a as usize, pr.b as usize);
    (pos(y, j) - pos(y, i)).norm() - members[i].body.radius - members[j].body.radius
}

/// A touching pair's contact at a state (`Ctx::pair_now`).
struct PairNow<'a> {
    law: &'a HertzLaw,
    /// Hertz stiffness, N/m^1.5.
    k: f64,
    /// Effective mass, kg.
    m_eff: f64,
    /// Overlap, m.
    overlap: f64,
    /// Closing speed, m/s.
    closing: f64,
    /// The smaller diameter, m.
    size: f64,
}

/// Contacts still pushing at the start of a step (see `Ctx::pushing`).
#[derive(Debug, Default, Clone)]
struct Pushing {
    specimen: Vec<bool>,
    pairs: Vec<bool>,
    /// Pairs apart at the step start and closing at an impact's speed (at least
    /// `RAMP_MIN_SPEED`): their touch ends the step (located within `1e-6 R`, weighted by
    /// `KINK_SCALE` as the kinks).
    approaching: Vec<bool>,
    /// Per member, the nozzle-wall event that ends its step: its touch (approaching at
    /// an impact's speed) or its kink (a young contact still pushing).
    wall: Vec<WallEvent>,
}

/// Which nozzle-wall event a member's step may end at (see `Pushing::wall`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum WallEvent {
    None,
    Touch,
    Kink,
}

/// Whether a contact's kink must end the step of `h` that may meet it, for the
/// contact now at `overlap` (m) changing at `rate` (m/s), of stiffness `k` and
/// effective mass `m_eff`, with friction `mu`, at `tolerance`: what the step would miss of it by not
/// stopping there (`dopri::KINK_MISS` at the bound [`HertzLaw::kink_slope`]; with
/// friction the tangential force turns with it, and the contact point's spin error
/// is 2.5 times the tangential velocity's) exceeds [`UNSEEN_SHARE`] of the error
/// the tolerance allows a step, velocity or position (`size`: the smaller body's
/// diameter, m). An impact's kink matters; the
/// kinks of a bed's or a pile's contacts, opening and closing at millimetres per
/// second, do not, and locating each of them cut every step of their island (a
/// 10,240-shot bed: two steps in five).
#[allow(clippy::too_many_arguments)]
fn kink_matters(
    tolerance: f64,
    k: f64,
    m_eff: f64,
    (overlap, rate): (f64, f64),
    h: f64,
    mu: f64,
    size: f64,
) -> bool {
    let miss = HertzLaw::kink_slope(k, m_eff, overlap, rate) * (1.0 + 2.5 * mu) / m_eff;
    let allowed = UNSEEN_SHARE * tolerance;
    miss * KINK_MISS[0] * h * h > allowed || miss * KINK_MISS[1] * h * h * h > allowed * size
}

/// Share of the error the tolerance allows a step (`tolerance` times 1 m/s of velocity,
/// times the shot's diameter of position) that a contact's kink or a slow touch may cost
/// a step that does not stop there ([`kink_matters`], `HertzLaw::touch_span`):
/// the error estimate underrates both (session 6: an impact's unlocated kink cost its
/// rebound 2e-4 at tolerance 1e-5), so they are bounded beforehand, well inside it.
const UNSEEN_SHARE: f64 = 0.1;

/// Weight of the unloading margins among the event margins: the location stops within
/// `1e-9 R` of a margin's root, which for a kink (a margin about the overlap, tens of
/// micrometres at its peak) is needlessly tight; weighted, it stops within `1e-6 R`. The
/// roots, hence which event comes first, do not change.
const KINK_SCALE: f64 = 1e-3;

/// Weight of the jet's region margins among the event margins (as [`KINK_SCALE`]): a
/// region's border is located within `1e-5 R` past it instead of `1e-9 R`. A step that
/// ends that far past it has taken the old region's air for at most `1e-5 R / |v|`:
/// for a 0.8 mm shot at 50 m/s, 0.08 ns, so about 1.4e-6 m/s of velocity where the
/// air's acceleration jumps most (about 1.75e4 m/s^2 at the end of the core), against
/// the `1e-6 (|v| + 1 m/s)` = 5e-5 m/s the default tolerance allows per step.
/// The tighter band missed the trial step the dense output guessed one time in two, and
/// each miss cost a trial step more (session 36: -1.8 % right-hand sides on the nozzle
/// stream, -11 % on one shot's flight; a lone shot's impact speed moves by 6e-10).
const REGION_SCALE: f64 = 1e-4;

/// First step after a contact onset, as a fraction of the contact step.
pub(crate) const ONSET_STEP: f64 = 0.01;
/// A contact whose onset lies within this fraction of its Hertz time before a step's
/// start starts there: its touch was located at the step's start, which leaves up to
/// `1e-6 R` of overlap (the touch's margin is weighted by `KINK_SCALE`), i.e. up to
/// `1e-3 t_c` at `RAMP_MIN_SPEED` and about `1e-5 t_c` at an impact's speed. The
/// correction itself counts from the actual onset.
pub(crate) const AT_ONSET: f64 = 1e-3;
/// Rebound-speed error (of the closing speed) that `HertzLaw::onset_correction` leaves
/// after a first step of `t_c / 10`, for the Tsuji damping factor 0.80 (LIGGGHTS'
/// damping for restitution 0.3; the worst of 0.80, 0.48, 0.25 and 0.075, for 0.3, 0.5,
/// 0.7, 0.9: 6e-4, 2.9e-4, 1.1e-4, 2.2e-5; dimensionless impact, the rest of the
/// contact in steps of `t_c / 10`, against a converged run), doubled; the error falls as
/// the step's `ONSET_ORDER` power (2.8 measured from `t_c / 10` down to `t_c / 100`).
const ONSET_ERROR: f64 = 1.2e-3;
/// See `ONSET_ERROR`.
const ONSET_ORDER: f64 = 2.8;
/// Largest error norm at which a lone shot's step starting on an impact's touch is kept
/// (its length is `first_contact_step`'s, whose error the onset correction bounds).
const ONSET_TRUST: f64 = 10.0;

/// Length (s) of the step that starts on an impact's touch and is corrected by
/// `HertzLaw::onset_correction` (Hertz time `tc`, `n` steps per contact): the step whose
/// error model (`ONSET_ERROR`) meets the tolerance, between `ONSET_STEP` and one contact
/// step. At tolerance 1e-4 it is `t_c / 24`, at 1e-6 `t_c / 126`.
pub(crate) fn first_contact_step(tc: f64, n: f64, tolerance: f64) -> f64 {
    (0.1 * tc * (tolerance / ONSET_ERROR).powf(1.0 / ONSET_ORDER))
        .clamp(ONSET_STEP * tc / n, tc / n)
}

/// Closing speed (m/s) from which a touch is an impact: located, its first steps growing
/// gradually from the onset step; a slower touch is found inside a step, which is cut to
/// its span (`HertzLaw::touch_span`), and the step after it too, then contact steps.
const RAMP_MIN_SPEED: f64 = 0.1;

/// Advances the island's `members` (with candidate `pairs`) from `t0` to `t1`.
pub fn advance(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &mut [IslandPair],
    t0: f64,
    t1: f64,
    scratch: &mut Scratch,
    out: &mut IslandOutput,
) {
    advance_observed(phys, members, pairs, t0, t1, scratch, out, &mut |_, _| {});
}

/// [`advance`], calling `observer(t, y)` after every accepted step, where `y` holds the
/// members' states as `[x, y, z, vx, vy, vz]` per member (SI). For tests and probes.
#[allow(clippy::too_many_arguments)]
pub fn advance_observed(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &mut [IslandPair],
    t0: f64,
    t1: f64,
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    observer: &mut dyn FnMut(f64, &[f64]),
) {
    match phys.method {
        Method::Verlet { step } => {
            let span = VerletSpan {
                t0,
                t1,
                apart_after: None,
                entries: Entries::Held { since: t0 - step },
            };
            advance_verlet(phys, members, pairs, span, step, scratch, out, observer);
        }
        Method::Hybrid { step } => {
            let span = (t0, t1, None);
            advance_hybrid(
                phys, members, pairs, span, step, false, scratch, out, observer,
            );
        }
        Method::Adaptive => {
            let stop = Stop::default();
            advance_adaptive(phys, members, pairs, t0, t1, stop, scratch, out, observer);
        }
    }
}

/// Advances a lone shot (an island of one, no candidate pair) from `t0` to `t1`, letting
/// its last step run past `t1` when nothing happens in that step: no contact in progress
/// or starting, no jet-region crossing, the shot stays in the domain. Its state at `t1`
/// is then the step's dense output (fourth order, the step's own accuracy), and the
/// step is kept in [`ShotState::ahead`]: the next windows read the state from it until
/// they pass its end, where integration resumes from the step's exact end. A free shot
/// thus takes the steps its accuracy needs, not one per synchronisation window. A shot
/// that joins a larger island goes on from its dense-output state (the step is dropped).
///
/// `observer(t, y)` sees the state after every step taken and at `t1`, as in
/// [`advance_observed`].
pub fn advance_alone(
    phys: &Physics,
    m: &mut ShotState,
    t0: f64,
    t1: f64,
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    observer: &mut dyn FnMut(f64, &[f64]),
) {
    if !phys.method.adaptive_flight() {
        advance_observed(
            phys,
            std::slice::from_mut(m),
            &mut [],
            t0,
            t1,
            scratch,
            out,
            observer,
        );
        return;
    }
    if let Some(k) = Kept::read(phys, m, t1) {
        k.store(m);
        observer(t1, k.state());
        return;
    }
    let mut t0 = t0;
    if let Some(step) = m.ahead.take() {
        // The kept step ends within the window: go on from its exact end.
        scratch.y.resize(state_len(phys), 0.0);
        let at = step.end();
        step.at(at, &mut scratch.y);
        store_state(std::slice::from_mut(m), &scratch.y);
        observer(at, &scratch.y);
        t0 = at;
    }
    let m = std::slice::from_mut(m);
    if let Method::Hybrid { step } = phys.method {
        let span = (t0, t1, None);
        advance_hybrid(phys, m, &mut [], span, step, true, scratch, out, observer);
        return;
    }
    let stop = Stop {
        alone: true,
        ..Stop::default()
    };
    advance_adaptive(phys, m, &mut [], t0, t1, stop, scratch, out, observer);
}

/// A lone shot's state length: position and velocity, and the spin with friction.
fn state_len(phys: &Physics) -> usize {
    if phys.contacts.friction.is_some() {
        9
    } else {
        6
    }
}

/// The state at a window's end `t1` of a lone shot whose kept step
/// ([`ShotState::ahead`]) runs past `t1`: all that [`advance_alone`] does for it is read
/// the step's dense output there. The window scheduler reads it without handing the
/// shot to an island (no copy of its state).
#[derive(Debug, Clone, Copy)]
pub struct Kept {
    y: [f64; 9],
    len: usize,
}

impl Kept {
    /// The kept state at `t1`, if `m`'s kept step runs past `t1` (the adaptive method).
    #[inline]
    pub fn read(phys: &Physics, m: &ShotState, t1: f64) -> Option<Self> {
        let step = m.ahead.as_ref()?;
        if !phys.method.adaptive_flight() || t1 >= step.end() {
            return None;
        }
        let mut k = Kept {
            y: [0.0; 9],
            len: state_len(phys),
        };
        step.at(t1, &mut k.y[..k.len]);
        Some(k)
    }

    /// The flat state (`[x v]`, then `w` with friction).
    #[inline]
    pub fn state(&self) -> &[f64] {
        &self.y[..self.len]
    }

    /// The shot's position.
    #[inline]
    pub fn pos(&self) -> Vec3 {
        pos(&self.y, 0)
    }

    /// Writes the state into `m` (as any step's end: only an active shot moves); its kept
    /// step stays.
    #[inline]
    pub fn store(&self, m: &mut ShotState) {
        store_state(std::slice::from_mut(m), self.state());
    }
}

/// Whether any member is in contact (with the specimen, the wall or another member).
pub fn in_contact(members: &[ShotState], pairs: &[IslandPair]) -> bool {
    members
        .iter()
        .any(|m| m.is_active() && (m.on_specimen || m.on_wall))
        || pairs.iter().any(|p| p.touching)
}

/// [`advance_observed`] (either method), stopping early at the end of the first
/// accepted step at or after `apart_after` at which no contact is in progress: the
/// event scheduler (`crate::events`) resolves a collision with it and hands the shots
/// back to free flight. Returns the time reached (`t1` if contacts last that long).
#[allow(clippy::too_many_arguments)]
pub fn advance_until_apart(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &mut [IslandPair],
    t0: f64,
    t1: f64,
    apart_after: f64,
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    observer: &mut dyn FnMut(f64, &[f64]),
) -> f64 {
    // Free flight (closed form) hands the shots over with no force history: the fixed
    // step's starting forces are evaluated afresh.
    for m in members.iter_mut() {
        m.verlet_acc = None;
    }
    match phys.method {
        Method::Verlet { step } => {
            let span = VerletSpan {
                t0,
                t1,
                apart_after: Some(apart_after),
                entries: Entries::Clocks,
            };
            advance_verlet(phys, members, pairs, span, step, scratch, out, observer)
        }
        Method::Hybrid { step } => {
            let span = (t0, t1, Some(apart_after));
            advance_hybrid(
                phys, members, pairs, span, step, false, scratch, out, observer,
            )
        }
        Method::Adaptive => {
            let stop = Stop {
                apart_after: Some(apart_after),
                ..Stop::default()
            };
            advance_adaptive(phys, members, pairs, t0, t1, stop, scratch, out, observer)
        }
    }
}

/// Where [`advance_adaptive`] stops short of its window's end.
#[derive(Debug, Clone, Copy, Default)]
struct Stop {
    /// At the end of the first accepted step from then on with no contact in progress
    /// (the event scheduler's clusters).
    apart_after: Option<f64>,
    /// A lone shot, whose last step may run past the window's end (`advance_alone`).
    alone: bool,
    /// As soon as a contact is in progress: at a located onset (the end of the step cut
    /// at the touch), or at once if one is when a step starts ([`advance_hybrid`]).
    onset: bool,
}

/// [`Method::Hybrid`]: the members fly under error control ([`advance_adaptive`], which
/// stops at the first located onset) and step at the fixed `step` while any contact is in
/// progress ([`advance_verlet`], from the touch until a step ends with none), from `t0` to
/// `t1`; with `apart_after` (the event scheduler's clusters, whose members keep their own
/// clocks) it stops at the first step end from then on with no contact in progress, as
/// [`advance_until_apart`] does. `alone`: a lone shot, whose last adaptive step may run
/// past `t1` ([`advance_alone`]). Returns the time reached.
#[allow(clippy::too_many_arguments)]
fn advance_hybrid(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &mut [IslandPair],
    (t0, t1, apart_after): (f64, f64, Option<f64>),
    step: f64,
    alone: bool,
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    observer: &mut dyn FnMut(f64, &[f64]),
) -> f64 {
    let mut t = t0;
    while t < t1 && members.iter().any(|m| m.is_active()) {
        if in_contact(members, pairs) {
            let span = VerletSpan {
                t0: t,
                t1,
                apart_after: Some(t),
                entries: if apart_after.is_some() {
                    Entries::Clocks
                } else {
                    Entries::Held { since: t }
                },
            };
            for m in members.iter_mut() {
                m.ahead = None;
            }
            t = advance_verlet(phys, members, pairs, span, step, scratch, out, observer);
        } else {
            // The fixed step's last forces belong to the contact just ended.
            for m in members.iter_mut() {
                m.verlet_acc = None;
            }
            let stop = Stop {
                apart_after,
                alone,
                onset: true,
            };
            t = advance_adaptive(phys, members, pairs, t, t1, stop, scratch, out, observer);
        }
        if apart_after.is_some_and(|ta| t >= ta) && !in_contact(members, pairs) {
            break;
        }
    }
    t
}

#[allow(clippy::too_many_arguments)]
fn advance_adaptive(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &mut [IslandPair],
    t0: f64,
    t1: f64,
    Stop {
        apart_after,
        alone,
        onset: until_onset,
    }: Stop,
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    observer: &mut dyn FnMut(f64, &[f64]),
) -> f64 {
    // (The hybrid method's flight stops at the touch: no contact it integrates carries a
    // tangential history.)
    assert!(
        until_onset
            || !matches!(
                phys.contacts.friction,
                Some(friction::Friction {
                    law: friction::Tangential::History { .. },
                    ..
                })
            ),
        "the history tangential law runs on the fixed-step and hybrid methods only (the \
         scene loader refuses it with the adaptive one)"
    );
    let n = members.len();
    // The members' states hold at `t0`: a step kept from an earlier window is stale.
    for m in members.iter_mut() {
        m.ahead = None;
    }
    // Only a lone shot slides on the specimen (away from the nozzle wall):
    // in an island it is pressed by its neighbours as well, and steps with them.
    let slides = phys.sliding && n == 1 && pairs.is_empty() && !members[0].on_wall;
    if !slides {
        for m in members.iter_mut() {
            m.sliding = false;
        }
    }
    // May the last step run past `t1` (see `advance_alone`)? Not again at a time where
    // a step that tried found an event in it.
    let alone = alone && n == 1 && pairs.is_empty();
    // Fed shots are held back here in windows; the event scheduler holds them at their
    // entry events, and its clusters start members at their own clocks (`t_start`).
    // (Only islands with a shot still to enter: a scan of the members at every step
    // cost the 10,240-shot bed 3 %.)
    let holds = apart_after.is_none()
        && members
            .iter()
            .any(|m| m.is_active() && m.t_start >= t0 && m.t_start > 0.0);
    // Whether a member enters at `t0` or later (held entries only move later), and
    // whether eddies end steps: the scans for them at every step are skipped otherwise
    // (a status never turns active again, and eddies come with turbulence only).
    let later = members.iter().any(|m| m.is_active() && m.t_start >= t0);
    let gusty = phys.forces.turbulence.is_some();
    let mut no_pass_at = f64::NAN;
    let spin = phys.contacts.friction.is_some();
    let width = if spin { 9 } else { 6 };
    scratch.dopri.resize(width * n);
    scratch.y.resize(width * n, 0.0);
    scratch.y_new.resize(width * n, 0.0);
    scratch.err.resize(width * n, 0.0);
    load_state(members, &mut scratch.y, spin);
    let r_min = members
        .iter()
        .map(|m| m.body.radius)
        .fold(f64::INFINITY, f64::min);
    let tol_g = 1e-9 * r_min;
    let mut t = t0;
    let mut h_next = members
        .iter()
        .filter(|m| m.is_active())
        .map(|m| if m.h_next > 0.0 { m.h_next } else { 1e-6 })
        .fold(f64::INFINITY, f64::min);
    let Scratch {
        dopri,
        y,
        y_new,
        err,
        pushing,
        dense,
        probe,
        laws,
    } = scratch;
    pair_laws(phys, members, pairs, laws);
    let ctx = Ctx {
        phys,
        onsets_located: true,
        regions_set: false,
        blocks: Blocks::plan(phys, members, pairs),
        laws,
    };
    dopri.invalidate();
    let mut work = WorkCounters::default();

    while t < t1 {
        if !members.iter().any(|m| m.is_active()) {
            break;
        }
        // A shot held back here is not moving at `t`: no onset with it is found.
        if holds {
            hold_entries(members, pairs, (t, t), y, &mut work);
        }
        if ctx.apply_events(members, pairs, t, y, out) {
            dopri.invalidate();
        }
        if until_onset && in_contact(members, pairs) {
            break;
        }
        // Step size: controller proposal, window end, next shot entering, contact caps.
        // A shot sliding on the specimen steps as its error control allows: every event
        // of its motion is located (`Ctx::event_margin`).
        let max_step = if slides && members[0].sliding {
            f64::INFINITY
        } else {
            phys.max_step
        };
        let h_wanted = h_next.min(max_step);
        let mut h = h_wanted;
        let mut lands_at = None;
        let may_pass = alone
            && no_pass_at != t
            && moving(&members[0], t)
            && !members[0].on_specimen
            && !members[0].on_wall;
        if t + h >= t1 && !may_pass {
            h = t1 - t;
            lands_at = Some(t1);
        }
        for m in members.iter().filter(|_| later || gusty) {
            if m.is_active() && m.t_start > t && m.t_start < t + h {
                h = m.t_start - t;
                lands_at = Some(m.t_start);
            }
            // A step ends where an eddy does: the next one is drawn there.
            if moving(m, t) && m.gust_until > t && m.gust_until < t + h {
                h = m.gust_until - t;
                lands_at = Some(m.gust_until);
            }
        }
        if !members.iter().any(|m| moving(m, t)) {
            // Nobody moves before the next shot enters: jump there.
            t = lands_at.unwrap_or(t + h);
            dopri.invalidate();
            continue;
        }
        let (cap, onsets) = ctx.contact_cap(members, pairs, t, y);
        let at = (t, onsets);
        if cap < h {
            h = cap;
            lands_at = None;
        }
        ctx.pushing(members, pairs, t, y, h, pushing);
        let g0 = ctx.event_margin(members, pairs, pushing, t, y);
        // Trial steps until the error is acceptable.
        let mut rejected = false;
        let err_norm = loop {
            trial(
                &ctx, dopri, members, pairs, pushing, at, y, h, y_new, err, &mut work,
            );
            let finite = y_new.iter().all(|v| v.is_finite());
            let e = if finite {
                ctx.error_norm(members, t, y, err)
            } else {
                f64::INFINITY
            };
            // A lone shot's step that starts on an impact's touch is as long as the
            // corrected start needs for the tolerance (`first_contact_step`): the error
            // estimate sees the start before its correction, and rejected three in four
            // such steps one to three times (session 35). It is trusted up to ten times
            // the tolerance; beyond that something else is wrong with the step.
            if e <= 1.0 || (alone && at.1 == Onsets::AtStart && e <= ONSET_TRUST) {
                break e;
            }
            work.steps_rejected += 1;
            rejected = true;
            h *= if e.is_finite() {
                step_factor(e, 0.2, f64::INFINITY)
            } else {
                0.25
            };
            lands_at = None;
            if h < MIN_STEP {
                break f64::NAN;
            }
        };
        if err_norm.is_nan() {
            fail_island(
                members,
                t,
                y,
                out,
                "the integrator's step size collapsed below 1e-15 s",
                "loosen [integrator] tolerance, or check the materials' moduli and the shot sizes",
            );
            break;
        }
        let g1 = ctx.event_margin(members, pairs, pushing, t + h, y_new);
        let mut cut_above = false;
        if may_pass && t + h > t1 {
            // The step runs past the window end: keep it only if nothing happens in it.
            let r = members[0].body.radius;
            let clear = |y: &[f64], g: f64| {
                let p = pos(y, 0);
                g >= 0.0
                    && phys.domain.contains(&p)
                    && phys
                        .contacts
                        .wall
                        .is_none_or(|w| w.geometry(&p, r).is_none_or(|g| g.gap > 0.0))
            };
            let mut err_norm = err_norm;
            let mut passes = clear(y_new, g1);
            // Only the jet's region boundaries crossed: where the air's formulas meet,
            // with a kink in its force and nothing else happening.
            let regions_only = !passes
                && g1 < 0.0
                && g0 > 0.0
                && clear(
                    y_new,
                    ctx.margin_of(members, pairs, pushing, t + h, y_new, false),
                );
            if regions_only {
                // The step is cut just past the first boundary, as inside a window, and
                // kept even if it ends past the window end: the next step, wherever it
                // starts, takes the new region (`Ctx::apply_events`). Stopping short of
                // the boundary instead (as for the events below) left it for the next
                // window, whose step ran into it again and was thrown away: two trial
                // steps per crossing (session 36).
                let (b, e) = cut_at_event(
                    &ctx,
                    (dopri, dense, probe),
                    members,
                    pairs,
                    pushing,
                    at,
                    y,
                    (h, g0, g1, tol_g),
                    y_new,
                    err,
                    &mut work,
                );
                let gb = ctx.margin_of(members, pairs, pushing, t + b, y_new, false);
                if e > 1.0 || !clear(y_new, gb) {
                    work.steps_rejected += 1;
                    no_pass_at = t;
                    dopri.invalidate();
                    continue;
                }
                if t + b > t1 {
                    (h, err_norm, passes) = (b, e, true);
                } else {
                    // The boundary lies inside the window: an ordinary step to it.
                    h = b;
                    lands_at = None;
                    cut_above = true;
                }
            } else if !passes && g1 < 0.0 && g0 > 0.0 {
                // An event inside the step (the specimen, the nozzle wall, the domain's
                // edge): a step that stops short of it may still run past the window
                // end. Without it the shot would step window by window up to the event.
                // Where the margin crosses zero, by the step's dense output (no right-hand
                // side needed): regula falsi, Illinois variant, keeping a point before it.
                dopri.dense_into(t, y, y_new, h, dense);
                probe.clone_from(y);
                let (mut lo, mut g_lo, mut hi, mut g_hi, mut side) = (0.0, g0, h, g1, 0);
                for _ in 0..12 {
                    let c = lo + (hi - lo) * g_lo / (g_lo - g_hi);
                    if !(c > lo && c < hi) {
                        break;
                    }
                    dense.at(t + c, probe);
                    let g = ctx.event_margin(members, pairs, pushing, t + c, probe);
                    if g >= 0.0 {
                        (lo, g_lo) = (c, g);
                        if side == 1 {
                            g_hi *= 0.5;
                        }
                        side = 1;
                    } else {
                        (hi, g_hi) = (c, g);
                        if side == -1 {
                            g_lo *= 0.5;
                        }
                        side = -1;
                    }
                    if hi - lo < 0.01 * hi {
                        break;
                    }
                }
                let b = 0.99 * lo;
                if t + b > t1 {
                    work.steps_rejected += 1;
                    trial(
                        &ctx, dopri, members, pairs, pushing, at, y, b, y_new, err, &mut work,
                    );
                    let e = if y_new.iter().all(|v| v.is_finite()) {
                        ctx.error_norm(members, t, y, err)
                    } else {
                        f64::INFINITY
                    };
                    let gb = ctx.event_margin(members, pairs, pushing, t + b, y_new);
                    if e <= 1.0 && clear(y_new, gb) {
                        (h, err_norm, passes) = (b, e, true);
                    }
                }
            }
            if passes {
                let m = &mut members[0];
                m.steps += 1;
                work.shot_steps += 1;
                work.steps_accepted += 1;
                let step = dopri.dense(t, y, y_new, h);
                step.at(t1, y);
                m.ahead = Some(std::sync::Arc::new(step));
                // The controller's own proposal, whatever cut this step short. Bringing
                // the earlier, longer proposal back after a step cut short of an event
                // (as the steps below do) carried the bore's uniform-flow step into the
                // mixing layer, where it was rejected again and again: over 96 seeds of
                // the 10,000-shot stream this proposal halves the rejected trials, saves
                // 8.8 % of the right-hand sides, and its outcomes are the nearest to the
                // converged reference of the builds measured (docs/performance-history.md,
                // "The controller's own proposal after a kept step, session 35").
                h_next = h * step_factor(err_norm, 0.2, 5.0);
                t = t1;
                observer(t, y);
                break;
            }
            if !regions_only {
                no_pass_at = t;
                continue;
            }
        }
        // Events inside the step: cut the step back to the first one (done above for a
        // lone shot's step that crossed only region boundaries).
        if g1 < 0.0 && !cut_above {
            lands_at = None;
            // The step's dense output estimates the margin inside it at no cost. The step
            // cut back to the event must be accurate too: a contact its stages meet that
            // the whole step's did not (a shot that drifted slowly into the bore wall, met
            // by a step cut at the exit plane) is not. Retried shorter.
            let (b, e) = cut_at_event(
                &ctx,
                (dopri, dense, probe),
                members,
                pairs,
                pushing,
                at,
                y,
                (h, g0.max(0.0), g1, tol_g),
                y_new,
                err,
                &mut work,
            );
            if e > 1.0 {
                work.steps_rejected += 1;
                h_next = b * if e.is_finite() {
                    step_factor(e, 0.2, 1.0)
                } else {
                    0.25
                };
                dopri.invalidate();
                continue;
            }
            h = b;
        }
        // Accept.
        for m in members.iter_mut() {
            if moving(m, t) {
                m.steps += 1;
                work.shot_steps += 1;
                if m.on_specimen && m.hits == 1 {
                    m.first_contact_steps += 1;
                }
            }
        }
        work.steps_accepted += 1;
        ctx.record_onsets(members, pairs, t, h, y, y_new, out);
        std::mem::swap(y, y_new);
        let t_prev = t;
        t = lands_at.unwrap_or(t + h);
        dopri.accept_fsal();
        if onsets == Onsets::AtStart {
            dopri.invalidate(); // the last stage saw the state before its correction
        }
        // A step cut at a kink ends just past it (within the location's margin), where
        // its last stage saw the force unclamped, a hair below zero, and the next step
        // sees it clamped: the difference is of the margin's order (1e-9 R of overlap),
        // so the stage is reused. (Evaluating it again after such steps cost the dense
        // bed, whose one island meets a kink every few steps, 7 % more right-hand sides.)
        if later
            && members
                .iter()
                .any(|m| m.is_active() && m.t_start > t_prev && m.t_start <= t)
        {
            dopri.invalidate(); // a shot entered: the right-hand side changed
        }
        let controller = h * step_factor(err_norm, 0.2, 5.0);
        // A step shortened by a clamp, a cap or an event says nothing against the
        // controller's earlier proposal; a rejected one does.
        h_next = if rejected || h >= h_wanted {
            controller
        } else {
            controller.max(h_wanted)
        };
        if slides && ctx.slide(&mut members[0], t, y, &mut work) {
            dopri.invalidate();
        }
        if holds {
            hold_entries(members, pairs, (t, t), y, &mut work);
        }
        observer(t, y);
        match ctx.end_of_step(
            members,
            pairs,
            t,
            y,
            out,
            "the shots are too fast or the materials too soft for these sizes: check the materials' youngs_modulus_gpa and the speeds",
        ) {
            None => break,
            Some(true) => dopri.invalidate(),
            Some(false) => {}
        }
        if apart_after.is_some_and(|ta| t >= ta) && !in_contact(members, pairs) {
            break;
        }
        if until_onset && in_contact(members, pairs) {
            break;
        }
    }
    store_state(members, y);
    for m in members.iter_mut().filter(|m| m.is_active()) {
        m.h_next = h_next;
    }
    out.work.add(&work);
    t
}

/// The end of the shortest step that takes a margin `g` from `>= 0` (at `lo`) to within
/// `tol_g` below zero, given a bracket `(lo, g(lo))`, `(hi, g(hi) < 0)` of step lengths;
/// `g` evaluates a trial step. Returns the end and whether `g`'s last evaluation was at
/// it (that trial step's state then is the step's, and the caller need not redo it; it
/// is `false` when `g` was not called: the end is `hi`). Illinois
/// secant, with the secant point kept a little inside the bracket: a root next to one end
/// (a step that starts on a touch, a kink all but found) is then bracketed in a step or
/// two instead of by bisection.
pub(crate) fn first_crossing(
    (mut a, mut ga): (f64, f64),
    (mut b, mut gb): (f64, f64),
    tol_g: f64,
    g: &mut dyn FnMut(f64) -> f64,
) -> (f64, bool) {
    let mut side = 0i8;
    let mut last = f64::NAN;
    // The margin at `b` itself: `gb` is the Illinois weight, halved when the search stays
    // on one side, and must not end it (it did until session 8, up to a few tolerances
    // past the crossing).
    let mut at_b = gb;
    for _ in 0..200 {
        if at_b > -tol_g || b - a <= 1e-13 * b {
            break;
        }
        let guard = 1e-3 * (b - a);
        let c = b - gb * (b - a) / (gb - ga);
        let c = if c.is_finite() {
            c.clamp(a + guard, b - guard)
        } else {
            0.5 * (a + b)
        };
        let gc = g(c);
        last = c;
        if gc < 0.0 {
            (b, gb, at_b) = (c, gc, gc);
            if side == -1 {
                ga *= 0.5;
            }
            side = -1;
        } else {
            (a, ga) = (c, gc);
            if side == 1 {
                gb *= 0.5;
            }
            side = 1;
        }
    }
    (b, last == b)
}

/// The first fraction `s` in `(0, 1]` of a step where `gap(s) < 0`, given
/// `gap(0) >= 0 > gap(1)` (`gap`: an onset's gap on the step's interpolant). A clear
/// crossing (the step ends more than `tol` inside) is found by the safeguarded secant in
/// a few evaluations; an overlap at the rounding level (a resting pile's touching
/// neighbours) by bisection to the last bit, where the secant would stop at once at the
/// step's end (measured on the dense bed: 27 % more steps). Bisection everywhere cost 60
/// evaluations per onset, 2.5 % of the pack stream's instructions.
fn onset_fraction(gap: &dyn Fn(f64) -> f64, tol: f64) -> f64 {
    let (g0, g1) = (gap(0.0), gap(1.0));
    if g1 < -tol {
        return first_crossing((0.0, g0), (1.0, g1), tol, &mut |s| gap(s)).0;
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if gap(mid) < 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// Samples of the estimated margin that look for its first sign change in a step.
const GUESS_SAMPLES: usize = 4;

/// [`first_crossing`] for a margin `g` along a step whose dense output gives a cheap
/// estimate `guess` of it (no right-hand side): the first sign change of `guess` on
/// [`GUESS_SAMPLES`] points and its root there are found first, then `g` is evaluated
/// at that root and, if that misses `(-tol_g, 0]`, once more a Newton step further (with
/// `guess`'s slope, aiming at `-tol_g / 10`); only if both miss does the secant go on,
/// from the tightest bracket known. Returns the end and whether `g`'s last evaluation
/// was at it. On the pack stream this takes 1-2 trial steps per event instead of 4-5.
/// (Aiming at the window's middle, `-tol_g / 2`, measurably worsened loose-tolerance
/// wall rebounds, 7e-4 -> 1.1e-3 at tolerance 1e-3: the dashpot's `delta^(1/4)` makes
/// the rebound sensitive to the overlap a located touch starts from.)
pub(crate) fn first_crossing_guided(
    lo: (f64, f64),
    hi: (f64, f64),
    tol_g: f64,
    guess: &mut dyn FnMut(f64) -> f64,
    g: &mut dyn FnMut(f64) -> f64,
) -> (f64, bool) {
    if hi.1 > -tol_g {
        return (hi.0, false);
    }
    let mut last = f64::NAN;
    let mut eval = |c: f64| {
        last = c;
        g(c)
    };
    let (mut a, mut b) = (lo, hi);
    let tighten = |a: &mut (f64, f64), b: &mut (f64, f64), c: f64, gc: f64| {
        if gc < 0.0 {
            if c < b.0 {
                *b = (c, gc);
            }
        } else if c > a.0 {
            *a = (c, gc);
        }
    };
    // The first sign change of `guess` on a few samples, then its root there.
    let (mut glo, mut ghi) = (lo, hi);
    for k in 1..GUESS_SAMPLES {
        let c = lo.0 + (hi.0 - lo.0) * k as f64 / GUESS_SAMPLES as f64;
        let gc = guess(c);
        if gc < 0.0 {
            ghi = (c, gc);
            break;
        }
        glo = (c, gc);
    }
    let (c, _) = first_crossing(glo, ghi, 0.25 * tol_g, guess);
    if c > lo.0 && c < hi.0 {
        let gc = eval(c);
        if gc <= 0.0 && gc > -tol_g {
            return (c, true);
        }
        tighten(&mut a, &mut b, c, gc);
        let d = 1e-3 * (c - lo.0);
        let slope = (guess(c) - guess(c - d)) / d;
        let next = c - (gc + 0.1 * tol_g) / slope;
        if slope < 0.0 && next > a.0 && next < b.0 {
            let gn = eval(next);
            if gn <= 0.0 && gn > -tol_g {
                return (next, true);
            }
            tighten(&mut a, &mut b, next, gn);
        }
    }
    let (end, _) = first_crossing(a, b, tol_g, &mut eval);
    (end, last == end)
}

/// A run event's cause for an overlap the guard found ([`Ctx::overlap_violation`]).
fn overlap_cause(overlap: &str) -> String {
    format!("{overlap}: Hertz contact does not hold there")
}

fn fail_island(
    members: &mut [ShotState],
    t: f64,
    y: &[f64],
    out: &mut IslandOutput,
    cause: &str,
    suggestion: &str,
) {
    for (i, m) in members.iter_mut().enumerate() {
        if moving(m, t) {
            m.status = ShotStatus::Failed;
            m.t_stop = Some(t);
            m.pos = pos(y, i);
            m.vel = vel(y, i);
            out.events.push(RunEvent {
                shot: m.id.0,
                time_s: t,
                cause: cause.to_string(),
                suggestion: suggestion.into(),
            });
        }
    }
}

/// Kicks member `i`'s angular velocity (of `n` in the flat state) by `dt` of the angular
/// acceleration in `acc`.
#[inline]
fn kick_spin(y: &mut [f64], acc: &[f64], n: usize, i: usize, dt: f64) {
    let o = 6 * n + 3 * i;
    add_scaled(&mut y[o..o + 3], &acc[o..o + 3], dt);
}

/// `y + dt * a`, component by component, as [`add_scaled`] computes it.
#[inline]
fn kicked(y: &Vec3, a: &Vec3, dt: f64) -> Vec3 {
    Vec3::new(y.x + dt * a.x, y.y + dt * a.y, y.z + dt * a.z)
}

/// `y += dt * a`, component by component (`y` and `a` of one length: one bounds check).
#[inline]
fn add_scaled(y: &mut [f64], a: &[f64], dt: f64) {
    for (y, a) in y.iter_mut().zip(a) {
        *y += dt * a;
    }
}

/// Whether every entry of `y` is finite, without a branch per entry (a step's state is
/// checked after every fixed step).
#[inline]
fn all_finite(y: &[f64]) -> bool {
    // An entry is infinite or NaN when its exponent bits are all set.
    const EXP: u64 = 0x7ff0_0000_0000_0000;
    y.iter()
        .fold(0u64, |bad, v| bad | u64::from(v.to_bits() & EXP == EXP))
        == 0
}

/// Where a velocity-Verlet step (length `h`, ending at state `y` with forces `acc`, having
/// started with forces `prev`) of member `i` (radius `r`) touched the specimen `shape`: the
/// time into the step, the centre and the velocity there. The step started at
/// `x0, v0` (its two half kicks undone) and drifted along `x0 + v0 s + a0 s^2 / 2`, which
/// at `s = h` is exactly the position it ended at; before the touch only the forces at
/// its start acted. (Recording the state at the step's end instead, as a fixed-step DEM
/// code sees the contact, takes the impact up to a step late and already slowed by the
/// contact: 3.5e-3 of the impact speed for a 70 m/s shot at 20 ns steps.)
fn touch_state(
    shape: &SpecimenShape,
    y: &[f64],
    acc: &[f64],
    prev: &[f64],
    i: usize,
    h: f64,
    r: f64,
) -> (f64, Vec3, Vec3) {
    let (a0, a1) = (vel(prev, i), vel(acc, i));
    let v_half = vel(y, i) - 0.5 * h * a1;
    let (x0, v0) = (pos(y, i) - h * v_half, v_half - 0.5 * h * a0);
    let at = |s: f64| x0 + v0 * s + 0.5 * a0 * s * s;
    if !shape.is_plane() {
        // Positive at the start, negative at the end: bisected to 1e-12 of the step
        // (the drift's gap is smooth and, over a contact-sized step, monotone).
        let gap = |s: f64| shape.distance(&at(s)) - r;
        let (mut lo, mut hi) = (0.0, h);
        if gap(0.0) <= 0.0 {
            hi = 0.0;
        }
        while hi - lo > 1e-12 * h {
            let mid = 0.5 * (lo + hi);
            if gap(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        return (hi, at(hi), v0 + a0 * hi);
    }
    // gap(s) = x0.z + v0.z s + a0.z s^2 / 2 - r: positive at the start, negative at the
    // end; its first root in [0, h].
    let (qa, qb, qc) = (0.5 * a0.z, v0.z, x0.z - r);
    let s = if qc <= 0.0 {
        0.0
    } else {
        let disc = (qb * qb - 4.0 * qa * qc).max(0.0).sqrt();
        let q = -0.5 * (qb + qb.signum() * disc);
        [qc / q, q / qa]
            .into_iter()
            .filter(|s| s.is_finite() && (0.0..=h).contains(s))
            .fold(h, f64::min)
    };
    (s, x0 + v0 * s + 0.5 * a0 * s * s, v0 + a0 * s)
}

/// The span of an [`advance_verlet`] call.
#[derive(Debug, Clone, Copy)]
struct VerletSpan {
    t0: f64,
    t1: f64,
    /// Stop at the first step end from then on with no contact in progress.
    apart_after: Option<f64>,
    entries: Entries,
}

/// How [`advance_verlet`] starts members that enter the run during its span.
#[derive(Debug, Clone, Copy)]
enum Entries {
    /// As fed shots on windows: a shot entering in `(since, t]` starts moving at the end
    /// `t` of a step, or waits if it would land on a moving one (`hold_entries`).
    Held { since: f64 },
    /// The event scheduler's clusters: each member joins at its own clock (`t_start`),
    /// where a step ends.
    Clocks,
}

/// Fixed-step velocity Verlet (kick-drift-kick; velocity-dependent forces see the half-step
/// velocity, as in LIGGGHTS' nve/sphere). See [`Method::Verlet`]. From `t0` to `t1`; with
/// `apart_after` (the event scheduler's clusters, the hybrid method's contacts) it stops at
/// the first step end from then on with no contact in progress. Returns the time reached.
#[allow(clippy::too_many_arguments)]
fn advance_verlet(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &mut [IslandPair],
    VerletSpan {
        t0,
        t1,
        apart_after,
        entries,
    }: VerletSpan,
    step: f64,
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    observer: &mut dyn FnMut(f64, &[f64]),
) -> f64 {
    let n = members.len();
    // With friction the shots spin: angular velocities are kicked as the velocities are.
    let spin = phys.contacts.friction.is_some();
    load_state(members, &mut scratch.y, spin);
    scratch.y_new.resize(scratch.y.len(), 0.0);
    // `prev`: the forces at the start of the step, for the impacts' touch (`touch_state`).
    let Scratch {
        y,
        y_new: acc,
        err: prev,
        laws,
        ..
    } = scratch;
    prev.resize(acc.len(), 0.0);
    pair_laws(phys, members, pairs, laws);
    let ctx = Ctx {
        phys,
        onsets_located: false,
        regions_set: true,
        blocks: Blocks::plan(phys, members, pairs),
        laws,
    };
    let mut work = WorkCounters::default();
    let set_regions = |members: &mut [ShotState], t: f64, y: &[f64]| {
        if let Some(field) = &phys.forces.field {
            for (i, m) in members.iter_mut().enumerate() {
                if moving(m, t) {
                    m.locate_at(field, &pos(y, i));
                }
            }
        }
    };
    let mut t = t0;
    // Shots entering in this window (a batch's, placed at the start, never are).
    // The event scheduler's clusters (`apart_after`) start members at their own clocks
    // (`t_start`): steps end there, and such a member joins at its clock with the
    // others' positions then. Fed shots are held back (`hold_entries`) on windows only.
    let (clocks, entries) = match entries {
        Entries::Clocks => (true, false),
        Entries::Held { since } => {
            let entries = members.iter().any(|m| m.t_start > since);
            if entries {
                // (A shot entering exactly at `t0` joins the run in this window.)
                hold_entries(members, pairs, (since, t0), y, &mut work);
            }
            (false, entries)
        }
    };
    set_regions(members, t, y);
    ctx.apply_events(members, pairs, t, y, out);
    // The history law's tangential forces (`Ctx::history`); empty for the viscous law.
    let history = matches!(
        phys.contacts.friction,
        Some(friction::Friction {
            law: friction::Tangential::History { .. },
            ..
        })
    );
    let mut tangent = Vec::new();
    // The forces at `t`: with the history law, its contacts first advanced by `dt`
    // (`None`: read as they are).
    let forces = |ctx: &Ctx,
                  members: &mut [ShotState],
                  pairs: &mut [IslandPair],
                  (t, dt): (f64, Option<f64>),
                  y: &[f64],
                  (tangent, acc): (&mut Vec<Vec3>, &mut [f64]),
                  work: &mut WorkCounters| {
        if history {
            ctx.history(
                members,
                pairs,
                t,
                y,
                dt.unwrap_or(0.0),
                dt.is_none(),
                tangent,
            );
        }
        let tf = history.then_some(&tangent[..]);
        ctx.rhs(members, pairs, None, tf, t, y, acc, work);
    };
    forces(
        &ctx,
        members,
        pairs,
        (t, None),
        y,
        (&mut tangent, acc),
        &mut work,
    );
    // Shots that stepped before take their last evaluation (see `ShotState::verlet_acc`).
    for (i, m) in members.iter().enumerate() {
        if let Some((a, alpha)) = m.verlet_acc {
            acc[6 * i + 3..6 * i + 6].copy_from_slice(a.as_slice());
            if spin {
                acc[6 * n + 3 * i..6 * n + 3 * i + 3].copy_from_slice(alpha.as_slice());
            }
        }
    }
    // A lone shot: its steps away from every contact take its body forces alone and
    // skip the passes that would find nothing (`Ctx::free_steps`). In a pile on windows
    // half the shot-steps are such steps (session 67), in a nozzle's stream nearly all.
    // (No eddies to renew at a step's end either: the fixed step refuses turbulence.)
    // Its entry and its clock change nothing there: free steps start once it moves, no
    // other member's clock can cut them, and without a pair `hold_entries` holds none.
    let lone = phys.free_steps
        && n == 1
        && pairs.is_empty()
        && !history
        && phys.forces.turbulence.is_none();
    while t < t1 && members.iter().any(|m| m.is_active()) {
        if lone {
            let span = (&mut t, t1, step, apart_after);
            let state = (&mut y[..], &mut *acc, &mut *prev);
            if ctx.free_steps(&mut members[0], span, spin, state, out, &mut work, observer) {
                break;
            }
            if t >= t1 || !members[0].is_active() {
                break;
            }
            // The next step ends in reach of a contact: the general step below.
        }
        // (A member's clock ahead ends the step there: its `t_start`, with `clocks`.)
        let stop = if clocks {
            members
                .iter()
                .filter(|m| m.is_active() && m.t_start > t)
                .map(|m| m.t_start)
                .fold(t1, f64::min)
        } else {
            t1
        };
        let h = if stop - t <= step * (1.0 + 1e-9) {
            stop - t
        } else {
            step
        };
        // Kick and drift, and the step counted.
        for (i, m) in members.iter_mut().enumerate() {
            if !moving(m, t) {
                continue;
            }
            let (x, v) = y[6 * i..6 * i + 6].split_at_mut(3);
            add_scaled(v, &acc[6 * i + 3..6 * i + 6], 0.5 * h);
            add_scaled(x, v, h);
            if spin {
                kick_spin(y, acc, n, i, 0.5 * h);
            }
            m.steps += 1;
            work.shot_steps += 1;
            if m.on_specimen && m.hits == 1 {
                m.first_contact_steps += 1;
            }
        }
        let t_new = if h == stop - t { stop } else { t + h };
        // A shot entering during the step starts moving at its end; on top of one already
        // moving it waits instead (as the adaptive method holds it at its entry time).
        if entries {
            hold_entries(members, pairs, (t, t_new), y, &mut work);
        }
        t = t_new;
        set_regions(members, t, y);
        // Forces at the new positions (with the half-step velocities), second kick. (The
        // step's starting forces move to `prev`: `rhs` writes every entry of `acc`.)
        std::mem::swap(acc, prev);
        forces(
            &ctx,
            members,
            pairs,
            (t, Some(h)),
            y,
            (&mut tangent, acc),
            &mut work,
        );
        for (i, m) in members.iter().enumerate() {
            // (A member joining at `t` on its clock took no part of the step.)
            if moving(m, t) && !(clocks && m.t_start == t) {
                add_scaled(
                    &mut y[6 * i + 3..6 * i + 6],
                    &acc[6 * i + 3..6 * i + 6],
                    0.5 * h,
                );
                if spin {
                    kick_spin(y, acc, n, i, 0.5 * h);
                }
            }
        }
        work.steps_accepted += 1;
        if !all_finite(y) {
            fail_island(
                members,
                t,
                y,
                out,
                "the state stopped being finite",
                "use a smaller fixed step",
            );
            break;
        }
        // Contacts are seen when a step ends overlapping, as a fixed-step DEM code sees them;
        // a specimen impact is recorded where the shot touched, on the step's free path.
        let recorded = out.impacts.len();
        // Without blocks, the step's end in one pass (`Ctx::fixed_step_end`).
        let one_pass = ctx.blocks.is_none();
        let (violation, outside) = if one_pass {
            ctx.fixed_step_end(members, pairs, t, y, out)
        } else {
            ctx.apply_events(members, pairs, t, y, out);
            (None, false)
        };
        for imp in &mut out.impacts[recorded..] {
            if let Some(i) = members.iter().position(|m| m.id.0 == imp.shot) {
                let shape = &ctx
                    .phys
                    .contacts
                    .specimen
                    .as_ref()
                    .expect("BUG: impact without specimen")
                    .shape;
                let (s, p, v) = touch_state(shape, y, acc, prev, i, h, members[i].body.radius);
                let w = if spin {
                    // The spin the step carried across its drift.
                    omega(y, n, i) - 0.5 * h * omega(acc, n, i)
                } else {
                    members[i].omega
                };
                let (r, mass) = (members[i].body.radius, members[i].body.mass);
                let (before, first) = (imp.collisions_before, imp.first_hit == 1);
                *imp = Impact::on(
                    shape,
                    imp.shot,
                    t - h + s,
                    &p,
                    &v,
                    &w,
                    r,
                    mass,
                    before,
                    first,
                );
            }
        }
        observer(t, y);
        let suggestion = "use a smaller fixed step";
        if let Some(cause) = violation {
            fail_island(members, t, y, out, &overlap_cause(&cause), suggestion);
            break;
        }
        if one_pass {
            if outside {
                ctx.leave_domain(members, t, y);
            }
        } else if ctx
            .end_of_step(members, pairs, t, y, out, suggestion)
            .is_none()
        {
            break;
        }
        if apart_after.is_some_and(|ta| t >= ta) && !in_contact(members, pairs) {
            break;
        }
    }
    store_state(members, y);
    for (i, m) in members.iter_mut().enumerate() {
        m.verlet_acc = moving(m, t).then(|| {
            let alpha = if spin {
                omega(acc, n, i)
            } else {
                Vec3::zeros()
            };
            (vel(acc, i), alpha)
        });
    }
    out.work.add(&work);
    t
}

#[cfg(test)]
mod tests {
    use super::{all_finite, first_crossing_guided};

    /// The exponent test agrees with `f64::is_finite` on the edge cases of the format.
    #[test]
    fn all_finite_is_is_finite_on_every_entry() {
        let finite = [
            0.0,
            -0.0,
            1.0,
            -3.5e-300,
            f64::MIN_POSITIVE / 8.0, // subnormal
            f64::MAX,
            f64::MIN,
        ];
        let not = [f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
        assert!(all_finite(&finite));
        assert!(all_finite(&[]));
        for bad in not {
            for k in 0..=finite.len() {
                let mut y = finite.to_vec();
                y.insert(k, bad);
                assert!(!all_finite(&y), "{bad} at {k}");
                assert_eq!(all_finite(&y), y.iter().all(|v| v.is_finite()));
            }
        }
    }

    /// Runs the guided search on margin `g` with estimate `guess` over `[0, 1]`:
    /// (end, held, evaluations of `g`, `g` at the end).
    fn locate(
        g: &dyn Fn(f64) -> f64,
        guess: &dyn Fn(f64) -> f64,
        tol: f64,
    ) -> (f64, bool, usize, f64) {
        let mut n = 0;
        let mut last = f64::NAN;
        let (end, held) = first_crossing_guided(
            (0.0, g(0.0)),
            (1.0, g(1.0)),
            tol,
            &mut |c| guess(c),
            &mut |c| {
                n += 1;
                last = c;
                g(c)
            },
        );
        assert_eq!(
            held,
            last == end,
            "held says whether the last evaluation was at the end"
        );
        (end, held, n, g(end))
    }

    #[test]
    fn an_impacts_kink_matters_and_a_beds_does_not() {
        use super::kink_matters;
        use crate::contact::hertz::{HertzLaw, contact_time};
        // Two steel shots of 0.8 mm (m* = 1.05e-6 kg, K = 2.18e9 N/m^1.5), tolerance 1e-6.
        let m_eff = 0.5 * 7850.0 * std::f64::consts::PI / 6.0 * 0.8e-3f64.powi(3);
        let law = HertzLaw::new(210e9, 0.3, 210e9, 0.3, 0.9);
        let k = law.stiffness(0.2e-3);
        let matters =
            |state: (f64, f64), h: f64| kink_matters(1e-6, k, m_eff, state, h, 0.0, 0.8e-3);
        // An impact at 70 m/s, in its contact steps: its kink ends a step.
        assert!(matters((0.0, 70.0), contact_time(m_eff, k, 70.0) / 10.0));
        // The same at 4 m/s (a squeezed bed bursting), in steps of 20 ns.
        assert!(matters((1.2e-6, 2.0), 20e-9));
        // A bed's contact under a few layers (1.3 nm), chattering at 1 mm/s, in steps of
        // 0.1 us: it does not.
        assert!(!matters((1.3e-9, 1e-3), 0.1e-6));
        // The line between: where the step's miss is a tenth of the tolerance.
        let slope = HertzLaw::kink_slope(k, m_eff, 1.3e-9, 1e-3) / m_eff;
        let h = (0.1 * 1e-6 / (slope * crate::integrate::dopri::KINK_MISS[0])).sqrt();
        assert!(!matters((1.3e-9, 1e-3), 0.99 * h) && matters((1.3e-9, 1e-3), 1.01 * h));
        // Friction turns the tangential force with it: the line moves down.
        assert!(kink_matters(
            1e-6,
            k,
            m_eff,
            (1.3e-9, 1e-3),
            0.9 * h,
            0.3,
            0.8e-3
        ));
    }

    #[test]
    fn a_good_guess_locates_the_crossing_in_one_or_two_evaluations() {
        // A margin like a touch's: linear in the step length near its root at 0.37; the
        // guess off by 1e-6 (a dense output's error), the window 1e-10 wide.
        let g = |c: f64| 0.37 - c + 0.05 * (c - 0.37).powi(2);
        let guess = |c: f64| g(c) + 1e-6;
        let (end, held, n, ge) = locate(&g, &guess, 1e-10);
        assert!(ge <= 0.0 && ge > -1e-10, "g(end) = {ge:e}");
        assert!((end - 0.37).abs() < 1e-9);
        assert!(held && n <= 2, "{n} evaluations");
    }

    #[test]
    fn a_poor_guess_still_ends_inside_the_window() {
        // The guess's root 0.05 away: the secant goes on from the bracket it left.
        let g = |c: f64| 0.37 - c;
        let guess = |c: f64| 0.42 - c;
        let (end, _, _, ge) = locate(&g, &guess, 1e-12);
        assert!(ge <= 0.0 && ge > -1e-12, "g(end) = {ge:e}");
        assert!((end - 0.37).abs() < 1e-11);
    }

    #[test]
    fn the_search_ends_on_the_margin_not_on_its_illinois_weight() {
        // A margin that falls steeply at the step's end, just outside the window there:
        // the secant lands on the positive side twice, which halves the weight of the
        // end point; the search must still go on until the margin itself is in the window.
        let tol = 1e-6;
        let g = |c: f64| (1.0 - c * c) * (1.0 + 1.2e-6) - 1.2e-6;
        let (end, _) = super::first_crossing((0.0, g(0.0)), (1.0, g(1.0)), tol, &mut |c| g(c));
        assert!(g(end) <= 0.0 && g(end) > -tol, "g(end) = {:e}", g(end));
    }

    #[test]
    fn onsets_are_placed_where_the_gap_first_turns_negative() {
        use super::onset_fraction;
        let tol = 4e-16;
        // A clear crossing (an impact): at the root, to the tolerance.
        let impact = |s: f64| 2e-6 * (0.3 - s);
        let s = onset_fraction(&impact, tol);
        assert!(
            impact(s) <= 0.0 && impact(s) > -tol && s < 0.3 + 1e-9,
            "s = {s}"
        );
        // Neighbours resting against each other: the gap falls by rounding-level amounts
        // over the step (-1.8e-16 m at its end, inside `tol`); the onset is where it
        // first turns negative, not the step's end (the dense bed took 27 % more steps
        // when it was put there).
        let resting = |s: f64| if s < 0.016 { 0.0 } else { -1.8e-16 * s };
        let s = onset_fraction(&resting, tol);
        assert!(s > 0.015 && s < 0.017, "s = {s}");
    }

    #[test]
    fn the_first_of_several_crossings_is_found() {
        // Crossings downwards at 0.2 and 0.8 (up at 0.5): the step ends at the first.
        let g = |c: f64| -(c - 0.2) * (c - 0.5) * (c - 0.8);
        let (end, _, _, ge) = locate(&g, &g, 1e-12);
        assert!(ge <= 0.0 && ge > -1e-12, "g(end) = {ge:e}");
        assert!((end - 0.2).abs() < 1e-9, "end {end}");
    }
}
