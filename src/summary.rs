//! Run summary: hit fraction, impact-speed and impact-radius statistics and histograms
//! in the paper's bins (5 m/s as its Figure 12, 5 mm as its Figure 13), effects used,
//! step and contact counts. Statistics are over first hits (one per shot, as the paper
//! counts particles); rebound hits are counted separately.

use crate::contact::specimen::SpecimenShape;
use crate::counters::WorkCounters;
use crate::record::loading::{JetLoading, LoadingTally};
use crate::record::{Impact, RunEvent};
use crate::scene::{EffectDecision, Scene};
use crate::sim::{RunOutput, RunSink, RunTail};
use crate::state::{ShotState, ShotStatus};
use serde::Serialize;

/// Descriptive statistics of a sample.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stats {
    /// Sample size.
    pub count: usize,
    /// Mean.
    pub mean: f64,
    /// Median.
    pub median: f64,
    /// 10th percentile (linear interpolation).
    pub p10: f64,
    /// 90th percentile.
    pub p90: f64,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

/// Percentile `q` in [0, 100] of sorted data, with linear interpolation (numpy default).
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let pos = q / 100.0 * (sorted.len() - 1) as f64;
    let lo = pos.floor() as usize;
    let hi = pos.ceil() as usize;
    sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - lo as f64)
}

impl Stats {
    /// Statistics of `values`, or `None` for an empty sample.
    pub fn of(values: &[f64]) -> Option<Stats> {
        if values.is_empty() {
            return None;
        }
        let mut v = values.to_vec();
        v.sort_by(f64::total_cmp);
        Some(Stats {
            count: v.len(),
            mean: v.iter().sum::<f64>() / v.len() as f64,
            median: percentile(&v, 50.0),
            p10: percentile(&v, 10.0),
            p90: percentile(&v, 90.0),
            min: v[0],
            max: v[v.len() - 1],
        })
    }
}

/// Integer statistics (step counts).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CountStats {
    /// Shots counted.
    pub count: usize,
    /// Smallest.
    pub min: u64,
    /// Median.
    pub median: u64,
    /// Largest.
    pub max: u64,
}

impl CountStats {
    fn of(mut v: Vec<u64>) -> Option<CountStats> {
        if v.is_empty() {
            return None;
        }
        v.sort_unstable();
        Some(CountStats {
            count: v.len(),
            min: v[0],
            median: v[v.len() / 2],
            max: v[v.len() - 1],
        })
    }
}

/// Fixed-width histogram starting at zero.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Histogram {
    /// Quantity and unit.
    pub quantity: String,
    /// Bin width (unit of `quantity`).
    pub bin_width: f64,
    /// Lower edge of each bin.
    pub lower_edges: Vec<f64>,
    /// Counts per bin.
    pub counts: Vec<usize>,
    /// Values at or above the last bin's upper edge.
    pub overflow: usize,
}

impl Histogram {
    /// Histogram of `values` with `bins` bins of `width` from 0 (negative values go to bin 0).
    pub fn new(quantity: &str, values: &[f64], width: f64, bins: usize) -> Histogram {
        let mut counts = vec![0; bins];
        let mut overflow = 0;
        for &v in values {
            let k = (v.max(0.0) / width).floor() as usize;
            if k < bins {
                counts[k] += 1;
            } else {
                overflow += 1;
            }
        }
        Histogram {
            quantity: quantity.to_string(),
            bin_width: width,
            lower_edges: (0..bins).map(|k| k as f64 * width).collect(),
            counts,
            overflow,
        }
    }
}

/// Step counts the acceptance tests and users look at.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepReport {
    /// Accepted island steps.
    pub accepted: u64,
    /// Rejected trial steps (incl. event-location trials).
    pub rejected: u64,
    /// Shot-steps (accepted steps x shots moved).
    pub shot_steps: u64,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// Per shot: steps from entry to the onset of its first specimen contact.
    pub flight_to_first_contact: Option<CountStats>,
    /// Per shot: steps during its first specimen contact.
    pub first_contact: Option<CountStats>,
}

/// Contact counts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactReport {
    /// Shot-specimen contacts (= impact records).
    pub shot_specimen: usize,
    /// Shot-shot contacts.
    pub shot_shot: u64,
    /// Shot-nozzle-wall contacts.
    pub shot_wall: u64,
}

/// The integrator the scene asked for.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IntegratorReport {
    /// `adaptive`, `verlet` or `hybrid`.
    pub method: String,
    /// Relative error tolerance per step (the adaptive method's, and the hybrid method's
    /// in flight).
    pub tolerance: f64,
    /// The fixed step, ns (`verlet`; `hybrid` inside contacts).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fixed_step_ns: Option<f64>,
}

/// Everything summary.json holds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// "peenflow".
    pub tool: String,
    /// Crate version.
    pub version: String,
    /// Scene file.
    pub scene: String,
    /// Scene title.
    pub title: String,
    /// Seed.
    pub seed: u64,
    /// Simulated time, s.
    pub simulated_time_s: f64,
    /// Shots in the run.
    pub shots: usize,
    /// Shots the feed should have delivered on average (rate x duration for streams).
    pub shots_expected: f64,
    /// Shots with at least one specimen contact.
    pub shots_hit: usize,
    /// `shots_hit / shots`.
    pub hit_fraction: f64,
    /// Shots that never reached the specimen.
    pub never_hit: usize,
    /// Shots dropped on leaving the domain.
    pub left_domain: usize,
    /// Shots stopped by a numerical failure (see `events`).
    pub failed: usize,
    /// All impact records.
    pub impacts: usize,
    /// First hits (one per shot that hit).
    pub first_hits: usize,
    /// Rebound hits.
    pub rebound_hits: usize,
    /// Normal impact speed of first hits, m/s (the paper's y-direction velocity).
    pub normal_speed_m_s: Option<Stats>,
    /// Impact speed of first hits, m/s.
    pub speed_m_s: Option<Stats>,
    /// Distance of first hits from the jet axis, m.
    pub radius_m: Option<Stats>,
    /// On a cylindrical specimen: where first hits sit around it, m of arc from its
    /// crest line (signed; `SpecimenShape::unrolled`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub around_m: Option<Stats>,
    /// On a grooved specimen: where first hits sit across it, m of arc from the middle of
    /// the groove at the origin (signed; `SpecimenShape::unrolled`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub across_m: Option<Stats>,
    /// On a grooved specimen: the impacts on each zone of its surface (bottom, root
    /// fillet, flank, edge, land), from the bottom up.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub zones: Vec<ZoneStats>,
    /// The grooved specimen is a gear (for the report's words; summary.json's
    /// `zones` and `across_m` are the same on both).
    #[serde(skip)]
    pub on_gear: bool,
    /// Normal impact speed of first hits in 5 m/s bins (paper Figure 12).
    pub normal_speed_histogram: Histogram,
    /// Impact radius of first hits in 5 mm bins (paper Figure 13).
    pub radius_histogram: Histogram,
    /// How heavily the shots load the air jet, from the first hits (beyond the paper:
    /// [`crate::record::loading`]); absent without the jet, without a first hit that met
    /// no other shot before, and for feeds other than a stream or a batch.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jet_loading: Option<JetLoading>,
    /// Effects and why.
    pub effects: Vec<EffectDecision>,
    /// Wall-clock time of the simulation, s.
    pub wall_time_s: f64,
    /// Worker threads.
    pub threads: usize,
    /// Step counts.
    pub steps: StepReport,
    /// Contact counts.
    pub contacts: ContactReport,
    /// Work counters per stage and effect.
    pub work: WorkCounters,
    /// The integration method and its settings.
    pub integrator: IntegratorReport,
    /// Scheduler that ran: `windows`, `events` (ballistic scenes) or `independent` (no
    /// shot-shot contact).
    pub scheduler: String,
    /// Why the scheduler that ran is not the one the scene chose (the event scheduler
    /// gave up on a dense pile and the run was redone on windows), if so.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub scheduler_note: Option<String>,
    /// Synchronisation windows.
    pub windows: u64,
    /// Windows re-run after an unpaired overlap.
    pub window_redos: u64,
    /// Most shot states the run held at once (streamed windows runs: the shots in flight
    /// and those waiting to be written in id order; otherwise every shot fed).
    pub peak_shots_held: usize,
    /// Shots stopped, with time, cause and suggested fix.
    pub events: Vec<RunEvent>,
}

/// The impacts on one zone of a grooved specimen ([`crate::contact::groove::Zone`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ZoneStats {
    /// `bottom`, `fillet`, `flank`, `edge` or `land`.
    pub zone: String,
    /// First hits there.
    pub first_hits: usize,
    /// All impacts there (first hits and rebounds).
    pub impacts: usize,
    /// Normal impact speed of the first hits there, m/s.
    pub normal_speed_m_s: Option<Stats>,
    /// Incidence of the first hits there, degrees from the surface's normal.
    pub angle_deg: Option<Stats>,
}

/// Builds a summary from the records as a run hands them over (a [`RunSink`]): counts,
/// and the few numbers per first hit that exact percentiles and the jet's loading need
/// (at most 80 bytes per shot that hits), never the records themselves.
#[derive(Debug, Clone, Default)]
pub struct SummaryBuilder {
    normal: Vec<f64>,
    speed: Vec<f64>,
    radius: Vec<f64>,
    around: Vec<f64>,
    /// On a groove, per zone: impacts, and the normal speeds and angles of first hits.
    zone_impacts: [usize; 5],
    zone_first: [(Vec<f64>, Vec<f64>); 5],
    shape: SpecimenShape,
    impacts: usize,
    shots: usize,
    shots_hit: usize,
    left_domain: usize,
    failed: usize,
    to_first_contact: Vec<u64>,
    first_contact: Vec<u64>,
    collisions: u64,
    wall_contacts: u64,
    loading: LoadingTally,
    /// Runs pooled into these records (0 or 1: one run).
    runs: usize,
}

impl RunSink for SummaryBuilder {
    fn impacts(&mut self, batch: &[Impact]) {
        self.impacts += batch.len();
        self.loading.impacts(batch);
        if let SpecimenShape::Groove(g) = &self.shape {
            for i in batch {
                let z = g.zone(&crate::Vec3::new(i.x_m, i.y_m, i.z_m)) as usize;
                self.zone_impacts[z] += 1;
                if i.first_hit == 1 {
                    self.zone_first[z].0.push(i.normal_speed_m_s);
                    self.zone_first[z].1.push(i.angle_deg);
                }
            }
        }
        for i in batch.iter().filter(|i| i.first_hit == 1) {
            self.normal.push(i.normal_speed_m_s);
            self.speed.push(i.speed_m_s);
            self.radius.push(i.radius_m());
            if !self.shape.is_plane() {
                let p = crate::Vec3::new(i.x_m, i.y_m, i.z_m);
                self.around.push(self.shape.unrolled(&p).0);
            }
        }
    }

    fn shot(&mut self, s: &ShotState) {
        self.shots += 1;
        self.loading.shot(s.body.mass);
        if s.hits > 0 {
            self.shots_hit += 1;
            self.first_contact.push(s.first_contact_steps);
        }
        match s.status {
            ShotStatus::LeftDomain => self.left_domain += 1,
            ShotStatus::Failed => self.failed += 1,
            ShotStatus::Active => {}
        }
        if let Some(k) = s.steps_to_first_contact {
            self.to_first_contact.push(k);
        }
        self.collisions += s.collisions as u64;
        self.wall_contacts += s.wall_contacts as u64;
    }
}

impl SummaryBuilder {
    /// A builder for a run on the specimen surface `shape`.
    pub fn on(shape: SpecimenShape) -> Self {
        SummaryBuilder {
            shape,
            ..Default::default()
        }
    }

    /// The summary of the run whose records this builder received.
    pub fn finish(
        self,
        scene: &Scene,
        effects: &[EffectDecision],
        run: &RunTail,
        wall_time: f64,
        threads: usize,
    ) -> Summary {
        let n = self.shots;
        let first_hits = self.normal.len();
        let jet_loading =
            self.loading
                .finish(scene, effects, n, self.runs.max(1), run.air_speed_factor);
        let radius_mm: Vec<f64> = self.radius.iter().map(|r| r * 1e3).collect();
        Summary {
            tool: "peenflow".into(),
            version: env!("CARGO_PKG_VERSION").into(),
            scene: scene.path.clone(),
            title: scene.title.clone(),
            seed: scene.seed,
            simulated_time_s: run.end_time,
            shots: n,
            shots_expected: scene.feed.expected_count(),
            shots_hit: self.shots_hit,
            hit_fraction: if n > 0 {
                self.shots_hit as f64 / n as f64
            } else {
                0.0
            },
            never_hit: n - self.shots_hit,
            left_domain: self.left_domain,
            failed: self.failed,
            impacts: self.impacts,
            first_hits,
            rebound_hits: self.impacts - first_hits,
            normal_speed_m_s: Stats::of(&self.normal),
            speed_m_s: Stats::of(&self.speed),
            radius_m: Stats::of(&self.radius),
            around_m: match self.shape {
                SpecimenShape::Cylinder { .. } => Stats::of(&self.around),
                _ => None,
            },
            across_m: match self.shape {
                SpecimenShape::Groove(_) => Stats::of(&self.around),
                _ => None,
            },
            on_gear: matches!(&self.shape, SpecimenShape::Groove(g) if g.gear().is_some()),
            zones: match self.shape {
                SpecimenShape::Groove(_) => crate::contact::groove::Zone::ALL
                    .iter()
                    .zip(self.zone_impacts.iter().zip(&self.zone_first))
                    .map(|(z, (&impacts, (vn, angle)))| ZoneStats {
                        zone: z.name().into(),
                        first_hits: vn.len(),
                        impacts,
                        normal_speed_m_s: Stats::of(vn),
                        angle_deg: Stats::of(angle),
                    })
                    .collect(),
                _ => Vec::new(),
            },
            normal_speed_histogram: Histogram::new(
                "normal impact speed, m/s",
                &self.normal,
                5.0,
                30,
            ),
            radius_histogram: Histogram::new("impact radius, mm", &radius_mm, 5.0, 10),
            jet_loading,
            effects: effects.to_vec(),
            wall_time_s: wall_time,
            threads,
            steps: StepReport {
                accepted: run.work.steps_accepted,
                rejected: run.work.steps_rejected,
                shot_steps: run.work.shot_steps,
                rhs_evaluations: run.work.rhs_evaluations,
                flight_to_first_contact: CountStats::of(self.to_first_contact),
                first_contact: CountStats::of(self.first_contact),
            },
            contacts: ContactReport {
                shot_specimen: self.impacts,
                shot_shot: self.collisions / 2,
                shot_wall: self.wall_contacts,
            },
            work: run.work,
            integrator: IntegratorReport {
                method: scene.integrator.method.name().into(),
                tolerance: scene.integrator.tolerance,
                fixed_step_ns: scene
                    .integrator
                    .method
                    .fixed_step()
                    .map(|h| (h * 1e15).round() / 1e6),
            },
            scheduler: run.scheduler.to_string(),
            scheduler_note: run.scheduler_note.clone(),
            windows: run.windows,
            window_redos: run.window_redos,
            peak_shots_held: run.peak_shots_held,
            events: run.events.clone(),
        }
    }
}

impl Summary {
    /// Builds the summary of a finished run.
    pub fn new(
        scene: &Scene,
        effects: &[EffectDecision],
        out: &RunOutput,
        wall_time: f64,
        threads: usize,
    ) -> Summary {
        Self::pooled(scene, effects, out, wall_time, threads, 1)
    }

    /// The summary of `runs` runs of a scene (over seeds) whose records `out` pools.
    pub fn pooled(
        scene: &Scene,
        effects: &[EffectDecision],
        out: &RunOutput,
        wall_time: f64,
        threads: usize,
        runs: usize,
    ) -> Summary {
        let mut b = SummaryBuilder::on(scene.specimen_shape.clone());
        b.runs = runs;
        b.impacts(&out.impacts);
        for s in &out.shots {
            b.shot(s);
        }
        b.finish(scene, effects, out, wall_time, threads)
    }

    /// Short human-readable report.
    pub fn text(&self) -> String {
        use std::fmt::Write;
        let mut s = String::new();
        let _ = writeln!(s, "{} — {}", self.scene, self.title);
        let _ = writeln!(
            s,
            "shots {}: {} hit the specimen ({:.1} %), {} never did; {} impact records ({} rebound hits)",
            self.shots,
            self.shots_hit,
            100.0 * self.hit_fraction,
            self.never_hit,
            self.impacts,
            self.rebound_hits
        );
        if (self.shots as f64) < 0.9 * self.shots_expected {
            let _ = writeln!(
                s,
                "warning: the inlet throttled the stream: {} of {:.0} expected shots entered (shots at rest block their entry spot until drag moves them); raise shots.feed.entry_speed_m_s or lower the rate",
                self.shots, self.shots_expected
            );
        }
        if self.left_domain + self.failed > 0 {
            let _ = writeln!(
                s,
                "stopped: {} left the domain, {} failed{}",
                self.left_domain,
                self.failed,
                if self.failed > 0 {
                    " (see the events below)"
                } else {
                    ""
                }
            );
        }
        if let Some(v) = &self.normal_speed_m_s {
            let _ = writeln!(
                s,
                "normal impact speed, m/s (first hits): mean {:.2}  median {:.2}  p10 {:.2}  p90 {:.2}  min {:.2}  max {:.2}",
                v.mean, v.median, v.p10, v.p90, v.min, v.max
            );
        }
        if let Some(r) = &self.radius_m {
            let _ = writeln!(
                s,
                "impact radius, mm (first hits):        mean {:.2}  median {:.2}  p10 {:.2}  p90 {:.2}  max {:.2}",
                r.mean * 1e3,
                r.median * 1e3,
                r.p10 * 1e3,
                r.p90 * 1e3,
                r.max * 1e3
            );
        }
        if let Some(l) = &self.jet_loading {
            s.push_str(&l.text());
        }
        let across = if self.on_gear {
            "across the teeth, mm of arc from the tooth space's middle"
        } else {
            "across the groove, mm of arc from its middle"
        };
        for (a, what) in [
            (&self.around_m, "around the bar, mm of arc from its crest"),
            (&self.across_m, across),
        ] {
            if let Some(a) = a {
                let _ = writeln!(
                    s,
                    "{what} (first hits): mean {:.2}  median {:.2}  p10 {:.2}  p90 {:.2}  min {:.2}  max {:.2}",
                    a.mean * 1e3,
                    a.median * 1e3,
                    a.p10 * 1e3,
                    a.p90 * 1e3,
                    a.min * 1e3,
                    a.max * 1e3
                );
            }
        }
        if !self.zones.is_empty() {
            let _ = writeln!(
                s,
                "{} zones:  first hits  impacts  normal speed m/s (first hits): mean  p10  p90  incidence deg: mean  p90",
                if self.on_gear { "gear" } else { "groove" }
            );
            for z in &self.zones {
                let _ = write!(s, "  {:<8} {:>10} {:>8}", z.zone, z.first_hits, z.impacts);
                if let (Some(v), Some(a)) = (&z.normal_speed_m_s, &z.angle_deg) {
                    let _ = write!(
                        s,
                        "  {:>32.2} {:>5.2} {:>5.2} {:>20.1} {:>5.1}",
                        v.mean, v.p10, v.p90, a.mean, a.p90
                    );
                }
                let _ = writeln!(s);
            }
        }
        for h in [&self.normal_speed_histogram, &self.radius_histogram] {
            let total: usize = h.counts.iter().sum::<usize>() + h.overflow;
            if total == 0 {
                continue;
            }
            let _ = writeln!(s, "{} (first hits):", h.quantity);
            let first = h.counts.iter().position(|&c| c > 0).unwrap_or(0);
            let last = h.counts.iter().rposition(|&c| c > 0).unwrap_or(0);
            let peak = *h.counts.iter().max().unwrap_or(&1).max(&1);
            for k in first..=last {
                let bar = "#".repeat((h.counts[k] * 40).div_ceil(peak));
                let _ = writeln!(
                    s,
                    "  {:>5.0}-{:<5.0} {:>5} {:>5.1} % {}",
                    h.lower_edges[k],
                    h.lower_edges[k] + h.bin_width,
                    h.counts[k],
                    100.0 * h.counts[k] as f64 / total as f64,
                    bar
                );
            }
            if h.overflow > 0 {
                let _ = writeln!(s, "  overflow    {:>5}", h.overflow);
            }
        }
        let _ = writeln!(s, "effects:");
        for e in &self.effects {
            let state = if e.on { "on" } else { "off" };
            let _ = writeln!(s, "  {:<20} {state:<3}  {}", e.name, e.reason);
        }
        let _ = writeln!(
            s,
            "work: {} steps ({} rejected), {} shot-steps, {} shot-shot and {} wall contacts, {} scheduler ({} windows, {} clusters); wall time {:.3} s on {} threads",
            self.steps.accepted,
            self.steps.rejected,
            self.steps.shot_steps,
            self.contacts.shot_shot,
            self.contacts.shot_wall,
            self.scheduler,
            self.windows,
            self.work.clusters,
            self.wall_time_s,
            self.threads
        );
        let it = &self.integrator;
        if let Some(ns) = it.fixed_step_ns {
            let _ = writeln!(
                s,
                "integrator: method = \"{}\", {ns} ns steps{}",
                it.method,
                if it.method == "hybrid" {
                    format!(" in contacts, tolerance {:e} in flight", it.tolerance)
                } else {
                    String::new()
                }
            );
        }
        if self.work.slides > 0 {
            let _ = writeln!(
                s,
                "settled: {} times a lone shot settled onto the specimen and slid or rolled along it (docs/model.md)",
                self.work.slides
            );
        }
        if let Some(note) = &self.scheduler_note {
            let _ = writeln!(s, "scheduler: {note}");
        }
        if self.work.entries_held > 0 {
            let _ = writeln!(
                s,
                "held: {} times a fed shot waited at the inlet for a shot there to move away (docs/scene-reference.md, stream feed)",
                self.work.entries_held
            );
        }
        for e in &self.events {
            let _ = writeln!(
                s,
                "event: shot {} at t = {:.6} ms: {}; {}",
                e.shot,
                e.time_s * 1e3,
                e.cause,
                e.suggestion
            );
        }
        s
    }
}
