//! Per-case statistics: each run's numbers (taken from its [`Summary`], the same numbers
//! `peenflow run` prints) and, across a case's seeds, their mean with a 95 % Student-t
//! confidence interval.

use crate::summary::Summary;
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, StudentsT};

/// One statistic of a run: name (dataset name in sweep.h5), units, description, value.
pub struct StatDef {
    /// Name.
    pub name: &'static str,
    /// Units.
    pub units: &'static str,
    /// Description.
    pub description: &'static str,
    /// Value from a run's summary (`None` when the run had no first hit).
    pub of: fn(&Summary) -> Option<f64>,
}

/// The statistics every case reports (over first hits, as the run summary).
pub const STATS: &[StatDef] = &[
    StatDef {
        name: "hit_fraction",
        units: "1",
        description: "share of shots that reached the specimen",
        of: |s| Some(s.hit_fraction),
    },
    StatDef {
        name: "speed_mean_m_s",
        units: "m/s",
        description: "mean normal impact speed of first hits",
        of: |s| s.normal_speed_m_s.as_ref().map(|x| x.mean),
    },
    StatDef {
        name: "speed_p10_m_s",
        units: "m/s",
        description: "10th percentile of the normal impact speed of first hits",
        of: |s| s.normal_speed_m_s.as_ref().map(|x| x.p10),
    },
    StatDef {
        name: "speed_p50_m_s",
        units: "m/s",
        description: "median normal impact speed of first hits",
        of: |s| s.normal_speed_m_s.as_ref().map(|x| x.median),
    },
    StatDef {
        name: "speed_p90_m_s",
        units: "m/s",
        description: "90th percentile of the normal impact speed of first hits",
        of: |s| s.normal_speed_m_s.as_ref().map(|x| x.p90),
    },
    StatDef {
        name: "radius_p50_mm",
        units: "mm",
        description: "median distance of first hits from the jet axis",
        of: |s| s.radius_m.as_ref().map(|x| x.median * 1e3),
    },
    StatDef {
        name: "radius_p90_mm",
        units: "mm",
        description: "90th percentile of the distance of first hits from the jet axis",
        of: |s| s.radius_m.as_ref().map(|x| x.p90 * 1e3),
    },
    StatDef {
        name: "jet_momentum_share",
        units: "1",
        description: "share of the jet's momentum flow the shots take (one-way coupling holds while it is small; docs/model.md)",
        of: |s| s.jet_loading.as_ref().map(|l| l.momentum_fraction),
    },
];

/// A statistic across a case's seeds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AcrossSeeds {
    /// Seeds that had a value.
    pub n: usize,
    /// Mean over those seeds.
    pub mean: Option<f64>,
    /// Sample standard deviation (n - 1).
    pub std: Option<f64>,
    /// Lower end of the 95 % confidence interval of the mean (Student t, n - 1 dof).
    pub ci_low: Option<f64>,
    /// Upper end.
    pub ci_high: Option<f64>,
}

impl AcrossSeeds {
    /// Mean, standard deviation and 95 % confidence interval of the present values.
    pub fn of(values: &[Option<f64>]) -> AcrossSeeds {
        let v: Vec<f64> = values.iter().flatten().copied().collect();
        let n = v.len();
        if n == 0 {
            return AcrossSeeds {
                n,
                mean: None,
                std: None,
                ci_low: None,
                ci_high: None,
            };
        }
        let mean = v.iter().sum::<f64>() / n as f64;
        if n == 1 {
            return AcrossSeeds {
                n,
                mean: Some(mean),
                std: None,
                ci_low: None,
                ci_high: None,
            };
        }
        let var = v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let std = var.sqrt();
        let t = StudentsT::new(0.0, 1.0, (n - 1) as f64)
            .expect("BUG: t distribution with n - 1 >= 1")
            .inverse_cdf(0.975);
        let half = t * std / (n as f64).sqrt();
        AcrossSeeds {
            n,
            mean: Some(mean),
            std: Some(std),
            ci_low: Some(mean - half),
            ci_high: Some(mean + half),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn confidence_interval_matches_the_t_table() {
        // n = 5: t_{0.975, 4} = 2.776445 (tables); values 1..5: mean 3, s = 1.5811.
        let a = AcrossSeeds::of(&[Some(1.0), Some(2.0), Some(3.0), Some(4.0), Some(5.0)]);
        assert_eq!(a.n, 5);
        assert!((a.mean.unwrap() - 3.0).abs() < 1e-15);
        let half = 2.776445 * 1.5811388 / 5f64.sqrt();
        assert!((a.ci_high.unwrap() - 3.0 - half).abs() < 1e-5);
        assert!((3.0 - a.ci_low.unwrap() - half).abs() < 1e-5);
        // Missing values are left out; one value has no interval.
        let b = AcrossSeeds::of(&[None, Some(2.0)]);
        assert_eq!((b.n, b.mean, b.ci_low), (1, Some(2.0), None));
    }
}
