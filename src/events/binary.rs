//! Lone contacts in ballistic flight, resolved in closed form where the
//! motion is free and in a two-body frame where it is not: the event scheduler's lean
//! path for the contacts of a falling stream (a shot meeting one other shot, or the
//! specimen, with nobody else near).
//!
//! * **Two shots.** Gravity is the same for both, so their centre of mass flies in closed
//!   form and only the relative position `r = x_j - x_i` feels the contact,
//!   `r'' = F(delta, delta') n / m*` with `delta = R_i + R_j - |r|`, `n = r / |r|`.
//! * **A shot and the specimen.** `z'' = F(delta, delta') / m - g` with `delta = R - z`;
//!   the motion along the plane is free.
//! * **Friction** (`mu > 0`): the state also carries the spins (both shots' for a pair;
//!   the tangential force is internal, so the centre of mass still flies in closed form),
//!   with the island integrator's tangential law, lever arms and spin error weights.
//!   After the kink the normal force is zero, so the tangential force is too: the release
//!   stays closed form, the spins constant.
//!
//! `F` is the island integrator's Hertz-Tsuji force, clamped at zero. The phases are
//! those the island integrator goes through, in one body's state:
//! * approach: free flight up to the touch, found in closed form (the impact record of a
//!   specimen touch is taken there, exactly);
//! * loading and unloading: Dormand-Prince steps with the island's error norm and caps
//!   (first step 1 % of a contact step, then at most `t_c / contact_steps`);
//! * the kink: the step that would take the unclamped force below zero is cut back to
//!   where it crosses zero (located as the island's events: from the step's dense output,
//!   then trial steps);
//! * release: with the force at zero the motion is free again (the overlap only falls, so
//!   the force cannot return) and the parting time is closed form.
//!
//! A contact still on at the chunk's end is handed back touching and continued in the
//! next chunk. Whatever this path does not cover (a contact found overlapping, too deep an
//! overlap, one lasting beyond three Hertz times, a collapsing step) returns `None`, and
//! the caller integrates the shots as an island instead.

use crate::Vec3;
use crate::contact::friction::{self, INERTIA_FACTOR};
use crate::contact::hertz::{self, HertzLaw};
use crate::contact::table::{ContactTable, Course, SAMPLES};
use crate::contact::{PairContact, SpecimenContact, effective_mass};
use crate::integrate::dopri::{DenseStep, Dopri5, step_factor};
use crate::integrate::island::{
    AT_ONSET, MIN_CONTACT_SPEED, MIN_STEP, ONSET_STEP, first_contact_step, first_crossing_guided,
};
use crate::integrate::{add_at, vec_at};

use super::flight::{Flight, closest_approach, pair_touch};
use crate::counters::WorkCounters;
use crate::record::Impact;
use crate::state::ShotState;

/// One shot at the start of the chunk.
#[derive(Debug, Clone, Copy)]
pub struct Body {
    /// Position, m.
    pub pos: Vec3,
    /// Velocity, m/s.
    pub vel: Vec3,
    /// Mass, kg.
    pub mass: f64,
    /// Radius, m.
    pub radius: f64,
    /// Spin, rad/s (changed only by friction).
    pub omega: Vec3,
}

/// The integrator's settings.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Relative error per step.
    pub tolerance: f64,
    /// Steps per Hertz contact duration at most apart.
    pub contact_steps: f64,
}

/// A contact already in progress at the start of the chunk.
#[derive(Debug, Clone, Copy)]
pub struct InProgress {
    /// Touching time, s.
    pub onset: f64,
    /// Hertz duration estimate at the touch, s.
    pub contact_time: f64,
    /// A specimen contact's damping factor (`ShotState::specimen_damping`), taken when
    /// the restitution depends on the impact speed.
    pub damping: f64,
}

/// How the contact went, for `n` shots (2: a pair, 1: a shot on the specimen; arrays
/// hold them first).
#[derive(Debug, Clone, Default)]
pub struct Outcome {
    /// Shots involved.
    pub n: usize,
    /// Touching time, s.
    pub onset: f64,
    /// Whether the contact started in this chunk (else it was in progress).
    pub fresh: bool,
    /// Position and velocity of the first shot at the touch (a specimen impact's record).
    pub at_onset: (Vec3, Vec3),
    /// Hertz duration estimate at the touch, s.
    pub contact_time: f64,
    /// A specimen contact's Tsuji damping factor (`ShotState::specimen_damping`).
    pub damping: f64,
    /// Start of the contact phase in this chunk (the touch, or the chunk's start), s.
    pub from: f64,
    /// Time the force reached zero (the kink), s, or the chunk's end if it did not:
    /// from then on the shots fly free until `end`.
    pub kink: f64,
    /// Positions and velocities at `kink`.
    pub at_kink: [(Vec3, Vec3); 2],
    /// Time the shots are handed back: just after they part, or the chunk's end.
    pub end: f64,
    /// Whether they still overlap at `end` (the contact continues in the next chunk).
    pub touching: bool,
    /// Positions and velocities at `end`.
    pub state: [(Vec3, Vec3); 2],
    /// Spins after the contact (as they came without friction), rad/s.
    pub omega: [Vec3; 2],
    /// Whether friction acted (the spins were integrated).
    pub spins: bool,
    /// Sample times: `from`, after every accepted step, and `kink`.
    pub times: Vec<f64>,
    /// Positions and velocities at the sample times, `n` per sample.
    pub samples: Vec<(Vec3, Vec3)>,
    /// Largest squared speed of any shot at the samples, m^2/s^2.
    pub v_max2: f64,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected trials (error too large, or locating the kink).
    pub rejected: u64,
    /// Right-hand-side evaluations.
    pub rhs: u64,
}

impl Outcome {
    /// An empty outcome for `n` shots with room for a typical contact's samples.
    fn with_room(n: usize) -> Self {
        const SAMPLES: usize = 32;
        Outcome {
            times: Vec::with_capacity(SAMPLES),
            samples: Vec::with_capacity(SAMPLES * n),
            ..Outcome::default()
        }
    }

    fn sample(&mut self, t: f64, st: &[(Vec3, Vec3)]) {
        self.times.push(t);
        for x in st {
            self.v_max2 = self.v_max2.max(x.1.norm_squared());
            self.samples.push(*x);
        }
    }

    /// Records the end of the contact phase at `t` (the kink, or `e` if the contact
    /// still pushes there: then it is handed back touching at `e`). Returns whether the
    /// release follows.
    fn end_phase(&mut self, t: f64, at: [(Vec3, Vec3); 2], pushing: bool, e: f64) -> bool {
        self.kink = t;
        self.at_kink = at;
        self.sample(t, &at[..self.n]);
        if pushing {
            self.end = e;
            self.touching = true;
            self.state = at;
        }
        !pushing
    }

    /// Shot `q`'s (time, position, velocity) at each sample.
    pub fn path(&self, q: usize) -> impl Iterator<Item = (f64, Vec3, Vec3)> + '_ {
        self.times.iter().enumerate().map(move |(i, &t)| {
            (
                t,
                self.samples[i * self.n + q].0,
                self.samples[i * self.n + q].1,
            )
        })
    }
}

/// What is known of another shot's motion while a lean contact lasts: it flies free
/// from `(clock, pos, vel)` until `until`; before `clock` (if `bounded_before`) and
/// after `until` only that it moves no faster than `speed`. (Before `clock` without
/// `bounded_before`: not checked, the caller knows it clear then.)
#[derive(Debug, Clone, Copy)]
pub struct Neighbour {
    /// Start of its known free flight, s.
    pub clock: f64,
    /// Position at `clock`, m.
    pub pos: Vec3,
    /// Velocity at `clock`, m/s.
    pub vel: Vec3,
    /// End of its known free flight, s.
    pub until: f64,
    /// Whether it is to be checked before `clock` too (within `speed` of `pos`).
    pub bounded_before: bool,
    /// Speed bound outside its free flight, m/s.
    pub speed: f64,
    /// Contact distance to the shot checked against it, m.
    pub sigma: f64,
}

impl Neighbour {
    /// Whether a shot at `ours(t)` (position, velocity) over `[t0, t1]`, off that line by
    /// at most `dev` against a free shot (`dev_line` against a fixed point), keeps at
    /// least `sigma` from this neighbour.
    fn clear(
        &self,
        flight: &Flight,
        t0: f64,
        t1: f64,
        ours: &dyn Fn(f64) -> (Vec3, Vec3),
        dev: f64,
        dev_line: f64,
    ) -> bool {
        let (a, b) = (t0.max(self.clock), t1.min(self.until));
        if a < b {
            let (pm, vm) = ours(a);
            let (pc, vc) = flight.at(&self.pos, &self.vel, a - self.clock);
            if closest_approach(&(pc - pm), &(vc - vm), b - a) < self.sigma + dev {
                return false;
            }
        }
        // Outside its free flight: within `speed` of where it was last (or first) known.
        let anchored = |from: f64, to: f64, anchor: Vec3, slack: f64| {
            let (pm, vm) = ours(from);
            closest_approach(&(anchor - pm), &(-vm), to - from) >= self.sigma + dev_line + slack
        };
        if self.bounded_before && t0 < self.clock {
            let to = t1.min(self.clock);
            if !anchored(t0, to, self.pos, self.speed * (self.clock - t0)) {
                return false;
            }
        }
        if t1 > self.until {
            let from = t0.max(self.until);
            let anchor = flight.at(&self.pos, &self.vel, self.until - self.clock).0;
            if !anchored(from, t1, anchor, self.speed * (t1 - self.until)) {
                return false;
            }
        }
        true
    }
}

/// The contact phase of a six-value state (position, velocity of the one moving body):
/// [`Phase::run`] steps it from `t` to the kink or `e`, whichever comes first.
struct Phase<'a, R, M, O> {
    rhs: &'a R,
    margin: &'a M,
    overlap: &'a O,
    /// Deepest overlap allowed (the island integrator stops the shots beyond it).
    depth_limit: f64,
    /// Smallest body radius (the scale of position errors and of the kink's location).
    r_min: f64,
    /// Radii of the bodies whose spins follow the position and velocity in the state
    /// (friction on; empty without).
    spin_radii: &'a [f64],
    set: Settings,
    /// Hertz duration of the contact, s, and its onset, s.
    tc: f64,
    onset: f64,
    /// Frictionless: adds to a step that starts `a` (s) after the touch and lasts `h` (s)
    /// what its quadrature missed of the force's start (`HertzLaw::onset_correction`),
    /// given the states before and after it. With friction (whose tangential force
    /// starts the same way) `None`: the first step is then short instead.
    correct: Option<&'a Correction<'a>>,
}

/// See [`Phase::correct`]: `(a, h, y0, y1)`.
type Correction<'a> = dyn Fn(f64, f64, &[f64], &mut [f64]) + 'a;

impl<R, M, O> Phase<'_, R, M, O>
where
    R: Fn(&[f64], &mut [f64]),
    M: Fn(&[f64]) -> f64,
    O: Fn(&[f64]) -> f64,
{
    /// Steps `(t, y)` through the contact (`pushes`: it pushes from the start: a fresh
    /// touch, or one in progress at or short of the touching distance and closing) until
    /// the force reaches zero or `t` reaches `e`; `on_step` sees every accepted step before that.
    /// Returns whether the contact still pushes at the returned `t`; `None` if the lean
    /// path does not apply (too deep, too long, a collapsing step).
    #[allow(clippy::too_many_arguments)]
    fn run<const N: usize>(
        &self,
        y: &mut [f64; N],
        t: &mut f64,
        e: f64,
        pushes: bool,
        out: &mut Outcome,
        on_step: &mut dyn FnMut(&mut Outcome, f64, &[f64]),
    ) -> Option<bool> {
        let (tol, h_cap) = (self.set.tolerance, self.tc / self.set.contact_steps);
        let (sx, kink_tol) = (tol * 2.0 * self.r_min, 1e-6 * self.r_min);
        // A fresh contact pushes from the touch on; one in progress may be past its kink.
        let mut pushing = pushes || (self.margin)(y) > 0.0;
        let (mut y_new, mut err) = ([0.0; N], [0.0; N]);
        // The first step after the touch is corrected and `first_contact_step` long, or
        // without a correction short (the dashpot's delta^(1/4)), as in the island
        // integrator; a contact in progress starts at the contact step.
        let mut h = if *t - self.onset >= ONSET_STEP * h_cap {
            h_cap
        } else if self.correct.is_some() {
            first_contact_step(self.tc, self.set.contact_steps, tol)
        } else {
            ONSET_STEP * h_cap
        };
        // Steps starting within a contact step of the touch are corrected.
        let correct = |t: f64, h: f64, y: &[f64], y_new: &mut [f64]| {
            if let Some(c) = self.correct
                && t - self.onset < h_cap
            {
                c(t - self.onset, h, y, y_new);
            }
        };
        // The stages on the stack: the loops over `N` values unroll.
        let mut fixed = Dopri5::<[f64; N]>::fixed();
        let dopri = &mut fixed;
        let mut dense = DenseStep::default();
        let mut f = |_t: f64, y: &[f64], dy: &mut [f64]| (self.rhs)(y, dy);
        let error_norm = |y: &[f64], err: &[f64]| {
            let speed = vec_at(y, 3).norm();
            let sv = tol * (speed + 1.0);
            let e = (0..3).fold(0.0f64, |m, q| {
                m.max(err[q].abs() / sx).max(err[3 + q].abs() / sv)
            });
            // Spins as the island weighs them: the contact-point speed omega R on the
            // velocity's scale.
            self.spin_radii.iter().enumerate().fold(e, |m, (b, &r)| {
                let o = 6 + 3 * b;
                let w = vec_at(y, o).norm();
                let sw = tol * (speed + w * r + 1.0) / r;
                (0..3).fold(m, |m, q| m.max(err[o + q].abs() / sw))
            })
        };
        while pushing && *t < e {
            if *t - self.onset > 3.0 * self.tc {
                return None; // not an impact: let the island integrator hold it
            }
            h = h.min(h_cap);
            let lands = *t + h >= e;
            if lands {
                h = e - *t;
            }
            let en = loop {
                out.rhs += u64::from(dopri.step(&mut f, *t, y, h, &mut y_new, &mut err));
                correct(*t, h, y, &mut y_new);
                let en = if y_new.iter().all(|v| v.is_finite()) {
                    error_norm(y, &err)
                } else {
                    f64::INFINITY
                };
                if en <= 1.0 {
                    break en;
                }
                out.rejected += 1;
                h *= if en.is_finite() {
                    step_factor(en, 0.2, f64::INFINITY)
                } else {
                    0.25
                };
                if h < MIN_STEP {
                    return None;
                }
            };
            let full = h;
            let g1 = (self.margin)(&y_new);
            if g1 < 0.0 {
                // Cut the step back to the kink, located from the dense output first.
                pushing = false;
                // The step's dense output estimates the margin inside it at no cost.
                dopri.dense_into(*t, y, &y_new, h, &mut dense);
                let mut at = [0.0; N];
                let (hi, held) = first_crossing_guided(
                    (0.0, (self.margin)(y).max(0.0)),
                    (h, g1),
                    kink_tol,
                    &mut |c| {
                        dense.at(*t + c, &mut at);
                        (self.margin)(&at)
                    },
                    &mut |c| {
                        out.rhs += u64::from(dopri.step(&mut f, *t, y, c, &mut y_new, &mut err));
                        correct(*t, c, y, &mut y_new);
                        out.rejected += 1;
                        (self.margin)(&y_new)
                    },
                );
                if held {
                    // The last trial step ended at the kink: it is the step taken.
                    out.rejected -= 1;
                } else if hi != h {
                    out.rhs += u64::from(dopri.step(&mut f, *t, y, hi, &mut y_new, &mut err));
                    correct(*t, hi, y, &mut y_new);
                }
                h = hi;
            }
            out.steps += 1;
            // The last stage saw the state before the correction of a step from the touch.
            let stale = self.correct.is_some() && *t - self.onset <= AT_ONSET * self.tc;
            *y = y_new;
            *t = if lands && h == full { e } else { *t + h };
            dopri.accept_fsal();
            if stale {
                dopri.invalidate();
            }
            let overlap = (self.overlap)(y);
            if overlap > self.depth_limit {
                return None; // too deep: the island integrator stops it with the message
            }
            if overlap <= 0.0 {
                pushing = false;
            }
            if pushing && *t < e {
                on_step(out, *t, y);
            }
            h *= step_factor(en, 0.2, 5.0);
        }
        Some(pushing)
    }
}

impl Outcome {
    /// Whether shot `q`'s actual path (state `start` at `s`: free flight to `from`, the
    /// chords between the samples widened by their error bound, free flight from the
    /// kink to `end`) keeps clear of the neighbour `nb`.
    pub fn clear_of(
        &self,
        q: usize,
        flight: &Flight,
        s: f64,
        start: (Vec3, Vec3),
        nb: &Neighbour,
    ) -> bool {
        let g = flight.g;
        // Free pieces: the relative motion of two free shots is straight, exactly.
        let free = [
            (s, start.0, start.1, self.from),
            (self.kink, self.at_kink[q].0, self.at_kink[q].1, self.end),
        ];
        for (t0, p, v, t1) in free {
            let h = t1 - t0;
            if h > 0.0
                && !nb.clear(
                    flight,
                    t0,
                    t1,
                    &|t| flight.at(&p, &v, t - t0),
                    0.0,
                    0.5 * g * h * h,
                )
            {
                return false;
            }
        }
        let mut prev: Option<(f64, Vec3, Vec3)> = None;
        for (t1, p1, v1) in self.path(q) {
            let Some((t0, p0, v0)) = prev.replace((t1, p1, v1)) else {
                continue;
            };
            let h = t1 - t0;
            if h <= 0.0 {
                continue;
            }
            let dev = 0.5 * h * (v1 - v0).norm() + 0.5 * g * h * h;
            let chord = (p1 - p0) / h;
            if !nb.clear(
                flight,
                t0,
                t1,
                &|t| (p0 + chord * (t - t0), chord),
                dev,
                dev,
            ) {
                return false;
            }
        }
        true
    }

    /// A box holding shot `q`'s actual path from `s` (state `start`) to `end`, the
    /// chords' error bounds included.
    pub fn path_box(&self, q: usize, g: f64, s: f64, start: (Vec3, Vec3)) -> (Vec3, Vec3) {
        let (mut lo, mut hi) = (start.0, start.0);
        let mut dev = 0.5 * g * (self.end - s).powi(2);
        let mut prev: Option<(f64, Vec3)> = None;
        for (t1, p1, v1) in self
            .path(q)
            .chain([(self.end, self.state[q].0, self.state[q].1)])
        {
            if let Some((t0, v0)) = prev.replace((t1, v1)) {
                let h = t1 - t0;
                dev = dev.max(0.5 * h * (v1 - v0).norm() + 0.5 * g * h * h);
            }
            lo = lo.inf(&p1);
            hi = hi.sup(&p1);
        }
        (lo - Vec3::repeat(dev), hi + Vec3::repeat(dev))
    }

    /// Whether shot `q` of a pair (radius `r`, height `z_start` at the chunk's start)
    /// stays clear of the specimen plane `z = 0` throughout, the chords' error bound
    /// included.
    pub fn above_plane(&self, q: usize, z_start: f64, r: f64, g: f64) -> bool {
        let mut ok = [z_start, self.at_kink[q].0.z, self.state[q].0.z]
            .into_iter()
            .all(|z| z - r > 0.0);
        let mut prev: Option<(f64, Vec3, Vec3)> = None;
        for (t1, p1, v1) in self.path(q) {
            if let Some((t0, p0, v0)) = prev.replace((t1, p1, v1)) {
                let h = t1 - t0;
                let dev = 0.5 * h * (v1 - v0).norm() + 0.5 * g * h * h;
                ok &= p0.z.min(p1.z) - r > dev;
            } else {
                ok &= p1.z - r > 0.0;
            }
        }
        ok
    }

    /// Writes this outcome into shot `q`'s state (`c`): its position and velocity at
    /// `end`, its steps, and, for a specimen touch, its hit count and impact record
    /// (pushed to `impacts`).
    pub fn apply(&self, q: usize, c: &mut ShotState, impacts: &mut Vec<Impact>) {
        if self.n == 1 {
            if self.fresh {
                c.specimen_onset = self.onset;
                c.specimen_contact_time = self.contact_time;
                c.specimen_damping = self.damping;
                c.hits += 1;
                if c.hits == 1 {
                    c.steps_to_first_contact = Some(c.steps);
                }
                impacts.push(Impact::new(
                    c.id.0,
                    self.onset,
                    &self.at_onset.0,
                    &self.at_onset.1,
                    &c.omega,
                    c.body.radius,
                    c.body.mass,
                    c.collisions,
                    c.hits == 1,
                ));
            }
            if c.hits == 1 {
                c.first_contact_steps += self.steps;
            }
            c.on_specimen = self.touching;
        } else {
            c.collisions += u32::from(self.fresh);
        }
        (c.pos, c.vel) = self.state[q];
        c.omega = self.omega[q];
        c.steps += self.steps;
        c.ahead = None;
    }

    /// Adds this outcome's work to `w`.
    pub fn count(&self, w: &mut WorkCounters) {
        w.steps_accepted += self.steps;
        w.steps_rejected += self.rejected;
        w.shot_steps += self.n as u64 * self.steps;
        w.rhs_evaluations += self.rhs;
        if self.n == 2 {
            w.pair_contact_checks += self.rhs;
        } else {
            w.specimen_contact_checks += self.rhs;
            w.gravity_calls += self.rhs;
        }
        if self.spins {
            w.friction_calls += self.rhs;
        }
        w.contact_onsets += u64::from(self.fresh);
        w.lean_contacts += u64::from(self.fresh);
    }
}

fn vecs(y: &[f64]) -> (Vec3, Vec3) {
    (vec_at(y, 0), vec_at(y, 3))
}

/// Resolves the contact of shots `a` and `b` (states at `s`) over the chunk `[s, e]`,
/// the caller guaranteeing that nothing else touches them: from the touch (`progress`
/// `None`: it must come before `e`) or from `s` (a contact in progress) until they part,
/// or until `e` if they still overlap then. `apart_after`: parted shots are not handed
/// back before this time (the island's rule).
#[allow(clippy::too_many_arguments)]
pub fn resolve(
    law: &HertzLaw,
    table: Option<&ContactTable>,
    mu: f64,
    flight: &Flight,
    a: &Body,
    b: &Body,
    progress: Option<InProgress>,
    s: f64,
    e: f64,
    apart_after: f64,
    set: Settings,
) -> Option<Outcome> {
    let sigma = a.radius + b.radius;
    let r0 = b.pos - a.pos;
    let v0 = b.vel - a.vel;
    let m_eff = effective_mass(a.mass, b.mass);
    let r_eff = PairContact::effective_radius(a.radius, b.radius);
    let k = law.stiffness(r_eff);
    let (onset, tc, from, r_from) = match progress {
        None => {
            if r0.norm() <= sigma {
                return None;
            }
            let tau = pair_touch(&r0, &v0, sigma)?;
            if s + tau >= e {
                return None;
            }
            let r_on = r0 + v0 * tau;
            let closing = -v0.dot(&r_on) / r_on.norm();
            let tc = hertz::contact_time(m_eff, k, closing.max(MIN_CONTACT_SPEED));
            (s + tau, tc, s + tau, r_on)
        }
        Some(p) => (p.onset, p.contact_time, s, r0),
    };
    let h_cap = tc / set.contact_steps;
    let total = a.mass + b.mass;
    let (wa, wb) = (b.mass / total, a.mass / total);
    let com0 = (a.pos * a.mass + b.pos * b.mass) / total;
    let vcom0 = (a.vel * a.mass + b.vel * b.mass) / total;
    let lab = |t: f64, r: &Vec3, v: &Vec3| -> [(Vec3, Vec3); 2] {
        let (c, vc) = flight.at(&com0, &vcom0, t - s);
        [(c - r * wa, vc - v * wa), (c + r * wb, vc + v * wb)]
    };
    let mut out = Outcome {
        n: 2,
        onset,
        fresh: progress.is_none(),
        contact_time: tc,
        from,
        ..Outcome::with_room(2)
    };
    let st = lab(from, &r_from, &v0);
    out.at_onset = st[0];
    out.sample(from, &st);
    if let (Some(tb), None, true) = (table, progress, mu == 0.0) {
        let mut each = |t: f64, r: Vec3, v: Vec3| out.sample(t, &lab(t, &r, &v));
        let shape = Contact {
            law,
            k,
            mass: m_eff,
            onset,
            e,
        };
        if let Some((t, r, v)) = shape.pair(tb, sigma, &r_from, &v0, &mut each) {
            out.omega = [a.omega, b.omega];
            out.end_phase(t, lab(t, &r, &v), false, e);
            return release_pair(out, t, r, v, sigma, h_cap, apart_after, e, &lab);
        }
    }
    // With friction (`mu > 0`) the state carries both spins (values 6..12); the
    // tangential force acts at the middle of the overlap, as in the island integrator.
    let (ia, ib) = (
        INERTIA_FACTOR * a.mass * a.radius * a.radius,
        INERTIA_FACTOR * b.mass * b.radius * b.radius,
    );
    let m_t = friction::sphere_pair_mass(a.mass, b.mass);
    // Lever arms to the contact point, the middle of the overlap, and its slip (of
    // `a`'s point against `b`'s) in state `y` along the normal `n`.
    let contact_point = |y: &[f64], n: &Vec3, overlap: f64| {
        let (ra, rb) = (
            n * (a.radius - 0.5 * overlap),
            n * (0.5 * overlap - b.radius),
        );
        let (v, wa, wb) = (vec_at(y, 3), vec_at(y, 6), vec_at(y, 9));
        let slip = friction::tangential_part(&(wa.cross(&ra) - wb.cross(&rb) - v), n);
        (ra, rb, slip)
    };
    let rhs = |y: &[f64], dy: &mut [f64]| {
        let r = vec_at(y, 0);
        let v = vec_at(y, 3);
        dy[..3].copy_from_slice(&y[3..6]);
        let d = r.norm();
        let overlap = sigma - d;
        let mut acc = Vec3::zeros();
        let (mut alpha_a, mut alpha_b) = (Vec3::zeros(), Vec3::zeros());
        if overlap > 0.0 && d > 0.0 {
            let n = r / d;
            let f = law.force(k, m_eff, overlap, -v.dot(&n));
            acc = n * (f / m_eff);
            if y.len() > 6 {
                let (ra, rb, slip) = contact_point(y, &n, overlap);
                let gamma = friction::stick_damping(m_t, k, overlap);
                // On shot `a`; `b` feels the opposite.
                let ft = friction::tangential_force(mu, f, &slip, gamma);
                acc -= ft / m_eff;
                alpha_a = ra.cross(&ft) / ia;
                alpha_b = rb.cross(&(-ft)) / ib;
            }
        }
        dy[3..6].copy_from_slice(acc.as_slice());
        if y.len() > 6 {
            dy[6..9].copy_from_slice(alpha_a.as_slice());
            dy[9..12].copy_from_slice(alpha_b.as_slice());
        }
    };
    let margin = |y: &[f64]| {
        let r = vec_at(y, 0);
        let d = r.norm();
        let rate = -vec_at(y, 3).dot(&r) / d;
        law.unloading_margin(k, m_eff, sigma - d, rate)
    };
    let overlap = |y: &[f64]| sigma - vec_at(y, 0).norm();
    let r_min = a.radius.min(b.radius);
    let spins = mu > 0.0;
    let radii = [a.radius, b.radius];
    let v_impact = hertz::impact_speed(m_eff, k, tc);
    let terms = law.onset_terms(k, m_eff, v_impact);
    let correct = |at: f64, h: f64, y0: &[f64], y1: &mut [f64]| {
        let r = vec_at(y0, 0);
        let d = r.norm();
        if d > 0.0 {
            let n = r / d;
            let (dx, dv) = hertz::start_correction(terms, at, h);
            add_at(y1, 0, &(n * (dx / m_eff)));
            add_at(y1, 3, &(n * (dv / m_eff)));
            if spins {
                // The tangential force's start along the slip at the step's start: on
                // `a` the impulse `-s dv_t`, on `b` the opposite (see the rhs).
                let (ra, rb, slip) = contact_point(y0, &n, sigma - d);
                let sn = slip.norm();
                let d_t = friction::onset_terms(mu, terms, m_t, k, v_impact, sn);
                if sn > 0.0 && d_t.0 + d_t.1 > 0.0 {
                    let dir = slip / sn;
                    let (dx, dv) = hertz::start_correction(d_t, at, h);
                    add_at(y1, 0, &(dir * (dx / m_eff)));
                    add_at(y1, 3, &(dir * (dv / m_eff)));
                    let j = dir * -dv;
                    add_at(y1, 6, &(ra.cross(&j) / ia));
                    add_at(y1, 9, &(rb.cross(&-j) / ib));
                }
            }
        }
    };
    let phase = Phase {
        rhs: &rhs,
        margin: &margin,
        overlap: &overlap,
        depth_limit: r_eff,
        r_min,
        spin_radii: if spins { &radii } else { &[] },
        set,
        tc,
        onset,
        correct: Some(&correct),
    };
    let (wa, wb) = (a.omega, b.omega);
    let mut y = [
        r_from.x, r_from.y, r_from.z, v0.x, v0.y, v0.z, wa.x, wa.y, wa.z, wb.x, wb.y, wb.z,
    ];
    let mut t = from;
    // A contact handed on at its touch (rounding may leave the shots a hair apart) still
    // has all of its loading ahead.
    let at_touch = r_from.norm() >= sigma && v0.dot(&r_from) < 0.0;
    let mut sample = |out: &mut Outcome, t: f64, y: &[f64]| {
        let (r, v) = vecs(y);
        out.sample(t, &lab(t, &r, &v));
    };
    let pushes = progress.is_none() || at_touch;
    let pushing = if spins {
        phase.run(&mut y, &mut t, e, pushes, &mut out, &mut sample)?
    } else {
        let mut y6 = [y[0], y[1], y[2], y[3], y[4], y[5]];
        let p = phase.run(&mut y6, &mut t, e, pushes, &mut out, &mut sample)?;
        y[..6].copy_from_slice(&y6);
        p
    };
    out.omega = [vec_at(&y, 6), vec_at(&y, 9)];
    out.spins = spins;
    let (r, v) = vecs(&y);
    if !out.end_phase(t, lab(t, &r, &v), pushing, e) {
        return Some(out);
    }
    release_pair(out, t, r, v, sigma, h_cap, apart_after, e, &lab)
}

/// A pair's lab-frame states from their relative position and velocity at a time.
type Lab<'a> = dyn Fn(f64, &Vec3, &Vec3) -> [(Vec3, Vec3); 2] + 'a;

/// The release of a pair after its kink at `t` (relative position `r`, velocity `v`):
/// no force until the shots part, a straight line in `r`. `None` if they do not part.
#[allow(clippy::too_many_arguments)]
fn release_pair(
    mut out: Outcome,
    t: f64,
    r: Vec3,
    v: Vec3,
    sigma: f64,
    h_cap: f64,
    apart_after: f64,
    e: f64,
    lab: &Lab,
) -> Option<Outcome> {
    let c = r.norm_squared() - sigma * sigma;
    let vv = v.norm_squared();
    let b_half = r.dot(&v);
    let part = if c >= 0.0 {
        0.0
    } else if vv > 0.0 {
        (-b_half + (b_half * b_half - vv * c).sqrt()) / vv
    } else {
        return None;
    };
    // Handed back a thousandth of a contact step after parting (clearly apart), and not
    // before `apart_after`; or at the chunk's end, still overlapping.
    let end = (t + part + 1e-3 * h_cap).max(apart_after);
    out.end = end.min(e);
    out.touching = end > e;
    let r_end = r + v * (out.end - t);
    out.state = lab(out.end, &r_end, &v);
    Some(out)
}

/// A fresh frictionless contact's course from the dimensionless table
/// ([`crate::contact::table`]): the touch at `onset`, stiffness `k`, effective mass
/// `mass`; the kink must come before the chunk's end `e`.
struct Contact<'a> {
    law: &'a HertzLaw,
    k: f64,
    mass: f64,
    onset: f64,
    e: f64,
}

impl Contact<'_> {
    /// The time and length scales `(T, L)` of a contact closing at `u` and its course,
    /// for the parameters `(q, eps)` that `params` gives for `T`, if the table holds it
    /// and the kink comes before `e`.
    fn course(
        &self,
        tb: &ContactTable,
        u: f64,
        params: impl Fn(f64) -> (f64, f64),
    ) -> Option<(f64, f64, Course)> {
        if tb.alpha() != self.law.damping || u.is_nan() || u <= 0.0 {
            return None;
        }
        let time = (self.mass / (self.k * u.sqrt())).powf(0.4);
        let (q, eps) = params(time);
        let c = tb.course(q, eps)?;
        (self.onset + time * c.tau_kink < self.e).then_some((time, u * time, c))
    }

    /// Walks course `c` (time scale `time`): the states that `state` makes of its samples
    /// go to `each`, in order, but the last (the kink), whose time and state it returns.
    fn walk(
        &self,
        time: f64,
        c: &Course,
        state: impl Fn(f64, [f64; 3]) -> (Vec3, Vec3),
        each: &mut dyn FnMut(f64, Vec3, Vec3),
    ) -> (f64, Vec3, Vec3) {
        let at = |j: usize| {
            let fraction = (j + 1) as f64 / SAMPLES as f64; // 1 exactly at the kink
            let t = self.onset + time * c.tau_kink * fraction;
            let (x, v) = state(t, c.at[j]);
            (t, x, v)
        };
        for j in 0..SAMPLES - 1 {
            let (t, x, v) = at(j);
            each(t, x, v);
        }
        at(SAMPLES - 1)
    }

    /// A pair touching at distance `sigma` with relative position `r_on` and velocity
    /// `v0`: the relative states at the samples go to `each`; returns the kink's time
    /// and relative state. In the plane of `r_on` and `v0` the normal turns by
    /// `(w / u) eps Phi` while `|r| = sigma (1 - eps xi)` (module docs of the table).
    fn pair(
        &self,
        tb: &ContactTable,
        sigma: f64,
        r_on: &Vec3,
        v0: &Vec3,
        each: &mut dyn FnMut(f64, Vec3, Vec3),
    ) -> Option<(f64, Vec3, Vec3)> {
        let n0 = r_on.normalize();
        let u = -v0.dot(&n0);
        let vt = v0 + n0 * u;
        let w = vt.norm();
        let t_hat = if w > 0.0 { vt / w } else { Vec3::zeros() };
        let p = w / u;
        let (time, len, c) = self.course(tb, u, |time| {
            let eps = u * time / sigma;
            (p * p * eps, eps)
        })?;
        let eps = len / sigma;
        let rel = |[xi, rate, phi]: [f64; 3]| {
            let shrink = 1.0 - eps * xi;
            let (s, co) = (p * eps * phi).sin_cos();
            let (er, et) = (n0 * co + t_hat * s, t_hat * co - n0 * s);
            (er * (sigma * shrink), er * (-u * rate) + et * (w / shrink))
        };
        Some(self.walk(time, &c, |_, x| rel(x), each))
    }

    /// A shot of radius `r` touching the specimen at `(p, v)` under gravity `g`: its
    /// states at the samples go to `each`; returns the kink's time and state (free along
    /// the plane; `z = r - L xi`).
    fn specimen(
        &self,
        tb: &ContactTable,
        r: f64,
        g: f64,
        (p, v): (Vec3, Vec3),
        each: &mut dyn FnMut(f64, Vec3, Vec3),
    ) -> Option<(f64, Vec3, Vec3)> {
        let u = -v.z;
        let (time, len, c) = self.course(tb, u, |time| (-g * time / u, 0.0))?;
        let at = |t: f64, [xi, rate, _]: [f64; 3]| {
            let dt = t - self.onset;
            (
                Vec3::new(p.x + v.x * dt, p.y + v.y * dt, r - len * xi),
                Vec3::new(v.x, v.y, -u * rate),
            )
        };
        Some(self.walk(time, &c, at, each))
    }
}

/// Resolves the contact of shot `a` (state at `s`) with the specimen (the plane `z = 0`,
/// `law`) over the chunk `[s, e]`, as [`resolve`] does for a pair: from the touch
/// (`progress` `None`) or from `s`, until the shot leaves the plane or until `e`.
#[allow(clippy::too_many_arguments)]
pub fn resolve_specimen(
    sp: &SpecimenContact,
    table: Option<&ContactTable>,
    mu: f64,
    flight: &Flight,
    a: &Body,
    progress: Option<InProgress>,
    s: f64,
    e: f64,
    apart_after: f64,
    set: Settings,
) -> Option<Outcome> {
    let r = a.radius;
    let m = a.mass;
    let k = sp.law.stiffness(r);
    let (onset, tc, from, (p_from, v_from)) = match progress {
        None => {
            if a.pos.z <= r {
                return None;
            }
            let tau = flight.down_through(a.pos.z, a.vel.z, r)?;
            if s + tau >= e {
                return None;
            }
            let (mut p, v) = flight.at(&a.pos, &a.vel, tau);
            p.z = r; // on the plane, to rounding
            let tc = hertz::contact_time(m, k, (-v.z).max(MIN_CONTACT_SPEED));
            (s + tau, tc, s + tau, (p, v))
        }
        Some(pr) => (pr.onset, pr.contact_time, s, (a.pos, a.vel)),
    };
    // The contact's law: with a restitution curve, the damping of its touch.
    let law = &match (&sp.by_speed, progress) {
        (None, _) => sp.law,
        (Some(by_speed), None) => sp.law.with_damping(by_speed.damping(-v_from.z)),
        (Some(_), Some(pr)) => sp.law.with_damping(pr.damping),
    };
    let h_cap = tc / set.contact_steps;
    let mut out = Outcome {
        n: 1,
        onset,
        damping: law.damping,
        fresh: progress.is_none(),
        at_onset: (p_from, v_from),
        contact_time: tc,
        from,
        ..Outcome::with_room(1)
    };
    out.sample(from, &[(p_from, v_from)]);
    let g = flight.g;
    if let (Some(tb), None, true) = (table, progress, mu == 0.0) {
        let mut each = |t: f64, p: Vec3, v: Vec3| out.sample(t, &[(p, v)]);
        let shape = Contact {
            law,
            k,
            mass: m,
            onset,
            e,
        };
        if let Some((t, p, v)) = shape.specimen(tb, r, g, (p_from, v_from), &mut each) {
            out.omega = [a.omega, a.omega];
            out.end_phase(t, [(p, v); 2], false, e);
            return release_specimen(out, flight, t, p, v, r, h_cap, apart_after, e);
        }
    }
    // With friction (`mu > 0`) the state carries the spin (values 6..9); the tangential
    // force acts at the lowest point, as in the island integrator.
    let inertia = INERTIA_FACTOR * m * r * r;
    let m_t = friction::sphere_on_wall_mass(m);
    // The contact point, below the centre, and its slip in state `y`.
    let r_c = Vec3::new(0.0, 0.0, -r);
    let slip_at = |y: &[f64]| {
        friction::tangential_part(&(vec_at(y, 3) + vec_at(y, 6).cross(&r_c)), &Vec3::z())
    };
    let rhs = |y: &[f64], dy: &mut [f64]| {
        dy[..3].copy_from_slice(&y[3..6]);
        let overlap = r - y[2];
        let f = if overlap > 0.0 {
            law.force(k, m, overlap, -y[5])
        } else {
            0.0
        };
        let mut acc = Vec3::new(0.0, 0.0, f / m - g);
        let mut alpha = Vec3::zeros();
        if y.len() > 6 && overlap > 0.0 {
            let slip = slip_at(y);
            let gamma = friction::stick_damping(m_t, k, overlap);
            let ft = friction::tangential_force(mu, f, &slip, gamma);
            acc += ft / m;
            alpha = r_c.cross(&ft) / inertia;
        }
        dy[3..6].copy_from_slice(acc.as_slice());
        if y.len() > 6 {
            dy[6..9].copy_from_slice(alpha.as_slice());
        }
    };
    let margin = |y: &[f64]| law.unloading_margin(k, m, r - y[2], -y[5]);
    let overlap = |y: &[f64]| r - y[2];
    let v_impact = hertz::impact_speed(m, k, tc);
    let terms = law.onset_terms(k, m, v_impact);
    let correct = |at: f64, h: f64, y0: &[f64], y1: &mut [f64]| {
        let (dx, dv) = hertz::start_correction(terms, at, h);
        y1[2] += dx / m;
        y1[5] += dv / m;
        if y0.len() > 6 {
            // The tangential force's start along the slip at the step's start.
            let slip = slip_at(y0);
            let sn = slip.norm();
            let d_t = friction::onset_terms(mu, terms, m_t, k, v_impact, sn);
            if sn > 0.0 && d_t.0 + d_t.1 > 0.0 {
                let dir = slip / sn;
                let (dx, dv) = hertz::start_correction(d_t, at, h);
                add_at(y1, 0, &(dir * (-dx / m)));
                add_at(y1, 3, &(dir * (-dv / m)));
                add_at(y1, 6, &(r_c.cross(&(dir * -dv)) / inertia));
            }
        }
    };
    let phase = Phase {
        rhs: &rhs,
        margin: &margin,
        overlap: &overlap,
        depth_limit: 0.5 * r,
        r_min: r,
        spin_radii: if mu > 0.0 { &[r] } else { &[] },
        set,
        tc,
        onset,
        correct: Some(&correct),
    };
    let w = a.omega;
    let mut y = [
        p_from.x, p_from.y, p_from.z, v_from.x, v_from.y, v_from.z, w.x, w.y, w.z,
    ];
    let mut t = from;
    let at_touch = p_from.z >= r && v_from.z < 0.0;
    let mut sample = |out: &mut Outcome, t: f64, y: &[f64]| out.sample(t, &[vecs(y)]);
    let pushes = progress.is_none() || at_touch;
    let pushing = if mu > 0.0 {
        phase.run(&mut y, &mut t, e, pushes, &mut out, &mut sample)?
    } else {
        let mut y6 = [y[0], y[1], y[2], y[3], y[4], y[5]];
        let p = phase.run(&mut y6, &mut t, e, pushes, &mut out, &mut sample)?;
        y[..6].copy_from_slice(&y6);
        p
    };
    let spin = vec_at(&y, 6);
    out.omega = [spin, spin];
    out.spins = mu > 0.0;
    let (p, v) = vecs(&y);
    if !out.end_phase(t, [(p, v); 2], pushing, e) {
        return Some(out);
    }
    release_specimen(out, flight, t, p, v, r, h_cap, apart_after, e)
}

/// The release of a shot of radius `r` from the specimen after its kink at `t` (state
/// `p`, `v`): free flight until the centre climbs back to one radius.
#[allow(clippy::too_many_arguments)]
fn release_specimen(
    mut out: Outcome,
    flight: &Flight,
    t: f64,
    p: Vec3,
    v: Vec3,
    r: f64,
    h_cap: f64,
    apart_after: f64,
    e: f64,
) -> Option<Outcome> {
    let part = if p.z >= r {
        0.0
    } else {
        flight.up_through(p.z, v.z, r)?
    };
    let end = (t + part + 1e-3 * h_cap).max(apart_after);
    out.end = end.min(e);
    let (p_end, v_end) = flight.at(&p, &v, out.end - t);
    out.touching = p_end.z < r;
    out.state = [(p_end, v_end); 2];
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::hertz::HertzLaw;

    fn law(e: f64) -> HertzLaw {
        HertzLaw::new(210e9, 0.3, 210e9, 0.3, e)
    }

    /// The flat specimen of `law`, one restitution at every speed.
    fn flat(law: HertzLaw) -> SpecimenContact {
        SpecimenContact {
            law,
            by_speed: None,
            shape: crate::contact::specimen::SpecimenShape::Plane,
        }
    }

    fn shot(pos: Vec3, vel: Vec3) -> Body {
        Body {
            pos,
            vel,
            omega: Vec3::zeros(),
            mass: 7850.0 * std::f64::consts::PI / 6.0 * 0.8e-3f64.powi(3),
            radius: 0.4e-3,
        }
    }

    fn run(l: &HertzLaw, a: &Body, b: &Body, g: f64, tol: f64) -> Outcome {
        resolve(
            l,
            None,
            0.0,
            &Flight { g },
            a,
            b,
            None,
            0.0,
            1e-4,
            0.0,
            Settings {
                tolerance: tol,
                contact_steps: 10.0,
            },
        )
        .expect("a clean binary contact")
    }

    /// A neighbour known to fly free is checked against the actual paths exactly; one
    /// known only at a moment is kept at the distance it could cover at the speed bound
    /// (before that moment with `bounded_before`, after its free flight ends).
    #[test]
    fn neighbours_are_clear_only_beyond_what_they_can_reach() {
        let l = law(0.9);
        let a = shot(Vec3::new(0.0, 0.0, 5e-3), Vec3::new(0.0, 0.0, 49.0));
        let b = shot(Vec3::new(0.0, 0.0, 6e-3), Vec3::new(0.0, 0.0, -70.0));
        let flight = Flight { g: 9.81 };
        let o = run(&l, &a, &b, 9.81, 1e-8);
        let span = o.end;
        // 0.9 mm beside the meeting point (contact distance 0.8 mm).
        let beside = |until: f64, before: bool, speed: f64| Neighbour {
            clock: 0.5 * o.onset,
            pos: Vec3::new(0.9e-3, 0.0, 5e-3 + 49.0 * o.onset),
            vel: Vec3::new(0.0, 0.0, -9.81 * 0.5 * o.onset),
            until,
            bounded_before: before,
            speed,
            sigma: 0.8e-3,
        };
        let clear = |nb: &Neighbour| {
            (0..2).all(|q| {
                let start = if q == 0 {
                    (a.pos, a.vel)
                } else {
                    (b.pos, b.vel)
                };
                o.clear_of(q, &flight, 0.0, start, nb)
            })
        };
        assert!(clear(&beside(f64::INFINITY, false, 1e3)));
        // Known until the touch only: 150 m/s over the rest of the contact reaches the
        // pair, 20 m/s does not.
        let reach = |v: f64| v * (span - o.onset);
        assert!(reach(150.0) > 0.1e-3 && reach(20.0) < 0.1e-3);
        assert!(!clear(&beside(o.onset, false, 150.0)));
        assert!(clear(&beside(o.onset, false, 20.0)));
        // Known from the middle of the approach on only, checked before it too.
        assert!(!clear(&beside(f64::INFINITY, true, 1e3)));
        assert!(clear(&beside(f64::INFINITY, true, 1.0)));
        // Closer than contact distance on its free path: not clear whatever the bound.
        let mut close = beside(f64::INFINITY, false, 0.0);
        close.pos.x = 0.79e-3;
        assert!(!clear(&close));
    }

    /// Head-on: the relative speed comes back times the restitution, momentum is kept,
    /// the shots part, and the contact lasts about the Hertz time.
    #[test]
    fn head_on_returns_the_restitution() {
        let l = law(0.9);
        let a = shot(Vec3::new(0.0, 0.0, 5e-3), Vec3::new(0.0, 0.0, 49.0));
        let b = shot(Vec3::new(0.0, 0.0, 6e-3), Vec3::new(0.0, 0.0, -70.0));
        let o = run(&l, &a, &b, 9.81, 1e-8);
        let [(pa, va), (pb, vb)] = o.state;
        let e = (vb.z - va.z) / 119.0;
        assert!((e - 0.9).abs() < 1e-6, "restitution {e}");
        let p0 = a.vel + b.vel;
        let g = 9.81 * o.end;
        assert!((va + vb - p0 + Vec3::new(0.0, 0.0, 2.0 * g)).norm() < 1e-9);
        assert!((pb - pa).norm() > 0.8e-3);
        // Touch at the closed-form time; the contact lasts between 0.9 and 1.1 Hertz
        // times (the damping shortens it a little).
        assert!((o.onset - 0.2e-3 / 119.0).abs() < 1e-15);
        let lasted = o.end - o.onset;
        assert!(lasted > 0.8 * o.contact_time && lasted < 1.1 * o.contact_time);
    }

    /// Oblique: the tangential relative velocity is unchanged by a frictionless contact
    /// only in the frame of the final normal; the check here is the kinetic energy of
    /// the relative motion, which the dashpot can only take away, and the angular
    /// momentum of the pair about its centre of mass, which a central force keeps.
    #[test]
    fn oblique_keeps_angular_momentum_and_loses_energy() {
        let l = law(0.9);
        let a = shot(Vec3::new(0.0, 0.0, 5e-3), Vec3::new(0.0, 0.0, 49.0));
        let b = shot(Vec3::new(0.4e-3, 0.0, 6e-3), Vec3::new(0.0, 0.0, -70.0));
        let o = run(&l, &a, &b, 0.0, 1e-8);
        let [(pa, va), (pb, vb)] = o.state;
        let (r0, v0) = (b.pos - a.pos, b.vel - a.vel);
        let (r1, v1) = (pb - pa, vb - va);
        let l0 = r0.cross(&v0);
        let l1 = r1.cross(&v1);
        assert!((l1 - l0).norm() < 1e-9 * l0.norm(), "{l0} {l1}");
        assert!(v1.norm() < v0.norm());
        assert!(v1.norm() > 0.9 * v0.norm());
    }

    /// The tabulated course of a frictionless pair against the integrator at a tight
    /// tolerance, from head-on to grazing and from 2 to 150 m/s: velocities after the
    /// contact within 1e-7 of the impact speed, positions within 1e-7 of a radius, the
    /// hand-back time within 1e-5 of the contact time; the samples lie on the path.
    #[test]
    fn tabulated_pairs_match_the_integrator() {
        let l = law(0.9);
        let tb = ContactTable::new(l.damping);
        let set = Settings {
            tolerance: 1e-11,
            contact_steps: 10.0,
        };
        let flight = Flight { g: 9.81 };
        let mut tabulated = 0;
        for speed in [2.0, 70.0, 150.0] {
            for offset in [0.0, 0.3, 0.7, 0.95, 0.999] {
                let a = shot(
                    Vec3::new(0.0, 0.0, 5e-3),
                    Vec3::new(0.0, -0.01, 0.4 * speed),
                );
                let b = shot(
                    Vec3::new(0.8e-3 * offset, 0.0, 6e-3),
                    Vec3::new(0.0, 0.01, -0.6 * speed),
                );
                let go =
                    |table| resolve(&l, table, 0.0, &flight, &a, &b, None, 0.0, 1e-2, 0.0, set);
                let (t, i) = (go(Some(&tb)).unwrap(), go(None).unwrap());
                if t.steps > 0 {
                    continue; // off the table (a grazing contact): integrated
                }
                tabulated += 1;
                assert_eq!(t.samples.len(), 2 * (SAMPLES + 1));
                for q in 0..2 {
                    let (dp, dv) = (t.state[q].0 - i.state[q].0, t.state[q].1 - i.state[q].1);
                    assert!(dv.norm() < 1e-7 * speed, "{speed} {offset}: dv {dv}");
                    assert!(
                        dp.norm() < 1e-7 * 0.4e-3,
                        "{speed} {offset}: dp {}",
                        dp.norm()
                    );
                }
                assert!((t.end - i.end).abs() < 1e-5 * t.contact_time);
                // Every sample of the table's course is on the integrated path: within
                // the chord error bound of the integrator's dense samples.
                let r = |o: &Outcome, k: usize| o.samples[2 * k + 1].0 - o.samples[2 * k].0;
                for k in 1..=SAMPLES {
                    let tk = t.times[k];
                    let j = i
                        .times
                        .partition_point(|&x| x <= tk)
                        .clamp(1, i.times.len() - 1);
                    let f = (tk - i.times[j - 1]) / (i.times[j] - i.times[j - 1]);
                    let near = r(&i, j - 1) * (1.0 - f) + r(&i, j) * f;
                    assert!(
                        (r(&t, k) - near).norm() < 2e-3 * 0.8e-3,
                        "{speed} {offset}: sample {k} off the path"
                    );
                }
            }
        }
        assert!(tabulated >= 12, "only {tabulated} contacts on the table");
    }

    /// The same for a shot on the specimen under gravity, head-on and oblique.
    #[test]
    fn tabulated_specimen_impacts_match_the_integrator() {
        let l = law(0.7);
        let sp = flat(l);
        let tb = ContactTable::new(l.damping);
        let set = Settings {
            tolerance: 1e-11,
            contact_steps: 10.0,
        };
        let flight = Flight { g: 9.81 };
        for speed in [0.5, 20.0, 100.0] {
            for slant in [0.0, 1.0, 5.0] {
                let a = shot(
                    Vec3::new(1e-3, 0.0, 1e-3),
                    Vec3::new(slant * speed, 0.0, -speed),
                );
                let go = |table| {
                    resolve_specimen(&sp, table, 0.0, &flight, &a, None, 0.0, 1.0, 0.0, set)
                };
                let (t, i) = (go(Some(&tb)).unwrap(), go(None).unwrap());
                assert_eq!(t.steps, 0, "{speed} {slant}: not tabulated");
                let (dp, dv) = (t.state[0].0 - i.state[0].0, t.state[0].1 - i.state[0].1);
                assert!(dv.norm() < 1e-7 * speed, "{speed} {slant}: dv {dv}");
                assert!(dp.norm() < 1e-8 * 0.4e-3, "{speed} {slant}: dp {dp}");
                assert!((t.end - i.end).abs() < 1e-5 * t.contact_time);
                assert_eq!(t.at_onset, i.at_onset);
            }
        }
    }

    /// A shot dropped on the specimen: the impact is recorded where the centre is one
    /// radius up (closed form), the rebound speed is the restitution's, the contact lasts
    /// about the Hertz time, and the shot is handed back clear of the plane.
    #[test]
    fn specimen_impact_returns_the_restitution() {
        let l = law(0.7);
        let a = shot(Vec3::new(1e-3, 0.0, 1e-3), Vec3::new(3.0, 0.0, -70.0));
        let set = Settings {
            tolerance: 1e-8,
            contact_steps: 10.0,
        };
        let sp = flat(l);
        let until = |e: f64| {
            resolve_specimen(
                &sp,
                None,
                0.0,
                &Flight { g: 0.0 },
                &a,
                None,
                0.0,
                e,
                0.0,
                set,
            )
        };
        let o = until(1e-4).expect("a clean impact");
        let touch = 0.6e-3 / 70.0;
        assert!((o.onset - touch).abs() < 1e-15);
        assert!((o.at_onset.0.z - 0.4e-3).abs() < 1e-15);
        assert!((o.at_onset.0.x - (1e-3 + 3.0 * touch)).abs() < 1e-15);
        let (p, v) = o.state[0];
        assert!(
            (v.z / 70.0 - 0.7).abs() < 1e-6,
            "restitution {}",
            v.z / 70.0
        );
        assert_eq!(v.x, 3.0);
        assert!(p.z > 0.4e-3 && !o.touching);
        let lasted = o.end - o.onset;
        assert!(lasted > 0.8 * o.contact_time && lasted < 1.1 * o.contact_time);
        // In two chunks (cut inside the contact, continued from the state handed back)
        // it ends where one chunk does, to the tolerance.
        let cut = o.onset + 0.4 * o.contact_time;
        let first = until(cut).expect("the first half");
        assert!(first.touching && first.end == cut);
        let b = Body {
            pos: first.state[0].0,
            vel: first.state[0].1,
            ..a
        };
        let progress = InProgress {
            onset: first.onset,
            contact_time: first.contact_time,
            damping: first.damping,
        };
        let second = resolve_specimen(
            &sp,
            None,
            0.0,
            &Flight { g: 0.0 },
            &b,
            Some(progress),
            cut,
            1e-4,
            0.0,
            set,
        )
        .expect("the second half");
        assert!(!second.fresh && !second.touching);
        assert!((second.state[0].1.z - v.z).abs() < 1e-6 * 70.0);
        assert!((second.end - o.end).abs() < 1e-3 * o.contact_time);
    }

    /// A contact handed on at its touch, its shots a hair apart by rounding and closing,
    /// still has all of its loading ahead: it rebounds with the restitution (it was once
    /// released at once, closing, and handed back overlapping), for a pair and for the
    /// specimen.
    #[test]
    fn a_contact_continued_at_its_touch_still_loads() {
        let set = Settings {
            tolerance: 1e-8,
            contact_steps: 10.0,
        };
        let flight = Flight { g: 9.81 };
        let progress = InProgress {
            onset: 0.0,
            contact_time: 1e-6,
            damping: law(0.7).damping,
        };
        let hair = 1e-12;
        let a = shot(Vec3::new(0.0, 0.0, 5e-3), Vec3::new(0.0, 0.0, 49.0));
        let b = shot(
            Vec3::new(0.0, 0.0, 5e-3 + 0.8e-3 + hair),
            Vec3::new(0.0, 0.0, -70.0),
        );
        let o = resolve(
            &law(0.9),
            None,
            0.0,
            &flight,
            &a,
            &b,
            Some(progress),
            0.0,
            1e-4,
            0.0,
            set,
        )
        .expect("a contact in progress");
        let [(pa, va), (pb, vb)] = o.state;
        assert!(!o.touching && (pb - pa).norm() > 0.8e-3);
        assert!(
            ((vb.z - va.z) / 119.0 - 0.9).abs() < 1e-5,
            "{}",
            (vb.z - va.z) / 119.0
        );
        let c = shot(
            Vec3::new(0.0, 0.0, 0.4e-3 + hair),
            Vec3::new(0.0, 0.0, -70.0),
        );
        let o = resolve_specimen(
            &flat(law(0.7)),
            None,
            0.0,
            &flight,
            &c,
            Some(progress),
            0.0,
            1e-4,
            0.0,
            set,
        )
        .expect("a contact in progress");
        let (p, v) = o.state[0];
        assert!(!o.touching && p.z > 0.4e-3);
        assert!((v.z / 70.0 - 0.7).abs() < 1e-5, "{}", v.z / 70.0);
    }

    /// A contact that does not end inside the chunk is handed back still touching.
    #[test]
    fn contact_past_the_chunk_continues() {
        let l = law(0.9);
        let a = shot(Vec3::new(0.0, 0.0, 5e-3), Vec3::new(0.0, 0.0, 49.0));
        let b = shot(Vec3::new(0.0, 0.0, 6e-3), Vec3::new(0.0, 0.0, -70.0));
        let set = Settings {
            tolerance: 1e-6,
            contact_steps: 10.0,
        };
        let touch = 0.2e-3 / 119.0;
        let flight = Flight { g: 0.0 };
        let until = |e: f64| resolve(&l, None, 0.0, &flight, &a, &b, None, 0.0, e, 0.0, set);
        assert!(until(touch + 1e-7).is_some_and(|o| o.touching));
        assert!(until(touch + 1e-5).is_some_and(|o| !o.touching));
    }
}
