//! Coverage of a turning gear (beyond the paper), from runs of a still nozzle over a
//! rack of tooth spaces set at several offsets across one pitch.
//!
//! A gear is peened turning under a nozzle fixed in space while the nozzle (or the
//! gear) moves along the gear's axis at speed `v`. Near the nozzle the gear is the rack
//! of `[specimen] shape = "groove"` with a pitch `p`; as the gear turns, its tooth spaces
//! pass across the jet, so at any moment the nozzle sees the rack shifted across by an
//! offset `o` (`[specimen] offset_mm`), which runs through a whole pitch for each tooth
//! that passes. A sweep of still-nozzle runs at offsets `o_k` samples that cycle; run
//! `k` (a steady stream, exposure `T_k`) stands for the offsets nearer to `o_k` than to
//! any other on the circle of one pitch: the share `w_k` of the pitch (half the gaps to
//! its two neighbours; the shares sum to 1).
//!
//! A point of the gear at arc `u` across its tooth space (from the space's middle, on
//! the unrolled surface) passes the nozzle once a revolution; while the rack's offset
//! lies in run `k`'s share, the point sits where run `k`'s groove `j` is, for every `j`
//! in turn over the revolution (a tooth space, its neighbours, the next ones: rebounds
//! land there). A revolution takes `Z p / V` (`Z` teeth, surface speed `V`) and the
//! nozzle moves `f = v Z p / V` along the axis meanwhile; as long as `f` is small
//! against the pattern's length along the axis, the point is crossed by run `k`'s
//! pattern as by a nozzle moving along a still rack at `v Z / w_k`. Summing the chords
//! along the axis as [`super::traverse`] does, one pass of the nozzle along the gear
//! brings
//!
//! `n(u) = (1 / Z) sum_k w_k sum_j n_k(u + j P)`
//!
//! dents to the point, where `n_k` is run `k`'s single pass along the rack at speed `v`
//! (its dents' chords along the axis over `T_k v`) and `P` the profile's arc over one
//! pitch (a tooth space and a tooth top: [`crate::contact::groove::Groove::period_arc`]).
//! The rotation speed drops out: a faster gear brings more passes of the teeth, each
//! shorter. Coverage is `1 - exp(-n(u))` (Poisson arrivals), full coverage (98 %) takes
//! `ln 50` dents everywhere on the profile. The mean of `n` over the period is the
//! still nozzle's dented area per second spread over the gear's circumference `Z P`
//! and the axial speed (tests check it, and the whole law against a Monte Carlo
//! simulation of a turning gear).
//!
//! Assumed, besides the still nozzle's ([`super::traverse`]): the rack stands for the
//! gear near the nozzle. The gear blank's curvature is left out: the surface `x` from
//! the jet's foot is really turned by `x / R` (`R` the gear's radius there) and its
//! neighbouring teeth fall away by `x^2 / 2R`. docs/coverage.md measures what turning
//! the whole rack with each offset changes (`nozzle.angle_deg` and `azimuth_deg` zipped
//! with the offsets), a bound on what the curvature can do.

use super::Dent;
use super::traverse::{Across, FULL, Point, exposure, for_each_chord, least_or_most, points};
use crate::contact::groove::{Groove, Zone};

/// Still-nozzle runs at one offset of the rack (a sweep case's seeds).
#[derive(Debug, Clone)]
pub struct OffsetRuns<'a> {
    /// The rack's offset ([`crate::contact::groove::GrooveSize::offset`]), m.
    pub offset: f64,
    /// The dents of each independent run at this offset.
    pub runs: Vec<&'a [Dent]>,
}

/// A gear turning under the nozzle while the nozzle moves along the gear's axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Turning {
    /// Number of teeth `Z` (tooth spaces round the gear).
    pub teeth: u32,
    /// The nozzle's speed along the gear's axis, m/s.
    pub speed: f64,
}

/// One offset's part in a [`GearProfile`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct OffsetShare {
    /// The rack's offset, m.
    pub offset_m: f64,
    /// Its share of the pitch (the shares sum to 1).
    pub weight: f64,
    /// Dents of its runs.
    pub dents: usize,
    /// Its runs (seeds).
    pub runs: usize,
    /// Its still nozzle's dent rate, 1/s.
    pub dent_rate_per_s: f64,
}

/// Why runs do not make a turning gear.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum GearError {
    /// Fewer than two distinct offsets.
    #[error(
        "a turning gear needs runs at 2 or more offsets across one pitch (a sweep over specimen.offset_mm; examples/gear_turning_sweep.toml), got {0}"
    )]
    TooFewOffsets(usize),
    /// Two runs at the same offset (modulo the pitch).
    #[error(
        "offsets {0} mm and {1} mm are the same place on the rack (the pitch is {2} mm): give each offset once, its repeats as seeds of one sweep case"
    )]
    SameOffset(f64, f64, f64),
    /// A run without a dent rate.
    #[error(
        "the run at offset {0} mm needs at least two dents at different times in each seed (a dent rate)"
    )]
    NoRate(f64),
}

/// Metres as millimetres for messages, rounded to the nanometre.
fn mm(m: f64) -> f64 {
    (m * 1e9).round() / 1e6
}

/// The shares of the pitch `p` each offset stands for: the offsets are placed on the
/// circle of one pitch and each takes half the gaps to its two neighbours.
pub fn weights(offsets: &[f64], pitch: f64) -> Result<Vec<f64>, GearError> {
    let k = offsets.len();
    if k < 2 {
        return Err(GearError::TooFewOffsets(k));
    }
    let phase: Vec<f64> = offsets.iter().map(|o| o.rem_euclid(pitch)).collect();
    let mut order: Vec<usize> = (0..k).collect();
    order.sort_by(|&a, &b| phase[a].total_cmp(&phase[b]));
    // Gap after each offset in the circular order.
    let gap = |i: usize| {
        let (a, b) = (order[i], order[(i + 1) % k]);
        let g = phase[b] - phase[a];
        if i + 1 == k { g + pitch } else { g }
    };
    let mut w = vec![0.0; k];
    for i in 0..k {
        let g = gap(i);
        if g <= 1e-9 * pitch {
            let (a, b) = (order[i], order[(i + 1) % k]);
            return Err(GearError::SameOffset(
                mm(offsets[a]),
                mm(offsets[b]),
                mm(pitch),
            ));
        }
        let share = 0.5 * g / pitch;
        w[order[i]] += share;
        w[order[(i + 1) % k]] += share;
    }
    Ok(w)
}

/// Expected dents per point across one period of a turning gear's profile, after one
/// pass of the nozzle along the gear.
#[derive(Debug, Clone)]
pub struct GearProfile {
    /// The gear and the nozzle's motion.
    pub turning: Turning,
    /// The rack's pitch `p`, m.
    pub pitch: f64,
    /// The profile's arc over one pitch `P`, m.
    pub period: f64,
    /// Spacing of the points, m.
    pub spacing: f64,
    /// Width of the bands the profile is averaged over, m (0: none).
    pub band: f64,
    /// Each offset's part, in the order given.
    pub offsets: Vec<OffsetShare>,
    /// The profile: arc from the middle of a tooth space, in `[-P/2, P/2)`, increasing.
    pub points: Vec<Point>,
    /// With a feed per revolution: the helical bands along the axis.
    pub banding: Option<Bands>,
}

/// The dents' variation along the gear's axis at each point of a [`GearProfile`], for a
/// feed per revolution `f` (see [`GearProfile::new`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Bands {
    /// The nozzle's advance per revolution `f`, m.
    pub feed: f64,
    /// At each point: the square of the first harmonic's amplitude over the mean,
    /// estimated for the still nozzle's stream. The runs' dents are a sample of it, and
    /// their own harmonic's square carries their noise (more than a Poisson draw's:
    /// a shot's rebounds land near its first dent). Each run is split at the middle of
    /// its span into two independent halves `A`, `B` whose harmonics `S_A`, `S_B` each
    /// expect half the stream's: `4 Re(S_A conj(S_B))` estimates `|S|^2` without the
    /// noise (unbiased, negative where the noise exceeds the bands; average before
    /// taking the root).
    pub power: Vec<f64>,
    /// The amplitude for the runs' dents as they are (what resampling them gives; above
    /// the stream's by about `2 / sqrt(dents there)` in quadrature).
    pub sample: Vec<f64>,
}

impl Bands {
    /// The stream's amplitude at each point (0 where the estimate is below the noise).
    pub fn amplitude(&self) -> Vec<f64> {
        self.power.iter().map(|p| p.max(0.0).sqrt()).collect()
    }

    /// The rms amplitude over the points `idx` (their powers averaged first).
    pub fn rms(&self, idx: impl Iterator<Item = usize>) -> f64 {
        self.mean_power(idx, 1.0).0.max(0.0).sqrt()
    }

    /// The mean power over the points `idx` and its standard error, from the powers'
    /// scatter with neighbours `correlated` points apart counted as one (a dent and
    /// the band span several points).
    pub fn mean_power(&self, idx: impl Iterator<Item = usize>, correlated: f64) -> (f64, f64) {
        let p: Vec<f64> = idx.map(|i| self.power[i]).collect();
        let n = p.len() as f64;
        if p.is_empty() {
            return (0.0, 0.0);
        }
        let mean = p.iter().sum::<f64>() / n;
        let var = p.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
        (mean, (var * correlated.max(1.0) / n).sqrt())
    }
}

/// One zone of the profile (both sides of a tooth space together).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ZoneDents {
    /// `bottom`, `fillet`, `flank`, `edge` or `land`.
    pub zone: &'static str,
    /// `-` or `+`: the side of the tooth space (negative or positive arc); empty for the
    /// bottom and the tooth top (`land`), which span both.
    pub side: &'static str,
    /// Its span of arc from the tooth space's middle, m (the tooth top's runs past
    /// `P/2`: its two halves at the period's ends are one land).
    pub across_m: [f64; 2],
    /// Its arc over one period, m.
    pub arc_m: f64,
    /// Expected dents per point where fewest.
    pub least_dents: f64,
    /// That estimate's standard error.
    pub least_standard_error: f64,
    /// Where, m of arc from the tooth space's middle.
    pub least_arc_m: f64,
    /// Mean expected dents per point over the zone.
    pub mean_dents: f64,
    /// Coverage where least covered, and on average over the zone's points.
    pub least_coverage: f64,
    /// Mean coverage over the zone's points.
    pub mean_coverage: f64,
    /// The fastest nozzle that covers the whole zone fully (98 %) in one pass, m/s.
    pub full_coverage_speed_m_s: f64,
}

impl GearProfile {
    /// The profile of `offsets` (runs of the still nozzle over a rack of pitch `pitch`
    /// whose profile spans `period` of arc per pitch) under `turning`, with points about
    /// `spacing` m apart (at most 100,000 over a period), averaged over bands `band` m
    /// wide (as [`super::traverse::Track::new`]).
    ///
    /// With `feed`, the nozzle's advance per revolution `f` (m): a point meets the
    /// pattern once a revolution, `f` further along each time, so its dents vary along
    /// the axis with period `f`. A dent `i` whose chord along the axis is `c_i` there
    /// adds `c_i / f` on average and, to the first harmonic (`k = 2 pi / f`),
    /// `2 (c_i / f) sinc(k c_i / 2) cos(k (Y - y_i))`; the amplitude of the sum over its
    /// mean is the point's banding ([`Bands`]; 0: even; small as long as `f` is below
    /// about twice the pattern's spread along the axis).
    pub fn new(
        offsets: &[OffsetRuns<'_>],
        pitch: f64,
        period: f64,
        turning: Turning,
        spacing: f64,
        band: f64,
        feed: Option<f64>,
    ) -> Result<GearProfile, GearError> {
        let w = weights(&offsets.iter().map(|o| o.offset).collect::<Vec<_>>(), pitch)?;
        let m = ((period / spacing).ceil() as i64).clamp(1, 100_000);
        let step = period / m as f64;
        let mut sums = vec![(0.0, 0.0); m as usize];
        // The first harmonic along the axis: (cos, sin) sums of each half of the runs.
        let mut waves = vec![[0.0; 4]; if feed.is_some() { m as usize } else { 0 }];
        let mut shares = Vec::with_capacity(offsets.len());
        for (o, &wk) in offsets.iter().zip(&w) {
            let t = exposure(&o.runs).ok_or(GearError::NoRate(mm(o.offset)))?;
            let dents: usize = o.runs.iter().map(|r| r.len()).sum();
            // A track along the rack's axis, towards -y: the lateral offset is the arc.
            let across: Vec<Across> = o
                .runs
                .iter()
                .flat_map(|r| r.iter())
                .map(|d| Across::of(d, -1.0, 0.0))
                .collect();
            let scale = wk / (f64::from(turning.teeth) * t * turning.speed);
            for_each_chord(&across, step, band, |q, chord| {
                let s = &mut sums[q.rem_euclid(m) as usize];
                s.0 += chord * scale;
                s.1 += (chord * scale).powi(2);
            });
            if let Some(f) = feed {
                let k = std::f64::consts::TAU / f;
                for run in &o.runs {
                    let (t_lo, t_hi) =
                        run.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, d| {
                            (a.0.min(d.t), a.1.max(d.t))
                        });
                    let middle = 0.5 * (t_lo + t_hi);
                    for d in run.iter() {
                        let (sin, cos) = (k * d.y).sin_cos();
                        let half = if d.t < middle { 0 } else { 2 };
                        let a = Across::of(d, -1.0, 0.0);
                        for_each_chord(std::slice::from_ref(&a), step, band, |q, chord| {
                            let x = 0.5 * k * chord;
                            let sinc = if x.abs() < 1e-12 { 1.0 } else { x.sin() / x };
                            let a = chord * scale * sinc;
                            let w = &mut waves[q.rem_euclid(m) as usize];
                            w[half] += a * cos;
                            w[half + 1] += a * sin;
                        });
                    }
                }
            }
            shares.push(OffsetShare {
                offset_m: o.offset,
                weight: wk,
                dents,
                runs: o.runs.len(),
                dent_rate_per_s: dents as f64 / t,
            });
        }
        // Points at `i step` in [0, P): those at or past the middle move a period left.
        let at = |i: usize| {
            let u = i as f64 * step;
            if 2 * i as i64 >= m { u - period } else { u }
        };
        // Squared amplitude over the mean: of the stream (the halves' cross product)
        // and of the sample (their sum's square).
        let power = |cross: bool| -> Vec<f64> {
            waves
                .iter()
                .zip(&sums)
                .map(|(w, s)| {
                    let sq = if cross {
                        4.0 * (w[0] * w[2] + w[1] * w[3])
                    } else {
                        (w[0] + w[2]).powi(2) + (w[1] + w[3]).powi(2)
                    };
                    if s.0 > 0.0 {
                        4.0 * sq / (s.0 * s.0)
                    } else {
                        0.0
                    }
                })
                .collect()
        };
        let (stream, sample) = (power(true), power(false));
        let mut order: Vec<usize> = (0..m as usize).collect();
        order.sort_by(|&a, &b| at(a).total_cmp(&at(b)));
        let pts = points(order.iter().map(|&i| sums[i]).collect(), |j| at(order[j]));
        let banding = feed.map(|feed| Bands {
            feed,
            power: order.iter().map(|&i| stream[i]).collect(),
            sample: order.iter().map(|&i| sample[i].max(0.0).sqrt()).collect(),
        });
        Ok(GearProfile {
            turning,
            pitch,
            period,
            spacing: step,
            band,
            offsets: shares,
            points: pts,
            banding,
        })
    }

    /// The point with the fewest expected dents.
    pub fn least(&self) -> Point {
        least_or_most(&self.points, |a, b| b.dents < a.dents)
    }

    /// Mean expected dents per point over the period.
    pub fn mean(&self) -> f64 {
        self.points.iter().map(|p| p.dents).sum::<f64>() / self.points.len() as f64
    }

    /// The fastest nozzle (m/s) that covers the whole profile fully (98 %) in one pass,
    /// and the passes full coverage takes at this profile's speed (`None` where a point
    /// gets no dent).
    pub fn full_coverage(&self) -> Option<(f64, u64)> {
        let n = self.least().dents;
        (n > 0.0).then(|| {
            (
                self.turning.speed * n / FULL,
                (FULL / n).ceil().max(1.0) as u64,
            )
        })
    }

    /// The profile's zones in order across the tooth space (`groove`: the rack the
    /// runs are on): each zone on each side, the bottom across the middle and the tooth
    /// top across the period's ends; with the indices of their points.
    pub fn stretches(&self, groove: &Groove) -> Vec<Stretch> {
        let half = 0.5 * self.period;
        let mut spans = groove.zone_spans(-half, half);
        // The tooth top's halves at both ends are one land.
        if spans.len() > 1 && spans[0].2 == Zone::Land && spans[spans.len() - 1].2 == Zone::Land {
            let first = spans.remove(0);
            let last = spans.last_mut().expect("BUG: spans");
            last.1 = first.1 + self.period;
        }
        spans
            .into_iter()
            .map(|(a, b, zone)| {
                let inside = |u: f64| (a..b).contains(&u) || (a..b).contains(&(u + self.period));
                let side = match zone {
                    Zone::Bottom | Zone::Land => "",
                    _ if a + b < 0.0 => "-",
                    _ => "+",
                };
                Stretch {
                    zone,
                    side,
                    across: [a, b],
                    points: (0..self.points.len())
                        .filter(|&i| inside(self.points[i].offset))
                        .collect(),
                }
            })
            .filter(|s| !s.points.is_empty())
            .collect()
    }

    /// The profile zone by zone, in order across the tooth space ([`Self::stretches`]).
    pub fn zones(&self, groove: &Groove) -> Vec<ZoneDents> {
        let cov = super::traverse::coverage;
        self.stretches(groove)
            .into_iter()
            .map(|st| {
                let pts: Vec<Point> = st.points.iter().map(|&i| self.points[i]).collect();
                let least = least_or_most(&pts, |a, b| b.dents < a.dents);
                let n = pts.len() as f64;
                ZoneDents {
                    zone: st.zone.name(),
                    side: st.side,
                    across_m: st.across,
                    arc_m: n * self.spacing,
                    least_dents: least.dents,
                    least_standard_error: least.se,
                    least_arc_m: least.offset,
                    mean_dents: pts.iter().map(|p| p.dents).sum::<f64>() / n,
                    least_coverage: cov(least.dents),
                    mean_coverage: pts.iter().map(|p| cov(p.dents)).sum::<f64>() / n,
                    full_coverage_speed_m_s: self.turning.speed * least.dents / FULL,
                }
            })
            .collect()
    }
}

/// A zone of a [`GearProfile`] on one side of the tooth space ([`GearProfile::stretches`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Stretch {
    /// The zone.
    pub zone: Zone,
    /// `-`, `+` or empty (the bottom and the tooth top span both sides).
    pub side: &'static str,
    /// Its span of arc, m (the tooth top's runs past the period's end).
    pub across: [f64; 2],
    /// Indices of its points in [`GearProfile::points`].
    pub points: Vec<usize>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_are_half_the_gaps_on_the_circle_of_one_pitch() {
        let p = 10.0;
        let w = weights(&[0.0, 1.0, 5.0], p).unwrap();
        // Gaps 1, 4, 5 (5 -> 10 = 0 wraps round).
        assert_eq!(w, vec![0.3, 0.25, 0.45]);
        // Order and whole pitches do not matter.
        let v = weights(&[15.0, -9.0, 20.0], p).unwrap();
        let close = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
        assert!(close(&v, &[0.45, 0.25, 0.3]), "{v:?}");
        let even = weights(&[-5.0, -2.5, 0.0, 2.5], p).unwrap();
        assert!(close(&even, &[0.25; 4]), "{even:?}");
        assert_eq!(weights(&[1.0], p), Err(GearError::TooFewOffsets(1)));
        assert!(matches!(
            weights(&[1.0, 11.0, 3.0], p),
            Err(GearError::SameOffset(..))
        ));
        assert!(matches!(
            weights(&[0.0, 10.0], p),
            Err(GearError::SameOffset(..))
        ));
    }

    fn dents(xs: &[f64], r: f64, span: f64) -> Vec<Dent> {
        let n = xs.len();
        xs.iter()
            .enumerate()
            .map(|(i, &x)| Dent::disc(x, 0.0, r, span * i as f64 / n as f64))
            .collect()
    }

    #[test]
    fn the_profile_holds_the_dented_area_spread_over_the_circumference() {
        // Two offsets, dents in the middle groove and in its neighbours (folded in);
        // each run's exposure is 10 ms (span (N - 1) T / N).
        let (pitch, period, r) = (10e-3, 14e-3, 0.4e-3);
        let a = dents(&[0.0, 1e-3, -6.5e-3, 14.2e-3, 3e-3], r, 0.01);
        let b = dents(&[2e-3, -2e-3, 7.1e-3], r, 0.01);
        let runs = [
            OffsetRuns {
                offset: 0.0,
                runs: vec![&a],
            },
            OffsetRuns {
                offset: 2e-3,
                runs: vec![&b],
            },
        ];
        let turning = Turning {
            teeth: 25,
            speed: 2e-3,
        };
        for band in [0.0, 0.5e-3] {
            let g = GearProfile::new(&runs, pitch, period, turning, 1e-5, band, None).unwrap();
            assert_eq!(g.points.len(), 1400);
            assert!(g.points[0].offset >= -0.5 * period - 1e-12);
            assert!(g.points.last().unwrap().offset < 0.5 * period);
            // Two offsets on the circle share it equally; rates 500 and 300 dents/s.
            assert!((g.offsets[0].weight - 0.5).abs() < 1e-12);
            assert!((g.offsets[1].dent_rate_per_s - 300.0).abs() < 1e-9);
            let area = std::f64::consts::PI * r * r;
            let want = (0.5 * 500.0 + 0.5 * 300.0) * area / (25.0 * period * 2e-3);
            // Banded chords sum to the dent's area exactly; chords through the points
            // themselves sample it (error about (spacing / r)^1.5).
            let tol = if band > 0.0 { 1e-9 } else { 5e-3 };
            assert!(
                (g.mean() - want).abs() < tol * want,
                "band {band}: {} vs {want}",
                g.mean()
            );
        }
    }

    #[test]
    fn bands_are_those_of_the_stream_not_of_its_sample() {
        use rand::{Rng, SeedableRng};
        use rand_distr::{Distribution, Normal};
        // 80,000 small dents spread evenly across +-5 mm and normally along the axis
        // (sigma 3 mm): about 1,600 over each point. The stream's first harmonic over its
        // mean is 2 exp(-(k sigma)^2 / 2) (the dents' own length, 0.2 mm, takes off
        // under 0.1 %); the sample's adds about 2 / sqrt(1600) in quadrature.
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let along = Normal::new(0.0, 3e-3).unwrap();
        let mut draw = || -> Vec<Dent> {
            (0..40_000)
                .map(|i| {
                    let x = rng.random_range(-5e-3..5e-3);
                    Dent::disc(x, along.sample(&mut rng), 0.1e-3, i as f64 * 1e-4)
                })
                .collect()
        };
        let (a, b) = (draw(), draw());
        let runs = [
            OffsetRuns {
                offset: 0.0,
                runs: vec![&a],
            },
            OffsetRuns {
                offset: 5e-3,
                runs: vec![&b],
            },
        ];
        let turning = Turning {
            teeth: 20,
            speed: 1e-3,
        };
        let rms = |v: Vec<f64>| (v.iter().map(|a| a * a).sum::<f64>() / v.len() as f64).sqrt();
        for (feed, truth) in [(16e-3, 0.9993), (8e-3, 0.1243), (4e-3, 0.0)] {
            let g =
                GearProfile::new(&runs, 10e-3, 20e-3, turning, 0.05e-3, 0.0, Some(feed)).unwrap();
            let b = g.banding.unwrap();
            // Points well inside the dented span.
            let inside = |v: &[f64]| -> Vec<f64> {
                g.points
                    .iter()
                    .zip(v)
                    .filter(|(p, _)| p.offset.abs() < 4.5e-3)
                    .map(|(_, a)| *a)
                    .collect()
            };
            let est = b.rms((0..g.points.len()).filter(|&i| g.points[i].offset.abs() < 4.5e-3));
            let raw = rms(inside(&b.sample));
            let want = 2.0 * (-(std::f64::consts::TAU * 3e-3 / feed).powi(2) / 2.0).exp();
            assert!((want - truth).abs() < 1e-3, "{want}");
            // Where the truth is 0 the powers average to about 0 within their noise
            // (about 4e-4 over the span: a root of about 0.02).
            let tol = if truth > 0.0 { 0.02 } else { 0.04 };
            assert!(
                (est - truth).abs() < tol,
                "f = {} mm: {est:.4} against {truth}",
                feed * 1e3
            );
            if truth < 0.5 {
                assert!(raw > est + 0.005, "f = {} mm: sample {raw:.4}", feed * 1e3);
            }
        }
    }
}
