//! Work counters: how often each stage and effect ran. Reported in summary.json so a
//! user (and the tests) can see that effects which are off cost nothing.

use serde::Serialize;

/// Per-run (or per-island, then summed) work counts. Plain integers, summed in a fixed
/// order, so they are identical for any thread count.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct WorkCounters {
    /// Accepted integrator steps, summed over islands (one island step moves all its shots).
    pub steps_accepted: u64,
    /// Rejected trial steps (error too large, or bisection trials when locating events).
    pub steps_rejected: u64,
    /// Shot-steps: accepted steps times the shots they moved.
    pub shot_steps: u64,
    /// Right-hand-side evaluations (one per Runge-Kutta stage, per island).
    pub rhs_evaluations: u64,
    /// Jet-field samples (one per shot per stage with drag or lateral force on).
    pub flow_samples: u64,
    /// Drag force evaluations.
    pub drag_calls: u64,
    /// Lateral (lift) force evaluations.
    pub lateral_force_calls: u64,
    /// Gravity evaluations.
    pub gravity_calls: u64,
    /// Shot-specimen contact tests.
    pub specimen_contact_checks: u64,
    /// Shot-nozzle-wall contact tests.
    pub wall_contact_checks: u64,
    /// Shot-shot pair tests in the narrow phase.
    pub pair_contact_checks: u64,
    /// Neighbour searches (sweeps or cell-list builds) for shot-shot contact; a window
    /// that only filters the pairs its neighbour-list skin kept does not count.
    pub neighbour_searches: u64,
    /// Jet-region border crossings located (the fixed-step method locates none: each of
    /// its steps reads the shots' regions off their positions at its end).
    pub region_crossings: u64,
    /// Contact onsets located (all kinds).
    pub contact_onsets: u64,
    /// Tangential (friction) force evaluations.
    pub friction_calls: u64,
    /// Turbulent eddies drawn.
    pub eddies: u64,
    /// Event scheduler: free-flight events handled (entries, cell crossings, exits).
    pub flight_events: u64,
    /// Event scheduler: cluster resolutions (a contact and the shots near it, integrated
    /// together), counting continued chunks.
    pub clusters: u64,
    /// Event scheduler: cluster resolutions redone because a shot left outside came
    /// within contact.
    pub cluster_redos: u64,
    /// Event scheduler: contacts found already overlapping when their cluster started
    /// (should stay zero; reported so a user can see it).
    pub late_contacts: u64,
    /// Event scheduler: of `late_contacts`, those overlapping deeper than 1e-9 of their
    /// contact distance (a contact missed; the others are shots that had just parted,
    /// meeting again at the rounding level).
    pub late_contacts_deep: u64,
    /// Event scheduler: lone contacts (two shots, or a shot and the
    /// specimen) resolved in closed form and a two-body frame instead of as an island
    /// (`events/binary.rs`).
    pub lean_contacts: u64,
    /// Event scheduler: contacts in progress continued on the lean path when all that a
    /// cluster still held was that contact (`events/lone.rs`).
    pub lean_continuations: u64,
    /// Lone shots whose settled specimen contact turned into sliding on it
    /// (frictionless) or rolling (with friction), no longer stepped through (counted at
    /// each start: a rolling shot that slips and rolls again counts twice).
    pub slides: u64,
    /// Shots fed into the run whose entry was held back because they would have appeared
    /// overlapping a shot already there (counted at each hold).
    pub entries_held: u64,
    /// Windows scheduler: windows that lone shots slept through, per shot (`sim/sleep.rs`:
    /// not looked at, their states read off their kept steps when they wake).
    pub shot_windows_slept: u64,
    /// Fixed-step method: steps of lone shots away from every contact, taken on their
    /// body forces alone (`Physics::free_steps`; counted in `shot_steps` too).
    pub free_steps: u64,
}

impl WorkCounters {
    /// Adds `other` into `self`.
    pub fn add(&mut self, other: &WorkCounters) {
        self.steps_accepted += other.steps_accepted;
        self.steps_rejected += other.steps_rejected;
        self.shot_steps += other.shot_steps;
        self.rhs_evaluations += other.rhs_evaluations;
        self.flow_samples += other.flow_samples;
        self.drag_calls += other.drag_calls;
        self.lateral_force_calls += other.lateral_force_calls;
        self.gravity_calls += other.gravity_calls;
        self.specimen_contact_checks += other.specimen_contact_checks;
        self.wall_contact_checks += other.wall_contact_checks;
        self.pair_contact_checks += other.pair_contact_checks;
        self.neighbour_searches += other.neighbour_searches;
        self.region_crossings += other.region_crossings;
        self.contact_onsets += other.contact_onsets;
        self.friction_calls += other.friction_calls;
        self.eddies += other.eddies;
        self.flight_events += other.flight_events;
        self.clusters += other.clusters;
        self.cluster_redos += other.cluster_redos;
        self.late_contacts += other.late_contacts;
        self.late_contacts_deep += other.late_contacts_deep;
        self.lean_contacts += other.lean_contacts;
        self.lean_continuations += other.lean_continuations;
        self.slides += other.slides;
        self.entries_held += other.entries_held;
        self.shot_windows_slept += other.shot_windows_slept;
        self.free_steps += other.free_steps;
    }
}
