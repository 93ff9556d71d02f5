//! The run's picture, `impacts.png` / `impacts.svg`: where the shots hit the specimen,
//! coloured by normal impact speed, next to the histograms of the normal impact speed and
//! of the impact angle (first hits and rebound hits apart).
//!
//! [`ImpactFigure`] is a [`RunSink`]: it sees every impact as the run hands it over and
//! keeps what the picture needs in bounded memory, so the run still holds only the shots
//! in flight.
//! * The histograms count every impact, in fine bins (0.1 m/s, 1 degree) merged into
//!   at most 25 bars of 1-2-5 widths at the end (5-degree bars for the angle).
//! * The map draws every impact up to [`MAP_POINTS`], then a sample: every second,
//!   fourth, ... impact in the run's (time, shot) order, so the picture does
//!   not depend on the thread count. The title says when it is a sample. Faster impacts
//!   are drawn over slower ones, first hits over rebound hits.
//! * The frame is square, centred on the jet axis' foot when the air jet acts on the shots
//!   (on the middle of the impacts otherwise), and wide enough for the nearest 95 %
//!   of the impacts with a margin: the few far rebounds would otherwise shrink the
//!   pattern to a dot. The panel's title counts the impacts left outside.

use super::Impact;
use crate::plot::{self, BarPanel, Bars, Map, MapPoint};
use crate::sim::RunSink;
use crate::state::ShotState;
use std::path::Path;

/// The map draws every impact up to this many, and between half and all of this many
/// beyond.
pub const MAP_POINTS: usize = 10_000;

/// Fine bins of the normal speed, m/s; faster impacts go to an overflow count.
const SPEED_FINE: f64 = 0.1;
const SPEED_FINE_BINS: usize = 10_000;

/// Bars of a histogram at most.
const BARS: usize = 25;

/// Share of the sampled impacts the frame holds at least.
const FRAMED: f64 = 0.95;

/// One sampled impact: position (mm), normal speed (m/s), first hit.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Sampled {
    x: f64,
    y: f64,
    normal: f64,
    first: bool,
}

/// Collects a run's impacts for its picture (see the module docs).
#[derive(Debug, Clone)]
pub struct ImpactFigure {
    sample: Vec<Sampled>,
    stride: u64,
    seen: u64,
    /// Fine normal-speed counts, `[first hits, rebound hits]`.
    speed: [Vec<u64>; 2],
    speed_overflow: [u64; 2],
    /// One-degree impact-angle counts.
    angle: [[u64; 90]; 2],
}

impl Default for ImpactFigure {
    fn default() -> Self {
        ImpactFigure {
            sample: Vec::new(),
            stride: 1,
            seen: 0,
            speed: [vec![0; SPEED_FINE_BINS], vec![0; SPEED_FINE_BINS]],
            speed_overflow: [0; 2],
            angle: [[0; 90]; 2],
        }
    }
}

impl RunSink for ImpactFigure {
    fn impacts(&mut self, batch: &[Impact]) {
        for i in batch {
            let kind = usize::from(i.first_hit != 1);
            let k = (i.normal_speed_m_s.max(0.0) / SPEED_FINE) as usize;
            match self.speed[kind].get_mut(k) {
                Some(c) => *c += 1,
                None => self.speed_overflow[kind] += 1,
            }
            let a = i.angle_deg.clamp(0.0, 89.0) as usize;
            self.angle[kind][a] += 1;
            if self.seen.is_multiple_of(self.stride) {
                self.sample.push(Sampled {
                    x: i.x_m * 1e3,
                    y: i.y_m * 1e3,
                    normal: i.normal_speed_m_s,
                    first: i.first_hit == 1,
                });
                if self.sample.len() > MAP_POINTS {
                    // Keep every second one: the sample stays every `stride`-th impact.
                    let mut k = 0;
                    self.sample.retain(|_| {
                        k += 1;
                        k % 2 == 1
                    });
                    self.stride *= 2;
                }
            }
            self.seen += 1;
        }
    }

    fn shot(&mut self, _shot: &ShotState) {}
}

/// `bins` bars of `fine` counts, `merge` fine bins each, from the first.
fn merged(fine: &[u64], merge: usize, bins: usize) -> Vec<f64> {
    fine.chunks(merge)
        .take(bins)
        .map(|c| c.iter().sum::<u64>() as f64)
        .collect()
}

/// The bar width among 1-2-5 steps (in fine bins) that puts `top` fine bins into at most
/// [`BARS`] bars.
fn bar_width(top: usize) -> usize {
    [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10_000]
        .into_iter()
        .find(|w| top.div_ceil(*w) <= BARS)
        .unwrap_or(10_000)
}

/// `n` and `thing`, in the plural unless `n` is 1.
fn plural(n: u64, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

fn label(v: f64) -> String {
    let s = format!("{v:.1}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

impl ImpactFigure {
    /// The square frame `[x0, x1, y0, y1]` (mm) about `centre` (the middle of the
    /// sampled impacts when `None`), and the sampled impacts outside it.
    fn frame(&self, centre: Option<(f64, f64)>) -> ([f64; 4], usize) {
        let (cx, cy) = centre.unwrap_or_else(|| {
            let mid = |f: fn(&Sampled) -> f64| {
                let mut v: Vec<f64> = self.sample.iter().map(f).collect();
                v.sort_by(f64::total_cmp);
                v.get(v.len() / 2).copied().unwrap_or(0.0)
            };
            (mid(|s| s.x), mid(|s| s.y))
        });
        let mut d: Vec<f64> = self
            .sample
            .iter()
            .map(|s| (s.x - cx).abs().max((s.y - cy).abs()))
            .collect();
        d.sort_by(f64::total_cmp);
        let half = match d.len() {
            0 => 1.0,
            n => {
                let framed = d[((FRAMED * n as f64).ceil() as usize).clamp(1, n) - 1];
                // A margin of a fifth, but no wider than the farthest impact needs.
                (1.2 * framed).min(1.05 * d[n - 1]).max(0.5)
            }
        };
        let outside = d.iter().filter(|&&v| v > half).count();
        ([cx - half, cx + half, cy - half, cy + half], outside)
    }

    /// Writes `stem.png` and `stem.svg`. `axis_foot`: where the jet axis meets the
    /// specimen (mm), when the air jet acts on the shots.
    pub fn write(
        &self,
        stem: &Path,
        title: &str,
        axis_foot: Option<(f64, f64)>,
    ) -> Result<(), plot::PlotError> {
        let count = |h: &[u64]| h.iter().sum::<u64>();
        let firsts = count(&self.speed[0]) + self.speed_overflow[0];
        let rebounds = count(&self.speed[1]) + self.speed_overflow[1];
        let kinds = [("first hits", firsts), ("rebound hits", rebounds)];
        let shown: Vec<usize> = (0..2).filter(|&k| kinds[k].1 > 0 || k == 0).collect();

        // Normal speed: bars up to the fastest impact within the fine bins.
        let top = (0..2)
            .filter_map(|k| self.speed[k].iter().rposition(|&c| c > 0))
            .max()
            .map_or(1, |i| i + 1);
        let w = bar_width(top);
        let nbars = top.div_ceil(w);
        let speed_bars: Vec<Bars> = shown
            .iter()
            .map(|&k| Bars {
                name: kinds[k].0.into(),
                values: merged(&self.speed[k], w, nbars),
            })
            .collect();
        let speed_edges: Vec<String> = (0..nbars)
            .map(|b| label(b as f64 * w as f64 * SPEED_FINE))
            .collect();
        let overflow = self.speed_overflow[0] + self.speed_overflow[1];
        let speed_title = if overflow > 0 {
            format!(
                "Normal impact speed ({overflow} above {} m/s not shown)",
                label(SPEED_FINE * SPEED_FINE_BINS as f64)
            )
        } else {
            "Normal impact speed".to_string()
        };
        let speed_axis = format!(
            "normal speed, m/s ({} m/s bins, lower edge)",
            label(w as f64 * SPEED_FINE)
        );

        // Angle from the normal, 5-degree bars.
        let angle_bars: Vec<Bars> = shown
            .iter()
            .map(|&k| Bars {
                name: kinds[k].0.into(),
                values: merged(&self.angle[k], 5, 18),
            })
            .collect();
        let angle_edges: Vec<String> = (0..18).map(|b| (5 * b).to_string()).collect();

        let (extent, outside) = self.frame(axis_foot);
        let points: Vec<MapPoint> = self
            .sample
            .iter()
            .map(|s| MapPoint {
                x: s.x,
                y: s.y,
                value: s.normal,
                filled: s.first,
            })
            .collect();
        let value_max = self.sample.iter().map(|s| s.normal).fold(0.0, f64::max);
        let what = if self.stride > 1 {
            format!(
                "1 in {} of {} impacts ({} drawn)",
                self.stride,
                self.seen,
                self.sample.len()
            )
        } else {
            plural(self.seen, "impact")
        };
        let map_title = if outside > 0 {
            format!("Where the shots hit: {what}, {outside} outside the frame")
        } else {
            format!("Where the shots hit: {what}")
        };
        let map = Map {
            title: &map_title,
            labels: ("x, mm", "y, mm"),
            extent,
            points: &points,
            value_label: "normal speed, m/s",
            value_max,
            kinds: ("first hit", "rebound hit"),
            cross: axis_foot.map(|(x, y)| (x, y, "jet axis")),
        };
        let whole = format!(
            "{title}: {} ({}, {})",
            plural(self.seen, "impact"),
            plural(firsts, "first hit"),
            plural(rebounds, "rebound hit")
        );
        plot::map_with_bars(
            stem,
            &whole,
            &map,
            &[
                BarPanel {
                    title: &speed_title,
                    labels: (&speed_axis, "impacts"),
                    categories: &speed_edges,
                    bars: &speed_bars,
                },
                BarPanel {
                    title: "Impact angle from the normal",
                    labels: ("angle, degrees (5-degree bins, lower edge)", "impacts"),
                    categories: &angle_edges,
                    bars: &angle_bars,
                },
            ],
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;

    fn impact(k: u32, x_mm: f64, normal: f64, first: bool) -> Impact {
        let v = Vec3::new(0.3 * normal, 0.0, -normal);
        let p = Vec3::new(x_mm * 1e-3, 0.0, 4e-4);
        Impact::new(
            k,
            k as f64 * 1e-6,
            &p,
            &v,
            &Vec3::zeros(),
            4e-4,
            2e-6,
            0,
            first,
        )
    }

    #[test]
    fn the_sample_is_every_stride_th_impact_and_the_histograms_count_all() {
        let mut f = ImpactFigure::default();
        let n = 5 * MAP_POINTS as u32 / 2 + 17;
        let batch: Vec<Impact> = (0..n)
            .map(|k| impact(k, k as f64 * 1e-3, 10.0 + (k % 40) as f64, k % 3 != 0))
            .collect();
        // Handed over in uneven batches, as a run does.
        for part in batch.chunks(777) {
            f.impacts(part);
        }
        assert_eq!(f.seen, n as u64);
        assert!(f.sample.len() > MAP_POINTS / 2 && f.sample.len() <= MAP_POINTS);
        assert_eq!(f.stride, 4);
        for (j, s) in f.sample.iter().enumerate() {
            let k = j as u64 * f.stride;
            assert!(
                (s.x - k as f64 * 1e-3).abs() < 1e-9,
                "sample {j} is impact {k}"
            );
        }
        let all: u64 = f.speed.iter().flatten().sum::<u64>();
        assert_eq!(all, n as u64);
        let firsts: u64 = f.angle[0].iter().sum();
        assert_eq!(firsts, (0..n).filter(|k| k % 3 != 0).count() as u64);
        // Every impact at atan(0.3) = 16.7 degrees.
        assert_eq!(f.angle[0][16] + f.angle[1][16], n as u64);
    }

    #[test]
    fn bars_merge_fine_bins_into_at_most_25() {
        assert_eq!(bar_width(1), 1);
        assert_eq!(bar_width(25), 1);
        assert_eq!(bar_width(26), 2);
        assert_eq!(bar_width(640), 50); // 64 m/s in 5 m/s bars
        assert_eq!(merged(&[1, 2, 3, 4, 5, 6, 7], 3, 3), vec![6.0, 15.0, 7.0]);
    }

    #[test]
    fn the_frame_holds_the_nearest_impacts_and_counts_the_rest() {
        let mut f = ImpactFigure::default();
        // 99 impacts within 5 mm of the axis, one 90 mm away.
        let batch: Vec<Impact> = (0..100)
            .map(|k| {
                impact(
                    k,
                    if k == 50 { 90.0 } else { (k % 11) as f64 - 5.0 },
                    50.0,
                    true,
                )
            })
            .collect();
        f.impacts(&batch);
        let (e, outside) = f.frame(Some((0.0, 0.0)));
        assert_eq!(outside, 1);
        assert!((e[1] - 6.0).abs() < 1e-12, "{e:?}"); // 1.2 x 5 mm
        assert_eq!(e[0], -e[1]);
        // All near: the frame just holds the farthest.
        let g = {
            let mut g = ImpactFigure::default();
            g.impacts(&batch[..50]);
            g
        };
        let (e, outside) = g.frame(Some((0.0, 0.0)));
        assert_eq!(outside, 0);
        assert!((e[1] - 5.25).abs() < 1e-12, "{e:?}");
    }
}
