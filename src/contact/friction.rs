//! Tangential contact: Coulomb friction with a viscous stick regularisation (the
//! "no-history" law of Haff & Werner 1986, LAMMPS `tangential linear_nohistory`),
//! acting at the contact point, so it spins the shots.
//!
//! `F_t = -min(mu F_n, gamma_t |s|) s / |s|`, where `s` is the slip velocity of the
//! contact point (tangential part of the relative velocity, including `omega x r`) and
//! `F_n >= 0` the normal Hertz force. While `mu F_n` is the smaller term the contact
//! slides (Coulomb); otherwise the viscous term drives the slip to zero (sticking,
//! rolling). `gamma_t` is the critical damping of a tangential spring as stiff as the
//! normal contact at the current overlap, `gamma_t = 2 sqrt(m_t k_n)`,
//! `k_n = 1.5 K delta^(1/2)`, with the tangential effective mass `m_t` (`2/7 m` for a
//! solid sphere on a fixed surface). Slip then decays on the normal contact's own time
//! scale, which the step cap already resolves: no stiffer steps, and rigid-body impact
//! theory is recovered in both regimes (sliding: `Delta v_t = mu (1 + e) v_n`; rolling:
//! `v_t' = 5/7 v_t`, `omega' R = v_t'`), see tests/friction.rs.
//!
//! The other law, [`Tangential::History`] (`[friction] tangential = "history"`), is the
//! tangential spring with history that LIGGGHTS (`tangential history`), EDEM
//! ("Hertz-Mindlin (no slip)") and Rocky use: each contact carries its accumulated
//! tangential displacement `xi`, the force is `-k_t xi - gamma_t s` while it stays within
//! `mu F_n`, and `xi` is cut back to the cone when it does not ([`history_step`]). It
//! gives the rebound spin reversal of near-normal impacts that tangential elasticity
//! causes (Maw, Barber & Fawcett 1976), which the viscous law cannot. It runs on the
//! fixed-step method (`method = "verlet"`), where the history is advanced once per step
//! as a DEM code does.
//!
//! Not modelled (documented in docs/model.md): micro-slip within the contact area
//! (Mindlin-Deresiewicz's load-history-dependent stiffness), rolling resistance, air
//! torque and the Magnus force on spinning shots.

use crate::Vec3;

/// The tangential law of every contact (`[friction] tangential`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tangential {
    /// Coulomb with viscous stick regularisation, no history (the default).
    Viscous,
    /// Tangential spring with history (LIGGGHTS `tangential history`), with the ratio
    /// `G* / E*` of each contact kind's effective shear and Young's moduli (shot on
    /// specimen, shot on shot, shot on wall).
    History {
        /// `G* / E*`, shot on specimen.
        specimen: f64,
        /// `G* / E*`, shot on shot.
        shot: f64,
        /// `G* / E*`, shot on the nozzle wall.
        wall: f64,
    },
}

/// Coulomb coefficients per contact kind, and the tangential law.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Friction {
    /// Shot on specimen.
    pub specimen: f64,
    /// Shot on shot.
    pub shot: f64,
    /// Shot on nozzle wall.
    pub wall: f64,
    /// The tangential law.
    pub law: Tangential,
}

/// Effective shear modulus of two materials, `G* = 1 / ((2 - nu_1) / G_1 + (2 - nu_2) / G_2)`
/// with `G = E / (2 (1 + nu))` (Mindlin), over their effective Young's modulus
/// `E* = 1 / ((1 - nu_1^2) / E_1 + (1 - nu_2^2) / E_2)`: for one material
/// `(1 - nu) / (2 (2 - nu))`, 0.206 for steel's 0.3.
pub fn shear_ratio(e1: f64, nu1: f64, e2: f64, nu2: f64) -> f64 {
    let inv_g = |e: f64, nu: f64| 2.0 * (2.0 - nu) * (1.0 + nu) / e;
    let inv_e = |e: f64, nu: f64| (1.0 - nu * nu) / e;
    (inv_e(e1, nu1) + inv_e(e2, nu2)) / (inv_g(e1, nu1) + inv_g(e2, nu2))
}

/// The history law's tangential stiffness `k_t = 8 G* sqrt(R* delta)`, N/m, written with
/// the Hertz stiffness `K = (4/3) E* sqrt(R*)` of the same contact and `g = G* / E*`:
/// `6 g K sqrt(delta)`. (Its ratio to the normal contact's `dF_n / d delta = (3/2) K
/// sqrt(delta)` is `2 (1 - nu) / (2 - nu)`, 0.82 for steel.)
#[inline]
pub fn history_stiffness(g: f64, k: f64, overlap: f64) -> f64 {
    6.0 * g * k * overlap.max(0.0).sqrt()
}

/// The history law's tangential damping `gamma_t`, kg/s: the normal dashpot of the same
/// contact at the same overlap, `alpha sqrt(m* K) delta^(1/4)`
/// ([`crate::contact::hertz::HertzLaw::force`]), scaled by `sqrt(k_t / k_n)` with the
/// stiffnesses LIGGGHTS' `hertz` model writes them (`S_t = 8 G* a`, `S_n = 2 E* a`), that
/// is by `2 sqrt(G* / E*)`: LIGGGHTS' `gamma_t = -2 sqrt(5/6) beta sqrt(S_t m*)` next to
/// its `gamma_n` with `S_n`.
#[inline]
pub fn history_damping(g: f64, alpha: f64, m_eff: f64, k: f64, overlap: f64) -> f64 {
    2.0 * g.sqrt() * alpha * (m_eff * k).sqrt() * overlap.max(0.0).sqrt().sqrt()
}

/// One step `dt` of a contact's tangential history, as LIGGGHTS' `tangential history`
/// takes it in its force evaluation (positions at the step's end, velocities at its
/// half): the displacement grows by the slip, `xi += s dt`, and is turned into the
/// contact's current tangent plane (unit normal `n`, dropping its normal part); the force
/// is the spring's `-k_t xi` plus the dashpot's `-gamma_t s` while the spring stays within
/// Coulomb's `mu F_n`; otherwise it is the spring's force cut to `mu F_n`, and `xi` is cut
/// with it (the contact slides; no dashpot). Returns the force on the body whose contact
/// point slips with `slip`.
#[allow(clippy::too_many_arguments)]
pub fn history_step(
    xi: &mut Vec3,
    n: &Vec3,
    slip: &Vec3,
    dt: f64,
    k_t: f64,
    gamma_t: f64,
    mu: f64,
    f_n: f64,
) -> Vec3 {
    *xi += slip * dt;
    *xi -= n * xi.dot(n);
    let shear = xi.norm();
    let cap = mu * f_n.abs();
    if k_t * shear > cap {
        if shear == 0.0 {
            return Vec3::zeros();
        }
        let ft = *xi * (-cap / shear);
        *xi = ft / -k_t;
        ft
    } else {
        *xi * -k_t - slip * gamma_t
    }
}

/// Moment of inertia factor of a solid sphere: `I = 2/5 m R^2`.
pub const INERTIA_FACTOR: f64 = 0.4;

/// Tangential effective mass of a sphere (mass `m`) on a fixed surface: slip responds
/// to a force `F` at the contact point as `F (1/m + R^2/I) = 7 F / (2 m)`.
#[inline]
pub fn sphere_on_wall_mass(m: f64) -> f64 {
    m / (1.0 + 1.0 / INERTIA_FACTOR)
}

/// Tangential effective mass of two spheres: `1 / (1/m_t,1 + 1/m_t,2)`.
#[inline]
pub fn sphere_pair_mass(m1: f64, m2: f64) -> f64 {
    let (a, b) = (sphere_on_wall_mass(m1), sphere_on_wall_mass(m2));
    a * b / (a + b)
}

/// Stick damping `gamma_t = 2 sqrt(m_t 1.5 K delta^(1/2))`, kg/s.
#[inline]
pub fn stick_damping(m_t: f64, stiffness: f64, overlap: f64) -> f64 {
    2.0 * (m_t * 1.5 * stiffness * overlap.max(0.0).sqrt()).sqrt()
}

/// Tangential force on the body whose contact point slips with `slip` (already
/// tangential), for coefficient `mu`, normal force `f_n >= 0` and stick damping `gamma`.
#[inline]
pub fn tangential_force(mu: f64, f_n: f64, slip: &Vec3, gamma: f64) -> Vec3 {
    let s = slip.norm();
    if s == 0.0 || f_n <= 0.0 || mu == 0.0 {
        return Vec3::zeros();
    }
    let magnitude = (mu * f_n).min(gamma * s);
    slip * (-magnitude / s)
}

/// The start of a touch's tangential force, `|F_t| = d1 s^(1/4) + d2 s^(3/2) + ...`
/// (`s` the time since the touch), for an impact at normal speed `v0` whose normal force
/// starts as `c1 s^(1/4) + c2 s^(3/2)` (`HertzLaw::onset_terms`) with slip speed `slip`
/// at the touch. Both branches of the law start as `s^(1/4)` (`gamma_t` grows as
/// `delta^(1/4)`, `delta ~ v0 s`), so the regime at the touch holds through its first
/// steps: sliding, `(mu c1, mu c2)` exactly; sticking, `(gamma_1 |s|, 0)` with
/// `gamma_t = gamma_1 s^(1/4)`, the slip's own decay (of order `s^(3/2)`) left out.
pub fn onset_terms(
    mu: f64,
    (c1, c2): (f64, f64),
    m_t: f64,
    k: f64,
    v0: f64,
    slip: f64,
) -> (f64, f64) {
    if mu == 0.0 || slip == 0.0 {
        return (0.0, 0.0);
    }
    let g1 = 2.0 * (1.5 * m_t * k).sqrt() * v0.sqrt().sqrt();
    if mu * c1 <= g1 * slip {
        (mu * c1, mu * c2)
    } else {
        (g1 * slip, 0.0)
    }
}

/// Tangential part of `v` for the unit normal `n`.
#[inline]
pub fn tangential_part(v: &Vec3, n: &Vec3) -> Vec3 {
    v - n * v.dot(n)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The law itself just after a touch (`delta = v0 s`, normal force from its start
    /// `c1 s^(1/4) + c2 s^(3/2)`) against `onset_terms`' start, in both branches.
    #[test]
    fn a_touchs_tangential_force_starts_as_onset_terms_say() {
        let (k, m_t, v0, mu) = (2.2e9, 3.0e-7, 100.0, 0.3);
        let (c1, c2) = (1.2e3, 2.3e12);
        for slip in [60.0, 0.5] {
            let (d1, d2) = onset_terms(mu, (c1, c2), m_t, k, v0, slip);
            let sliding = slip > 1.0;
            assert_eq!(d1 == mu * c1, sliding);
            for s in [1e-13f64, 1e-11, 1e-10] {
                let f_n = c1 * s.powf(0.25) + c2 * s.powf(1.5);
                let gamma = stick_damping(m_t, k, v0 * s);
                let law = tangential_force(mu, f_n, &Vec3::new(slip, 0.0, 0.0), gamma).norm();
                let start = d1 * s.powf(0.25) + d2 * s.powf(1.5);
                // Sliding: exact. Sticking: the leading term (the slip held fixed here).
                assert!(
                    (law / start - 1.0).abs() < 1e-12,
                    "slip {slip} s {s}: {law} vs {start}"
                );
            }
        }
        assert_eq!(onset_terms(0.0, (c1, c2), m_t, k, v0, 60.0), (0.0, 0.0));
        assert_eq!(onset_terms(mu, (c1, c2), m_t, k, v0, 0.0), (0.0, 0.0));
    }

    #[test]
    fn coulomb_cap_and_stick_branch() {
        let slip = Vec3::new(3.0, 4.0, 0.0);
        // Sliding: capped at mu F_n, against the slip.
        let f = tangential_force(0.5, 10.0, &slip, 1e9);
        assert!((f.norm() - 5.0).abs() < 1e-12);
        assert!((f.normalize() + slip.normalize()).norm() < 1e-12);
        // Sticking: viscous gamma |s|.
        let f = tangential_force(0.5, 10.0, &slip, 0.2);
        assert!((f.norm() - 1.0).abs() < 1e-12);
        // No normal force, no friction.
        assert_eq!(tangential_force(0.5, 0.0, &slip, 1.0), Vec3::zeros());
        // Sphere on a wall: 2/7 of the mass.
        assert!((sphere_on_wall_mass(7.0) - 2.0).abs() < 1e-12);
        assert!((sphere_pair_mass(7.0, 7.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn history_sticks_within_the_cone_and_slides_on_it() {
        let n = Vec3::z();
        let slip = Vec3::new(2.0, 0.0, 0.0);
        // Within the cone: spring plus dashpot, xi grown by the slip.
        let mut xi = Vec3::new(1e-6, 0.0, 0.0);
        let f = history_step(&mut xi, &n, &slip, 1e-7, 1e6, 0.5, 0.3, 100.0);
        assert!((xi.x - 1.2e-6).abs() < 1e-18);
        assert!((f.x - (-1.2 - 1.0)).abs() < 1e-12, "{f}");
        // Beyond it: the force cut to mu F_n, xi cut with it, no dashpot.
        let mut xi = Vec3::new(1e-4, 0.0, 0.0);
        let f = history_step(&mut xi, &n, &slip, 1e-7, 1e6, 0.5, 0.3, 100.0);
        assert!((f.norm() - 30.0).abs() < 1e-12 && f.x < 0.0);
        assert!((xi.x - 3e-5).abs() < 1e-18);
        // Turned into the tangent plane.
        let mut xi = Vec3::new(1e-6, 0.0, 1e-6);
        history_step(&mut xi, &n, &Vec3::zeros(), 1e-7, 1e6, 0.0, 0.3, 100.0);
        assert_eq!(xi.z, 0.0);
        // Steel on steel: G*/E* = (1 - nu) / (2 (2 - nu)); k_t / k_n = 2 (1 - nu) / (2 - nu).
        let g = shear_ratio(210e9, 0.3, 210e9, 0.3);
        assert!((g - 0.7 / 3.4).abs() < 1e-15);
        let (k, d) = (2.0e10, 1e-6);
        let ratio = history_stiffness(g, k, d) / (1.5 * k * d.sqrt());
        assert!((ratio - 1.4 / 1.7).abs() < 1e-12);
    }
}
