//! How heavily the shots load the air jet (beyond the paper). The paper's jet is a
//! prescribed field: the shots take momentum from the air and the air does not lose it
//! (one-way coupling). That holds while what the shots take is a small part of the jet's
//! momentum flow; at a production feed through a small bore it is not (S330 at 3 kg/min
//! through the paper's 6 mm bore takes 15 % of it). A run reports the share from
//! its own first hits, and its summary warns above [`WARN_FRACTION`].
//!
//! The jet's momentum flow is the model's exit state's, `rho_c u_i^2 A` over the bore's
//! area `A`; in a free jet it is conserved downstream, and a jet that lost a share `phi`
//! of it to the shots would carry its (choked, fixed) mass flow about `phi` slower, which
//! would take about `0.6 phi` off the impact speeds (docs/model.md). What
//! the shots take is their rate times the mean momentum one takes from the air on its way,
//! along the jet's axis: its first hit's momentum less its entry momentum, over the first
//! hits that met no other shot before (a collision trades momentum between shots, not
//! with the air). Gravity's part is counted as the air's (under 0.3 % of it on the
//! paper's scene), and so is the nozzle wall's (none without friction: its push is
//! radial).
//!
//! A stream takes its feed's rate times that mean. A batch's shots all start at once and
//! fly together (the middle 80 % of the paper's 30 arrive within a fifth of a
//! millisecond, after about 3.5 ms): while they fly they take, per second, the mean over the counted
//! shots of one's momentum over its flight time, times the batch's size. Other feeds (a
//! list, a box, a bed) are not reported.

use serde::Serialize;

use super::Impact;
use crate::Vec3;
use crate::scene::{EffectDecision, Feed, Scene};

/// The share of the jet's momentum flow the shots take above which a summary warns.
pub const WARN_FRACTION: f64 = 0.10;

/// How much of the share comes off the impact speeds of a jet slowed by it at the same
/// mass flow: 0.58-0.65 for 0.3-0.8 mm shots from rest (`bench/jet_loading.py`).
const SPEED_PER_SHARE: f64 = 0.6;

/// What a run's first hits say about the shots' load on the jet (summary.json
/// `jet_loading`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JetLoading {
    /// `rho_c u_i A`, kg/s: the air through the bore at the model's exit state.
    pub air_mass_flow_kg_s: f64,
    /// `rho_c u_i^2 A`, N: the jet's momentum flow.
    pub jet_momentum_flow_n: f64,
    /// `stream` (the feed's rate) or `batch` (all its shots in flight at once).
    pub basis: &'static str,
    /// Shots per second through the jet: a batch's size over its shots' mean flight
    /// time to their first hits (the counted ones').
    pub shot_rate_per_s: f64,
    /// Shot mass per second, kg/s: the rate times the mean shot's mass.
    pub shot_mass_flow_kg_s: f64,
    /// Shot mass flow over air mass flow.
    pub mass_loading: f64,
    /// Mean momentum a shot takes from the air on its way to its first hit, along the
    /// jet's axis, kg m/s.
    pub momentum_per_shot_kg_m_s: f64,
    /// First hits with no shot-shot collision before, which that mean is over.
    pub shots_counted: usize,
    /// What the shots take per second, N: a stream's rate times the mean; a batch's
    /// size times the mean of one's momentum over its flight time.
    pub momentum_taken_n: f64,
    /// `momentum_taken_n / jet_momentum_flow_n`: to first order, the share by which the
    /// air would be slower were the coupling two-way (the impact speeds by about 0.6
    /// times it).
    pub momentum_fraction: f64,
    /// `one_way` (the paper's air) or `momentum` (the run's jet slowed by what the shots
    /// take: `crate::flow::coupling`).
    pub coupling: &'static str,
    /// The run's air speed over the scene's jet's (1 with one-way coupling).
    pub air_speed_factor: f64,
}

/// What the loading is read from, gathered as the records arrive (40 bytes per first
/// hit with no collision before it).
#[derive(Debug, Clone, Default)]
pub struct LoadingTally {
    /// Clean first hits' (no collision before) masses, times and momenta.
    clean: Vec<(f64, f64, Vec3)>,
    /// Mass of every shot fed, summed.
    fed_mass: f64,
}

impl LoadingTally {
    /// Notes a batch of impact records.
    pub fn impacts(&mut self, batch: &[Impact]) {
        for i in batch
            .iter()
            .filter(|i| i.first_hit == 1 && i.collisions_before == 0)
        {
            let momentum = Vec3::new(i.vx_m_s, i.vy_m_s, i.vz_m_s) * i.mass_kg;
            self.clean.push((i.mass_kg, i.time_s, momentum));
        }
    }

    /// Notes a shot fed, of `mass`.
    pub fn shot(&mut self, mass: f64) {
        self.fed_mass += mass;
    }

    /// The loading of `runs` runs of `scene` (pooled over seeds: `runs` of them) that fed
    /// `shots` shots, with `effects`, in a jet `air_speed_factor` times as fast as the
    /// scene's (`crate::sim::RunTail::air_speed_factor`); `None` without the jet (no
    /// drag, no lateral force), without a clean first hit, or for a feed neither a stream
    /// nor a batch.
    pub fn finish(
        self,
        scene: &Scene,
        effects: &[EffectDecision],
        shots: usize,
        runs: usize,
        air_speed_factor: f64,
    ) -> Option<JetLoading> {
        let air_on = effects
            .iter()
            .any(|e| e.on && (e.name == "drag" || e.name == "lateral_force"));
        if !air_on || self.clean.is_empty() || shots == 0 {
            return None;
        }
        let axis = scene.nozzle.axis();
        let (air_mass_flow, jet_momentum_flow) = crate::flow::coupling::jet_flows(scene);
        // Each counted shot's momentum taken from the air, along the axis, and its time
        // in flight (a batch's from 0).
        let gains = self.clean.iter().map(|&(mass, time, momentum)| {
            let entry = match &scene.feed {
                Feed::Stream { entry_speed, .. } => axis * (mass * entry_speed),
                _ => Vec3::zeros(),
            };
            ((momentum - entry).dot(&axis), time)
        });
        let counted = self.clean.len() as f64;
        let per_shot = gains.clone().map(|g| g.0).sum::<f64>() / counted;
        let (basis, rate, mass_flow, taken) = match &scene.feed {
            Feed::Stream { rate, .. } => {
                // The feed's own mass flow (`mass_flow_kg_min` gives the rate this way).
                let mass = scene.shot_material.density * scene.sizes.mean_volume();
                ("stream", *rate, rate * mass, rate * per_shot)
            }
            Feed::Batch { .. } => {
                let size = shots as f64 / runs.max(1) as f64;
                let mean_time = gains.clone().map(|g| g.1).sum::<f64>() / counted;
                let per_second = gains.map(|(p, t)| p / t).sum::<f64>() / counted;
                let rate = size / mean_time;
                (
                    "batch",
                    rate,
                    rate * self.fed_mass / shots as f64,
                    size * per_second,
                )
            }
            _ => return None,
        };
        Some(JetLoading {
            air_mass_flow_kg_s: air_mass_flow,
            jet_momentum_flow_n: jet_momentum_flow,
            basis,
            shot_rate_per_s: rate,
            shot_mass_flow_kg_s: mass_flow,
            mass_loading: mass_flow / air_mass_flow,
            momentum_per_shot_kg_m_s: per_shot,
            shots_counted: self.clean.len(),
            momentum_taken_n: taken,
            momentum_fraction: taken / jet_momentum_flow,
            coupling: scene.jet.coupling.name(),
            air_speed_factor,
        })
    }
}

impl JetLoading {
    /// The summary's lines: the loading, and a warning above [`WARN_FRACTION`].
    pub fn text(&self) -> String {
        let mut s = format!(
            "jet loading ({}): {:.4} kg/s of shot in {:.4} kg/s of air (mass loading {:.2}); the shots take {:.3} N of the jet's {:.2} N momentum flow ({:.1} %)\n",
            self.basis,
            self.shot_mass_flow_kg_s,
            self.air_mass_flow_kg_s,
            self.mass_loading,
            self.momentum_taken_n,
            self.jet_momentum_flow_n,
            100.0 * self.momentum_fraction
        );
        if self.coupling != "one_way" {
            s.push_str(&format!(
                "jet coupling ({}): the run's air is {:.1} % slower than the free jet's, carrying what the shots leave it\n",
                self.coupling,
                100.0 * (1.0 - self.air_speed_factor)
            ));
        } else if self.momentum_fraction > WARN_FRACTION {
            let cut = 100.0 * WARN_FRACTION / self.momentum_fraction;
            let what = match self.basis {
                "batch" => format!("the batch to below {cut:.0} % of its size"),
                _ => format!("the feed to below {cut:.0} % of its rate"),
            };
            s.push_str(&format!(
                "warning: the shots take {:.1} % of the jet's momentum, but the model's air does not slow down for them (one-way coupling): the impact speeds are likely about {:.0} % high. Cut {what} for a share under {:.0} %, set [jet] coupling = \"momentum\" for the jet the shots slow, or check the speeds against a measured one (docs/model.md, \"How heavily the shots load the jet\")\n",
                100.0 * self.momentum_fraction,
                100.0 * SPEED_PER_SHARE * self.momentum_fraction,
                100.0 * WARN_FRACTION
            ));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Scene;

    fn hit(t: f64, vel: Vec3, mass: f64, collisions: u32, first: bool) -> Impact {
        let pos = Vec3::new(0.0, 0.0, 0.4e-3);
        Impact::new(
            7,
            t,
            &pos,
            &vel,
            &Vec3::zeros(),
            0.4e-3,
            mass,
            collisions,
            first,
        )
    }

    /// Paper scene air (model.md's table): `rho* = 5.347`, `u_i = 313.25` through 6 mm.
    fn jet(scene: &Scene) -> (f64, f64) {
        let u = (1.4f64 * 287.05 * 293.0).sqrt() * (2.0f64 / 2.4).sqrt();
        let rho = 1.205 * 7.0 * (2.0f64 / 2.4).powf(2.5);
        let area = std::f64::consts::PI * 9e-6;
        assert!((scene.air.exit_velocity / u - 1.0).abs() < 1e-12);
        (rho * u * area, rho * u * u * area)
    }

    fn tally(hits: &[Impact], masses: &[f64]) -> LoadingTally {
        let mut t = LoadingTally::default();
        t.impacts(hits);
        for &m in masses {
            t.shot(m);
        }
        t
    }

    #[test]
    fn a_streams_share_is_its_rate_times_a_clean_shots_gain_over_the_jets_flow() {
        let mut scene = Scene::default_scene();
        let (m, rate, entry) = (2e-6, 20_000.0, 5.0);
        scene.feed = Feed::Stream {
            rate,
            duration: 0.01,
            entry_speed: entry,
            poisson: true,
        };
        let effects = scene.effects().decisions;
        let hits = [
            hit(2e-3, Vec3::new(1.0, 0.0, -55.0), m, 0, true),
            hit(3e-3, Vec3::new(0.0, 2.0, -45.0), 2.0 * m, 0, true),
            // Neither a collision's nor a rebound's momentum is the air's.
            hit(3e-3, Vec3::new(0.0, 0.0, -20.0), m, 1, true),
            hit(4e-3, Vec3::new(0.0, 0.0, -30.0), m, 0, false),
        ];
        let l = tally(&hits, &[m; 4])
            .finish(&scene, &effects, 4, 1, 1.0)
            .unwrap();
        let (air, flow) = jet(&scene);
        let gain = (m * (55.0 - entry) + 2.0 * m * (45.0 - entry)) / 2.0;
        assert_eq!(l.basis, "stream");
        assert_eq!(l.shots_counted, 2);
        assert!((l.air_mass_flow_kg_s / air - 1.0).abs() < 1e-12);
        assert!((l.jet_momentum_flow_n / flow - 1.0).abs() < 1e-12);
        assert!((l.momentum_per_shot_kg_m_s / gain - 1.0).abs() < 1e-12);
        assert!((l.momentum_fraction / (rate * gain / flow) - 1.0).abs() < 1e-12);
        // The feed's own mass flow: its rate times the shot's mass.
        let shot = 7850.0 * std::f64::consts::PI / 6.0 * 0.8e-3f64.powi(3);
        assert!((l.shot_mass_flow_kg_s / (rate * shot) - 1.0).abs() < 1e-12);
        assert!((l.mass_loading / (rate * shot / air) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_batchs_shots_take_their_momentum_over_their_flight_all_at_once() {
        let scene = Scene::default_scene();
        let effects = scene.effects().decisions;
        let m = 2e-6;
        let hits = [
            hit(2e-3, Vec3::new(0.0, 0.0, -50.0), m, 0, true),
            hit(4e-3, Vec3::new(0.0, 0.0, -60.0), m, 0, true),
        ];
        // Pooled over two seeds: four shots fed, two per run.
        let l = tally(&hits, &[m; 4])
            .finish(&scene, &effects, 4, 2, 1.0)
            .unwrap();
        let per_second = (m * 50.0 / 2e-3 + m * 60.0 / 4e-3) / 2.0;
        assert_eq!(l.basis, "batch");
        assert!((l.momentum_taken_n / (2.0 * per_second) - 1.0).abs() < 1e-12);
        assert!((l.shot_rate_per_s / (2.0 / 3e-3) - 1.0).abs() < 1e-12);
        assert!((l.momentum_per_shot_kg_m_s / (m * 55.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn no_jet_or_no_clean_hit_or_a_list_says_nothing() {
        let scene = Scene::default_scene();
        let mut effects = scene.effects().decisions;
        let m = 2e-6;
        let clean = [hit(2e-3, Vec3::new(0.0, 0.0, -50.0), m, 0, true)];
        let hit_after_a_collision = [hit(2e-3, Vec3::new(0.0, 0.0, -50.0), m, 2, true)];
        assert!(
            tally(&clean, &[m])
                .finish(&scene, &effects, 1, 1, 1.0)
                .is_some()
        );
        assert!(
            tally(&hit_after_a_collision, &[m])
                .finish(&scene, &effects, 1, 1, 1.0)
                .is_none()
        );
        let mut list = scene.clone();
        list.feed = Feed::List(Vec::new());
        assert!(
            tally(&clean, &[m])
                .finish(&list, &effects, 1, 1, 1.0)
                .is_none()
        );
        for e in effects.iter_mut() {
            if e.name == "drag" || e.name == "lateral_force" {
                e.on = false;
            }
        }
        assert!(
            tally(&clean, &[m])
                .finish(&scene, &effects, 1, 1, 1.0)
                .is_none()
        );
    }

    #[test]
    fn the_summary_warns_above_ten_percent_only() {
        let scene = Scene::default_scene();
        let effects = scene.effects().decisions;
        let m = 2e-6;
        let l = tally(&[hit(2e-3, Vec3::new(0.0, 0.0, -50.0), m, 0, true)], &[m])
            .finish(&scene, &effects, 1, 1, 1.0)
            .unwrap();
        for (share, warns) in [(0.099, false), (0.101, true), (0.4, true)] {
            let text = JetLoading {
                momentum_fraction: share,
                ..l.clone()
            }
            .text();
            assert_eq!(text.contains("warning:"), warns, "{text}");
        }
        let text = JetLoading {
            momentum_fraction: 0.4,
            ..l
        }
        .text();
        assert!(
            text.contains("Cut the batch to below 25 % of its size"),
            "{text}"
        );
        assert!(text.contains("speeds are likely about 24 % high"), "{text}");
    }
}
