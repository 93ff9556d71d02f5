//! Simulation: owns the shots and runs the pipeline, top to bottom, window by window.
//!
//! ```text
//! scene -> feed (initial shots) -> physics (flow field, force set, contact set)
//! loop over synchronisation windows [t, t + H]:
//!   broad phase: shots that may touch within H (cell list, reach-inflated radii)
//!   islands: connected groups of such shots (union-find); singletons fly alone
//!   integrate: every island on its own clock, in parallel (integrate::island)
//!   verify: no overlap between shots that were not paired (else merge and redo)
//!   commit: states, contact states, impacts, events, work counters
//! ```
//! Without shot-shot contact there is a single window: every shot flies alone from its
//! entry to the end, with no neighbour search at all. Islands are formed and their
//! outputs merged in shot-id order, so results do not depend on the thread count.

use crate::Vec3;
use crate::contact::broad::CellList;
use crate::contact::friction::{self, Tangential};
use crate::contact::restitution::SpeedLaw;
use crate::contact::{ContactSet, Friction, HertzLaw, PairContact, SpecimenContact, WallContact};
use crate::counters::WorkCounters;
use crate::export::vtk::SnapshotPoint;
use crate::flow::JetField;
use crate::forces::{DragModel, ForceSet, GravityModel, LateralForceModel, Turbulence};
use crate::integrate::island::{self, IslandOutput, IslandPair, Method, Physics, Scratch};
use crate::record::{Impact, RunEvent};
use crate::scene::{Effects, Scene, SceneError};
use crate::state::{ShotState, ShotStatus};
use rayon::prelude::*;
use rustc_hash::FxHashMap as HashMap;

mod sleep;
use sleep::{Sleeper, Sleepers};

/// Longest synchronisation window, s.
const MAX_WINDOW: f64 = 1e-4;
/// Shortest synchronisation window, s.
const MIN_WINDOW: f64 = 1e-8;
/// Window length of the fixed-step method, in diameters of travel at the fastest speed.
const VERLET_WINDOW: f64 = 0.125;
/// Largest island the window length tries to keep (see `Simulation::window`).
pub(crate) const MAX_ISLAND: usize = 32;
/// The windows' neighbour search widens each ball by this many of its shot's diameters
/// when the window has the same shots as the one before, and the windows after it reuse
/// what it found while every shot stays inside its widened ball
/// ([`CellList::pairs_tracked`]; the same pairs as a search of its own).
const BROAD_SKIN: f64 = 0.05;

/// How a run schedules its shots.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scheduler {
    /// Events when the scene allows them (ballistic free flight, no snapshots), else
    /// windows.
    #[default]
    Auto,
    /// Synchronisation windows with islands (any scene; parallel across islands).
    Windows,
    /// The event scheduler (`crate::events`): free flight in closed form, contacts
    /// resolved one cluster at a time. Scenes without air forces and nozzle wall only.
    Events,
}

impl Scheduler {
    /// The name used in scene files and summaries.
    pub fn name(self) -> &'static str {
        match self {
            Scheduler::Auto => "auto",
            Scheduler::Windows => "windows",
            Scheduler::Events => "events",
        }
    }
}

/// Builds the stages a scene calls for, and nothing else.
pub fn build_physics(scene: &Scene, effects: &Effects) -> Physics {
    let drag_law = DragModel {
        coefficient: scene.jet.drag_coefficient,
    };
    let field = (effects.drag || effects.lateral_force).then(|| JetField {
        exit: scene.nozzle.exit(),
        axis: scene.nozzle.axis(),
        bore: scene.nozzle.bore,
        length: scene.nozzle.length,
        exit_velocity: scene.air.exit_velocity,
        rho_core: scene.core_density(),
        rho_exit: scene.air.rho_exit,
        rho_ambient: scene.air.rho_ambient,
        lip_density_cap: scene.jet.lip_density_cap,
        model: scene.jet.model,
        layer: scene.jet.stagnation_layer,
        wall_jet: scene.jet.wall_jet,
        layer_surface: scene.specimen_shape.clone(),
    });
    let forces = ForceSet {
        drag: effects.drag.then_some(drag_law),
        lateral: effects.lateral_force.then_some(LateralForceModel {
            lift_coefficient: scene.jet.lift_coefficient,
            divergence_tan: scene.jet.divergence_tan,
            bore: scene.nozzle.bore,
            drag: drag_law,
        }),
        gravity: effects.gravity.then_some(GravityModel {
            acceleration: Vec3::new(0.0, 0.0, -scene.gravity),
        }),
        field,
        turbulence: (effects.turbulent_dispersion && effects.drag).then_some(Turbulence {
            intensity: scene.jet.turbulence_intensity,
            scale: 0.4,
            bore: scene.nozzle.bore,
            seed: scene.seed,
        }),
    };
    let shot = &scene.shot_material;
    let law = |other: &crate::scene::Material, e: f64| {
        HertzLaw::new(
            shot.youngs_modulus,
            shot.poisson_ratio,
            other.youngs_modulus,
            other.poisson_ratio,
            e,
        )
    };
    let contacts = ContactSet {
        specimen: effects.specimen_contact.then(|| SpecimenContact {
            law: law(&scene.specimen_material, scene.restitution.shot_specimen),
            by_speed: scene
                .restitution
                .shot_specimen_curve
                .clone()
                .map(|c| std::sync::Arc::new(SpeedLaw::new(c))),
            shape: scene.specimen_shape.clone(),
        }),
        wall: effects.nozzle_wall_contact.then(|| WallContact {
            law: law(&scene.nozzle_material, scene.restitution.shot_nozzle),
            tube: scene.nozzle.tube(),
        }),
        pair: effects.shot_shot_contact.then(|| PairContact {
            law: law(shot, scene.restitution.shot_shot),
        }),
        friction: effects.friction.then_some(Friction {
            specimen: scene.friction.shot_specimen,
            shot: scene.friction.shot_shot,
            wall: scene.friction.shot_nozzle,
            law: if scene.friction.history {
                let g = |other: &crate::scene::Material| {
                    friction::shear_ratio(
                        shot.youngs_modulus,
                        shot.poisson_ratio,
                        other.youngs_modulus,
                        other.poisson_ratio,
                    )
                };
                Tangential::History {
                    specimen: g(&scene.specimen_material),
                    shot: g(shot),
                    wall: g(&scene.nozzle_material),
                }
            } else {
                Tangential::Viscous
            },
        }),
    };
    Physics {
        forces,
        contacts,
        tolerance: scene.integrator.tolerance,
        contact_steps: scene.integrator.contact_steps,
        domain: scene.domain,
        max_step: scene.integrator.max_step,
        method: scene.integrator.method,
        // Sliding moves a shot in the specimen's plane: on a curved specimen shots step
        // through their contacts.
        sliding: scene.specimen_shape.is_plane(),
        blocks_min: island::BLOCKS_MIN,
        free_steps: true,
    }
}

/// Records shot positions at multiples of a snapshot interval, interpolating between
/// accepted steps with cubic Hermite polynomials (positions and velocities at both ends).
struct SnapshotTap {
    interval: f64,
    t_prev: f64,
    y_prev: Vec<f64>,
    members: Vec<(u32, f64, f64)>,
    points: Vec<(u64, SnapshotPoint)>,
}

impl SnapshotTap {
    fn new(interval: f64, t0: f64, members: &[ShotState], spin: bool) -> Self {
        let mut y_prev = Vec::with_capacity(6 * members.len());
        island::load_state(members, &mut y_prev, spin);
        SnapshotTap {
            interval,
            t_prev: t0,
            y_prev,
            members: members
                .iter()
                .map(|m| (m.id.0, 2.0 * m.body.radius, m.t_start))
                .collect(),
            points: Vec::new(),
        }
    }

    fn on_step(&mut self, t: f64, y: &[f64]) {
        let h = t - self.t_prev;
        if h <= 0.0 {
            return;
        }
        let k0 = (self.t_prev / self.interval).floor() as u64 + 1;
        let k1 = (t / self.interval).floor() as u64;
        for k in k0..=k1 {
            let tk = k as f64 * self.interval;
            let s = (tk - self.t_prev) / h;
            let (h00, h10, h01, h11) = (
                2.0 * s * s * s - 3.0 * s * s + 1.0,
                s * s * s - 2.0 * s * s + s,
                -2.0 * s * s * s + 3.0 * s * s,
                s * s * s - s * s,
            );
            for (i, &(id, diameter, t_start)) in self.members.iter().enumerate() {
                if tk < t_start {
                    continue;
                }
                let (a, b) = (&self.y_prev[6 * i..6 * i + 6], &y[6 * i..6 * i + 6]);
                let position = std::array::from_fn(|c| {
                    h00 * a[c] + h10 * h * a[3 + c] + h01 * b[c] + h11 * h * b[3 + c]
                });
                let velocity = std::array::from_fn(|c| (1.0 - s) * a[3 + c] + s * b[3 + c]);
                self.points.push((
                    k,
                    SnapshotPoint {
                        shot: id,
                        position,
                        velocity,
                        diameter,
                    },
                ));
            }
        }
        self.t_prev = t;
        self.y_prev.clear();
        self.y_prev.extend_from_slice(y);
    }
}

/// Advances an island over a window, recording snapshots when asked. A lone shot (one
/// member, no pair) takes its own steps across windows (`island::advance_alone`).
#[allow(clippy::too_many_arguments)]
fn advance_island(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &mut [IslandPair],
    t0: f64,
    t1: f64,
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    snapshot_interval: Option<f64>,
    apart: bool,
) -> Vec<(u64, SnapshotPoint)> {
    let mut tap = snapshot_interval
        .map(|dt| SnapshotTap::new(dt, t0, members, phys.contacts.friction.is_some()));
    let mut observe = |t: f64, y: &[f64]| {
        if let Some(tap) = tap.as_mut() {
            tap.on_step(t, y);
        }
    };
    if let ([m], []) = (&mut *members, &*pairs) {
        island::advance_alone(phys, m, t0, t1, scratch, out, &mut observe);
    } else if apart
        && let Some(points) = advance_apart(
            phys,
            members,
            pairs,
            (t0, t1),
            scratch,
            out,
            snapshot_interval,
        )
    {
        return points;
    } else {
        island::advance_observed(phys, members, pairs, t0, t1, scratch, out, &mut observe);
    }
    tap.map_or_else(Vec::new, |t| t.points)
}

/// One shot's path over a window: `(t, position, velocity)` after each step.
type Path = Vec<(f64, Vec3, Vec3)>;

/// Advances the members of an island on separate clocks, each as a lone shot
/// (`island::advance_alone`: its own steps, kept across window ends), if no pair of them
/// touches at `t0` and none comes into contact in the window: their paths (the steps'
/// ends, chords in between widened by their error bound) are checked pair by pair
/// afterwards. Shots that keep apart exert no force on one another, so each one's
/// motion is what the island integrator would give it, to its own tolerance, for the
/// steps its own accuracy needs instead of the island's smallest. Returns `None`, with
/// the members as they were, if a pair touches or overlaps at `t0`, comes within
/// contact, or a member is still to enter (entries are held against the members they
/// would overlap); the caller then integrates the island as one. The steps of an
/// attempt that failed are counted in `out.work`.
#[allow(clippy::too_many_arguments)]
fn advance_apart(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &[IslandPair],
    (t0, t1): (f64, f64),
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    snapshot_interval: Option<f64>,
) -> Option<Vec<(u64, SnapshotPoint)>> {
    // Members that overlap at `t0` without a contact on record yet (a bed's shots at
    // the start) are in contact: not worth an attempt.
    let overlap = |p: &IslandPair| {
        let (a, b) = (&members[p.a as usize], &members[p.b as usize]);
        a.is_active() && b.is_active() && (a.pos - b.pos).norm() < a.body.radius + b.body.radius
    };
    if !phys.method.adaptive_flight()
        || pairs.iter().any(|p| p.touching || overlap(p))
        || members
            .iter()
            .any(|m| m.is_active() && m.t_start >= t0 && m.t_start > 0.0)
    {
        return None;
    }
    let saved: Vec<ShotState> = members.to_vec();
    let spin = phys.contacts.friction.is_some();
    let mut trial = IslandOutput::default();
    let mut points = Vec::new();
    let mut paths: Vec<Path> = Vec::with_capacity(members.len());
    for m in members.iter_mut() {
        // Room for a few steps: the path grows in the step loop.
        let mut path: Path = Vec::with_capacity(8);
        path.push((t0, m.pos, m.vel));
        if m.is_active() {
            let mut tap =
                snapshot_interval.map(|dt| SnapshotTap::new(dt, t0, std::slice::from_ref(m), spin));
            let mut observe = |t: f64, y: &[f64]| {
                path.push((t, Vec3::new(y[0], y[1], y[2]), Vec3::new(y[3], y[4], y[5])));
                if let Some(tap) = tap.as_mut() {
                    tap.on_step(t, y);
                }
            };
            island::advance_alone(phys, m, t0, t1, scratch, &mut trial, &mut observe);
            if let Some(tap) = tap {
                points.extend(tap.points);
            }
        }
        paths.push(path);
    }
    let met = pairs.iter().any(|p| {
        let (a, b) = (p.a as usize, p.b as usize);
        saved[a].is_active()
            && saved[b].is_active()
            && !paths_keep_apart(
                &paths[a],
                &paths[b],
                saved[a].body.radius + saved[b].body.radius,
            )
    });
    if met {
        members.clone_from_slice(&saved);
        out.work.add(&trial.work);
        return None;
    }
    out.impacts.extend(trial.impacts);
    out.events.extend(trial.events);
    out.work.add(&trial.work);
    Some(points)
}

/// Whether two paths ([`Path`]) stay farther apart than `sigma` while both are known.
/// Between samples `(t0, p0, v0)` and `(t1, p1, v1)` (`h = t1 - t0`, chord velocity
/// `c = (p1 - p0) / h`) a path runs along the chord, off it by at most
/// `h |v1 - v0| / 2 + h max(|v0 - c|, |v1 - c|) / 4`: the second term bounds the cubic
/// through both ends' positions and velocities (exact for a constant acceleration `a`:
/// `a h^2 / 8`), the first is as much again and more, for a path the cubic does not
/// follow. A step's path is its Runge-Kutta step's, which the cubic follows to that
/// step's accuracy. (A bound from the body forces' acceleration bound instead, which
/// holds the air's full speed, came to a tenth of a millimetre over the bore's long
/// steps: two shots falling side by side a tenth of a millimetre apart failed the check
/// in every window.)
fn paths_keep_apart(a: &Path, b: &Path, sigma: f64) -> bool {
    let (Some(a_end), Some(b_end)) = (a.last(), b.last()) else {
        return true;
    };
    let (mut t, t_end) = (a[0].0.max(b[0].0), a_end.0.min(b_end.0));
    // A path's chord at `t` on its segment `k` (from sample `k` to `k + 1`) and that
    // segment's error bound.
    let chord = |p: &Path, k: usize, t: f64| -> Vec3 {
        let (s0, s1) = (&p[k], &p[(k + 1).min(p.len() - 1)]);
        let h = s1.0 - s0.0;
        if h > 0.0 {
            s0.1 + (s1.1 - s0.1) * ((t - s0.0) / h).clamp(0.0, 1.0)
        } else {
            s1.1
        }
    };
    let dev = |p: &Path, k: usize| -> f64 {
        let (s0, s1) = (&p[k], &p[(k + 1).min(p.len() - 1)]);
        let h = s1.0 - s0.0;
        if h <= 0.0 {
            return 0.0;
        }
        let c = (s1.1 - s0.1) / h;
        0.5 * h * (s1.2 - s0.2).norm() + 0.25 * h * (s0.2 - c).norm().max((s1.2 - c).norm())
    };
    // The segment holding `t` (the last one starting before it).
    let seg = |p: &Path, t: f64| p.partition_point(|s| s.0 <= t).clamp(1, p.len()) - 1;
    let (mut i, mut j) = (seg(a, t), seg(b, t));
    if (chord(b, j, t) - chord(a, i, t)).norm() < sigma + dev(a, i) + dev(b, j) {
        return false;
    }
    while t < t_end {
        let next = |p: &Path, k: usize| p.get(k + 1).map_or(f64::INFINITY, |s| s.0);
        let tn = next(a, i).min(next(b, j)).min(t_end);
        if tn > t {
            let d0 = chord(b, j, t) - chord(a, i, t);
            let d1 = chord(b, j, tn) - chord(a, i, tn);
            let margin = sigma + dev(a, i) + dev(b, j);
            if crate::events::flight::closest_approach(&d0, &((d1 - d0) / (tn - t)), tn - t)
                < margin
            {
                return false;
            }
        }
        t = tn;
        while i + 1 < a.len() - 1 && a[i + 1].0 <= t {
            i += 1;
        }
        while j + 1 < b.len() - 1 && b[j + 1].0 <= t {
            j += 1;
        }
        if tn == f64::INFINITY {
            break;
        }
    }
    true
}

/// Sub-windows an island's window is cut into (see [`advance_split`]). Measured on the
/// nozzle streams (docs/performance-history.md, session 31): two parts save the most; four, eight
/// and sixteen cost more in per-part work than they save in steps.
const SPLIT_PARTS: usize = 2;
/// Fewest members for which an island's window is cut into sub-windows.
const SPLIT_MIN: usize = 3;

/// Advances an island of the window `[t0, t1]` in [`SPLIT_PARTS`] sub-windows, each with
/// its own groups ([`sub_window`]): within a sub-window only the members that may touch
/// in it share a clock. An island is the closure of the shots that may touch within the
/// whole window (a shot that may be kicked pulls in everybody within its absolute reach);
/// over part of the window the reach shrinks with it, the closure falls apart, and a
/// contact's short steps are taken by the shots near it, not by every member.
/// `may_kick[k]`: whether the window took member `k` as possibly kicked (by a wall or a
/// neighbour); a member it did not cannot meet a wall in any part of the window.
#[allow(clippy::too_many_arguments)]
fn advance_split(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &mut [IslandPair],
    may_kick: &[bool],
    (t0, t1): (f64, f64),
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    snapshot_interval: Option<f64>,
    apart: bool,
) -> Vec<(u64, SnapshotPoint)> {
    let mut points = Vec::new();
    for k in 0..SPLIT_PARTS {
        let part = |k: usize| t0 + (t1 - t0) * k as f64 / SPLIT_PARTS as f64;
        let span = (
            part(k),
            if k + 1 == SPLIT_PARTS {
                t1
            } else {
                part(k + 1)
            },
        );
        let snap = snapshot_interval;
        points.extend(sub_window(
            phys, members, pairs, may_kick, span, scratch, out, snap, apart,
        ));
    }
    points
}

/// One sub-window `[a, b]` of [`advance_split`]: the window's candidate test
/// (`Simulation::refine_candidates`) on the island's pairs, groups by union-find, each
/// group advanced on its own clock, then the window's safety net (a member that moved
/// farther than its reach is checked for overlaps with members it was not grouped with;
/// any found are linked and the sub-window redone). Returns the snapshot points.
#[allow(clippy::too_many_arguments)]
fn sub_window(
    phys: &Physics,
    members: &mut [ShotState],
    pairs: &mut [IslandPair],
    may_kick: &[bool],
    (a, b): (f64, f64),
    scratch: &mut Scratch,
    out: &mut IslandOutput,
    snapshot_interval: Option<f64>,
    apart: bool,
) -> Vec<(u64, SnapshotPoint)> {
    let n = members.len();
    let on = |m: &ShotState| m.is_active();
    let acc: Vec<f64> = members.iter().map(|m| body_acc(phys, m)).collect();
    let reach: Vec<f64> = members
        .iter()
        .zip(&acc)
        .map(|(m, &acc)| inflated_radius(m, acc, a, b))
        .collect();
    let span = b - a;
    // The window's candidate test, by components: the kicked set spreads over the pairs
    // within absolute reach, so it is a union of their components, and a component is
    // kicked if a member may meet a wall, or a pair touches or closes by relative motion.
    // The pairs of a kicked component are linked; the members of the others fly apart.
    let mut uf = SlotUnionFind::new(n);
    let abs: Vec<bool> = pairs
        .iter()
        .map(|p| {
            let (i, j) = (p.a as usize, p.b as usize);
            on(&members[i])
                && on(&members[j])
                && (p.touching || (members[i].pos - members[j].pos).norm() < reach[i] + reach[j])
        })
        .collect();
    for (p, _) in pairs.iter().zip(&abs).filter(|x| *x.1) {
        uf.union(p.a as usize, p.b as usize);
    }
    let mut kicked = vec![false; n];
    for i in 0..n {
        // A member the window did not take as kicked meets no wall in any part of it.
        if may_kick[i] && on(&members[i]) && near_a_wall(phys, &members[i], reach[i], acc[i], a, b)
        {
            kicked[uf.find(i)] = true;
        }
    }
    for (p, _) in pairs.iter().zip(&abs).filter(|x| *x.1) {
        let r = uf.find(p.a as usize);
        if !kicked[r]
            && (p.touching || {
                let (i, j) = (p.a as usize, p.b as usize);
                closing(&members[i], &members[j], acc[i] + acc[j], span)
            })
        {
            kicked[r] = true;
        }
    }
    let mut linked: Vec<bool> = pairs
        .iter()
        .zip(&abs)
        .map(|(p, &x)| x && kicked[uf.find(p.a as usize)])
        .collect();
    loop {
        // Groups: members joined by linked pairs, in ascending order of their first member.
        let mut uf = SlotUnionFind::new(n);
        for (p, _) in pairs.iter().zip(&linked).filter(|x| *x.1) {
            uf.union(p.a as usize, p.b as usize);
        }
        let mut group_of = vec![usize::MAX; n];
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for i in 0..n {
            if !on(&members[i]) {
                continue;
            }
            let r = uf.find(i);
            if group_of[r] == usize::MAX {
                group_of[r] = groups.len();
                groups.push(Vec::new());
            }
            group_of[i] = group_of[r];
            groups[group_of[i]].push(i);
        }
        // Each group's linked pairs, in the island's order.
        let mut group_pairs: Vec<Vec<usize>> = vec![Vec::new(); groups.len()];
        for (p, pair) in pairs.iter().enumerate() {
            if linked[p] {
                group_pairs[group_of[pair.a as usize]].push(p);
            }
        }
        let mut results: Vec<(Vec<ShotState>, Vec<IslandPair>, IslandOutput)> =
            Vec::with_capacity(groups.len());
        let mut points = Vec::new();
        let mut slot = vec![0u32; n];
        for (g, gps) in groups.iter().zip(&group_pairs) {
            for (k, &i) in g.iter().enumerate() {
                slot[i] = k as u32;
            }
            let mut gm: Vec<ShotState> = g.iter().map(|&i| members[i].clone()).collect();
            let mut gp: Vec<IslandPair> = gps
                .iter()
                .map(|&p| IslandPair {
                    a: slot[pairs[p].a as usize],
                    b: slot[pairs[p].b as usize],
                    ..pairs[p]
                })
                .collect();
            let mut gout = IslandOutput::default();
            let snap = snapshot_interval;
            points.extend(advance_island(
                phys, &mut gm, &mut gp, a, b, scratch, &mut gout, snap, apart,
            ));
            results.push((gm, gp, gout));
        }
        // Verify: only a member that moved farther than its reach can meet one it was not
        // grouped with.
        let end = |i: usize| results[group_of[i]].0[slot[i] as usize].pos;
        let escaped = (0..n).any(|i| {
            on(&members[i]) && (end(i) - members[i].pos).norm() > reach[i] - members[i].body.radius
        });
        if escaped {
            let mut missed = false;
            for (p, pair) in pairs.iter().enumerate() {
                let (i, j) = (pair.a as usize, pair.b as usize);
                if linked[p] || !on(&members[i]) || !on(&members[j]) {
                    continue;
                }
                let gap =
                    (end(i) - end(j)).norm() - members[i].body.radius - members[j].body.radius;
                if gap < 0.0 {
                    linked[p] = true;
                    missed = true;
                }
            }
            if missed {
                continue;
            }
        }
        // Commit: members, the linked pairs' contact states, the outputs in group order.
        for ((g, gps), (gm, gp, gout)) in groups.iter().zip(&group_pairs).zip(results) {
            for (&p, done) in gps.iter().zip(gp) {
                pairs[p].touching = done.touching;
                pairs[p].contact_time = done.contact_time;
                pairs[p].onset = done.onset;
                pairs[p].xi = done.xi;
            }
            for (&i, m) in g.iter().zip(gm) {
                members[i] = m;
            }
            out.impacts.extend(gout.impacts);
            out.events.extend(gout.events);
            out.work.add(&gout.work);
        }
        return points;
    }
}

/// The body-force acceleration bound of shot `s` over a window: at its speed with a 1.5
/// margin for collision kicks, plus 1 m/s ([`ForceSet::acceleration_bound`]); computed
/// once per shot and window, for its reach, its tube test and its pairs' closing test.
///
/// [`ForceSet::acceleration_bound`]: crate::forces::ForceSet::acceleration_bound
#[inline]
fn body_acc(phys: &Physics, s: &ShotState) -> f64 {
    phys.forces
        .acceleration_bound(&s.body, 1.5 * s.vel.norm() + 1.0)
}

/// Radius of `s` plus how far it can move between `t0` and `t1`: speed (with a 1.5
/// margin for collision kicks) times span plus the body-force bound `a` ([`body_acc`]).
#[inline]
fn inflated_radius(s: &ShotState, a: f64, t0: f64, t1: f64) -> f64 {
    let span = (t1 - s.t_start.max(t0)).max(0.0);
    let speed = 1.5 * s.vel.norm();
    s.body.radius + speed * span + 0.5 * a * span * span + 1e-9
}

/// Whether shot `s`, whose reach over the window `t0..t1` is `reach`
/// ([`inflated_radius`]; `a` its [`body_acc`]), may touch the nozzle tube in it. Beside the tube
/// the gap decides. A shot more than a radius beyond either end, where
/// [`Tube::geometry`](crate::contact::Tube::geometry) says `None`, may still reach
/// that end (the exit's lip or face) within the window: it does if its distance along
/// the axis can come within a radius of the end's plane under the acceleration bound,
/// and its clearance is within its reach (session 27: a shot rising onto a nozzle
/// body's face was not taken as kicked, and a neighbour taken as independent of it was
/// run through). Shots leaving the exit are not: their distance along the axis grows.
#[inline]
fn may_reach_tube(
    s: &ShotState,
    tube: &crate::contact::Tube,
    reach: f64,
    a: f64,
    t0: f64,
    t1: f64,
) -> bool {
    let r = s.body.radius;
    if let Some(g) = tube.geometry(&s.pos, r) {
        return g.gap < reach - r;
    }
    let span = (t1 - s.t_start.max(t0)).max(0.0);
    let along = (s.pos - tube.exit).dot(&tube.axis);
    let v_along = s.vel.dot(&tube.axis);
    // Beyond the exit (downstream) the distance is `along`; beyond the inlet it is
    // measured upstream. Its least value over the window is at one end of it.
    let (dist, closing) = if along > 0.0 {
        (along, -v_along)
    } else {
        (-tube.length - along, v_along)
    };
    let least = dist - (closing * span + 0.5 * a * span * span).max(0.0) - 1e-9;
    least <= r && tube.clearance(&s.pos, r) < reach - r
}

/// Whether shots `sa` and `sb`, flying on body forces alone, can close their gap within
/// `span` by their relative motion (`gap < |v_a - v_b| span + (a_a + a_b) span^2 / 2`;
/// `acc` is `a_a + a_b`, each [`body_acc`]).
#[inline]
fn closing(sa: &ShotState, sb: &ShotState, acc: f64, span: f64) -> bool {
    let gap = (sa.pos - sb.pos).norm() - sa.body.radius - sb.body.radius;
    gap < (sa.vel - sb.vel).norm() * span + 0.5 * acc * span * span + 1e-9
}

/// Whether shot `s`, whose reach over `t0..t1` is `reach`, may be kicked by the specimen
/// or the nozzle tube in that span (or is in contact with either); `a` is its
/// [`body_acc`].
#[inline]
fn near_a_wall(phys: &Physics, s: &ShotState, reach: f64, a: f64, t0: f64, t1: f64) -> bool {
    let near_specimen = phys
        .contacts
        .specimen
        .as_ref()
        // Below a positive reach, the distance within it says the same for less.
        .is_some_and(|sp| match reach > 0.0 {
            true => sp.shape.distance_within(&s.pos, reach) < reach,
            false => sp.shape.distance(&s.pos) < reach,
        });
    let near_wall = phys
        .contacts
        .wall
        .is_some_and(|w| may_reach_tube(s, &w.tube, reach, a, t0, t1));
    near_specimen || near_wall || s.on_specimen || s.on_wall
}

/// What one island returns from a window. (The variants differ in size; boxing the
/// larger one would cost an allocation per stepped island in every window.)
#[allow(clippy::large_enum_variant)]
enum IslandResult {
    /// A lone shot whose kept step covers the window (most shots in flight, in most
    /// windows): its state at the window's end, read off that step in place.
    Kept(island::Kept),
    /// Its members, its pairs by global key, its output, its snapshot points.
    Stepped(
        Vec<ShotState>,
        Vec<((u32, u32), IslandPair)>,
        IslandOutput,
        Vec<(u64, SnapshotPoint)>,
    ),
}

/// Contact state of a shot pair that persists between windows.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PairState {
    contact_time: f64,
    onset: f64,
    xi: Vec3,
}

/// What a run produced: its records and its [`RunTail`] (whose fields read through:
/// `out.work`, `out.events`, ...).
#[derive(Debug, Clone)]
pub struct RunOutput {
    /// Impacts sorted by (time, shot).
    pub impacts: Vec<Impact>,
    /// Final shot states, by id.
    pub shots: Vec<ShotState>,
    /// Events, counters, snapshots and the scheduler that ran.
    pub tail: RunTail,
}

impl std::ops::Deref for RunOutput {
    type Target = RunTail;
    fn deref(&self) -> &RunTail {
        &self.tail
    }
}

impl std::ops::DerefMut for RunOutput {
    fn deref_mut(&mut self) -> &mut RunTail {
        &mut self.tail
    }
}

/// Receives a run's records as they become final (see [`Simulation::run_into`]).
pub trait RunSink {
    /// Impacts, in (time, shot) order across all calls.
    fn impacts(&mut self, batch: &[Impact]);
    /// A shot's final state, once it stopped (left the domain, failed) or at the end of
    /// the run: across calls, by the time it stopped, then id; shots still in the domain
    /// at the end last, by id.
    fn shot(&mut self, shot: &ShotState);
}

/// Both sinks get every record.
impl<A: RunSink, B: RunSink> RunSink for (A, B) {
    fn impacts(&mut self, batch: &[Impact]) {
        self.0.impacts(batch);
        self.1.impacts(batch);
    }
    fn shot(&mut self, shot: &ShotState) {
        self.0.shot(shot);
        self.1.shot(shot);
    }
}

/// What a run produced besides the records handed to its sink.
#[derive(Debug, Clone)]
pub struct RunTail {
    /// Shots that had to be stopped, by (time, shot).
    pub events: Vec<RunEvent>,
    /// Work counters.
    pub work: WorkCounters,
    /// Synchronisation windows run.
    pub windows: u64,
    /// Windows re-run because an unpaired overlap was found.
    pub window_redos: u64,
    /// Simulated end time, s.
    pub end_time: f64,
    /// Snapshots `(time, shots)` at the requested interval (empty when not asked for).
    pub snapshots: Vec<(f64, Vec<SnapshotPoint>)>,
    /// The scheduler that ran.
    pub scheduler: &'static str,
    /// Why it is not the one the scene chose (the event scheduler gave up), if so.
    pub scheduler_note: Option<String>,
    /// Most shot states held at once: the shots in flight plus, in a stream, those fed
    /// but not entered yet and finished ones waiting for an older shot to finish (shots
    /// go to the sink in id order); every shot fed when the run is not streamed.
    pub peak_shots_held: usize,
    /// The air's speed over the scene's (`[jet] coupling = "momentum"`: the jet the
    /// shots slow; 1 otherwise).
    pub air_speed_factor: f64,
}

/// A sink that keeps everything (what [`Simulation::run`] returns).
#[derive(Debug, Default)]
struct Collect {
    impacts: Vec<Impact>,
    shots: Vec<ShotState>,
}

impl RunSink for Collect {
    fn impacts(&mut self, batch: &[Impact]) {
        self.impacts.extend_from_slice(batch);
    }
    fn shot(&mut self, shot: &ShotState) {
        self.shots.push(shot.clone());
    }
}

/// The shots a run holds, indexed by id over ids `base..base + len`. A streamed run hands
/// each shot to its sink once it stopped and drops it; the slots of stopped shots behind
/// an older shot still in the domain (one at rest on the specimen) cost 8 bytes each until
/// that shot stops, so what a run holds follows the shots in flight, not every shot fed.
#[derive(Debug, Default)]
struct ShotStore {
    base: usize,
    q: std::collections::VecDeque<Option<Box<ShotState>>>,
    held: usize,
}

impl std::ops::Index<usize> for ShotStore {
    type Output = ShotState;
    #[inline]
    fn index(&self, i: usize) -> &ShotState {
        self.q[i - self.base]
            .as_deref()
            .expect("BUG: shot already handed to the sink")
    }
}

impl std::ops::IndexMut<usize> for ShotStore {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut ShotState {
        self.q[i - self.base]
            .as_deref_mut()
            .expect("BUG: shot already handed to the sink")
    }
}

/// The order shots are handed to a sink (and listed in shots.csv): by the time they
/// stopped, then id; shots still in the domain at the end (and any the feed had not
/// delivered) last, by id.
pub fn stop_order(a: &ShotState, b: &ShotState) -> std::cmp::Ordering {
    let t = |s: &ShotState| s.t_stop.unwrap_or(f64::INFINITY);
    t(a).total_cmp(&t(b)).then(a.id.cmp(&b.id))
}

impl ShotStore {
    fn from_vec(v: Vec<ShotState>) -> Self {
        ShotStore {
            base: 0,
            held: v.len(),
            q: v.into_iter().map(|s| Some(Box::new(s))).collect(),
        }
    }

    fn iter(&self) -> impl Iterator<Item = &ShotState> {
        self.q.iter().flatten().map(|b| &**b)
    }

    /// Shots held.
    fn held(&self) -> usize {
        self.held
    }

    /// Id slots spanned (held shots and the released ones between them).
    fn span(&self) -> usize {
        self.q.len()
    }

    fn push(&mut self, s: ShotState) {
        debug_assert_eq!(s.id.0 as usize, self.base + self.q.len());
        self.q.push_back(Some(Box::new(s)));
        self.held += 1;
    }

    /// Every shot, by id, moved out (only while none was handed out).
    fn take_all(&mut self) -> Vec<ShotState> {
        assert!(
            self.base == 0 && self.held == self.q.len(),
            "BUG: shots already handed to the sink"
        );
        self.held = 0;
        self.q
            .drain(..)
            .map(|b| *b.expect("BUG: checked"))
            .collect()
    }

    /// Hands the shots `ids` (stopped) to `sink` in stop order and drops them.
    fn release(&mut self, ids: &mut [usize], sink: &mut dyn RunSink) {
        ids.sort_by(|&a, &b| stop_order(&self[a], &self[b]));
        for &i in ids.iter() {
            let s = self.q[i - self.base]
                .take()
                .expect("BUG: shot released twice");
            sink.shot(&s);
            self.held -= 1;
        }
        while self.q.front().is_some_and(|s| s.is_none()) {
            self.q.pop_front();
            self.base += 1;
        }
    }

    /// Hands every shot still held to `sink` in stop order.
    fn release_all(&mut self, sink: &mut dyn RunSink) {
        let mut ids: Vec<usize> = (0..self.q.len())
            .filter(|&k| self.q[k].is_some())
            .map(|k| k + self.base)
            .collect();
        self.release(&mut ids, sink);
    }
}

/// Per-shot scratch values indexed by shot id over the ids a [`ShotStore`] holds.
#[derive(Debug, Default)]
struct ById<T> {
    base: usize,
    v: Vec<T>,
}

impl<T: Copy> ById<T> {
    fn reset(&mut self, store: &ShotStore, fill: T) {
        self.base = store.base;
        self.v.clear();
        self.v.resize(store.span(), fill);
    }
}

impl<T> ById<T> {
    /// Shot `i`'s entry, if the store holds `i`.
    #[inline]
    fn get(&self, i: usize) -> Option<&T> {
        self.v.get(i.checked_sub(self.base)?)
    }
}

impl<T> std::ops::Index<usize> for ById<T> {
    type Output = T;
    #[inline]
    fn index(&self, i: usize) -> &T {
        &self.v[i - self.base]
    }
}

impl<T> std::ops::IndexMut<usize> for ById<T> {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut T {
        &mut self.v[i - self.base]
    }
}

/// What a run tells its caller at once (see [`Simulation::with_notice`]).
pub type Notice = Box<dyn Fn(&str) + Sync>;

/// A run in progress.
pub struct Simulation {
    physics: Physics,
    /// [`RunTail::air_speed_factor`].
    air_speed_factor: f64,
    shots: ShotStore,
    /// A stream's generator while shots are created as they enter (streamed windows
    /// runs), with its next shot; `None` when every shot is in `shots`.
    feed: Option<(crate::feed::StreamFeed, Option<ShotState>)>,
    peak_held: usize,
    /// Shots that stopped in the last window (streamed runs hand them over).
    stopped: Vec<usize>,
    pairs: HashMap<(u32, u32), PairState>,
    t: f64,
    end: f64,
    impacts: Vec<Impact>,
    events: Vec<RunEvent>,
    work: WorkCounters,
    windows: u64,
    window_redos: u64,
    cells: CellList,
    snapshot_interval: Option<f64>,
    snapshot_points: Vec<(u64, SnapshotPoint)>,
    last_window: f64,
    /// Shot indices by entry time (then index): the feed's queue.
    by_start: Vec<usize>,
    /// How many of `by_start` have been admitted to `live`.
    admitted: usize,
    /// Admitted shots still active, ascending: the only ones a window looks at, so the
    /// per-window work follows the shots in flight, not every shot fed.
    live: Vec<usize>,
    /// Per-shot reach and kicked flags, reused across windows (entries of `live` only).
    reach_buf: ById<f64>,
    kicked_buf: ById<bool>,
    /// Each shot's place in the window's `idx` (`u32::MAX` outside it).
    slot_buf: ById<u32>,
    /// Each shot's body-force acceleration bound for the window ([`body_acc`]).
    acc_buf: ById<f64>,
    scheduler: Scheduler,
    /// Windows integrate their islands in parallel from this many shots taking steps.
    parallel_min_shots: usize,
    /// The event scheduler resolves lone contacts on its lean path (`events::binary`).
    lean_contacts: bool,
    /// Islands of [`SPLIT_MIN`] or more shots run in sub-windows ([`advance_split`]).
    sub_windows: bool,
    /// The members of an island that keep apart step on separate clocks
    /// ([`advance_apart`]).
    separate_clocks: bool,
    /// Told, during the run, what the caller should hear at once (see [`Self::with_notice`]).
    notice: Option<Notice>,
    /// Lone shots asleep across windows (`sleep`), and whether shots may sleep.
    sleepers: Sleepers,
    /// Whether each shot of the window had a pair in its broad phase.
    near_buf: ById<bool>,
    sleep: bool,
}

/// Shots the independent scheduler flies at a time when it streams its records.
const INDEPENDENT_CHUNK: usize = 4096;

/// Default of [`Simulation::with_parallel_min_shots`].
pub const PARALLEL_MIN_SHOTS: usize = 256;

/// Refuses shots placed overlapping the nozzle tube when its contact is on (a box of
/// shots drawn across a nozzle body, session 27: they were stopped at the first step as
/// "Hertz contact does not hold", with advice about materials). For box and bed feeds:
/// list shots are refused by the scene's check already, and batch and stream shots are
/// placed inside the bore.
fn starts_clear_of_the_tube(
    scene: &Scene,
    tube: &crate::contact::Tube,
    shots: &[ShotState],
) -> Result<(), SceneError> {
    for (i, s) in shots.iter().enumerate() {
        let Some(g) = tube.geometry(&s.pos, s.body.radius) else {
            continue;
        };
        if g.gap < 0.0 {
            return Err(SceneError::Invalid {
                path: scene.path.clone(),
                key: "shots.feed".into(),
                message: format!(
                    "shot {} of {} would start overlapping the nozzle tube by {} mm (centre at [{}, {}, {}] mm, {} mm from the nozzle axis; bore radius {} mm, outer radius {} mm): place the shots clear of the nozzle, or set nozzle_wall_contact = false under [effects]",
                    i + 1,
                    shots.len(),
                    crate::scene::validate::num(-g.gap * 1e3),
                    crate::scene::validate::num(s.pos.x * 1e3),
                    crate::scene::validate::num(s.pos.y * 1e3),
                    crate::scene::validate::num(s.pos.z * 1e3),
                    crate::scene::validate::num(tube.radial_distance(&s.pos) * 1e3),
                    crate::scene::validate::num(tube.bore_radius * 1e3),
                    crate::scene::validate::num(tube.outer_radius * 1e3),
                ),
            });
        }
    }
    Ok(())
}

/// Refuses shots placed outside the domain, which the run would drop as they start (a
/// list shot, or a box or bed laid out beyond it; session 65: they were dropped in the
/// first microsecond without a word). Batch and stream shots start in the bore, which
/// the domain takes in (`scene::validate`).
fn starts_inside_the_domain(scene: &Scene, shots: &[ShotState]) -> Result<(), SceneError> {
    let d = &scene.domain;
    let Some((i, s)) = shots.iter().enumerate().find(|(_, s)| !d.contains(&s.pos)) else {
        return Ok(());
    };
    let num = crate::scene::validate::num;
    let (key, what, fix) = match scene.feed {
        crate::scene::Feed::List(_) => (
            format!("shots.feed.shots[{i}].position_mm"),
            "the shot".to_string(),
            "move it inside",
        ),
        crate::scene::Feed::Box { .. } => (
            "shots.feed".to_string(),
            format!("shot {} of {} of the box", i + 1, shots.len()),
            "keep min_mm and max_mm inside",
        ),
        _ => (
            "shots.feed".to_string(),
            format!("shot {} of {} of the bed", i + 1, shots.len()),
            "use fewer cells (nx, ny) or layers",
        ),
    };
    let below = if d.bottom.is_finite() {
        format!(", at least {} mm", num(d.bottom * 1e3))
    } else {
        String::new()
    };
    Err(SceneError::Invalid {
        path: scene.path.clone(),
        key,
        message: format!(
            "{what} would start at [{}, {}, {}] mm, outside the domain (at most {} mm from the \
             vertical through the jet axis' foot, at most {} mm high{below}), and be dropped as \
             it starts: {fix}, or widen [domain] (radius_mm, above_inlet_mm)",
            num(s.pos.x * 1e3),
            num(s.pos.y * 1e3),
            num(s.pos.z * 1e3),
            num(d.radius * 1e3),
            num(d.top * 1e3),
        ),
    })
}

impl Simulation {
    /// A run of `scene` with its resolved `effects`: with `[jet] coupling = "momentum"`
    /// in the jet the shots slow ([`crate::flow::coupling`]).
    pub fn new(scene: &Scene, effects: &Effects) -> Result<Self, SceneError> {
        if scene.jet.coupling == crate::flow::coupling::Coupling::Momentum
            && (effects.drag || effects.lateral_force)
        {
            let (coupled, f) = crate::flow::coupling::coupled(scene, effects)?;
            let mut sim = Self::of_scene(&coupled, effects)?;
            sim.air_speed_factor = f;
            return Ok(sim);
        }
        Self::of_scene(scene, effects)
    }

    /// [`Simulation::new`] on the air as `scene` gives it.
    fn of_scene(scene: &Scene, effects: &Effects) -> Result<Self, SceneError> {
        let physics = build_physics(scene, effects);
        let scheduler = scene.integrator.scheduler;
        if scheduler == Scheduler::Events
            && let Some(why) = crate::events::unsuitable(&physics)
        {
            return Err(SceneError::Invalid {
                path: scene.path.clone(),
                key: "integrator.scheduler".into(),
                message: format!(
                    "\"events\" needs ballistic free flight, but {why}; use \"auto\" or \"windows\""
                ),
            });
        }
        // A stream that will run on windows is created shot by shot as the shots enter
        // (see `run_into`); it is generated once here so that a stream that cannot enter
        // is refused before anything is written.
        if matches!(scene.feed, crate::scene::Feed::Stream { .. })
            && physics.contacts.pair.is_some()
            && (scheduler == Scheduler::Windows || crate::events::unsuitable(&physics).is_some())
        {
            let mut check = crate::feed::StreamFeed::of_scene(scene);
            while check.next_shot()?.is_some() {}
            let mut feed = crate::feed::StreamFeed::of_scene(scene);
            let first = feed.next_shot()?;
            let mut sim = Simulation::from_parts(physics, Vec::new(), scene.duration)
                .with_scheduler(scheduler);
            sim.feed = Some((feed, first));
            return Ok(sim);
        }
        let shots = crate::feed::placed_shots(scene, physics.contacts.pair.is_some())?;
        starts_inside_the_domain(scene, &shots)?;
        if let Some(w) = &physics.contacts.wall
            && matches!(
                scene.feed,
                crate::scene::Feed::Box { .. } | crate::scene::Feed::Bed { .. }
            )
        {
            starts_clear_of_the_tube(scene, &w.tube, &shots)?;
        }
        Ok(Simulation::from_parts(physics, shots, scene.duration).with_scheduler(scheduler))
    }

    /// Chooses the scheduler (default [`Scheduler::Auto`]: events for ballistic scenes
    /// whose shots do not start in contact on the adaptive and hybrid methods, else
    /// windows; the fixed-step method takes events only when asked, as LIGGGHTS' manner
    /// is its default). [`Scheduler::Events`] on
    /// physics it does not suit, or with snapshots, falls back to windows (scene files
    /// asking for it on unsuitable physics are refused by [`Simulation::new`]).
    pub fn with_scheduler(mut self, scheduler: Scheduler) -> Self {
        self.scheduler = scheduler;
        self
    }

    /// `notice` is told at once what changes the run's course: the event scheduler giving
    /// up, after which the whole run starts again on windows (its progress from zero).
    /// The same text is [`RunTail::scheduler_note`] at the end.
    pub fn with_notice(mut self, notice: Notice) -> Self {
        self.notice = Some(notice);
        self
    }

    /// Windows integrate their islands in parallel (rayon) when at least `n` shots take
    /// steps in them, and on the calling thread below that (default
    /// [`PARALLEL_MIN_SHOTS`]). Results do not depend on it, nor on the thread count.
    pub fn with_parallel_min_shots(mut self, n: usize) -> Self {
        self.parallel_min_shots = n;
        self
    }

    /// Whether a lone shot whose specimen contact has settled slides (with friction:
    /// rolls) on the specimen (default) or steps through the pressed contact's oscillation until it
    /// leaves (`Physics::sliding`). For comparisons: both follow the same motion.
    pub fn with_sliding(mut self, on: bool) -> Self {
        self.physics.sliding = on;
        self
    }

    /// Whether the window scheduler runs islands of three or more shots in sub-windows,
    /// each with its own groups (default), or over the whole window with one clock. For
    /// comparisons: both integrate the same physics to the tolerance.
    pub fn with_sub_windows(mut self, on: bool) -> Self {
        self.sub_windows = on;
        self
    }

    /// Whether the window scheduler steps the members of an island that keep apart on
    /// separate clocks, checked afterwards (default), or on the island's one clock. For
    /// comparisons: both integrate the same physics to the tolerance.
    pub fn with_separate_clocks(mut self, on: bool) -> Self {
        self.separate_clocks = on;
        self
    }

    /// Whether the window scheduler lets lone shots riding a kept step sleep across
    /// windows (default; `sim::sleep`) or looks at every shot in flight in every window.
    /// For comparisons: the outputs are the same byte for byte.
    pub fn with_sleepers(mut self, on: bool) -> Self {
        self.sleep = on;
        self
    }

    /// Members from which an island's step passes (forces, margins, error norm) are split
    /// over the threads ([`Physics::blocks_min`]). For comparisons: the outputs are the
    /// same byte for byte.
    pub fn with_blocks_min(mut self, n: usize) -> Self {
        self.physics.blocks_min = n;
        self
    }

    /// Whether a lone shot's fixed steps away from every contact skip the contact passes
    /// ([`Physics::free_steps`]). For comparisons: the outputs are the same byte for byte.
    pub fn with_free_steps(mut self, on: bool) -> Self {
        self.physics.free_steps = on;
        self
    }

    /// Whether the event scheduler resolves lone frictionless contacts on its lean path
    /// (closed form and a two-body frame, `events::binary`; default) or every contact as
    /// an island. For comparisons: both resolve the same physics to the tolerance.
    pub fn with_lean_contacts(mut self, on: bool) -> Self {
        self.lean_contacts = on;
        self
    }

    /// The scheduler a run will use.
    pub fn scheduler_in_use(&self) -> &'static str {
        if self.physics.contacts.pair.is_none() {
            "independent"
        } else if self.snapshot_interval.is_none()
            && crate::events::unsuitable(&self.physics).is_none()
            && (self.scheduler == Scheduler::Events
                || (self.scheduler == Scheduler::Auto
                    && self.physics.method.adaptive_flight()
                    && !self.starts_packed()))
        {
            "events"
        } else {
            "windows"
        }
    }

    /// A run from explicit stages and shots (for tests and library users).
    pub fn from_parts(physics: Physics, mut shots: Vec<ShotState>, end: f64) -> Self {
        if let Some(field) = &physics.forces.field {
            for s in &mut shots {
                s.locate(field);
            }
        }
        let mut by_start: Vec<usize> = (0..shots.len()).collect();
        by_start.sort_by(|&a, &b| {
            shots[a]
                .t_start
                .total_cmp(&shots[b].t_start)
                .then(a.cmp(&b))
        });
        let n = shots.len();
        Simulation {
            by_start,
            admitted: 0,
            live: Vec::new(),
            reach_buf: ById::default(),
            kicked_buf: ById::default(),
            slot_buf: ById::default(),
            acc_buf: ById::default(),
            scheduler: Scheduler::Auto,
            parallel_min_shots: PARALLEL_MIN_SHOTS,
            lean_contacts: true,
            sub_windows: true,
            separate_clocks: true,
            notice: None,
            sleepers: Sleepers::default(),
            near_buf: ById::default(),
            sleep: true,
            physics,
            air_speed_factor: 1.0,
            shots: ShotStore::from_vec(shots),
            feed: None,
            peak_held: n,
            stopped: Vec::new(),
            pairs: HashMap::default(),
            t: 0.0,
            end,
            impacts: Vec::new(),
            events: Vec::new(),
            work: WorkCounters::default(),
            windows: 0,
            window_redos: 0,
            cells: CellList::default(),
            snapshot_interval: None,
            snapshot_points: Vec::new(),
            last_window: f64::INFINITY,
        }
    }

    /// Whether shots start in contact with each other or the specimen (a bed, a pile):
    /// persistent contacts are better served by windows, so `auto` picks them. Only the
    /// shots there when the run's first shot enters count: a stream's shots wait at
    /// their entry points, one after the other, and never meet there (until session 29
    /// they were taken as packed, and a stream in vacuum ran on windows, ten times
    /// slower).
    fn starts_packed(&self) -> bool {
        let first = self
            .shots
            .iter()
            .map(|s| s.t_start)
            .fold(f64::INFINITY, f64::min);
        let there: Vec<&ShotState> = self.shots.iter().filter(|s| s.t_start <= first).collect();
        if let Some(sp) = &self.physics.contacts.specimen
            && there.iter().any(|s| sp.gap(&s.pos, s.body.radius) <= 0.0)
        {
            return true;
        }
        let centres: Vec<Vec3> = there.iter().map(|s| s.pos).collect();
        let radii: Vec<f64> = there.iter().map(|s| s.body.radius * (1.0 + 1e-6)).collect();
        !CellList::default().pairs(&centres, &radii).is_empty()
    }

    /// Records shot positions every `interval` seconds (for ParaView series).
    pub fn record_snapshots(&mut self, interval: f64) {
        self.materialise();
        self.snapshot_interval = Some(interval);
        for s in self.shots.iter() {
            if s.t_start <= 0.0 {
                self.snapshot_points.push((
                    0,
                    SnapshotPoint {
                        shot: s.id.0,
                        position: [s.pos.x, s.pos.y, s.pos.z],
                        velocity: [s.vel.x, s.vel.y, s.vel.z],
                        diameter: 2.0 * s.body.radius,
                    },
                ));
            }
        }
    }

    /// The physics stages in use.
    pub fn physics(&self) -> &Physics {
        &self.physics
    }

    /// Runs to the end and returns everything. `progress` receives the finished
    /// fraction (0 to 1).
    pub fn run(self, progress: &(dyn Fn(f64) + Sync)) -> RunOutput {
        let mut all = Collect::default();
        let tail = self.run_into(&mut all, progress);
        all.shots.sort_by_key(|s| s.id);
        RunOutput {
            impacts: all.impacts,
            shots: all.shots,
            tail,
        }
    }

    /// Runs to the end, handing impacts and final shot states to `sink` as they become
    /// final. On windows without snapshots that happens during the run: impacts after
    /// each window, shots in the window they stopped, and a stream
    /// feed creates its shots as they enter, so the run holds the shots in flight rather
    /// than every shot fed ([`RunTail::peak_shots_held`]). The independent scheduler
    /// without snapshots hands records over after each group of shots it flies (see
    /// `run_independent_streamed`). The event scheduler holds every shot and hands
    /// everything over at the end. Same records, in the same order, either way.
    pub fn run_into(mut self, sink: &mut dyn RunSink, progress: &(dyn Fn(f64) + Sync)) -> RunTail {
        let mut scheduler = self.scheduler_in_use();
        let mut scheduler_note = None;
        let streamed =
            matches!(scheduler, "windows" | "independent") && self.snapshot_interval.is_none();
        if !streamed {
            self.materialise();
        }
        if scheduler == "events" {
            let mut shots = self.shots.take_all();
            match crate::events::run(
                &self.physics,
                &mut shots,
                self.end,
                self.lean_contacts,
                progress,
            ) {
                Ok(out) => self.commit_output(out),
                Err(gave_up) => {
                    // The shots are as they were given: the same run on windows.
                    scheduler = "windows";
                    let note = gave_up.to_string();
                    if let Some(notice) = &self.notice {
                        notice(&note);
                    }
                    scheduler_note = Some(note);
                }
            }
            self.shots = ShotStore::from_vec(shots);
        }
        if scheduler == "independent" && streamed {
            self.run_independent_streamed(sink, progress);
        } else if scheduler == "independent" {
            let mut shots = self.shots.take_all();
            self.run_independent(&mut shots, progress);
            self.shots = ShotStore::from_vec(shots);
        } else if scheduler == "windows" {
            while self.t < self.end {
                let now = self.t;
                self.admit(|t| t <= now);
                let t1 = self.window_end();
                let t1 = self.window(t1);
                self.last_window = t1 - self.t;
                self.t = t1;
                if streamed {
                    // A window's impacts lie inside it: sorted per window, they come out
                    // in global (time, shot) order.
                    self.emit_impacts(sink);
                    let mut stopped = std::mem::take(&mut self.stopped);
                    self.shots.release(&mut stopped, sink);
                    stopped.clear();
                    self.stopped = stopped;
                } else {
                    self.stopped.clear();
                }
                progress(self.t / self.end);
            }
            self.wake_sleepers(self.t, |_| true);
        }
        self.emit_impacts(sink);
        self.events
            .sort_by(|a, b| a.time_s.total_cmp(&b.time_s).then(a.shot.cmp(&b.shot)));
        let snapshots = self.collect_snapshots();
        self.shots.release_all(sink);
        // Shots the stream would have fed after the end.
        if let Some((feed, next)) = &mut self.feed {
            while let Some(mut s) = next.take() {
                if let Some(field) = &self.physics.forces.field {
                    s.locate(field);
                }
                sink.shot(&s);
                *next = feed
                    .next_shot()
                    .expect("BUG: the stream was checked when the run was set up");
            }
        }
        RunTail {
            snapshots,
            events: self.events,
            work: self.work,
            windows: self.windows,
            window_redos: self.window_redos,
            end_time: self.end,
            scheduler,
            scheduler_note,
            peak_shots_held: self.peak_held,
            air_speed_factor: self.air_speed_factor,
        }
    }

    /// Sorts the impacts recorded since the last call by (time, shot) and hands them over.
    fn emit_impacts(&mut self, sink: &mut dyn RunSink) {
        self.emit_impacts_before(sink, f64::INFINITY);
    }

    /// Sorts the impacts held by (time, shot) and hands over those before `t`, keeping
    /// the rest.
    fn emit_impacts_before(&mut self, sink: &mut dyn RunSink, t: f64) {
        self.impacts
            .sort_by(|a, b| a.time_s.total_cmp(&b.time_s).then(a.shot.cmp(&b.shot)));
        let k = self.impacts.partition_point(|i| i.time_s < t);
        if k > 0 {
            sink.impacts(&self.impacts[..k]);
        }
        self.impacts.drain(..k);
    }

    /// Creates every shot the stream will feed (runs that hold all their shots).
    fn materialise(&mut self) {
        if let Some((mut feed, mut next)) = self.feed.take() {
            while let Some(mut s) = next {
                if let Some(field) = &self.physics.forces.field {
                    s.locate(field);
                }
                self.by_start.push(s.id.0 as usize);
                self.shots.push(s);
                next = feed
                    .next_shot()
                    .expect("BUG: the stream was checked when the run was set up");
            }
            self.peak_held = self.peak_held.max(self.shots.held());
        }
    }

    /// Groups the recorded points by snapshot, dropping shots already stopped.
    fn collect_snapshots(&mut self) -> Vec<(f64, Vec<SnapshotPoint>)> {
        let Some(dt) = self.snapshot_interval else {
            return Vec::new();
        };
        let mut pts = std::mem::take(&mut self.snapshot_points);
        pts.sort_by_key(|(k, p)| (*k, p.shot));
        let mut out: Vec<(f64, Vec<SnapshotPoint>)> = Vec::new();
        for (k, p) in pts {
            let t = k as f64 * dt;
            if t > self.end + 0.5 * dt {
                continue;
            }
            if let Some(stop) = self.shots[p.shot as usize].t_stop
                && t > stop
            {
                continue;
            }
            match out.last_mut() {
                Some((tl, v)) if *tl == t => v.push(p),
                _ => out.push((t, vec![p])),
            }
        }
        out
    }

    /// [`Simulation::run_independent`] on [`INDEPENDENT_CHUNK`] shots at a time, in entry
    /// order, handing records over as they become final: a shot entering at `t` cannot
    /// hit before `t`, so once every shot entering before `t` has flown to the end, the
    /// impacts before `t` and the shots that stopped before it are final. The run holds
    /// the impacts after that time and the shots not yet stopped, not every record.
    fn run_independent_streamed(
        &mut self,
        sink: &mut dyn RunSink,
        progress: &(dyn Fn(f64) + Sync),
    ) {
        let end = self.end;
        let mut stopped: Vec<usize> = Vec::new();
        loop {
            let mut room = INDEPENDENT_CHUNK;
            self.admit(|t| {
                let due = t < end && room > 0;
                room -= usize::from(due);
                due
            });
            if self.live.is_empty() {
                break;
            }
            let ids = std::mem::take(&mut self.live);
            let mut chunk: Vec<ShotState> = ids.iter().map(|&i| self.shots[i].clone()).collect();
            self.run_independent(&mut chunk, &|_| {});
            for (&i, s) in ids.iter().zip(chunk) {
                if s.t_stop.is_some() {
                    stopped.push(i);
                }
                self.shots[i] = s;
            }
            // The next shot to enter (none: every record is final).
            let next = self
                .by_start
                .get(self.admitted)
                .map(|&i| self.shots[i].t_start)
                .or_else(|| {
                    self.feed
                        .as_ref()
                        .and_then(|(_, next)| next.as_ref().map(|s| s.t_start))
                })
                .filter(|&t| t < end)
                .unwrap_or(f64::INFINITY);
            self.emit_impacts_before(sink, next);
            let (mut done, later): (Vec<usize>, Vec<usize>) = stopped
                .iter()
                .partition(|&&i| self.shots[i].t_stop.is_some_and(|t| t < next));
            self.shots.release(&mut done, sink);
            stopped = later;
            progress(next.min(end) / end);
        }
    }

    /// No shot-shot contact: every shot flies alone over the whole run.
    fn run_independent(&mut self, shots: &mut [ShotState], progress: &(dyn Fn(f64) + Sync)) {
        let phys = &self.physics;
        let end = self.end;
        let total = shots.len().max(1) as f64;
        let done = std::sync::atomic::AtomicUsize::new(0);
        let snap = self.snapshot_interval;
        let outputs: Vec<(IslandOutput, Vec<(u64, SnapshotPoint)>)> = shots
            .par_iter_mut()
            .map_init(Scratch::default, |scratch, shot| {
                let mut out = IslandOutput::default();
                let t0 = shot.t_start.min(end);
                let pts = advance_island(
                    phys,
                    std::slice::from_mut(shot),
                    &mut [],
                    t0,
                    end,
                    scratch,
                    &mut out,
                    snap,
                    false,
                );
                let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                progress(n as f64 / total);
                (out, pts)
            })
            .collect();
        self.windows = 1;
        for (o, pts) in outputs {
            self.commit_output(o);
            self.snapshot_points.extend(pts);
        }
    }

    fn commit_output(&mut self, o: IslandOutput) {
        self.impacts.extend(o.impacts);
        self.events.extend(o.events);
        self.work.add(&o.work);
    }

    /// Moves the shots of the feed's queue whose entry time passes `due` into `live`
    /// (kept ascending).
    fn admit(&mut self, mut due: impl FnMut(f64) -> bool) {
        let mut added = false;
        while let Some(&i) = self.by_start.get(self.admitted) {
            if !due(self.shots[i].t_start) {
                break;
            }
            self.live.push(i);
            self.admitted += 1;
            added = true;
        }
        // A stream created as it enters: ids follow entry times.
        while let Some((feed, next)) = &mut self.feed {
            let Some(mut s) = next.take_if(|s| due(s.t_start)) else {
                break;
            };
            *next = feed
                .next_shot()
                .expect("BUG: the stream was checked when the run was set up");
            if let Some(field) = &self.physics.forces.field {
                s.locate(field);
            }
            self.live.push(s.id.0 as usize);
            self.shots.push(s);
            added = true;
        }
        if added {
            self.live.sort_unstable();
            self.peak_held = self.peak_held.max(self.shots.held());
        }
    }

    /// End of the next window: `self.t` plus [`Self::window_length`], at most the run's
    /// end. With the fixed-step method windows end on the step grid (multiples of the
    /// step from time zero, at least one step on), so every step is a whole step.
    fn window_end(&self) -> f64 {
        let h = self.window_length();
        let t1 = match self.physics.method {
            Method::Verlet { step } => {
                let k0 = (self.t / step).round();
                (((self.t + h) / step).floor().max(k0 + 1.0)) * step
            }
            Method::Adaptive | Method::Hybrid { .. } => self.t + h,
        };
        t1.min(self.end)
    }

    /// Window length: about the time the fastest shot needs to cross the smallest shot's
    /// diameter, so islands stay small.
    fn window_length(&self) -> f64 {
        let mut v_max: f64 = 0.0;
        let mut d_min = f64::INFINITY;
        let mut cursor = 0;
        for &i in &self.live {
            // A sleeper is active and entered; its diameter is kept with it (its state,
            // far in memory, is not read).
            if let Some(z) = self.sleepers.find(i, &mut cursor) {
                d_min = d_min.min(z.diameter);
                continue;
            }
            let s = &self.shots[i];
            if s.is_active() && s.t_start <= self.t {
                v_max = v_max.max(s.vel.norm());
                d_min = d_min.min(2.0 * s.body.radius);
            }
        }
        // A sleeper's speed counts where it could be the largest (read off its step).
        for z in self.sleepers.iter() {
            if z.speed_bound() > v_max {
                v_max = v_max.max(z.speed_at(&self.physics, &self.shots[z.id], self.t));
            }
        }
        if !d_min.is_finite() {
            // Nobody has entered yet: jump to the next entry (bounded by MAX_WINDOW):
            // admitted shots not yet entered, or the next in the feed's queue.
            let next = self
                .live
                .iter()
                .chain(self.by_start.get(self.admitted))
                .map(|&i| &self.shots[i])
                .chain(self.feed.as_ref().and_then(|f| f.1.as_ref()))
                .filter(|s| s.is_active() && s.t_start > self.t)
                .map(|s| s.t_start)
                .fold(f64::INFINITY, f64::min);
            return (next - self.t).clamp(MIN_WINDOW, MAX_WINDOW);
        }
        if matches!(self.physics.method, Method::Verlet { .. }) {
            // Every shot takes the same fixed step whatever its island, so large islands
            // cost nothing extra (`window` does not shrink them): windows only bound the
            // candidate pairs, as a DEM code's neighbour-list skin does. An eighth of a
            // diameter at the fastest speed gives each shot a reach of about a fifth of a
            // diameter (the 1.5 kick margin), LIGGGHTS' usual skin.
            return (VERLET_WINDOW * d_min / v_max.max(1e-9)).clamp(MIN_WINDOW, MAX_WINDOW);
        }
        // Grow by at most 4x per window: dense groups need short windows, and starting
        // from a long one would make the first candidate search percolate.
        (d_min / v_max.max(1e-9))
            .min(4.0 * self.last_window)
            .clamp(MIN_WINDOW, MAX_WINDOW)
    }

    /// Candidate pairs (sorted) for the window `[t0, t1]` out of `widest` (pairs found
    /// with the absolute reach of a longer window, sorted), given the window's shots
    /// `idx` (ascending; `slot` their places in it) and each shot's absolute reach `reach`.
    ///
    /// A shot that touches nothing during the window keeps its velocity up to body forces,
    /// so two such shots can only meet if their *relative* motion closes the gap:
    /// `gap < |v_i - v_j| H + (a_i + a_j) H^2 / 2`. Shots moving together (a stream, a
    /// falling pack) are then independent however close. A shot that may be kicked (its
    /// absolute reach touches the specimen or the bore wall, or it is in a pair closing by
    /// relative motion, or in contact) may leave with any velocity, so its pairs use the
    /// absolute reach, and whoever it may hit may be kicked in turn: the kicked set is
    /// propagated through the absolute-reach pairs. `kicked` is set for the shots in such
    /// pairs only (a shot alone within its reach has no pair to keep, so its walls are
    /// not tested: session 35, -2.2 % instructions on the nozzle stream).
    fn refine_candidates(
        &self,
        (idx, slot): (&[usize], &ById<u32>),
        widest: &[(u32, u32)],
        (reach, acc): (&ById<f64>, &ById<f64>),
        kicked: &mut ById<bool>,
        t0: f64,
        t1: f64,
    ) -> Vec<(u32, u32)> {
        let span = t1 - t0;
        let entered = |i: usize| self.shots[i].t_start < t1;
        // Pairs within absolute reach (and pairs in contact), both shots taking part.
        let abs: Vec<(u32, u32)> = widest
            .iter()
            .copied()
            .filter(|&(a, b)| {
                let (a, b) = (a as usize, b as usize);
                entered(a)
                    && entered(b)
                    && ((self.shots[a].pos - self.shots[b].pos).norm() < reach[a] + reach[b]
                        || self.pairs.contains_key(&(a as u32, b as u32)))
            })
            .collect();
        let closing =
            |a: usize, b: usize| closing(&self.shots[a], &self.shots[b], acc[a] + acc[b], span);
        // The kicked set spreads over the pairs within absolute reach, so it is a union
        // of their components: a component is kicked if a member may meet a wall, or a
        // pair of it touches or closes by relative motion.
        let n = idx.len();
        let mut uf = SlotUnionFind::new(n);
        // Only shots in a pair within absolute reach: a shot without one is an island of
        // its own, whose wall contacts its integration locates, and its flag is read
        // nowhere (the sub-windows' `may_kick` is for islands of three or more).
        let mut paired = vec![false; n];
        for &(a, b) in &abs {
            paired[slot[a as usize] as usize] = true;
            paired[slot[b as usize] as usize] = true;
        }
        let mut seed = vec![false; n];
        for (k, &i) in idx.iter().enumerate() {
            let s = &self.shots[i];
            seed[k] = paired[k]
                && s.is_active()
                && entered(i)
                && near_a_wall(&self.physics, s, reach[i], acc[i], t0, t1);
        }
        for &(a, b) in &abs {
            let (ka, kb) = (slot[a as usize] as usize, slot[b as usize] as usize);
            if self.pairs.contains_key(&(a, b)) || closing(a as usize, b as usize) {
                seed[ka] = true;
                seed[kb] = true;
            }
            uf.union(ka, kb);
        }
        let mut root_kicked = vec![false; n];
        for k in 0..n {
            if seed[k] {
                root_kicked[uf.find(k)] = true;
            }
        }
        for (k, &i) in idx.iter().enumerate() {
            kicked[i] = root_kicked[uf.find(k)];
        }
        abs.into_iter()
            .filter(|&(a, b)| {
                kicked[a as usize] || kicked[b as usize] || closing(a as usize, b as usize)
            })
            .collect()
    }

    /// Candidate pairs (global ids, sorted) for a window ending at `t1` (the longest): the
    /// shots `idx` with their reach-inflated radii `reach` ([`inflated_radius`]), plus
    /// every pair in contact;
    /// and the sleepers whose balls met anything, woken at the window's start (ascending).
    /// Their pairs are among the candidates, found with their balls (which hold their
    /// reach balls): `refine_candidates` tests the reach.
    fn candidates(
        &mut self,
        idx: &[usize],
        reach: &ById<f64>,
        t1: f64,
    ) -> (Vec<(u32, u32)>, Vec<usize>) {
        // The window's shots and the sleepers, ascending by id, each with its ball.
        let mut ids = Vec::with_capacity(idx.len() + self.sleepers.len());
        let mut centres = Vec::with_capacity(ids.capacity());
        let mut inflated = Vec::with_capacity(ids.capacity());
        let mut skin = Vec::with_capacity(ids.capacity());
        let (t0, h) = (self.t, t1 - self.t);
        // Which entries are sleepers, and which met another ball.
        let mut asleep = Vec::with_capacity(ids.capacity());
        let mut zs = self.sleepers.iter().peekable();
        for &i in idx {
            while let Some(z) = zs.next_if(|z| z.id < i) {
                ids.push(z.id);
                centres.push(z.centre(t0));
                inflated.push(z.radius(h));
                skin.push(BROAD_SKIN * z.diameter);
                asleep.push(true);
            }
            ids.push(i);
            centres.push(self.shots[i].pos);
            inflated.push(reach[i]);
            skin.push(2.0 * BROAD_SKIN * self.shots[i].body.radius);
            asleep.push(false);
        }
        for z in zs {
            ids.push(z.id);
            centres.push(z.centre(t0));
            inflated.push(z.radius(h));
            skin.push(BROAD_SKIN * z.diameter);
            asleep.push(true);
        }
        // Shot ids are their indices and `ids` ascends: the pairs stay sorted.
        let local = self.cells.pairs_tracked(&centres, &inflated, &ids, &skin);
        if !self.cells.filtered_last() {
            self.work.neighbour_searches += 1;
        }
        // Shots with a pair (a lone one among them does not fall asleep after the window:
        // it would wake at once), and the sleepers met.
        let mut met = vec![false; ids.len()];
        for &(a, b) in &local {
            met[a as usize] = true;
            met[b as usize] = true;
        }
        self.near_buf.reset(&self.shots, false);
        let mut woken = Vec::new();
        for (k, &i) in ids.iter().enumerate() {
            if met[k] {
                self.near_buf[i] = true;
                if asleep[k] {
                    woken.push(i);
                }
            }
        }
        if !woken.is_empty() {
            let mut k = 0;
            self.wake_sleepers(t0, |z| {
                while woken.get(k).is_some_and(|&i| i < z.id) {
                    k += 1;
                }
                woken.get(k) == Some(&z.id)
            });
        }
        let mut candidates: Vec<(u32, u32)> = local
            .into_iter()
            .map(|(a, b)| (ids[a as usize] as u32, ids[b as usize] as u32))
            .collect();
        if !self.pairs.is_empty() {
            candidates.extend(self.pairs.keys().copied());
            candidates.sort_unstable();
            candidates.dedup();
        }
        (candidates, woken)
    }

    /// Runs one synchronisation window from `self.t` to at most `t1`, and returns where
    /// it ended. The window shrinks (by 4, a few times) while an island would hold more
    /// than [`MAX_ISLAND`] shots: shots that may touch share a clock, so a large island
    /// makes all its shots pay the smallest step among them. Islands held together by
    /// contacts in progress cannot be split, and are accepted as they are.
    fn window(&mut self, t1: f64) -> f64 {
        let t0 = self.t;
        self.windows += 1;
        // A shot that stopped meanwhile must not leave a stale contact behind, nor one
        // whose entry was held back after its onset with a shot at the inlet was found
        // (`island::hold_entries`): it has not entered yet, and its partner may fall
        // asleep before it does.
        let live = |s: &ShotState| s.is_active() && s.t_start <= t0;
        self.pairs
            .retain(|k, _| live(&self.shots[k.0 as usize]) && live(&self.shots[k.1 as usize]));
        self.admit(|t| t < t1);
        self.wake_sleepers(t0, |z| z.due(t1));
        loop {
            if let Some(end) = self.window_pass(t1) {
                return end;
            }
            // A shot went beyond its reach: the overlap search looks at every shot's end.
            self.wake_sleepers(t0, |_| true);
        }
    }

    /// Whether shot `i` is awake (by a search of the sleepers).
    fn awake(&self, i: u32) -> bool {
        !self.sleepers.iter().any(|z| z.id == i as usize)
    }

    /// Wakes the sleepers `pick` chooses at `t` (their states read off their steps).
    fn wake_sleepers(&mut self, t: f64, pick: impl FnMut(&Sleeper) -> bool) {
        for z in self.sleepers.take(pick) {
            z.wake(&self.physics, &mut self.shots[z.id], t);
        }
    }

    /// [`Self::window`] once its shots are admitted and its sleepers due woken: `None`
    /// when a shot went beyond its reach while others sleep (nothing committed).
    fn window_pass(&mut self, t1: f64) -> Option<f64> {
        let t0 = self.t;
        let (h0, mut t1) = (t1 - t0, t1);
        let mut contact: Option<usize> = None;
        // Shots taking part: active, awake and entering before the (longest) window ends.
        let mut cursor = 0;
        let mut all: Vec<usize> = self
            .live
            .iter()
            .copied()
            .filter(|&i| self.sleepers.find(i, &mut cursor).is_none())
            .filter(|&i| self.shots[i].is_active() && self.shots[i].t_start < t1)
            .collect();
        if all.is_empty() && self.sleepers.is_empty() {
            return Some(t1);
        }
        let mut reach = std::mem::take(&mut self.reach_buf);
        let mut kicked = std::mem::take(&mut self.kicked_buf);
        let mut slot = std::mem::take(&mut self.slot_buf);
        let mut acc = std::mem::take(&mut self.acc_buf);
        reach.reset(&self.shots, 0.0);
        acc.reset(&self.shots, 0.0);
        kicked.reset(&self.shots, false);
        slot.reset(&self.shots, u32::MAX);
        for &i in &all {
            acc[i] = body_acc(&self.physics, &self.shots[i]);
            reach[i] = inflated_radius(&self.shots[i], acc[i], t0, t1);
        }
        // Candidates for the longest window; shorter windows only need a subset of them.
        // Sleepers whose balls meet anything wake and join.
        let (widest, woken) = self.candidates(&all, &reach, t1);
        if !woken.is_empty() {
            for &i in &woken {
                acc[i] = body_acc(&self.physics, &self.shots[i]);
                reach[i] = inflated_radius(&self.shots[i], acc[i], t0, t1);
            }
            all.extend(woken);
            all.sort_unstable();
        }
        if all.is_empty() {
            // Nobody awake, and no sleeper's ball met another's: they sleep through.
            (self.reach_buf, self.kicked_buf, self.slot_buf, self.acc_buf) =
                (reach, kicked, slot, acc);
            self.work.shot_windows_slept += self.sleepers.len() as u64;
            return Some(t1);
        }
        // The window end `reach` holds (the longest first, as `all` is).
        let mut reach_t1 = t1;
        let (idx, mut candidates) = loop {
            let idx: Vec<usize> = all
                .iter()
                .copied()
                .filter(|&i| self.shots[i].t_start < t1)
                .collect();
            if t1 != reach_t1 {
                for &i in &idx {
                    reach[i] = inflated_radius(&self.shots[i], acc[i], t0, t1);
                }
                reach_t1 = t1;
            }
            // Places in this (possibly shortened) window's `idx`; none for shots that
            // enter after it.
            for &i in &all {
                slot[i] = u32::MAX;
            }
            for (k, &i) in idx.iter().enumerate() {
                slot[i] = k as u32;
            }
            let candidates =
                self.refine_candidates((&idx, &slot), &widest, (&reach, &acc), &mut kicked, t0, t1);
            // With the fixed-step method an island's size costs nothing (every shot
            // takes the same step anyway): islands are not split.
            if !self.physics.method.adaptive_flight() {
                break (idx, candidates);
            }
            let largest = largest_island(&idx, &slot, candidates.iter());
            // Stop when islands are small, when they are mostly held together by contacts
            // in progress (shrinking cannot split those), or at the shortest window.
            let contact =
                *contact.get_or_insert_with(|| largest_island(&idx, &slot, self.pairs.keys()));
            if largest <= MAX_ISLAND.max(2 * contact) || t1 - t0 <= 4.0 * MIN_WINDOW {
                break (idx, candidates);
            }
            t1 = t0 + 0.25 * (t1 - t0);
        };
        self.reach_buf = reach;
        self.kicked_buf = kicked;
        self.acc_buf = acc;
        loop {
            let islands = Islands::form(&idx, &slot, &candidates);
            let results = self.integrate_islands(&islands, t0, t1);
            // Verify: an overlap at the window end between shots that were not paired
            // means the reach bound was beaten (e.g. a shot kicked by a collision).
            let ends: Vec<Vec3> = {
                let mut pos = vec![Vec3::zeros(); idx.len()];
                for ((isl, _), result) in islands.iter().zip(&results) {
                    for (k, &gi) in isl.iter().enumerate() {
                        pos[slot[gi] as usize] = match result {
                            IslandResult::Kept(kept) => kept.pos(),
                            IslandResult::Stepped(members, ..) => members[k].pos,
                        };
                    }
                }
                pos
            };
            // Only a shot that moved farther than the reach its pairs were found with can
            // meet a shot it was not paired with: a shot within its reach that flew with
            // body forces alone (not kicked) kept to its relative-motion bound, and every
            // pair within absolute reach involving a kicked shot is a candidate. Without
            // such a shot the overlap search is skipped (it would find nothing).
            let escaped = idx.iter().zip(&ends).any(|(&i, e)| {
                let s = &self.shots[i];
                (e - s.pos).norm() > self.reach_buf[i] - s.body.radius
            });
            if !escaped {
                self.commit_islands(&islands, results, (t1, h0));
                break;
            }
            // The search looks at every shot's end: the sleepers' read off their steps.
            let mut ends = ends;
            let mut ids = idx.clone();
            for z in self.sleepers.iter() {
                ids.push(z.id);
                ends.push(z.pos_at(&self.physics, &self.shots[z.id], t1));
            }
            let radii: Vec<f64> = ids.iter().map(|&i| self.shots[i].body.radius).collect();
            self.work.neighbour_searches += 1;
            let missed: Vec<(u32, u32)> = self
                .cells
                .pairs(&ends, &radii)
                .into_iter()
                .map(|(a, b)| {
                    let (a, b) = (ids[a as usize] as u32, ids[b as usize] as u32);
                    (a.min(b), a.max(b))
                })
                .filter(|p| candidates.binary_search(p).is_err())
                .collect();
            if !self.sleepers.is_empty()
                && missed
                    .iter()
                    .any(|&(a, b)| !self.awake(a) || !self.awake(b))
            {
                // A sleeper met: the window again with every shot awake.
                self.slot_buf = slot;
                return None;
            }
            if !missed.is_empty() {
                self.window_redos += 1;
                candidates.extend(missed);
                candidates.sort_unstable();
                continue;
            }
            self.commit_islands(&islands, results, (t1, h0));
            break;
        }
        self.slot_buf = slot;
        let shots = &self.shots;
        let stopped = &mut self.stopped;
        let (sleepers, mut cursor) = (&self.sleepers, 0);
        self.live.retain(|&i| {
            let active = sleepers.find(i, &mut cursor).is_some() || shots[i].is_active();
            if !active {
                stopped.push(i);
            }
            active
        });
        self.pairs
            .retain(|k, _| shots[k.0 as usize].is_active() && shots[k.1 as usize].is_active());
        Some(t1)
    }

    fn integrate_islands(&self, islands: &Islands, t0: f64, t1: f64) -> Vec<IslandResult> {
        let phys = &self.physics;
        let snap = self.snapshot_interval;
        let run = |scratch: &mut Scratch, (members_idx, gpairs): (&[usize], &[(u32, u32)])| {
            // A lone shot whose kept step covers the window only reads its state there
            // (`island::advance_alone` would do the same on a copy of it).
            if let ([i], [], None) = (members_idx, gpairs, snap)
                && let Some(kept) = island::Kept::read(phys, &self.shots[*i], t1)
            {
                return IslandResult::Kept(kept);
            }
            let mut members: Vec<ShotState> =
                members_idx.iter().map(|&i| self.shots[i].clone()).collect();
            // Members are in ascending order (`form_islands` keeps `idx`'s): a pair's
            // local indices by binary search (a linear one cost 9 % of a 3,000-shot
            // pile on the fixed-step method, whose islands hold up to every shot).
            debug_assert!(members_idx.windows(2).all(|w| w[0] < w[1]));
            let local = |g: u32| {
                members_idx
                    .binary_search(&(g as usize))
                    .expect("BUG: pair outside island") as u32
            };
            let mut pairs: Vec<IslandPair> = gpairs
                .iter()
                .map(|&(a, b)| {
                    let st = self.pairs.get(&(a, b));
                    IslandPair {
                        a: local(a),
                        b: local(b),
                        touching: st.is_some(),
                        contact_time: st.map_or(0.0, |s| s.contact_time),
                        onset: st.map_or(0.0, |s| s.onset),
                        xi: st.map_or(Vec3::zeros(), |s| s.xi),
                    }
                })
                .collect();
            let mut out = IslandOutput::default();
            let split = self.sub_windows
                && members.len() >= SPLIT_MIN
                && phys.method.adaptive_flight()
                && members.iter().all(|m| m.t_start <= t0);
            let pts = if split {
                let kick: Vec<bool> = members_idx.iter().map(|&i| self.kicked_buf[i]).collect();
                let (m, p) = (&mut members, &mut pairs);
                let apart = self.separate_clocks;
                advance_split(phys, m, p, &kick, (t0, t1), scratch, &mut out, snap, apart)
            } else {
                advance_island(
                    phys,
                    &mut members,
                    &mut pairs,
                    t0,
                    t1,
                    scratch,
                    &mut out,
                    snap,
                    self.separate_clocks,
                )
            };
            let keyed = gpairs.iter().copied().zip(pairs).collect();
            IslandResult::Stepped(members, keyed, out, pts)
        };
        // Small windows run on this thread: handing a window's few steps to the pool and
        // waking its workers costs more than it saves (measured: the 10,000-shot nozzle
        // stream ran 30 % slower on one worker of the pool than on this thread, and no
        // faster on two). Same results either way.
        // Shots that will take steps (a lone shot whose kept step covers the window only
        // reads its state from it).
        let busy: usize = islands
            .iter()
            .filter(|(isl, pairs)| {
                isl.len() > 1
                    || !pairs.is_empty()
                    || self.shots[isl[0]]
                        .ahead
                        .as_ref()
                        .is_none_or(|a| a.end() <= t1)
            })
            .map(|(isl, _)| isl.len())
            .sum();
        if rayon::current_num_threads() == 1 || busy < self.parallel_min_shots {
            let mut scratch = Scratch::default();
            islands.iter().map(|x| run(&mut scratch, x)).collect()
        } else {
            (0..islands.len())
                .into_par_iter()
                .map_init(Scratch::default, |scratch, k| run(scratch, islands.get(k)))
                .collect()
        }
    }

    /// Stores the islands' results at the window's end `t1`, and puts lone shots riding a
    /// kept step to sleep (`h0` the window's length before it shrank, if it did).
    fn commit_islands(
        &mut self,
        islands: &Islands,
        results: Vec<IslandResult>,
        (t1, h0): (f64, f64),
    ) {
        let sleep =
            self.sleep && self.snapshot_interval.is_none() && self.physics.method.adaptive_flight();
        let mut asleep = Vec::new();
        for ((isl, gpairs), result) in islands.iter().zip(results) {
            let (members, pairs, out, pts) = match result {
                IslandResult::Kept(kept) => {
                    let s = &mut self.shots[isl[0]];
                    kept.store(s);
                    if sleep && !self.near_buf[isl[0]] {
                        asleep.extend(Sleeper::new(&self.physics, s, t1, h0));
                    }
                    continue;
                }
                IslandResult::Stepped(members, pairs, out, pts) => (members, pairs, out, pts),
            };
            let lone = sleep && members.len() == 1 && gpairs.is_empty() && !self.near_buf[isl[0]];
            self.snapshot_points.extend(pts);
            for (k, m) in members.into_iter().enumerate() {
                self.shots[isl[k]] = m;
            }
            let s = &self.shots[isl[0]];
            if lone && s.is_active() {
                asleep.extend(Sleeper::new(&self.physics, s, t1, h0));
            }
            for (key, p) in pairs {
                if p.touching {
                    self.pairs.insert(
                        key,
                        PairState {
                            contact_time: p.contact_time,
                            onset: p.onset,
                            xi: p.xi,
                        },
                    );
                } else {
                    self.pairs.remove(&key);
                }
            }
            self.commit_output(out);
        }
        self.work.shot_windows_slept += self.sleepers.len() as u64;
        self.sleepers.extend(asleep);
    }
}

/// Whether a shot never touched the specimen.
pub fn never_hit(s: &ShotState) -> bool {
    s.hits == 0
}

/// Counts of shots by status.
pub fn status_counts(shots: &[ShotState]) -> [(ShotStatus, usize); 3] {
    let count = |st| shots.iter().filter(|s| s.status == st).count();
    [
        (ShotStatus::Active, count(ShotStatus::Active)),
        (ShotStatus::LeftDomain, count(ShotStatus::LeftDomain)),
        (ShotStatus::Failed, count(ShotStatus::Failed)),
    ]
}

/// Union-find over slots `0..n` (a window's shots by their place in its ascending
/// `idx`, an island's members): the root of a set is its smallest slot, hence its
/// smallest shot id.
struct SlotUnionFind {
    parent: Vec<u32>,
}

impl SlotUnionFind {
    fn new(n: usize) -> Self {
        SlotUnionFind {
            parent: (0..n as u32).collect(),
        }
    }

    fn find(&mut self, x: usize) -> usize {
        let mut x = x as u32;
        while self.parent[x as usize] != x {
            let up = self.parent[self.parent[x as usize] as usize];
            self.parent[x as usize] = up;
            x = up;
        }
        x as usize
    }

    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb) as u32;
        }
    }
}

/// The slot of shot `g` in a window's `idx` (the candidate pairs' shots all take part).
#[inline]
fn slot_of(slot: &ById<u32>, g: u32) -> usize {
    let k = slot[g as usize];
    assert!(
        k != u32::MAX,
        "BUG: a candidate pair's shot outside the window"
    );
    k as usize
}

/// Size of the largest connected group of `idx` under `pairs` (union-find only). A
/// pair's shot outside `idx` (a contact of a shot held back at the inlet, entering after
/// the window) is a node of its own, which still links the shots it touches.
fn largest_island<'a>(
    idx: &[usize],
    slot: &ById<u32>,
    pairs: impl Iterator<Item = &'a (u32, u32)>,
) -> usize {
    let mut uf = SlotUnionFind::new(idx.len());
    let mut extra: HashMap<u32, usize> = HashMap::default();
    let mut node = |uf: &mut SlotUnionFind, g: u32| match slot.get(g as usize) {
        Some(&k) if k != u32::MAX => k as usize,
        _ => *extra.entry(g).or_insert_with(|| {
            uf.parent.push(uf.parent.len() as u32);
            uf.parent.len() - 1
        }),
    };
    for &(a, b) in pairs {
        let (ka, kb) = (node(&mut uf, a), node(&mut uf, b));
        uf.union(ka, kb);
    }
    let mut size = vec![0u32; idx.len()];
    let mut largest = 0;
    for k in 0..idx.len() {
        let r = uf.find(k);
        size[r] += 1;
        largest = largest.max(size[r] as usize);
    }
    largest
}

/// A window's islands: the connected groups of its shots under the candidate pairs,
/// ordered by their smallest shot id, each with its members (ascending) and its pairs
/// (sorted), stored flat (no allocation per island: most are lone shots).
struct Islands {
    members: Vec<usize>,
    starts: Vec<u32>,
    pairs: Vec<(u32, u32)>,
    pair_starts: Vec<u32>,
}

impl Islands {
    /// The islands of `idx` (ascending; `slot` its inverse) under `candidates`
    /// (sorted, both shots in `idx`).
    fn form(idx: &[usize], slot: &ById<u32>, candidates: &[(u32, u32)]) -> Self {
        let n = idx.len();
        let mut uf = SlotUnionFind::new(n);
        for &(a, b) in candidates {
            uf.union(slot_of(slot, a), slot_of(slot, b));
        }
        // Islands numbered as their smallest slot comes up; members by counting sort.
        let mut of_root = vec![u32::MAX; n];
        let mut island = vec![0u32; n];
        let mut count = 0u32;
        let mut starts = vec![0u32];
        for k in 0..n {
            let r = uf.find(k);
            if of_root[r] == u32::MAX {
                of_root[r] = count;
                count += 1;
                starts.push(0);
            }
            island[k] = of_root[r];
            starts[island[k] as usize + 1] += 1;
        }
        for c in 0..count as usize {
            starts[c + 1] += starts[c];
        }
        let mut members = vec![0usize; n];
        let mut fill = starts.clone();
        for (k, &i) in idx.iter().enumerate() {
            let c = island[k] as usize;
            members[fill[c] as usize] = i;
            fill[c] += 1;
        }
        let mut pair_starts = vec![0u32; count as usize + 1];
        for &(a, _) in candidates {
            pair_starts[island[slot_of(slot, a)] as usize + 1] += 1;
        }
        for c in 0..count as usize {
            pair_starts[c + 1] += pair_starts[c];
        }
        let mut pairs = vec![(0u32, 0u32); candidates.len()];
        let mut fill = pair_starts.clone();
        for &p in candidates {
            let c = island[slot_of(slot, p.0)] as usize;
            pairs[fill[c] as usize] = p;
            fill[c] += 1;
        }
        Islands {
            members,
            starts,
            pairs,
            pair_starts,
        }
    }

    fn len(&self) -> usize {
        self.starts.len() - 1
    }

    /// Island `k`'s members and pairs.
    fn get(&self, k: usize) -> (&[usize], &[(u32, u32)]) {
        let (a, b) = (self.starts[k] as usize, self.starts[k + 1] as usize);
        let (c, d) = (
            self.pair_starts[k] as usize,
            self.pair_starts[k + 1] as usize,
        );
        (&self.members[a..b], &self.pairs[c..d])
    }

    fn iter(&self) -> impl Iterator<Item = (&[usize], &[(u32, u32)])> {
        (0..self.len()).map(|k| self.get(k))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn path(samples: &[(f64, [f64; 3], [f64; 3])]) -> Path {
        samples
            .iter()
            .map(|&(t, p, v)| (t, Vec3::from(p), Vec3::from(v)))
            .collect()
    }

    #[test]
    fn paths_that_cross_between_their_samples_meet() {
        // Head-on along x, 10 apart at both samples' times... but they cross at t = 0.5.
        let a = path(&[
            (0.0, [-5.0, 0.0, 0.0], [10.0, 0.0, 0.0]),
            (1.0, [5.0, 0.0, 0.0], [10.0, 0.0, 0.0]),
        ]);
        let b = path(&[
            (0.0, [5.0, 0.0, 0.0], [-10.0, 0.0, 0.0]),
            (1.0, [-5.0, 0.0, 0.0], [-10.0, 0.0, 0.0]),
        ]);
        assert!(!paths_keep_apart(&a, &b, 0.1));
        // The same, 2 apart in y: they pass clear of a contact distance of 1.
        let c = path(&[
            (0.0, [5.0, 2.0, 0.0], [-10.0, 0.0, 0.0]),
            (1.0, [-5.0, 2.0, 0.0], [-10.0, 0.0, 0.0]),
        ]);
        assert!(paths_keep_apart(&a, &c, 1.0));
        assert!(!paths_keep_apart(&a, &c, 2.5));
    }

    #[test]
    fn paths_sampled_at_different_times_are_compared_on_every_piece() {
        // `a` turns at t = 0.5 (a sample of its own), towards `b`'s straight path.
        let a = path(&[
            (0.0, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            (0.5, [0.5, 0.0, 0.0], [0.0, 1.0, 0.0]),
            (1.0, [0.5, 0.5, 0.0], [0.0, 1.0, 0.0]),
        ]);
        let b = path(&[
            (0.0, [0.5, 0.6, 0.0], [0.0, 0.0, 0.0]),
            (1.0, [0.5, 0.6, 0.0], [0.0, 0.0, 0.0]),
        ]);
        // Closest at t = 1: 0.1 apart (the chord error bound of a's corner piece is zero
        // at its ends: its velocity is constant along it).
        assert!(!paths_keep_apart(&a, &b, 0.2));
        assert!(paths_keep_apart(&a, &b, 0.05));
        // Only while both are known: `late`, known from t = 0.6, sits 0.3 from a's first
        // piece (which, widened by its bound, would reach it) and 0.25 from its second.
        let late = path(&[
            (0.6, [0.25, 0.3, 0.0], [0.0, 0.0, 0.0]),
            (1.0, [0.25, 0.3, 0.0], [0.0, 0.0, 0.0]),
        ]);
        assert!(paths_keep_apart(&a, &late, 0.2));
        let all_along = path(&[
            (0.0, [0.25, 0.3, 0.0], [0.0, 0.0, 0.0]),
            (1.0, [0.25, 0.3, 0.0], [0.0, 0.0, 0.0]),
        ]);
        assert!(!paths_keep_apart(&a, &all_along, 0.2));
    }

    #[test]
    fn a_curved_piece_is_widened_by_its_error_bound() {
        // `a` goes out along x and comes back within one piece: x(t) = t - t^2, at the
        // origin at both ends, 0.25 out at t = 0.5. `b` sits at x = 0.3: the chord says
        // 0.3 apart, the path comes within 0.05.
        let a = path(&[
            (0.0, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            (1.0, [0.0, 0.0, 0.0], [-1.0, 0.0, 0.0]),
        ]);
        let b = path(&[
            (0.0, [0.3, 0.0, 0.0], [0.0, 0.0, 0.0]),
            (1.0, [0.3, 0.0, 0.0], [0.0, 0.0, 0.0]),
        ]);
        assert!(!paths_keep_apart(&a, &b, 0.1));
        // No change of velocity, but both ends' velocity off the chord's: the cubic
        // through them, y(s) = h s (1 - s)(1 - 2 s), leaves the chord by up to 0.096
        // (at s = 0.21) and comes within 0.26 of `near`, which the chord keeps 0.35 from.
        let s = path(&[
            (0.0, [0.0, 0.0, 0.0], [1.0, 1.0, 0.0]),
            (1.0, [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]),
        ]);
        let near = path(&[
            (0.0, [0.2, 0.35, 0.0], [0.0, 0.0, 0.0]),
            (1.0, [0.2, 0.35, 0.0], [0.0, 0.0, 0.0]),
        ]);
        assert!(!paths_keep_apart(&s, &near, 0.3));
        assert!(paths_keep_apart(&s, &near, 0.05));
    }
}
