//! Event scheduler: the fast path for scenes whose free flight is ballistic (no air
//! forces, no nozzle wall; gravity optional), such as LIGGGHTS' falling pack.
//!
//! ```text
//! free shots fly in closed form (flight.rs); a priority queue holds, per free shot, the
//! times at which it enters, touches another free shot or the specimen, leaves the domain
//! or crosses a cell of the persistent grid (grid.rs)
//! pop the earliest event:
//!   cell crossing: move the shot, predict touches with the shots of the new cell layer
//!   touch (shot-shot or shot-specimen): a cluster = the shots involved, plus every shot
//!     that may come within contact while the contact lasts; the cluster is integrated by
//!     the island integrator (integrate::island::advance_until_apart) from just before
//!     the touch until no contact is left, then its shots fly free again
//! ```
//!
//! Free flight costs no steps at all: a shot pays integrator steps only while in contact,
//! where its steps are the island integrator's (same contact law, onset location, impact
//! record and accuracy controls as the window scheduler in `sim.rs`).
//!
//! **The fixed-step method** (`method = "verlet"`, with `scheduler = "events"` asked
//! for) runs here too: a cluster is stepped by velocity Verlet at the fixed step from
//! its start (`island::advance_until_apart`), contacts seen at step ends and impacts
//! recorded at the touch, as on windows, and the history law's tangential
//! displacements are kept across chunks with the pairs (`PairState::xi`) and the shots
//! (`ShotState::specimen_xi`). Only the step grid differs from the windows run's (it
//! starts at each cluster's start, not at zero). Every contact opens a cluster: the
//! lean path is the adaptive method's.
//!
//! **Look-ahead and its guards.** A cluster is integrated ahead of the queue's time (to
//! the end of its contact), so a shot outside it must not reach it meanwhile:
//! * shots whose free path comes within contact distance (plus 10 %) of a member's free
//!   path during the chunk join the cluster (closure over the new members);
//! * after integration, the members' actual paths are compared with the free paths of
//!   the shots left outside; an overlap means the cluster is redone with that shot
//!   (`cluster_redos`);
//! * a nearby shot with a pending touch of its own before the chunk ends (its path is
//!   about to change) cuts the chunk there (or joins, if that is imminent); shots already
//!   resolved further ahead, and shots of other clusters in progress, join if they are
//!   within the speed bound (they stay frozen until their own clock);
//! * the gathering assumes no shot moves faster than the speed bound (the fastest free
//!   shot, plus what gravity can add); a member seen faster than that inside the chunk
//!   (shots squeezed between others can leave faster than they came) makes the cluster
//!   gather again with the speed it reached (`cluster_redos`);
//! * a nearby shot's pending touch is a lower bound kept from its last prediction; one
//!   already past is stale (predicted with a shot whose path has changed since) and is
//!   found afresh before it is relied on (`Engine::pending`: until session 59 such a
//!   shot was taken as free for good, and a contact it hid was met 2 um deep);
//! * a free shot's pending touch says when its path changes only while the paths around
//!   it stay as they are: a shot near it may change first (at its own touch, or as its
//!   cluster resumes) and then reach it. The lone path and the gathering take a
//!   relied-on free path as known only until the earliest such change could reach it
//!   (`Engine::chain_bound`: the shot's line against the changing shot's sphere growing
//!   at the speed bound; until session 62 contacts were met 1.5-18.7 um deep this way,
//!   in about one random box in 65);
//! * a member whose group parts before the chunk ends flies free only until its next
//!   touch (with a member then free, a shot outside near it, or the specimen:
//!   `Engine::free_until`); past that, its pairs with the groups that run on, and a shot
//!   outside it touches, are checked with the contact distance widened by what the speed
//!   bound allows, and the chunk is cut at the touch (or the pair carried, the shot
//!   joined) if they may meet (until session 60 they were checked on the free path, and a
//!   contact was met 18 um deep);
//! * continuations that may take the lean path (one contact left) come after the other
//!   clusters resuming at the same time (`Kind::ContinueLone`), which may take in the
//!   free shots the lean path would rely on;
//! * a contact found overlapping when its cluster starts is counted in `late_contacts`
//!   (reported in summary.json: about 1 in 3,000-5,000 contacts on the 10,000-shot
//!   pack, all of them overlaps at the rounding level between shots that had just
//!   parted; deeper ones, contacts missed, also in `late_contacts_deep`).
//!
//! A touch whose contact nobody else can come near while it lasts (one contact, with or
//! without friction: two shots, or a shot and the specimen) is resolved at its event on the lean
//! path without opening a cluster (lone.rs); the rest open clusters as above. A cluster
//! left holding one contact in progress continues it the same way when nobody else can
//! come near.
//!
//! Inside a cluster, only the member pairs whose free paths come within contact distance
//! plus 3 % during the contact's likely span (three Hertz times) are integrated together;
//! a near miss is not. After integration every other candidate pair is checked on the
//! members' actual paths (samples of each step, chords in between) until both are handed
//! back to free flight: a pair whose paths met redoes the chunk with it carried
//! (`cluster_redos`; from the third try every candidate pair is carried). Groups of shots
//! passing close by a contact were integrated with it until session 9, at every step.
//!
//! A member gathered for safety that ends up touching nothing (no pair in its chunk, the
//! specimen out of reach) is not integrated at all: it keeps its free path, its clock
//! and its pending events. A group with a single contact (two shots, or a
//! shot and the specimen) whose other shots fly clear of it takes the lean path
//! (binary.rs: closed-form flight, one body's state through the contact) instead of the
//! island integrator; `Simulation::with_lean_contacts(false)` turns it off. The queue is a calendar queue (queue.rs): same order as one
//! binary heap, cheaper pops.
//!
//! A cluster still in contact after its chunk (a shot resting on the specimen, a
//! persistent clump) continues with chunks doubling up to 0.1 ms; members not in contact
//! are released to free flight. A chunk still unverified after `MAX_REDOS` redos, or
//! latest integrator steps that carry more than `sim::MAX_ISLAND` shots each on average
//! (a pile integrated as one island; `PileWatch`), make the scheduler give up
//! ([`GaveUp`]); the caller redoes the run on windows. Processing is sequential and ordered by (time, kind,
//! shots): results do not depend on the thread count. The engine works on the shots in
//! Z-curve order of where they start (memory locality; `spatial_order`) and keys pairs
//! by shot id, never by its own indices.

pub mod binary;
pub mod flight;
pub mod grid;
mod lone;
pub mod queue;

use crate::Vec3;
use crate::contact::broad::CellList;
use crate::contact::table::{self, ContactTable};
use crate::contact::{PairContact, effective_mass, hertz};
use crate::counters::WorkCounters;
use crate::integrate::island::{
    self, IslandOutput, IslandPair, MIN_CONTACT_SPEED, Method, Physics, Scratch,
};
use crate::state::{ShotState, ShotStatus};
use flight::{Flight, closest_approach, pair_touch};
use grid::Grid;
use queue::Calendar;
use rustc_hash::FxHashMap as HashMap;
use std::cmp::Ordering;

const NONE: u32 = u32::MAX;
/// Longest cluster chunk, s.
const MAX_CHUNK: f64 = 1e-4;
/// Redos of one cluster chunk before the scheduler gives up (`Engine::gave_up`).
const MAX_REDOS: u32 = 8;
/// The scheduler judges its islands' size over its latest integrator steps, in blocks of
/// this many (nothing before the first block ends: the first clusters' sizes say little
/// about the run).
const PILE_BLOCK_STEPS: u64 = 10_000;
/// Blocks the judgement spans: the whole run until there are this many, then the latest
/// `PILE_BLOCKS - 1` whole blocks and the one in progress. Long enough that a burst of
/// large clusters the scheduler gets through passes (55.7 shots per step over one block,
/// 27.8 over four, in a scene it runs in 1.6 s against 2.7 s on windows), short enough
/// that a pile forming late is seen while it forms, not once the whole run's average
/// catches up (session 29: a 3,000-shot pile gave up at 0.305 ms on the whole run's
/// average, 0.26 ms on the latest blocks').
const PILE_BLOCKS: usize = 5;
/// Free paths closer than contact distance times (1 + this) join a cluster.
const SLACK: f64 = 0.1;
/// Cluster members whose free paths come closer than contact distance times (1 + this)
/// within `LINK_HORIZON` Hertz times of the chunk's start are integrated together; the
/// other candidate pairs are verified on the actual paths (measured on the pack stream:
/// 0 and 0.01 redo too many chunks, 0.1 links most near misses; 0.03 is the fewest
/// instructions).
const LINK_SLACK: f64 = 0.03;
/// See `LINK_SLACK` (measured: 1.5 and 2 link too few, redoing more chunks).
const LINK_HORIZON: f64 = 3.0;
/// Clusters larger than this find their pairs with a cell list instead of all pairs.
const ALL_PAIRS_UP_TO: usize = 48;

/// Why a scene cannot use the event scheduler (`None`: it can).
pub fn unsuitable(phys: &Physics) -> Option<&'static str> {
    if phys.forces.field.is_some() || phys.forces.drag.is_some() || phys.forces.lateral.is_some() {
        return Some(
            "the air jet acts on the shots (drag or lateral force on): free flight is not ballistic",
        );
    }
    if phys.forces.turbulence.is_some() {
        return Some("turbulent dispersion is on");
    }
    if phys.contacts.wall.is_some() {
        return Some("nozzle wall contact is on");
    }
    if phys
        .contacts
        .specimen
        .as_ref()
        .is_some_and(|sp| !sp.shape.is_plane())
    {
        return Some(
            "the specimen is not the flat plate (its contacts are predicted on the plane only)",
        );
    }
    if phys.forces.gravity.is_some_and(|g| {
        g.acceleration.x != 0.0 || g.acceleration.y != 0.0 || g.acceleration.z > 0.0
    }) {
        return Some("gravity does not point down (-z)");
    }
    None
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Kind {
    Enter,
    Leave,
    Floor,
    Touch,
    Cross,
    Continue,
    /// A cluster left holding one contact in progress, which may continue on the lean path
    /// (lone.rs): after the others resuming at the same time, which may take in the free
    /// shots it would rely on (session 60).
    ContinueLone,
}

#[derive(Debug, Clone, Copy)]
struct Ev {
    t: f64,
    kind: Kind,
    a: u32,
    b: u32,
    va: u32,
    vb: u32,
}

impl Ord for Ev {
    fn cmp(&self, o: &Self) -> Ordering {
        self.t
            .total_cmp(&o.t)
            .then(self.kind.cmp(&o.kind))
            .then(self.a.cmp(&o.a))
            .then(self.b.cmp(&o.b))
            .then(self.va.cmp(&o.va))
            .then(self.vb.cmp(&o.vb))
    }
}
impl PartialOrd for Ev {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl PartialEq for Ev {
    fn eq(&self, o: &Self) -> bool {
        self.cmp(o) == Ordering::Equal
    }
}
impl Eq for Ev {}

/// Contact state of a touching pair carried between chunks of a cluster.
#[derive(Debug, Clone, Copy)]
struct PairState {
    contact_time: f64,
    onset: f64,
    /// The history law's tangential displacement (`IslandPair::xi`).
    xi: Vec3,
}

#[derive(Debug, Clone)]
struct Cluster {
    /// Member shot indices.
    members: Vec<usize>,
    /// Touching pairs (global ids, ascending).
    pairs: HashMap<(u32, u32), PairState>,
    /// Time the chunk starts.
    clock: f64,
    /// Hertz duration of the contact that started it, s.
    tc: f64,
    /// Chunks run so far.
    chunks: u32,
    /// Do not stop before this time (a touch predicted at `t` happens just after it).
    apart_after: f64,
    /// Onset of the contact that opened the cluster (a continued chunk: its start).
    onset: f64,
    /// Generation (stale `Continue` events carry an older one).
    gen_: u32,
}

/// A free shot's earliest pending touch (`with`: the other shot, or itself for the
/// specimen) and its earliest pending touch with anybody else. Both are lower bounds:
/// touches predicted with shots whose paths changed since stay counted.
#[derive(Debug, Clone, Copy)]
struct Pending {
    t: f64,
    with: u32,
    t_other: f64,
}

impl Pending {
    const NONE: Pending = Pending {
        t: f64::INFINITY,
        with: NONE,
        t_other: f64::INFINITY,
    };

    fn note(&mut self, t: f64, with: usize) {
        let with = with as u32;
        if with == self.with {
            self.t = self.t.min(t);
        } else if t < self.t {
            self.t_other = self.t;
            self.t = t;
            self.with = with;
        } else {
            self.t_other = self.t_other.min(t);
        }
    }

    /// Earliest pending touch with anybody but `who`.
    fn without(&self, who: &[usize]) -> f64 {
        if who.iter().any(|&i| i as u32 == self.with) {
            self.t_other
        } else {
            self.t
        }
    }
}

/// Counts a contact found overlapping by `depth` (m) in `late_contacts`, and in
/// `late_contacts_deep` if that is more than [`LATE_DEPTH`] of `scale` (the contact
/// distance of a pair, a shot's radius on the specimen).
fn count_late(work: &mut WorkCounters, depth: f64, scale: f64) {
    work.late_contacts += 1;
    work.late_contacts_deep += u64::from(depth > LATE_DEPTH * scale);
}

/// An overlap found at a contact's start deeper than this share of its scale is a
/// contact missed ([`count_late`]); shallower ones are two shots that had just parted,
/// meeting again at the rounding level (about 1e-15 of the contact distance).
const LATE_DEPTH: f64 = 1e-9;

/// The root (smallest node) of each of `n` nodes' connected group under `edges`.
fn group_roots(n: usize, edges: impl Iterator<Item = (usize, usize)>) -> Vec<usize> {
    fn root(p: &mut [usize], mut x: usize) -> usize {
        while p[x] != x {
            p[x] = p[p[x]];
            x = p[x];
        }
        x
    }
    let mut parent: Vec<usize> = (0..n).collect();
    for (a, b) in edges {
        let (a, b) = (root(&mut parent, a), root(&mut parent, b));
        if a != b {
            parent[a.max(b)] = a.min(b);
        }
    }
    (0..n).map(|k| root(&mut parent, k)).collect()
}

/// Whether two sampled paths (`(t, position)`, times ascending, positions linear in
/// between) come closer than `sigma` while both are known.
fn paths_meet(a: &[(f64, Vec3)], b: &[(f64, Vec3)], sigma: f64) -> bool {
    paths_meet_from(a, b, sigma, f64::NEG_INFINITY)
}

/// [`paths_meet`] from time `from` on.
///
/// Both paths are read at every sample time of either within the time both cover, in
/// ascending order, and the relative motion between two such times is linear: two
/// cursors walk the samples once (a chunk's paths hold a sample per fixed step, and this
/// is called for every watched pair).
fn paths_meet_from(a: &[(f64, Vec3)], b: &[(f64, Vec3)], sigma: f64, from: f64) -> bool {
    let (Some(&(a0, _)), Some(&(a1, _)), Some(&(b0, _)), Some(&(b1, _))) =
        (a.first(), a.last(), b.first(), b.last())
    else {
        return false;
    };
    let (t0, t1) = (a0.max(b0).max(from), a1.min(b1));
    if t1 < t0 {
        return false;
    }
    let (mut ca, mut cb) = (PathCursor::new(a, t0), PathCursor::new(b, t0));
    // The sample times strictly inside `(t0, t1)` of each path, merged, then `t1`.
    let inside = |p: &[(f64, Vec3)]| {
        let lo = p.partition_point(|s| s.0 <= t0);
        let hi = lo + p[lo..].partition_point(|s| s.0 < t1);
        lo..hi
    };
    let (mut ia, mut ib) = (inside(a), inside(b));
    let merged = std::iter::from_fn(move || {
        let ta = (ia.start < ia.end).then(|| a[ia.start].0);
        let tb = (ib.start < ib.end).then(|| b[ib.start].0);
        match (ta, tb) {
            (Some(x), Some(y)) if x.total_cmp(&y).is_le() => {
                ia.start += 1;
                Some(x)
            }
            (_, Some(y)) => {
                ib.start += 1;
                Some(y)
            }
            (Some(x), None) => {
                ia.start += 1;
                Some(x)
            }
            (None, None) => None,
        }
    });
    let (mut t, mut d) = (t0, cb.at(t0) - ca.at(t0));
    if d.norm() < sigma {
        return true;
    }
    for tn in merged.chain(std::iter::once(t1)) {
        let dn = cb.at(tn) - ca.at(tn);
        if tn > t && closest_approach(&d, &((dn - d) / (tn - t)), tn - t) < sigma {
            return true;
        }
        (t, d) = (tn, dn);
    }
    d.norm() < sigma
}

/// A sampled path read at ascending times (linear between samples, the end samples
/// held beyond them): the interpolation of [`paths_meet_from`], its segment found by
/// walking forward rather than by a search at each time.
struct PathCursor<'p> {
    path: &'p [(f64, Vec3)],
    /// The first sample not before the last time read.
    next: usize,
}

impl<'p> PathCursor<'p> {
    fn new(path: &'p [(f64, Vec3)], t: f64) -> Self {
        let next = path.partition_point(|s| s.0 < t);
        PathCursor { path, next }
    }

    /// The position at `t`, not before the last time read.
    fn at(&mut self, t: f64) -> Vec3 {
        let p = self.path;
        if p.len() == 1 {
            return p[0].1;
        }
        while self.next < p.len() && p[self.next].0 < t {
            self.next += 1;
        }
        let k = self.next.clamp(1, p.len() - 1);
        let ((ta, pa), (tb, pb)) = (p[k - 1], p[k]);
        if tb > ta {
            pa + (pb - pa) * ((t - ta) / (tb - ta)).clamp(0.0, 1.0)
        } else {
            pb
        }
    }
}

/// What integrating one cluster chunk produced (on copies of the members).
struct Chunk {
    /// Time each member reached (its group stopped once apart).
    t_end: Vec<f64>,
    /// The members' states.
    copies: Vec<ShotState>,
    /// The island pairs (member indices), with their contact states.
    pairs: Vec<IslandPair>,
    /// Impacts, run events, work.
    out: IslandOutput,
    /// A shot left outside that came within contact of a member.
    violator: Option<usize>,
    /// Member pairs overlapping at the end without having been paired (global ids).
    missed: Vec<(u32, u32)>,
    /// Where the chunk must end instead: a member flown on from its group's end changes
    /// its path there, within reach of a group that ran on (`Engine::free_until`).
    cut: Option<f64>,
    /// Fastest member speed seen at the start and at step ends, m/s.
    v_seen: f64,
    /// Members left on their free path (state, clock and pending events still valid).
    unchanged: Vec<bool>,
}

/// A shot's free-flight state as the scans read it: position and velocity at `t_ref`, and
/// the radius.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
struct Fly {
    pos: Vec3,
    vel: Vec3,
    t_ref: f64,
    radius: f64,
}

/// A shot's standing in the event loop.
#[derive(Debug, Clone, Copy)]
struct Slot {
    /// Bumped whenever the shot's path changes: events predicted before are stale.
    ver: u32,
    /// Cluster slot of a shot in a cluster in progress, else `NONE`.
    owner: u32,
    /// Entered, active and in the grid.
    present: bool,
}

/// The scheduler's state.
struct Engine<'a> {
    phys: &'a Physics,
    flight: Flight,
    end: f64,
    shots: &'a mut [ShotState],
    /// What the neighbour scans read of each shot, one cache line per shot (the states
    /// are a few hundred bytes): `shots[i].pos / vel` (kept in step by `sync`), the time
    /// they hold at, and the radius.
    fly: Vec<Fly>,
    /// What the event loop checks of a shot for every event it pops and every shot a
    /// scan finds, side by side (one memory access instead of three).
    slot: Vec<Slot>,
    /// Earliest pending events that change the shot's path (touches).
    next_change: Vec<Pending>,
    /// Membership stamps for cluster gathering.
    mark: Vec<u64>,
    /// A member's index in the cluster being integrated.
    local: Vec<u32>,
    stamp: u64,
    grid: Grid,
    queue: Calendar<Ev>,
    clusters: Vec<Option<Cluster>>,
    free_slots: Vec<usize>,
    v_max: f64,
    r_max: f64,
    t_now: f64,
    /// Source of cluster generations (unique across slots, so a reused slot never
    /// matches a stale `Continue`).
    next_gen: u32,
    out: IslandOutput,
    scratch: Scratch,
    /// Whether lone contacts take the lean path (the adaptive method only: the
    /// fixed-step method steps every contact, as LIGGGHTS does).
    lean: bool,
    /// A step for the fixed-step method, s, for the give-up message ([`fixed_step_hint`]).
    fixed_step: f64,
    /// The tabulated impacts of the pair and the specimen law, where the lean path may
    /// use them (frictionless, tolerance at least `table::FROM_TOLERANCE`).
    tables: [Option<ContactTable>; 2],
    cells: CellList,
    buf: Vec<usize>,
    /// Scratch for [`Engine::pending_now`] (called while `buf` is in use).
    buf2: Vec<usize>,
    /// Scratch for the shots whose paths may change soon (`Engine::changers_in`).
    changers: Vec<(usize, f64)>,
    /// Set when a cluster chunk stays unverified after `MAX_REDOS` redos (a member
    /// outran the speed bound, or a shot outside reached a member): the run stops, as
    /// accepting it would leave a contact to be found late, up to a whole overlap deep
    /// (random dense, frictional packs found this in session 23). Set too when its
    /// latest integrator steps have carried more than `sim::MAX_ISLAND` shots each on
    /// average (a pile integrated as one island: windows split it; session 24, the
    /// latest steps since session 29).
    gave_up: Option<GaveUp>,
    /// Judges the islands' size over the latest integrator steps.
    pile_watch: PileWatch,
}

/// Why the event scheduler stopped a run before its end (see `Engine::gave_up`): the
/// shots are left as they were given, to be run on windows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GaveUp {
    /// Start of the cluster chunk it gave up on, s.
    pub time_s: f64,
    /// Shots in that cluster.
    pub members: usize,
    /// Why.
    pub why: GiveUpReason,
    /// A step for the fixed-step method on this scene, s ([`fixed_step_hint`]).
    pub fixed_step: f64,
    /// Whether the run is on the fixed-step method already (the message then suggests
    /// no step).
    pub on_fixed_step: bool,
}

/// Shots carried per integrator step over the latest steps: the whole run until it has
/// `PILE_BLOCKS` blocks of `PILE_BLOCK_STEPS` steps, then the latest `PILE_BLOCKS - 1`
/// whole blocks and the one in progress.
#[derive(Debug, Default)]
struct PileWatch {
    /// The work counters (accepted steps, shot-steps) where each of the latest
    /// `PILE_BLOCKS` blocks began, oldest first.
    marks: [(u64, u64); PILE_BLOCKS],
}

impl PileWatch {
    /// Takes the run's counters so far (accepted integrator steps and shot-steps, both
    /// counted from the run's start); the reason to give up once the latest steps carry
    /// more than `sim::MAX_ISLAND` shots each on average (nothing before the first block
    /// ends).
    fn judge(&mut self, steps_accepted: u64, shot_steps: u64) -> Option<GiveUpReason> {
        if steps_accepted - self.marks[PILE_BLOCKS - 1].0 >= PILE_BLOCK_STEPS {
            self.marks.rotate_left(1);
            self.marks[PILE_BLOCKS - 1] = (steps_accepted, shot_steps);
        }
        let (from_steps, from_shot_steps) = self.marks[0];
        let (steps, carried) = (steps_accepted - from_steps, shot_steps - from_shot_steps);
        (steps_accepted >= PILE_BLOCK_STEPS && carried > crate::sim::MAX_ISLAND as u64 * steps)
            .then(|| GiveUpReason::Islands {
                mean: carried as f64 / steps as f64,
                steps,
            })
    }
}

/// Why the event scheduler gave up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GiveUpReason {
    /// A cluster chunk was still unverified after `MAX_REDOS` redos.
    Unverified,
    /// Its latest integrator steps (`steps` of them, at least `PILE_BLOCK_STEPS`)
    /// carried `mean` shots each on average, more than `sim::MAX_ISLAND`.
    Islands {
        /// Shots per integrator step.
        mean: f64,
        /// Integrator steps the mean is taken over.
        steps: u64,
    },
}

impl std::fmt::Display for GaveUp {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let why = match self.why {
            GiveUpReason::Unverified => format!(
                "a cluster of {} shots kept being reached by shots from outside it",
                self.members
            ),
            GiveUpReason::Islands { mean, steps } => format!(
                "its clusters (the last of {} shots) carried {mean:.1} shots per integrator step on average over its latest {steps} steps, more than the {} the window scheduler keeps its islands to",
                self.members,
                crate::sim::MAX_ISLAND
            ),
        };
        let ns = self.fixed_step * 1e9;
        let ns = if ns >= 10.0 {
            format!("{ns:.0}")
        } else {
            format!("{:.2}", ns)
        };
        if self.on_fixed_step {
            return write!(
                f,
                "the event scheduler gave up at t = {:.6} ms: {why} (a dense pile); the run was redone on windows, where the fixed-step method steps every shot on one grid (`scheduler = \"windows\"` under [integrator] skips the attempt: docs/performance.md)",
                self.time_s * 1e3,
            );
        }
        write!(
            f,
            "the event scheduler gave up at t = {:.6} ms: {why} (a dense pile); the run was redone on windows (`scheduler = \"windows\"` under [integrator] skips the attempt; `method = \"verlet\"` with `fixed_step_ns = {ns}`, a fiftieth of the fastest impact's contact time, steps a pile as LIGGGHTS does, at that step's accuracy and usually much faster: docs/performance.md)",
            self.time_s * 1e3,
        )
    }
}

/// A fixed step for `method = "verlet"` on `shots`, as a DEM code such as LIGGGHTS would
/// choose it: a fiftieth of the shortest Hertz contact time at the fastest shot's speed,
/// of the smallest shot on the specimen or of two such shots meeting head-on, s.
pub fn fixed_step_hint(phys: &Physics, shots: &[ShotState]) -> f64 {
    let Some(small) = shots
        .iter()
        .min_by(|a, b| a.body.radius.total_cmp(&b.body.radius))
    else {
        return f64::INFINITY;
    };
    let (r, m) = (small.body.radius, small.body.mass);
    let v = shots
        .iter()
        .map(|s| s.vel.norm())
        .fold(0.0, f64::max)
        .max(1e-3);
    let mut tc = f64::INFINITY;
    if let Some(sp) = &phys.contacts.specimen {
        tc = tc.min(hertz::contact_time(
            m,
            sp.law.stiffness(sp.shape.stiffest_radius(r)),
            v,
        ));
    }
    if let Some(pc) = &phys.contacts.pair {
        let k = pc.law.stiffness(PairContact::effective_radius(r, r));
        tc = tc.min(hertz::contact_time(effective_mass(m, m), k, 2.0 * v));
    }
    tc / 50.0
}

/// Runs `shots` from 0 to `end` with the event scheduler (see the module docs); returns
/// the impacts, run events and work counters, or why it gave up (the shots are then as
/// given). `progress` gets the finished fraction.
pub fn run(
    phys: &Physics,
    shots: &mut [ShotState],
    end: f64,
    lean: bool,
    progress: &(dyn Fn(f64) + Sync),
) -> Result<IslandOutput, GaveUp> {
    // The engine runs on the shots in space-filling-curve order of where they start, so
    // that shots that meet mostly sit near each other in memory (the states are a few
    // hundred bytes each); they go back to their places afterwards.
    let order = spatial_order(shots);
    let mut sorted: Vec<ShotState> = order.iter().map(|&i| shots[i].clone()).collect();
    let mut eng = Engine::new(phys, &mut sorted, end);
    eng.lean = eng.lean && lean;
    eng.run(progress);
    if let Some(g) = eng.gave_up {
        return Err(g);
    }
    let out = eng.out;
    for (s, &i) in sorted.into_iter().zip(&order) {
        shots[i] = s;
    }
    Ok(out)
}

/// Indices of `shots` in Morton (Z-curve) order of their starting positions on cells of
/// two contact distances (ties: index order).
fn spatial_order(shots: &[ShotState]) -> Vec<usize> {
    let (mut lo, mut r_max) = (Vec3::repeat(f64::INFINITY), 1e-9f64);
    for s in shots {
        lo = lo.inf(&s.pos);
        r_max = r_max.max(s.body.radius);
    }
    let cell = 4.0 * r_max;
    // Spreads the low 21 bits of `v` to every third bit.
    let spread = |v: u64| {
        let mut x = v & 0x1f_ffff;
        x = (x | x << 32) & 0x001f_0000_0000_ffff;
        x = (x | x << 16) & 0x001f_0000_ff00_00ff;
        x = (x | x << 8) & 0x100f_00f0_0f00_f00f;
        x = (x | x << 4) & 0x10c3_0c30_c30c_30c3;
        (x | x << 2) & 0x1249_2492_4924_9249
    };
    let key = |p: &Vec3| {
        let c = |k: usize| (((p[k] - lo[k]) / cell).max(0.0) as u64).min(0x1f_ffff);
        spread(c(0)) | spread(c(1)) << 1 | spread(c(2)) << 2
    };
    let mut order: Vec<usize> = (0..shots.len()).collect();
    order.sort_by_cached_key(|&i| (key(&shots[i].pos), i));
    order
}

impl<'a> Engine<'a> {
    fn new(phys: &'a Physics, shots: &'a mut [ShotState], end: f64) -> Self {
        let n = shots.len();
        let fixed_step = fixed_step_hint(phys, shots);
        let g = phys.forces.gravity.map_or(0.0, |g| -g.acceleration.z);
        let r_max = shots
            .iter()
            .map(|s| s.body.radius)
            .fold(0.0, f64::max)
            .max(1e-9);
        let v_max = shots.iter().map(|s| s.vel.norm()).fold(0.0, f64::max);
        // The grid's box: where the shots start, widened by how far they can fly, within
        // the domain (outer cells reach to infinity anyway).
        let (mut lo, mut hi) = (Vec3::repeat(f64::INFINITY), Vec3::repeat(f64::NEG_INFINITY));
        for s in shots.iter() {
            lo = lo.inf(&s.pos);
            hi = hi.sup(&s.pos);
        }
        if n == 0 {
            lo = Vec3::zeros();
            hi = Vec3::zeros();
        }
        let margin = (v_max + g * end) * end + 2.0 * r_max;
        let d = &phys.domain;
        lo = (lo - Vec3::repeat(margin)).sup(&Vec3::new(-d.radius, -d.radius, f64::NEG_INFINITY));
        hi = (hi + Vec3::repeat(margin)).inf(&Vec3::new(d.radius, d.radius, d.top));
        if phys.contacts.specimen.is_some() {
            lo.z = lo.z.max(-r_max);
        }
        let hi = hi.sup(&(lo + Vec3::repeat(2.0 * r_max)));
        // Up to 32 cells (128 bytes) per shot: the box above is widened by how far the
        // shots can fly, so with fewer the cells outgrow the contact distance and every
        // prediction scans more neighbours (the pack stream: 8 per shot gave 1.64 mm
        // cells for 0.84 mm contacts and 6.5 % more instructions than 32, 1.05 mm; 64
        // gained nothing).
        let max_cells = (32 * n).clamp(1 << 16, 1 << 23);
        let grid = Grid::new(lo, hi, 2.0 * r_max * 1.05, n, max_cells);
        Engine {
            phys,
            flight: Flight { g },
            end,
            fly: shots
                .iter()
                .map(|s| Fly {
                    pos: s.pos,
                    vel: s.vel,
                    t_ref: s.t_start.max(0.0),
                    radius: s.body.radius,
                })
                .collect(),
            slot: vec![
                Slot {
                    ver: 0,
                    owner: NONE,
                    present: false,
                };
                n
            ],
            next_change: vec![Pending::NONE; n],
            mark: vec![0; n],
            local: vec![0; n],
            stamp: 0,
            grid,
            // One bucket per shot (four until session 16: the same pops, 2-3 % slower on
            // the 10,000-shot pack stream, more buckets to allocate and miss).
            queue: Calendar::new(end, n.clamp(1 << 10, 1 << 18)),
            clusters: Vec::new(),
            free_slots: Vec::new(),
            v_max,
            r_max,
            t_now: 0.0,
            next_gen: 0,
            out: IslandOutput::default(),
            scratch: Scratch::default(),
            lean: matches!(phys.method, Method::Adaptive),
            fixed_step,
            tables: {
                let c = &phys.contacts;
                let table = |law: Option<&crate::contact::HertzLaw>| {
                    law.filter(|_| c.friction.is_none() && phys.tolerance >= table::FROM_TOLERANCE)
                        .map(|l| ContactTable::new(l.damping))
                };
                [
                    table(c.pair.as_ref().map(|p| &p.law)),
                    // A restitution curve gives each contact its own damping: integrated.
                    table(
                        c.specimen
                            .as_ref()
                            .filter(|s| s.by_speed.is_none())
                            .map(|s| &s.law),
                    ),
                ]
            },
            cells: CellList::default(),
            buf: Vec::new(),
            buf2: Vec::new(),
            changers: Vec::new(),
            gave_up: None,
            pile_watch: PileWatch::default(),
            shots,
        }
    }

    fn push(&mut self, t: f64, kind: Kind, a: usize, b: usize) {
        let (va, vb) = (
            self.slot[a].ver,
            if kind == Kind::Touch {
                self.slot[b].ver
            } else {
                0
            },
        );
        self.queue.push(
            t,
            Ev {
                t,
                kind,
                a: a as u32,
                b: b as u32,
                va,
                vb,
            },
        );
    }

    /// Free-flight state of shot `i` at `t` (not before its reference time).
    #[inline]
    fn state_at(&self, i: usize, t: f64) -> (Vec3, Vec3) {
        let f = &self.fly[i];
        self.flight.at(&f.pos, &f.vel, (t - f.t_ref).max(0.0))
    }

    /// Copies shot `i`'s position and velocity into its `fly` entry (after any change).
    #[inline]
    fn sync(&mut self, i: usize) {
        let f = &mut self.fly[i];
        f.pos = self.shots[i].pos;
        f.vel = self.shots[i].vel;
    }

    /// Upper bound of any shot's speed until the end.
    fn v_bound(&self) -> f64 {
        self.v_max + self.flight.g * self.end + 1e-6
    }

    fn run(&mut self, progress: &(dyn Fn(f64) + Sync)) {
        let n = self.shots.len();
        for i in 0..n {
            if !self.shots[i].is_active() {
                continue;
            }
            if self.shots[i].t_start <= 0.0 {
                self.enter(i);
            } else if self.shots[i].t_start <= self.end {
                self.push(self.shots[i].t_start, Kind::Enter, i, i);
            }
        }
        for i in 0..n {
            if self.slot[i].present {
                self.predict(i);
            }
        }
        let mut handled = 0u64;
        while let Some(ev) = self.queue.pop() {
            if ev.t > self.end || self.gave_up.is_some() {
                break;
            }
            self.t_now = ev.t;
            handled += 1;
            if handled.is_multiple_of(1 << 14) {
                progress(self.t_now / self.end);
            }
            let (a, b) = (ev.a as usize, ev.b as usize);
            let free_valid = |e: &Self, i: usize, v: u32| {
                e.slot[i].present && e.slot[i].owner == NONE && e.slot[i].ver == v
            };
            match ev.kind {
                Kind::Enter => {
                    if self.shots[a].is_active() && !self.slot[a].present {
                        self.out.work.flight_events += 1;
                        if let Some(wait) = self.entry_blocked(a, ev.t) {
                            // Held back, as in the islands (`island::hold_entries`).
                            let t = ev.t + wait;
                            self.shots[a].t_start = t;
                            self.out.work.entries_held += 1;
                            if t <= self.end {
                                self.push(t, Kind::Enter, a, a);
                            }
                        } else {
                            self.enter(a);
                            self.predict(a);
                        }
                    }
                }
                Kind::Leave => {
                    if free_valid(self, a, ev.va) {
                        self.out.work.flight_events += 1;
                        let (p, v) = self.state_at(a, ev.t);
                        let s = &mut self.shots[a];
                        s.pos = p;
                        s.vel = v;
                        s.status = ShotStatus::LeftDomain;
                        s.t_stop = Some(ev.t);
                        self.fly[a].t_ref = ev.t;
                        self.sync(a);
                        self.slot[a].ver += 1;
                        self.slot[a].present = false;
                        self.grid.remove(a);
                    }
                }
                Kind::Cross => {
                    if free_valid(self, a, ev.va) {
                        self.out.work.flight_events += 1;
                        self.cross(a, b, ev.t);
                    }
                }
                Kind::Floor => {
                    if free_valid(self, a, ev.va) {
                        self.start_cluster(&[a], ev.t);
                    }
                }
                Kind::Touch => {
                    if free_valid(self, a, ev.va) && free_valid(self, b, ev.vb) {
                        self.start_cluster(&[a, b], ev.t);
                    }
                }
                Kind::Continue | Kind::ContinueLone => {
                    if self.clusters[a].as_ref().is_some_and(|c| c.gen_ == ev.va) {
                        self.resolve(a);
                    }
                }
            }
        }
        // Free shots fly to the end.
        self.t_now = self.end;
        for i in 0..n {
            if self.slot[i].present && self.slot[i].owner == NONE && self.fly[i].t_ref < self.end {
                let (p, v) = self.state_at(i, self.end);
                self.shots[i].pos = p;
                self.shots[i].vel = v;
                self.fly[i].t_ref = self.end;
                self.sync(i);
            }
        }
        progress(1.0);
    }

    /// Whether shot `i`, fed into the run at `t`, would appear overlapping a shot already
    /// there (free shots at `t`, shots in a cluster where it holds them): then the time
    /// to wait before trying again, that the two need to cover a contact distance at
    /// their speeds (see `island::hold_entries`).
    fn entry_blocked(&self, i: usize, t: f64) -> Option<f64> {
        self.phys.contacts.pair?;
        let s = &self.shots[i];
        let mut wait = None;
        self.grid.for_each_near(self.grid.cell_of(&s.pos), |j| {
            if j == i || !self.slot[j].present || wait.is_some() {
                return;
            }
            let (p, v) = if self.slot[j].owner == NONE {
                self.state_at(j, t)
            } else {
                (self.shots[j].pos, self.shots[j].vel)
            };
            let reach = s.body.radius + self.shots[j].body.radius;
            if (p - s.pos).norm() < reach {
                wait = Some(reach / (v.norm() + s.vel.norm()).max(1e-3));
            }
        });
        wait
    }

    fn enter(&mut self, i: usize) {
        self.slot[i].present = true;
        self.fly[i].t_ref = self.shots[i].t_start.max(0.0);
        let c = self.grid.cell_of(&self.shots[i].pos);
        self.grid.place(i, c);
    }

    /// Predicts every event of free shot `i` from its reference state.
    fn predict(&mut self, i: usize) {
        self.next_change[i] = Pending::NONE;
        let mut nb = std::mem::take(&mut self.buf);
        nb.clear();
        self.grid.for_each_near(self.grid.at[i], |j| nb.push(j));
        for &j in &nb {
            if j != i && self.slot[j].present && self.slot[j].owner == NONE {
                self.predict_pair(i, j);
            }
        }
        self.buf = nb;
        if let Some(t) = self.floor_time(i) {
            self.push(t, Kind::Floor, i, i);
            self.next_change[i].note(t, i);
        }
        let (t, s) = (self.fly[i].t_ref, &self.shots[i]);
        let (p, v) = (s.pos, s.vel);
        let d = self.phys.domain;
        let leave = [
            self.flight.up_through(p.z, v.z, d.top),
            Flight::out_of_radius(&p, &v, d.radius),
        ]
        .into_iter()
        .flatten()
        .fold(f64::INFINITY, f64::min);
        if t + leave <= self.end {
            self.push(t + leave, Kind::Leave, i, i);
        }
        self.schedule_cross(i, t);
    }

    /// When free shots `i` and `j` touch on their free paths, if they do: the time, and
    /// how deep they overlap already (m; zero if they do not).
    fn pair_touch_time(&self, i: usize, j: usize) -> Option<(f64, f64)> {
        let t0 = self.fly[i].t_ref.max(self.fly[j].t_ref);
        let (pi, vi) = self.state_at(i, t0);
        let (pj, vj) = self.state_at(j, t0);
        let sigma = self.fly[i].radius + self.fly[j].radius;
        let dx = pj - pi;
        if dx.norm_squared() < sigma * sigma {
            Some((t0, sigma - dx.norm()))
        } else {
            pair_touch(&dx, &(vj - vi), sigma).map(|tau| (t0 + tau, 0.0))
        }
    }

    /// The earliest pending change of free shot `c`'s path, found afresh: its touches
    /// with the free shots near it and with the specimen, as [`Self::predict`] notes
    /// them. `next_change` keeps a touch predicted with a shot whose path has changed
    /// since as a lower bound; once such a touch is past it says nothing, and it may hide
    /// one still to come (a shot taken as free through its real touch was met late,
    /// 2 um deep, on LIGGGHTS' stream.in).
    fn pending_now(&mut self, c: usize) -> Pending {
        let mut p = Pending::NONE;
        let mut nb = std::mem::take(&mut self.buf2);
        nb.clear();
        self.grid.for_each_near(self.grid.at[c], |j| nb.push(j));
        for &j in &nb {
            if j != c
                && self.slot[j].present
                && self.slot[j].owner == NONE
                && let Some((t, _)) = self.pair_touch_time(c, j)
                && t <= self.end
            {
                p.note(t, j);
            }
        }
        self.buf2 = nb;
        if let Some(t) = self.floor_time(c) {
            p.note(t, c);
        }
        p
    }

    /// When free shot `i` reaches the specimen's plane on its free path, if it does
    /// before the end.
    fn floor_time(&self, i: usize) -> Option<f64> {
        let (t, s) = (self.fly[i].t_ref, &self.shots[i]);
        self.phys.contacts.specimen.as_ref()?;
        let tau = self.flight.down_through(s.pos.z, s.vel.z, s.body.radius)?;
        (t + tau <= self.end).then_some(t + tau)
    }

    /// Shot `c`'s [`Pending`]; if the kept one is past (`c` free), found afresh
    /// ([`Self::pending_now`]), with the kept one's later touch with anybody else still
    /// counted, and kept.
    fn pending(&mut self, c: usize) -> Pending {
        let kept = self.next_change[c];
        if kept.t >= self.t_now || self.slot[c].owner != NONE {
            return kept;
        }
        let mut p = self.pending_now(c);
        if kept.t_other >= self.t_now && kept.t_other < f64::INFINITY {
            p.note(kept.t_other, NONE as usize);
        }
        self.next_change[c] = p;
        p
    }

    /// Into `out`: the shots of `found` but `who` and the members of the cluster marked
    /// `st` whose paths may change before `e`, each with the earliest time it may (a
    /// cluster's clock, a pending touch with anybody but `who`; NaN: the kept pending touch
    /// is past, to be found afresh if needed).
    fn changers_in(
        &self,
        found: &[usize],
        who: &[usize],
        st: u64,
        e: f64,
        out: &mut Vec<(usize, f64)>,
    ) {
        out.clear();
        for &j in found {
            if !self.slot[j].present || self.mark[j] == st || who.contains(&j) {
                continue;
            }
            let kept = self.next_change[j].without(who);
            let tc = match (self.slot[j].owner != NONE, kept >= self.t_now) {
                (true, _) => self.fly[j].t_ref,
                (false, true) => kept,
                (false, false) => f64::NAN,
            };
            if tc.is_nan() || tc < e {
                out.push((j, tc));
            }
        }
    }

    /// How long free shot `k`'s free path (known until `until`) stays its path: until a
    /// shot of `changers` (shot, when its path may change; NaN: to be found afresh)
    /// could reach it after its change, anywhere within the speed bound `vb` of where it
    /// changed (only changes before `e` matter). `k`'s pending touch is exact only while
    /// the paths around it stay as they are (session 62).
    fn chain_bound(
        &mut self,
        k: usize,
        changers: &mut [(usize, f64)],
        who: &[usize],
        until: f64,
        vb: f64,
        e: f64,
    ) -> f64 {
        let (t_now, g) = (self.t_now, self.flight.g);
        let tk = self.fly[k].t_ref.max(t_now);
        let (pk, rk) = (self.state_at(k, tk).0, self.fly[k].radius);
        let mut b = until;
        for entry in changers.iter_mut() {
            let (j, tc) = *entry;
            if j == k {
                continue;
            }
            // Too far to reach k before `b` (or `e`) whenever it changes: both move at
            // most `vb` (compared where both are known: their clocks, or now).
            let owned = self.slot[j].owner != NONE;
            let tj0 = if owned {
                self.fly[j].t_ref
            } else {
                self.fly[j].t_ref.max(t_now)
            };
            let horizon = b.min(e);
            let reach = self.fly[j].radius + rk + vb * ((tj0 - tk).abs() + 2.0 * (horizon - t_now));
            if (self.state_at(j, tj0).0 - pk).norm_squared() > reach * reach {
                continue;
            }
            let tc = if tc.is_nan() {
                let t = self.pending(j).without(who);
                entry.1 = t;
                t
            } else {
                tc
            };
            // Where and when its path may change (a shot of a cluster: at its clock).
            let tj = if owned { tj0 } else { tc.max(tj0) };
            if tj >= horizon {
                continue;
            }
            let pj = self.state_at(j, tj).0;
            // k's line from where both are known, against j's sphere growing at `vb`
            // from where it changes (k's fall off its line, over what is left, added to
            // the contact distance).
            let t0 = tj.max(tk);
            let (pk0, vk) = self.state_at(k, t0);
            let h = horizon - t0;
            let sig = self.fly[j].radius + rk + vb * (t0 - tj) + 0.5 * g * h * h;
            let d = pk0 - pj;
            let c = d.norm_squared() - sig * sig;
            if c <= 0.0 {
                b = b.min(t0);
                continue;
            }
            let a = vk.norm_squared() - vb * vb;
            let bb = d.dot(&vk) - sig * vb;
            let disc = bb * bb - a * c;
            if disc >= 0.0 {
                let den = -bb + disc.sqrt();
                if den > 0.0 {
                    b = b.min(t0 + c / den);
                }
            }
        }
        b
    }

    fn predict_pair(&mut self, i: usize, j: usize) {
        let touch = self.pair_touch_time(i, j);
        if let Some((t, depth)) = touch {
            if depth > 0.0 {
                // Overlapping free shots: a contact was missed. Count it, and let a
                // cluster push them apart now rather than letting them pass through each
                // other.
                let sigma = self.fly[i].radius + self.fly[j].radius;
                count_late(&mut self.out.work, depth, sigma);
            }
            if t <= self.end {
                let (a, b) = (i.min(j), i.max(j));
                self.push(t, Kind::Touch, a, b);
                self.next_change[i].note(t, j);
                self.next_change[j].note(t, i);
            }
        }
    }

    /// The next cell face free shot `i` crosses (event `b` = axis * 2 + upwards).
    ///
    /// Looked for from the shot's state at `now` (its flight's start, or the crossing
    /// just made), not from its flight's start: a shot rising through a face and falling
    /// back through it crosses that face twice in one flight, and from the start the
    /// first crossing up, already past, was found again and again (until session 29 the
    /// run never ended: a shot thrown up 1 m/s under gravity, or one rebounding slowly).
    fn schedule_cross(&mut self, i: usize, now: f64) {
        let c = self.grid.at[i];
        let (p, v) = self.state_at(i, now);
        let mut best = (f64::INFINITY, 0usize);
        for axis in 0..3 {
            let (lo, hi) = self.grid.faces(&c, axis);
            let (down, up) = if axis == 2 {
                (
                    lo.and_then(|f| self.flight.down_through(p.z, v.z, f)),
                    hi.and_then(|f| self.flight.up_through(p.z, v.z, f)),
                )
            } else {
                (
                    lo.filter(|_| v[axis] < 0.0)
                        .map(|f| ((f - p[axis]) / v[axis]).max(0.0)),
                    hi.filter(|_| v[axis] > 0.0)
                        .map(|f| ((f - p[axis]) / v[axis]).max(0.0)),
                )
            };
            if let Some(tau) = down
                && tau < best.0
            {
                best = (tau, 2 * axis);
            }
            if let Some(tau) = up
                && tau < best.0
            {
                best = (tau, 2 * axis + 1);
            }
        }
        if now + best.0 <= self.end {
            self.push(now + best.0, Kind::Cross, i, best.1);
        }
    }

    fn cross(&mut self, i: usize, code: usize, now: f64) {
        let (axis, up) = (code / 2, code % 2 == 1);
        let mut c = self.grid.at[i];
        c[axis] = if up { c[axis] + 1 } else { c[axis] - 1 };
        self.grid.place(i, c);
        // Shots that just became neighbours: the layer beyond the new cell.
        let dims = self.grid.dims();
        let beyond = if up {
            (c[axis] + 1 < dims[axis]).then(|| c[axis] + 1)
        } else {
            c[axis].checked_sub(1)
        };
        if let Some(l) = beyond {
            let mut lo = c.map(|v| v as i64 - 1);
            let mut hi = c.map(|v| v as i64 + 1);
            lo[axis] = l as i64;
            hi[axis] = l as i64;
            let mut nb = std::mem::take(&mut self.buf);
            nb.clear();
            self.grid.for_each_in(lo, hi, |j| nb.push(j));
            for &j in &nb {
                if j != i && self.slot[j].present && self.slot[j].owner == NONE {
                    self.predict_pair(i, j);
                }
            }
            self.buf = nb;
        }
        self.schedule_cross(i, now);
    }

    /// Opens a cluster for a touch predicted at `t_on` between the free shots `who` (one
    /// shot: the specimen), starting one contact step before it.
    fn start_cluster(&mut self, who: &[usize], t_on: f64) {
        if self.lone_contact(who, t_on) {
            return;
        }
        let tc = self.contact_time(who, t_on);
        let back = tc / self.phys.contact_steps;
        let s = who
            .iter()
            .map(|&i| self.fly[i].t_ref)
            .fold(t_on - back, f64::max);
        let slot = self.free_slots.pop().unwrap_or_else(|| {
            self.clusters.push(None);
            self.clusters.len() - 1
        });
        for &i in who {
            self.slot[i].owner = slot as u32;
            self.slot[i].ver += 1;
        }
        self.clusters[slot] = Some(Cluster {
            members: who.to_vec(),
            pairs: HashMap::default(),
            clock: s,
            tc,
            chunks: 0,
            apart_after: t_on + 2.0 * back,
            onset: t_on,
            gen_: 0,
        });
        self.resolve(slot);
    }

    /// Hertz duration of the touch of `who` at `t`.
    fn contact_time(&self, who: &[usize], t: f64) -> f64 {
        let c = &self.phys.contacts;
        match who {
            [a, b] => {
                let pc = c
                    .pair
                    .as_ref()
                    .expect("BUG: shot-shot touch without pair contact");
                let (pa, va) = self.state_at(*a, t);
                let (pb, vb) = self.state_at(*b, t);
                let d = pb - pa;
                let nrm = if d.norm() > 0.0 {
                    d / d.norm()
                } else {
                    Vec3::z()
                };
                let (ba, bb) = (self.shots[*a].body, self.shots[*b].body);
                let k = pc
                    .law
                    .stiffness(PairContact::effective_radius(ba.radius, bb.radius));
                let closing = -(vb - va).dot(&nrm);
                hertz::contact_time(
                    effective_mass(ba.mass, bb.mass),
                    k,
                    closing.max(MIN_CONTACT_SPEED),
                )
            }
            [a] => {
                let sp = c
                    .specimen
                    .as_ref()
                    .expect("BUG: floor touch without specimen");
                let (p, v) = self.state_at(*a, t);
                let b = self.shots[*a].body;
                let k = sp.law.stiffness(sp.effective_radius(&p, b.radius));
                hertz::contact_time(b.mass, k, (-v.z).max(MIN_CONTACT_SPEED))
            }
            _ => unreachable!("BUG: a touch involves one or two shots"),
        }
    }

    /// Integrates cluster `slot` over its next chunk (see the module docs), then either
    /// continues it or hands its shots back to free flight.
    fn resolve(&mut self, slot: usize) {
        let cl = self.clusters[slot]
            .take()
            .expect("BUG: resolving an empty cluster slot");
        if cl.chunks > 0 && self.lone_continuation(&cl) {
            self.free_slots.push(slot);
            return;
        }
        let mut cl = cl;
        self.out.work.clusters += 1;
        let s = cl.clock;
        let growth = 2f64.powi(cl.chunks.min(30) as i32);
        let min_chunk = 0.25 * cl.tc;
        let mut e = (s + (2.0 * cl.tc * growth).min(MAX_CHUNK).max(cl.tc)).min(self.end);
        e = e.min(self.speed_cap(&cl.members, s, min_chunk));
        let mut vb = self.v_bound();
        self.stamp += 1;
        let st = self.stamp;
        for &m in &cl.members {
            self.mark[m] = st;
        }
        // Free shots left outside but near (shot, member, closest free approach): checked
        // against the members' actual paths afterwards.
        let mut near: Vec<(usize, usize, f64)> = Vec::new();
        let mut scanned = 0;
        let mut redos = 0;
        let mut found: Vec<usize> = Vec::new();
        let mut extra: Vec<(u32, u32)> = Vec::new();
        loop {
            // Gather: closure over members not scanned yet.
            while scanned < cl.members.len() {
                let m = cl.members[scanned];
                scanned += 1;
                let tm = self.fly[m].t_ref.max(s);
                let (pm, vm) = self.state_at(m, tm);
                let rm = self.fly[m].radius;
                let reach = rm + self.r_max + 2.0 * vb * (e - s) + SLACK * 2.0 * self.r_max;
                found.clear();
                self.grid.for_each_within(&pm, reach, |c| found.push(c));
                let mut changers = std::mem::take(&mut self.changers);
                let mut changers_found = false;
                for &c in &found {
                    if !self.slot[c].present || self.mark[c] == st {
                        continue;
                    }
                    let sigma = rm + self.fly[c].radius;
                    let tc_ref = self.fly[c].t_ref;
                    // A shot resolved ahead (its cluster ended, or paused, after `s`) is
                    // taken on its free path from its own clock; before that, its
                    // cluster's checks covered the members' free paths. (A shot of a
                    // paused cluster is in contact: its path will bend, which the
                    // verification below and that cluster's own checks see.)
                    let t_a = tm.max(tc_ref);
                    if t_a >= e {
                        continue;
                    }
                    let (pm_a, vm_a) = self.flight.at(&pm, &vm, t_a - tm);
                    let (pc, vc) = self.state_at(c, t_a);
                    let (dx, dv) = (pc - pm_a, vc - vm_a);
                    // Joins now if it comes near before the member's contact starts (the
                    // member's free path is exact until then); later meetings, on the
                    // member's changed path, are found by the verification.
                    if (t_a <= cl.onset || self.slot[c].owner != NONE)
                        && closest_approach(&dx, &dv, (cl.onset - t_a).max(0.0))
                            < sigma * (1.0 + SLACK)
                    {
                        self.join(&mut cl, c, st);
                        continue;
                    }
                    let dmin = closest_approach(&dx, &dv, e - t_a);
                    // (Its pending touch, found afresh if the kept one is past, only
                    // where it can matter: it is at least `t_now`.)
                    let nc = if dmin < sigma * (1.0 + SLACK) + 2.0 * vb * (e - self.t_now) {
                        let nc = self.pending(c).t;
                        if self.slot[c].owner == NONE {
                            if !changers_found {
                                self.changers_in(&found, &[], st, e, &mut changers);
                                changers_found = true;
                            }
                            // (Only a change before the chunk's end by more than the
                            // time to close the gap matters.)
                            let t_lim = e - (dmin - sigma * (1.0 + SLACK)).max(0.0) / (2.0 * vb);
                            self.chain_bound(c, &mut changers, &[], nc, vb, t_lim)
                        } else {
                            nc
                        }
                    } else {
                        self.next_change[c].t
                    };
                    if nc >= self.t_now
                        && nc < e
                        && dmin < sigma * (1.0 + SLACK) + 2.0 * vb * (e - nc)
                    {
                        // Its path changes before the chunk ends, close by.
                        if nc < s + min_chunk {
                            self.join(&mut cl, c, st);
                            continue;
                        }
                        e = nc;
                    }
                    if dmin < sigma + 2.0 * vb * (e - s) {
                        near.push((c, m, dmin));
                    }
                }
                self.changers = changers;
            }
            // Integrate a copy of the members.
            e = e.min(self.speed_cap(&cl.members, s, min_chunk));
            // After two redos every candidate pair is carried (no more path checks).
            let chunk = self.integrate(&cl, s, e, &near, st, &extra, redos >= 2);
            if redos < MAX_REDOS {
                if chunk.v_seen > vb {
                    // A member outran the speed bound the gathering assumed: gather
                    // again with the speed it reached.
                    redos += 1;
                    self.out.work.cluster_redos += 1;
                    vb = 1.25 * chunk.v_seen;
                    near.clear();
                    scanned = 0;
                    continue;
                }
                if let Some(c) = chunk.violator {
                    redos += 1;
                    self.out.work.cluster_redos += 1;
                    self.join(&mut cl, c, st);
                    continue;
                }
                if !chunk.missed.is_empty() || chunk.cut.is_some() {
                    redos += 1;
                    self.out.work.cluster_redos += 1;
                    extra.extend(chunk.missed);
                    if let Some(t) = chunk.cut {
                        e = t;
                    }
                    continue;
                }
            }
            if chunk.v_seen > vb || chunk.violator.is_some() {
                self.gave_up = Some(GaveUp {
                    time_s: s,
                    members: cl.members.len(),
                    why: GiveUpReason::Unverified,
                    fixed_step: self.fixed_step,
                    on_fixed_step: !matches!(self.phys.method, Method::Adaptive),
                });
                return;
            }
            let members = cl.members.len();
            self.commit(slot, cl, e, chunk);
            // A pile integrated as one island makes every member take the step of
            // whichever is mid-impact; windows split it into islands of at most
            // `MAX_ISLAND` shots, and beat this scheduler by far once its steps carry more
            // than that on average (a 3,000-shot pile: 217 s against 21 s, session 24).
            // (On the fixed-step method every shot takes the same step anyway: a large
            // cluster costs per shot-step what windows would, and they would also step
            // the shots in free flight. Only an unverified chunk makes it give up.)
            let w = &self.out.work;
            if matches!(self.phys.method, Method::Adaptive)
                && let Some(why) = self.pile_watch.judge(w.steps_accepted, w.shot_steps)
            {
                self.gave_up = Some(GaveUp {
                    time_s: s,
                    members,
                    why,
                    fixed_step: self.fixed_step,
                    on_fixed_step: false,
                });
            }
            return;
        }
    }

    /// Latest chunk end for `members` starting at `s`: no member may cross more than its
    /// radius at 1.5 times the fastest member's speed (the island's pair list assumes
    /// so), but at least `min_chunk / 4`.
    fn speed_cap(&self, members: &[usize], s: f64, min_chunk: f64) -> f64 {
        let (mut v, mut r) = (0.0f64, f64::INFINITY);
        for &m in members {
            v = v.max(self.shots[m].vel.norm());
            r = r.min(self.shots[m].body.radius);
        }
        s + (r / (1.5 * v + 1e-9)).max(0.25 * min_chunk)
    }

    /// Whether shot state `c` at `t0` flies free until `e` without reaching the specimen.
    fn flies_clear(&self, c: &ShotState, t0: f64, e: f64) -> bool {
        self.phys.contacts.specimen.is_none()
            || (!c.on_specimen
                && c.pos.z > c.body.radius
                && self
                    .flight
                    .down_through(c.pos.z, c.vel.z, c.body.radius)
                    .is_none_or(|tau| t0 + tau > e))
    }

    /// Adds shot `c` (and, if it belongs to another cluster, that whole cluster) to `cl`.
    fn join(&mut self, cl: &mut Cluster, c: usize, st: u64) {
        let oc = self.slot[c].owner;
        if oc != NONE && self.clusters[oc as usize].is_some() {
            let other = self.clusters[oc as usize]
                .take()
                .expect("BUG: cluster slot vanished");
            self.free_slots.push(oc as usize);
            for &m in &other.members {
                if self.mark[m] != st {
                    self.mark[m] = st;
                    cl.members.push(m);
                }
            }
            cl.pairs.extend(other.pairs);
            cl.tc = cl.tc.max(other.tc);
        } else if self.mark[c] != st {
            self.mark[c] = st;
            cl.members.push(c);
        }
    }

    /// Integrates the cluster's members over `[s, e]` on copies (`link_all`: carry every
    /// candidate pair, as after two redos).
    #[allow(clippy::too_many_arguments)]
    fn integrate(
        &mut self,
        cl: &Cluster,
        s: f64,
        e: f64,
        near: &[(usize, usize, f64)],
        st: u64,
        extra: &[(u32, u32)],
        link_all: bool,
    ) -> Chunk {
        let members = &cl.members;
        let n = members.len();
        let mut copies: Vec<ShotState> = Vec::with_capacity(n);
        let mut starts: Vec<(Vec3, Vec3, f64)> = Vec::with_capacity(n);
        for &m in members {
            let mut c = self.shots[m].clone();
            let tm = self.fly[m].t_ref;
            if tm <= s {
                let (p, v) = self.state_at(m, s);
                c.pos = p;
                c.vel = v;
            } else {
                c.t_start = tm; // frozen until its own clock
            }
            // A shot coming out of free flight starts at the contact step, not at the
            // step its last contact ended with (which the controller would reject).
            if cl.chunks == 0 {
                c.h_next = cl.tc / self.phys.contact_steps;
            }
            starts.push((c.pos, c.vel, tm.max(s)));
            copies.push(c);
        }
        // Pairs that can touch during the chunk: reach-inflated radii (1.5 x own speed,
        // as the window scheduler), plus pairs in contact and pairs a redo added.
        let span = e - s;
        let ids: Vec<u32> = copies.iter().map(|c| c.id.0).collect();
        let key = |i: usize, j: usize| {
            let (a, b) = (ids[i], ids[j]);
            (a.min(b), a.max(b))
        };
        let g = self.flight.g;
        let reach: Vec<f64> = copies
            .iter()
            .map(|c| {
                c.body.radius * (1.0 + SLACK) + 1.5 * c.vel.norm() * span + 0.5 * g * span * span
            })
            .collect();
        let centres: Vec<Vec3> = copies.iter().map(|c| c.pos).collect();
        let mut local: Vec<(u32, u32)> = Vec::new();
        // The candidate pairs an island carries; the others (`watched`) are checked
        // against the members' actual paths afterwards.
        let mut linked: Vec<(u32, u32)> = Vec::new();
        let mut watched: Vec<(u32, u32)> = Vec::new();
        let index: HashMap<u32, u32> = copies
            .iter()
            .enumerate()
            .map(|(k, c)| (c.id.0, k as u32))
            .collect();
        if self.phys.contacts.pair.is_some() {
            local = self.close_pairs(&centres, &reach);
            for &(a, b) in cl.pairs.keys().chain(extra) {
                if let (Some(&i), Some(&j)) = (index.get(&a), index.get(&b)) {
                    linked.push((i.min(j), i.max(j)));
                }
            }
            linked.sort_unstable();
            linked.dedup();
            let forced = linked.len();
            // A pair whose free paths come within the slack of a touch over the contact's
            // likely span is carried; one that does not meets only if a member's path
            // bends or the contact lasts longer, and is verified on the paths (a miss
            // redoes the chunk with it carried).
            let horizon = e.min(s + LINK_HORIZON * cl.tc);
            for &(i, j) in &local {
                // (Forced pairs: the sorted head of `linked`; pairs pushed below follow.)
                if link_all || linked[..forced].binary_search(&(i, j)).is_ok() {
                    linked.push((i, j));
                    continue;
                }
                let ((pi, vi, ti), (pj, vj, tj)) = (starts[i as usize], starts[j as usize]);
                let ta = ti.max(tj);
                let (pa, va) = self.flight.at(&pi, &vi, ta - ti);
                let (pb, vb) = self.flight.at(&pj, &vj, ta - tj);
                let sigma = copies[i as usize].body.radius + copies[j as usize].body.radius;
                if closest_approach(&(pb - pa), &(vb - va), (horizon - ta).max(0.0))
                    < sigma * (1.0 + LINK_SLACK)
                {
                    linked.push((i, j));
                } else {
                    watched.push((i, j));
                }
            }
            local.extend_from_slice(&linked);
            local.sort_unstable();
            local.dedup();
            linked.sort_unstable();
            linked.dedup();
        }
        let ipairs: Vec<IslandPair> = linked
            .iter()
            .map(|&(i, j)| {
                let st = cl.pairs.get(&key(i as usize, j as usize));
                if st.is_none() {
                    let (ci, cj) = (&copies[i as usize], &copies[j as usize]);
                    if ci.t_start <= s
                        && cj.t_start <= s
                        && (ci.pos - cj.pos).norm() < ci.body.radius + cj.body.radius
                    {
                        let sigma = ci.body.radius + cj.body.radius;
                        count_late(&mut self.out.work, sigma - (ci.pos - cj.pos).norm(), sigma);
                    }
                }
                IslandPair {
                    a: i,
                    b: j,
                    touching: st.is_some(),
                    contact_time: st.map_or(0.0, |p| p.contact_time),
                    onset: st.map_or(0.0, |p| p.onset),
                    xi: st.map_or(Vec3::zeros(), |p| p.xi),
                }
            })
            .collect();
        if let Some(sp) = &self.phys.contacts.specimen {
            for c in &copies {
                let gap = sp.gap(&c.pos, c.body.radius);
                if !c.on_specimen && c.t_start <= s && gap < 0.0 {
                    count_late(&mut self.out.work, -gap, c.body.radius);
                }
            }
        }
        // Integrate each connected group (under the pairs) as its own island: shots
        // gathered for safety but touching nobody do not share a clock. Samples: each
        // member's position after every step of its island.
        let roots = group_roots(n, ipairs.iter().map(|p| (p.a as usize, p.b as usize)));
        let mut groups: Vec<Vec<usize>> = Vec::new();
        let mut group_of = vec![usize::MAX; n];
        for k in 0..n {
            let r = roots[k];
            if group_of[r] == usize::MAX {
                group_of[r] = groups.len();
                groups.push(Vec::new());
            }
            let g = group_of[r];
            group_of[k] = g;
            groups[g].push(k);
        }
        let mut group_pairs: Vec<Vec<IslandPair>> = vec![Vec::new(); groups.len()];
        let mut slot = vec![0u32; n];
        for grp in &groups {
            for (q, &k) in grp.iter().enumerate() {
                slot[k] = q as u32;
            }
        }
        for pr in &ipairs {
            let g = group_of[pr.a as usize];
            group_pairs[g].push(IslandPair {
                a: slot[pr.a as usize],
                b: slot[pr.b as usize],
                ..*pr
            });
        }
        let mut out = IslandOutput::default();
        let mut unchanged = vec![false; n];
        let mut v_seen = copies
            .iter()
            .map(|c| c.vel.norm_squared())
            .fold(0.0, f64::max);
        let mut t_end = vec![s; n];
        let mut paths: Vec<Vec<(f64, Vec3)>> = vec![Vec::new(); n];
        let mut sub: Vec<ShotState> = Vec::new();
        for (g, grp) in groups.iter().enumerate() {
            // A shot gathered for safety that can touch nothing (no pair, the specimen
            // out of reach) keeps its free path: closed form, no steps.
            if let [k] = grp[..]
                && group_pairs[g].is_empty()
                && self.flies_clear(&copies[k], starts[k].2, e)
            {
                let m = members[k];
                copies[k] = self.shots[m].clone();
                t_end[k] = self.fly[m].t_ref;
                paths[k] = vec![(starts[k].2, starts[k].0), (e, self.state_at(m, e).0)];
                unchanged[k] = true;
                continue;
            }
            // One contact (two shots, or a shot and the specimen), everyone
            // else in the group flying clear of it: resolved in closed form and a
            // two-body frame (binary.rs), no island.
            if let Some((lean, o)) = self.try_lean(grp, &group_pairs[g], &copies, cl, s, e) {
                let shots = &lean[..o.n];
                for (q, &k) in shots.iter().enumerate() {
                    o.apply(q, &mut copies[k], &mut out.impacts);
                    t_end[k] = o.end;
                    paths[k] = o.path(q).map(|(t, p, _)| (t, p)).collect();
                    paths[k].push((o.end, o.state[q].0));
                }
                for &k in grp {
                    if !shots.contains(&k) {
                        let m = members[k];
                        copies[k] = self.shots[m].clone();
                        t_end[k] = self.fly[m].t_ref;
                        paths[k] = vec![(starts[k].2, starts[k].0), (e, self.state_at(m, e).0)];
                        unchanged[k] = true;
                    }
                }
                if o.n == 2 {
                    let (la, lb) = (slot[lean[0]], slot[lean[1]]);
                    for pr in group_pairs[g].iter_mut() {
                        if (pr.a.min(pr.b), pr.a.max(pr.b)) == (la.min(lb), la.max(lb)) {
                            pr.touching = o.touching;
                            pr.onset = o.onset;
                            pr.contact_time = o.contact_time;
                        }
                    }
                }
                v_seen = v_seen.max(o.v_max2);
                o.count(&mut out.work);
                continue;
            }
            sub.clear();
            sub.extend(grp.iter().map(|&k| copies[k].clone()));
            // Step times, and the group's positions after each step (one run per step).
            let (mut times, mut at) = (Vec::new(), Vec::new());
            let te = island::advance_until_apart(
                self.phys,
                &mut sub,
                &mut group_pairs[g],
                s,
                e,
                cl.apart_after.max(s),
                &mut self.scratch,
                &mut out,
                &mut |t, y| {
                    for q in 0..grp.len() {
                        let v2 = y[6 * q + 3].powi(2) + y[6 * q + 4].powi(2) + y[6 * q + 5].powi(2);
                        v_seen = v_seen.max(v2);
                    }
                    times.push(t);
                    at.extend(
                        (0..grp.len()).map(|q| Vec3::new(y[6 * q], y[6 * q + 1], y[6 * q + 2])),
                    );
                },
            );
            for (q, &k) in grp.iter().enumerate() {
                copies[k] = sub[q].clone();
                t_end[k] = te;
                paths[k] = times
                    .iter()
                    .zip(at.chunks_exact(grp.len()))
                    .map(|(&t, p)| (t, p[q]))
                    .collect();
            }
        }
        let mut ipairs_out: Vec<IslandPair> = Vec::with_capacity(ipairs.len());
        for (g, grp) in groups.iter().enumerate() {
            for pr in &group_pairs[g] {
                ipairs_out.push(IslandPair {
                    a: grp[pr.a as usize] as u32,
                    b: grp[pr.b as usize] as u32,
                    ..*pr
                });
            }
        }
        let ipairs = ipairs_out;
        // Verify: shots left outside against the members' actual paths.
        for (k, &m) in members.iter().enumerate() {
            self.local[m] = k as u32;
        }
        let (free_until, deflected) =
            self.free_until(&copies, &t_end, &unchanged, &local, near, st);
        let vb = self.v_bound().max(v_seen.sqrt());
        let mut violator = None;
        'verify: for &(c, m, _) in near {
            if self.mark[c] == st || self.mark[m] != st {
                continue;
            }
            let k = self.local[m] as usize;
            let sigma = self.fly[c].radius + self.fly[m].radius;
            let t0 = starts[k].2.max(self.fly[c].t_ref);
            for &(t, pm) in &paths[k] {
                if t < t0 {
                    continue;
                }
                let (pc, _) = self.state_at(c, t);
                if (pc - pm).norm() < sigma {
                    violator = Some(c);
                    break 'verify;
                }
            }
        }
        for (c, &m) in copies.iter_mut().zip(members) {
            c.t_start = self.shots[m].t_start;
        }
        // Members that overlap at the chunk end (groups that finished early flown on
        // freely) without having been paired, or whose actual paths met though their
        // free paths did not: redo with them.
        let mut missed = Vec::new();
        let mut cut = f64::INFINITY;
        let min_chunk = 0.25 * cl.tc;
        // A shot outside that a member flown on from its group's end touches before the
        // groups that run on end leaves its free path there (`free_until`): against their
        // paths, it may be anywhere its speed takes it from then on. Unless even that
        // keeps them apart, the chunk ends at the touch, or, too early for that, the shot
        // joins.
        for &(c, t) in &deflected {
            for &(c2, m, _) in near {
                let k = self.local[m] as usize;
                if c2 != c || self.mark[m] != st || unchanged[k] || t_end[k] <= t {
                    continue;
                }
                let h = t_end[k] - t;
                let free = [
                    (t, self.state_at(c, t).0),
                    (t_end[k], self.state_at(c, t_end[k]).0),
                ];
                let sigma = self.fly[c].radius + self.fly[m].radius;
                let widen = 2.0 * vb * h + 0.125 * self.flight.g * h * h;
                if paths_meet_from(&free, &paths[k], sigma + widen, t) {
                    if t >= s + min_chunk {
                        cut = cut.min(t);
                    } else if violator.is_none() {
                        violator = Some(c);
                    }
                }
            }
        }
        for &(i, j) in &watched {
            let (i, j) = (i as usize, j as usize);
            if unchanged[i] && unchanged[j] {
                continue; // both flew their free paths, which stay apart
            }
            // Until both are handed back to free flight (the scheduler predicts their
            // touches from then on).
            let until = t_end[i].max(t_end[j]);
            let full = |k: usize| {
                let (p0, _, t0) = starts[k];
                let c = &copies[k];
                let mut v = Vec::with_capacity(paths[k].len() + 2);
                v.push((t0, p0));
                v.extend(paths[k].iter().filter(|(t, _)| *t > t0 && *t <= until));
                if t_end[k] < until && c.is_active() {
                    v.push((until, self.flight.at(&c.pos, &c.vel, until - t_end[k]).0));
                }
                v
            };
            let sigma = copies[i].body.radius + copies[j].body.radius;
            let (path_i, path_j) = (full(i), full(j));
            if paths_meet(&path_i, &path_j, sigma) {
                missed.push(key(i, j));
                continue;
            }
            // A shot flown on from its group's end past its next change (`free_until`)
            // may be anywhere its speed takes it from there: unless even that keeps the
            // pair apart, the chunk ends at the change (the scheduler meets it, and the
            // other group continues from there), or, too early for that, the pair is
            // carried.
            let changed = free_until[i].min(free_until[j]);
            if changed < until
                && paths_meet_from(
                    &path_i,
                    &path_j,
                    sigma + 2.0 * vb * (until - changed),
                    changed,
                )
            {
                if changed >= s + min_chunk {
                    cut = cut.min(changed);
                } else {
                    missed.push(key(i, j));
                }
            }
        }
        if self.phys.contacts.pair.is_some() {
            let ends: Vec<Vec3> = copies
                .iter()
                .zip(&t_end)
                .map(|(c, &te)| self.flight.at(&c.pos, &c.vel, e - te).0)
                .collect();
            let radii: Vec<f64> = copies.iter().map(|c| c.body.radius).collect();
            for (i, j) in self.close_pairs(&ends, &radii) {
                if local.binary_search(&(i, j)).is_err()
                    && copies[i as usize].is_active()
                    && copies[j as usize].is_active()
                {
                    missed.push(key(i as usize, j as usize));
                }
            }
        }
        Chunk {
            t_end,
            copies,
            pairs: ipairs,
            out,
            violator,
            missed,
            cut: (cut < e).then_some(cut),
            v_seen: v_seen.sqrt(),
            unchanged,
        }
    }

    /// How long each member of a chunk flies free after its group's end
    /// `t_end` (`INFINITY` for the members that do not change or end with the last
    /// group): until its first touch with another member then flying free, with a shot
    /// outside near it (`near`), or with the specimen. The scheduler meets those touches
    /// only after the commit, while the pairs a member forms with the shots of groups that
    /// run longer are checked on its free path (session 60: a shot re-touching its group's
    /// shots as the group parted was checked on its free path against a longer group, and
    /// met one of its shots 18 um deep). Also the shots outside whose free paths such a
    /// touch ends before the last group does, with its time (`deflected`).
    fn free_until(
        &self,
        copies: &[ShotState],
        t_end: &[f64],
        unchanged: &[bool],
        local: &[(u32, u32)],
        near: &[(usize, usize, f64)],
        st: u64,
    ) -> (Vec<f64>, Vec<(usize, f64)>) {
        let n = copies.len();
        let last = (0..n)
            .filter(|&k| !unchanged[k])
            .map(|k| t_end[k])
            .fold(f64::NEG_INFINITY, f64::max);
        let early = |k: usize| !unchanged[k] && copies[k].is_active() && t_end[k] < last;
        let mut until = vec![f64::INFINITY; n];
        let mut deflected = Vec::new();
        if !(0..n).any(early) {
            return (until, deflected);
        }
        let flight = &self.flight;
        // First touch of two free states `(position, velocity, time)`, closing.
        let touch = |a: (Vec3, Vec3, f64), b: (Vec3, Vec3, f64), sigma: f64| {
            let t0 = a.2.max(b.2);
            let (pa, va) = flight.at(&a.0, &a.1, t0 - a.2);
            let (pb, vb) = flight.at(&b.0, &b.1, t0 - b.2);
            pair_touch(&(pb - pa), &(vb - va), sigma).map_or(f64::INFINITY, |tau| t0 + tau)
        };
        let free = |k: usize| (copies[k].pos, copies[k].vel, t_end[k]);
        for k in (0..n).filter(|&k| early(k)) {
            let c = &copies[k];
            if self.phys.contacts.specimen.is_some()
                && let Some(tau) = flight.down_through(c.pos.z, c.vel.z, c.body.radius)
            {
                until[k] = t_end[k] + tau;
            }
        }
        for &(i, j) in local {
            let (i, j) = (i as usize, j as usize);
            let free_i = early(i) || (unchanged[i] && copies[i].is_active());
            let free_j = early(j) || (unchanged[j] && copies[j].is_active());
            if (early(i) || early(j)) && free_i && free_j {
                let sigma = copies[i].body.radius + copies[j].body.radius;
                let t = touch(free(i), free(j), sigma);
                until[i] = until[i].min(t);
                until[j] = until[j].min(t);
            }
        }
        for &(c, m, _) in near {
            if self.mark[c] == st || self.mark[m] != st {
                continue;
            }
            let k = self.local[m] as usize;
            if self.slot[c].owner == NONE && early(k) {
                let f = &self.fly[c];
                let t = touch(
                    free(k),
                    (f.pos, f.vel, f.t_ref),
                    f.radius + copies[k].body.radius,
                );
                until[k] = until[k].min(t);
                if t < last {
                    deflected.push((c, t));
                }
            }
        }
        (until, deflected)
    }

    /// The lean path (binary.rs) for group `grp` (cluster-local indices into `copies`,
    /// states at `s`; `pairs` in group slots), if it applies: no nozzle
    /// wall; every shot of the group free from `s` on; one contact in the group, in
    /// progress or the group's first touch on free paths, between two shots or between a
    /// shot and the specimen, over (or still on) at `e` with its shots inside the domain;
    /// the shots of a pair clear of the specimen throughout; every other shot of the group
    /// clear of the specimen, of the others' free paths and of the actual paths of the
    /// contact's shots until they are handed back. Returns the contact's shots (cluster
    /// indices, the first `n`) and the outcome; `None`: integrate the group as an island.
    fn try_lean(
        &mut self,
        grp: &[usize],
        pairs: &[IslandPair],
        copies: &[ShotState],
        cl: &Cluster,
        s: f64,
        e: f64,
    ) -> Option<([usize; 2], binary::Outcome)> {
        let c = &self.phys.contacts;
        if !self.lean || c.wall.is_some() {
            return None;
        }
        if !grp
            .iter()
            .all(|&k| copies[k].is_active() && !copies[k].on_wall)
        {
            return None;
        }
        // A shot resolved ahead (`t_start > s`) holds its state at its own clock and
        // flies free from there.
        let clock = |k: usize| copies[k].t_start.max(s);
        let flight = self.flight;
        let at = |k: usize, t: f64| flight.at(&copies[k].pos, &copies[k].vel, t - clock(k));
        // Free paths are straight relative lines (the same gravity for all).
        let touch = |i: usize, j: usize| {
            let t0 = clock(i).max(clock(j));
            let ((pi, vi), (pj, vj)) = (at(i, t0), at(j, t0));
            let sigma = copies[i].body.radius + copies[j].body.radius;
            let t = pair_touch(&(pj - pi), &(vj - vi), sigma)?;
            (t0 + t < e).then_some(t0 + t)
        };
        let floor = |i: usize| {
            let m = &copies[i];
            c.specimen.as_ref()?;
            let t = flight.down_through(m.pos.z, m.vel.z, m.body.radius)?;
            (clock(i) + t < e).then_some(clock(i) + t)
        };
        // The contact: the one in progress (one at most), else the group's first touch.
        // (`lean[1] == lean[0]`: the specimen.)
        let mut on: Vec<([usize; 2], binary::InProgress)> = Vec::new();
        for pr in pairs.iter().filter(|p| p.touching) {
            let progress = binary::InProgress {
                onset: pr.onset,
                contact_time: pr.contact_time,
                damping: f64::NAN,
            };
            on.push(([grp[pr.a as usize], grp[pr.b as usize]], progress));
        }
        for &k in grp.iter().filter(|&&k| copies[k].on_specimen) {
            let m = &copies[k];
            let progress = binary::InProgress {
                onset: m.specimen_onset,
                contact_time: m.specimen_contact_time,
                damping: m.specimen_damping,
            };
            on.push(([k, k], progress));
        }
        let (lean, progress) = match on[..] {
            [] => {
                let (mut first, mut lean) = (f64::INFINITY, None);
                for pr in pairs {
                    let (i, j) = (grp[pr.a as usize], grp[pr.b as usize]);
                    if let Some(t) = touch(i, j)
                        && t < first
                    {
                        (first, lean) = (t, Some([i, j]));
                    }
                }
                for &k in grp {
                    if let Some(t) = floor(k)
                        && t < first
                    {
                        (first, lean) = (t, Some([k, k]));
                    }
                }
                (lean?, None)
            }
            [(lean, progress)] => (lean, Some(progress)),
            _ => return None,
        };
        let n = if lean[0] == lean[1] { 1 } else { 2 };
        let in_lean = |k: usize| k == lean[0] || k == lean[1];
        if lean.iter().any(|&k| copies[k].t_start > s) {
            return None;
        }
        // The other shots: clear of the specimen and of each other on free paths.
        for &k in grp.iter().filter(|&&k| !in_lean(k)) {
            if !self.flies_clear(&copies[k], clock(k), e) {
                return None;
            }
        }
        for pr in pairs {
            let (i, j) = (grp[pr.a as usize], grp[pr.b as usize]);
            if !in_lean(i) && !in_lean(j) && touch(i, j).is_some() {
                return None;
            }
        }
        let body = |m: &ShotState| binary::Body {
            pos: m.pos,
            vel: m.vel,
            omega: m.omega,
            mass: m.body.mass,
            radius: m.body.radius,
        };
        let bodies: Vec<binary::Body> = lean[..n].iter().map(|&k| body(&copies[k])).collect();
        let o = self.lean_outcome(&bodies, progress, s, e, cl.apart_after.max(s))?;
        if !o.state[..n]
            .iter()
            .all(|(p, _)| self.phys.domain.contains(p))
        {
            return None;
        }
        // Each shot's path: free flight (a parabola) from `s` to the contact, chords
        // between the contact's samples (off the path by at most half a step times the
        // step's change of velocity), free flight from the kink to `end`. After `end`
        // the scheduler predicts the handed-back shots' touches as for any free shot.
        let specimen = c.specimen.is_some() && n == 2;
        for q in 0..n {
            let m = &copies[lean[q]];
            let r = m.body.radius;
            if specimen && !o.above_plane(q, m.pos.z, r, self.flight.g) {
                return None;
            }
            for &k in grp.iter().filter(|&&k| !in_lean(k)) {
                let nb = binary::Neighbour {
                    clock: clock(k),
                    pos: copies[k].pos,
                    vel: copies[k].vel,
                    until: f64::INFINITY,
                    bounded_before: false,
                    speed: 0.0,
                    sigma: copies[k].body.radius + r,
                };
                if !o.clear_of(q, &flight, s, (m.pos, m.vel), &nb) {
                    return None;
                }
            }
        }
        Some((lean, o))
    }

    /// The lean path (binary.rs) for `bodies` (two shots, or one on the specimen) from
    /// `s` to at most `e`: fresh (`progress` `None`) or a contact in progress.
    fn lean_outcome(
        &mut self,
        bodies: &[binary::Body],
        progress: Option<binary::InProgress>,
        s: f64,
        e: f64,
        apart_after: f64,
    ) -> Option<binary::Outcome> {
        let c = &self.phys.contacts;
        let set = binary::Settings {
            tolerance: self.phys.tolerance,
            contact_steps: self.phys.contact_steps,
        };
        let mu = |f: fn(&crate::contact::Friction) -> f64| c.friction.as_ref().map_or(0.0, f);
        match bodies {
            [a, b] => binary::resolve(
                &c.pair.as_ref()?.law,
                self.tables[0].as_ref(),
                mu(|f| f.shot),
                &self.flight,
                a,
                b,
                progress,
                s,
                e,
                apart_after,
                set,
            ),
            [a] => binary::resolve_specimen(
                c.specimen.as_ref()?,
                self.tables[1].as_ref(),
                mu(|f| f.specimen),
                &self.flight,
                a,
                progress,
                s,
                e,
                apart_after,
                set,
            ),
            _ => None,
        }
    }

    /// Pairs `(i, j)`, `i < j`, whose balls `(centres, radii)` overlap.
    fn close_pairs(&mut self, centres: &[Vec3], radii: &[f64]) -> Vec<(u32, u32)> {
        let n = centres.len();
        if n <= ALL_PAIRS_UP_TO {
            let mut v = Vec::new();
            for i in 0..n {
                for j in i + 1..n {
                    if (centres[i] - centres[j]).norm() < radii[i] + radii[j] {
                        v.push((i as u32, j as u32));
                    }
                }
            }
            v
        } else {
            let mut v = self.cells.pairs(centres, radii);
            for p in &mut v {
                *p = (p.0.min(p.1), p.0.max(p.1));
            }
            v.sort_unstable();
            v
        }
    }

    /// Writes a cluster chunk's result back: continues the cluster if contacts remain,
    /// releases the other shots to free flight.
    fn commit(&mut self, slot: usize, mut cl: Cluster, e: f64, chunk: Chunk) {
        let Chunk {
            t_end,
            copies,
            pairs: ipairs,
            out,
            unchanged,
            ..
        } = chunk;
        self.out.impacts.extend(out.impacts);
        self.out.events.extend(out.events);
        self.out.work.add(&out.work);
        let members = std::mem::take(&mut cl.members);
        // Who is still in contact.
        let mut held = vec![false; members.len()];
        cl.pairs.clear();
        for p in &ipairs {
            if p.touching {
                let (i, j) = (p.a as usize, p.b as usize);
                if copies[i].is_active() && copies[j].is_active() {
                    held[i] = true;
                    held[j] = true;
                    let (a, b) = (copies[i].id.0, copies[j].id.0);
                    cl.pairs.insert(
                        (a.min(b), a.max(b)),
                        PairState {
                            contact_time: p.contact_time,
                            onset: p.onset,
                            xi: p.xi,
                        },
                    );
                }
            }
        }
        for (k, c) in copies.iter().enumerate() {
            if c.is_active() && (c.on_specimen || c.on_wall) {
                held[k] = true;
            }
        }
        let continues = e < self.end && held.iter().any(|&h| h);
        for (k, (c, &m)) in copies.into_iter().zip(&members).enumerate() {
            if unchanged[k] {
                self.slot[m].owner = NONE;
                continue;
            }
            self.v_max = self.v_max.max(c.vel.norm());
            let active = c.is_active();
            self.shots[m] = c;
            self.sync(m);
            self.slot[m].ver += 1;
            self.slot[m].owner = NONE;
            if !active {
                self.slot[m].present = false;
                self.grid.remove(m);
                continue;
            }
            if self.fly[m].t_ref < t_end[k] {
                self.fly[m].t_ref = t_end[k];
            }
            let cell = self.grid.cell_of(&self.shots[m].pos);
            self.grid.place(m, cell);
        }
        self.free_slots.push(slot);
        if continues {
            // The shots still in contact continue, one cluster per group held together
            // by contacts (clusters never stay merged for longer than they touch).
            let roots = group_roots(
                members.len(),
                ipairs
                    .iter()
                    .filter(|p| p.touching && held[p.a as usize] && held[p.b as usize])
                    .map(|p| (p.a as usize, p.b as usize)),
            );
            let mut group_slot: HashMap<usize, usize> = HashMap::default();
            let mut order: Vec<usize> = Vec::new();
            for k in 0..members.len() {
                if !held[k] {
                    continue;
                }
                let r = roots[k];
                let next = self.free_slots.pop().unwrap_or_else(|| {
                    self.clusters.push(None);
                    self.clusters.len() - 1
                });
                let gs = *group_slot.entry(r).or_insert_with(|| {
                    order.push(next);
                    next
                });
                if gs != next {
                    self.free_slots.push(next);
                }
                let m = members[k];
                self.slot[m].owner = gs as u32;
                self.next_change[m] = Pending {
                    t: e,
                    with: m as u32,
                    t_other: e,
                };
                let c = self.clusters[gs].get_or_insert_with(|| Cluster {
                    members: Vec::new(),
                    pairs: HashMap::default(),
                    clock: e,
                    tc: cl.tc,
                    chunks: cl.chunks + 1,
                    apart_after: e,
                    onset: e,
                    gen_: 0,
                });
                c.members.push(m);
            }
            for (key, ps) in &cl.pairs {
                // (Keys are shot ids; the owner is looked up by the shot's index.)
                let Some(m) = members
                    .iter()
                    .copied()
                    .find(|&m| self.shots[m].id.0 == key.0)
                else {
                    continue;
                };
                let o = self.slot[m].owner;
                if o != NONE
                    && let Some(c) = self.clusters[o as usize].as_mut()
                {
                    c.pairs.insert(*key, *ps);
                }
            }
            for gs in order {
                self.next_gen += 1;
                let g = self.next_gen;
                let mut kind = Kind::Continue;
                if let Some(c) = self.clusters[gs].as_mut() {
                    c.gen_ = g;
                    if c.members.len() + c.pairs.len() <= 3 && c.members.len() == c.pairs.len() + 1
                    {
                        kind = Kind::ContinueLone;
                    }
                }
                self.queue.push(
                    e,
                    Ev {
                        t: e,
                        kind,
                        a: gs as u32,
                        b: 0,
                        va: g,
                        vb: 0,
                    },
                );
            }
        }
        // Released shots fly free again.
        for (&m, _) in members.iter().zip(&unchanged).filter(|(_, u)| !**u) {
            if self.slot[m].present && self.slot[m].owner == NONE && self.fly[m].t_ref < self.end {
                self.predict(m);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Feeds `watch` a run in chunks of `chunk` integrator steps, the i-th step carrying
    /// `shots(i)` shots; the step count at which it gives up, if it does.
    fn watch_run(
        watch: &mut PileWatch,
        from: u64,
        steps: u64,
        chunk: u64,
        carried_before: u64,
        shots: impl Fn(u64) -> u64,
    ) -> (Option<(u64, GiveUpReason)>, u64) {
        let mut carried = carried_before;
        let mut i = from;
        while i < from + steps {
            let n = chunk.min(from + steps - i);
            carried += (i..i + n).map(&shots).sum::<u64>();
            i += n;
            if let Some(why) = watch.judge(i, carried) {
                return (Some((i, why)), carried);
            }
        }
        (None, carried)
    }

    /// A pile forming late is seen while it forms: after 200,000 steps of lone contacts
    /// (one shot each), 60 shots per step from then on give up once they are more than
    /// (32 - 1) / 59 of the latest four to five blocks, where the whole run's average
    /// (what the rule took until session 29) would still read 1 + 59 x 50,000 / 250,000 =
    /// 12.8 after 50,000 such steps. A burst of one block at 60 shots per step amid
    /// steps of two does not: over the latest four blocks or more it reads at most
    /// (60 + 3 x 2) / 4 = 16.5. Nothing is judged before the first block ends.
    #[test]
    fn the_pile_watch_judges_the_latest_steps() {
        let max = crate::sim::MAX_ISLAND as u64;
        let mut w = PileWatch::default();
        // 100 steps at 100 shots: not judged yet.
        assert!(w.judge(100, 100 * 100).is_none());
        let mut w = PileWatch::default();
        let (gave, carried) = watch_run(&mut w, 0, 200_000, 137, 0, |_| 1);
        assert!(gave.is_none());
        let (gave, _) = watch_run(&mut w, 200_000, 100_000, 137, carried, |_| 60);
        let (at, why) = gave.expect("a pile forming late must be seen");
        let GiveUpReason::Islands { mean, steps } = why else {
            panic!("{why:?}")
        };
        assert!(mean > max as f64 && mean <= 60.0, "{mean}");
        assert!(
            steps >= (PILE_BLOCKS as u64 - 1) * PILE_BLOCK_STEPS,
            "{steps}"
        );
        // The latest steps span at most five blocks, each overshooting by at most a
        // chunk: (31 / 59) x 5 x 10,137 = 26,632 steps of pile.
        let n = at - 200_000;
        assert!(n <= 26_632 + 137, "gave up {n} steps into the pile");
        let whole_run = (200_000 + 60 * n) as f64 / (200_000 + n) as f64;
        assert!(whole_run < max as f64, "{whole_run}");

        let mut w = PileWatch::default();
        let burst = |i: u64| if (60_000..70_000).contains(&i) { 60 } else { 2 };
        let (gave, _) = watch_run(&mut w, 0, 200_000, 137, 0, burst);
        assert!(gave.is_none(), "{gave:?}");
    }

    fn straight(p0: Vec3, v: Vec3, times: &[f64]) -> Vec<(f64, Vec3)> {
        times.iter().map(|&t| (t, p0 + v * t)).collect()
    }

    /// Two shots crossing between their samples (apart at every sample time) meet; the
    /// same paths offset by 1 % of contact distance beyond it do not.
    #[test]
    fn paths_that_cross_between_samples_meet() {
        let sigma = 0.8e-3;
        let times = [0.0, 1e-5, 2e-5];
        let a = straight(
            Vec3::new(-0.5e-3, 0.0, 0.0),
            Vec3::new(100.0, 0.0, 0.0),
            &times,
        );
        // `b` waits at 0.79 mm beside the middle of `a`'s path.
        let b = straight(Vec3::new(0.0, 0.79e-3, 0.0), Vec3::zeros(), &times);
        for &(t, p) in &a {
            let q = b.iter().find(|s| s.0 == t).unwrap().1;
            assert!((p - q).norm() > sigma, "apart at the samples");
        }
        assert!(paths_meet(&a, &b, sigma));
        let far = straight(Vec3::new(0.0, 0.808e-3, 0.0), Vec3::zeros(), &times);
        assert!(!paths_meet(&a, &far, sigma));
    }

    /// [`paths_meet_from`] as it was written before session 70: every sample time of
    /// either path collected and sorted, each path read by a binary search per time.
    fn paths_meet_from_by_search(
        a: &[(f64, Vec3)],
        b: &[(f64, Vec3)],
        sigma: f64,
        from: f64,
    ) -> bool {
        let (Some(&(a0, _)), Some(&(a1, _)), Some(&(b0, _)), Some(&(b1, _))) =
            (a.first(), a.last(), b.first(), b.last())
        else {
            return false;
        };
        let (t0, t1) = (a0.max(b0).max(from), a1.min(b1));
        if t1 < t0 {
            return false;
        }
        let at = |p: &[(f64, Vec3)], t: f64| -> Vec3 {
            if p.len() == 1 {
                return p[0].1;
            }
            let k = p.partition_point(|s| s.0 < t).clamp(1, p.len() - 1);
            let ((ta, pa), (tb, pb)) = (p[k - 1], p[k]);
            if tb > ta {
                pa + (pb - pa) * ((t - ta) / (tb - ta)).clamp(0.0, 1.0)
            } else {
                pb
            }
        };
        let mut times: Vec<f64> = a
            .iter()
            .chain(b)
            .map(|s| s.0)
            .filter(|&t| t > t0 && t < t1)
            .collect();
        times.push(t1);
        times.sort_unstable_by(f64::total_cmp);
        let (mut t, mut d) = (t0, at(b, t0) - at(a, t0));
        if d.norm() < sigma {
            return true;
        }
        for &tn in &times {
            let dn = at(b, tn) - at(a, tn);
            if tn > t && closest_approach(&d, &((dn - d) / (tn - t)), tn - t) < sigma {
                return true;
            }
            (t, d) = (tn, dn);
        }
        d.norm() < sigma
    }

    /// The cursors' walk decides as the search did, on random paths near the contact
    /// distance: sampled at their own times, at shared times, with repeated times, one
    /// sample long, starting and ending apart, read from a time inside.
    #[test]
    fn the_walk_along_two_paths_decides_as_the_search_did() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(70);
        let sigma = 0.8e-3;
        let (mut met, mut apart) = (0, 0);
        for case in 0..20_000 {
            let path = |rng: &mut rand::rngs::StdRng, shared: &[f64]| {
                let n = rng.random_range(1..12);
                let mut times: Vec<f64> = if case % 3 == 0 {
                    shared.iter().copied().take(n).collect()
                } else {
                    let t0 = rng.random_range(0.0..2e-6);
                    (0..n).map(|_| t0 + rng.random_range(0.0..1e-5)).collect()
                };
                if case % 7 == 0 && times.len() > 1 {
                    times[1] = times[0]; // a repeated time
                }
                times.sort_by(f64::total_cmp);
                let p0 = Vec3::new(
                    rng.random_range(-1e-3..1e-3),
                    rng.random_range(-1e-3..1e-3),
                    0.0,
                );
                let v = Vec3::new(
                    rng.random_range(-60.0..60.0),
                    rng.random_range(-60.0..60.0),
                    0.0,
                );
                // Kinked at each sample, as contacts bend a path.
                times
                    .iter()
                    .map(|&t| {
                        let kink = Vec3::new(
                            rng.random_range(-2e-4..2e-4),
                            rng.random_range(-2e-4..2e-4),
                            0.0,
                        );
                        (t, p0 + v * t + kink)
                    })
                    .collect::<Vec<_>>()
            };
            let shared: Vec<f64> = (0..12).map(|k| k as f64 * 1e-6).collect();
            let (a, b) = (path(&mut rng, &shared), path(&mut rng, &shared));
            let from = if case % 2 == 0 {
                f64::NEG_INFINITY
            } else {
                rng.random_range(0.0..1e-5)
            };
            let got = paths_meet_from(&a, &b, sigma, from);
            assert_eq!(
                got,
                paths_meet_from_by_search(&a, &b, sigma, from),
                "case {case}: {a:?} {b:?} from {from}"
            );
            if got { met += 1 } else { apart += 1 }
        }
        println!("met {met}, apart {apart}");
        assert!(met > 2000 && apart > 2000, "met {met}, apart {apart}");
    }

    /// Samples at different times: each path is read between its own samples; only the
    /// time both paths cover counts.
    #[test]
    fn paths_are_compared_where_both_are_known() {
        let sigma = 0.8e-3;
        let a = straight(Vec3::zeros(), Vec3::new(100.0, 0.0, 0.0), &[0.0, 1e-5]);
        // `b` sits on `a`'s path at 0.5 mm: reached at 5 us.
        let b_on = straight(Vec3::new(0.5e-3, 0.0, 0.0), Vec3::zeros(), &[3e-6, 7e-6]);
        assert!(paths_meet(&a, &b_on, sigma));
        // Known only after `a` has passed 2 mm beyond it (and one sample long).
        let b_late = [(1e-5 + 1e-9, Vec3::new(-1.5e-3, 0.0, 0.0))];
        assert!(!paths_meet(&a, &b_late, sigma));
        let b_once = [(5e-6, Vec3::new(0.5e-3, 0.7e-3, 0.0))];
        assert!(paths_meet(&a, &b_once, sigma));
        assert!(!paths_meet(&a, &[], sigma));
    }
}
