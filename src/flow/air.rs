//! Air state of the supply and at the nozzle exit (paper Eqs 2, 3 and 8).
//!
//! Reads the air-supply settings of the scene and derives the densities and the exit
//! velocity that the jet field ([`super::jet`]) uses. Pure data: built once per run.

/// Supply and exit state of the compressed air. All quantities SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AirState {
    /// Ambient (atmospheric) air density `rho_ab`, kg/m^3 (paper: 1.205).
    pub rho_ambient: f64,
    /// Stagnation (compressor) density `rho_0 = rho_ab (P + P_b) / P_b`, kg/m^3 (Eq 2).
    pub rho_stagnation: f64,
    /// Density at the nozzle exit `rho*`, kg/m^3 (Eq 3 when choked: 0.634 rho_0).
    pub rho_exit: f64,
    /// Air velocity at the nozzle exit `u_i`, m/s (Eq 8; ~313 m/s choked at 293 K).
    pub exit_velocity: f64,
    /// Whether the nozzle is choked (`(P + P_b)/P_b` at or above the critical ratio).
    pub is_choked: bool,
    /// Absolute supply pressure over ambient pressure, `(P + P_b)/P_b`.
    pub pressure_ratio: f64,
}

impl AirState {
    /// Derives the air state.
    ///
    /// * `gauge_pressure` `P`, Pa; `ambient_pressure` `P_b`, Pa (absolute);
    /// * `temperature` stagnation temperature, K; `kappa` ratio of specific heats;
    /// * `gas_constant` specific gas constant, J/(kg K); `rho_ambient` `rho_ab`, kg/m^3.
    ///
    /// Choked (`(P+P_b)/P_b >= ((kappa+1)/2)^(kappa/(kappa-1))`, 1.893 for air):
    /// `rho* = rho_0 (2/(kappa+1))^(1/(kappa-1))`, `u_i = a_0 sqrt(2/(kappa+1))`.
    /// Otherwise Eq 8 with the exit pressure equal to ambient:
    /// `u_i^2/2 = a_0^2/(kappa-1) (1 - (P_b/(P+P_b))^((kappa-1)/kappa))` and the
    /// isentropic exit density `rho_0 (P_b/(P+P_b))^(1/kappa)`.
    pub fn new(
        gauge_pressure: f64,
        ambient_pressure: f64,
        temperature: f64,
        kappa: f64,
        gas_constant: f64,
        rho_ambient: f64,
    ) -> Self {
        let ratio = (gauge_pressure + ambient_pressure) / ambient_pressure;
        let rho_stagnation = rho_ambient * ratio;
        let a0 = (kappa * gas_constant * temperature).sqrt();
        let critical = critical_pressure_ratio(kappa);
        let (rho_exit, exit_velocity, is_choked) = if ratio >= critical {
            let rho = rho_stagnation * (2.0 / (kappa + 1.0)).powf(1.0 / (kappa - 1.0));
            (rho, a0 * (2.0 / (kappa + 1.0)).sqrt(), true)
        } else {
            let pr = 1.0 / ratio;
            let u2 = 2.0 * a0 * a0 / (kappa - 1.0) * (1.0 - pr.powf((kappa - 1.0) / kappa));
            (
                rho_stagnation * pr.powf(1.0 / kappa),
                u2.max(0.0).sqrt(),
                false,
            )
        };
        AirState {
            rho_ambient,
            rho_stagnation,
            rho_exit,
            exit_velocity,
            is_choked,
            pressure_ratio: ratio,
        }
    }
}

/// Critical (choking) pressure ratio `((kappa+1)/2)^(kappa/(kappa-1))`: 1.893 for kappa = 1.4.
pub fn critical_pressure_ratio(kappa: f64) -> f64 {
    ((kappa + 1.0) / 2.0).powf(kappa / (kappa - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_supply_is_choked_with_paper_constants() {
        let a = AirState::new(0.6e6, 0.1e6, 293.0, 1.4, 287.05, 1.205);
        assert!(a.is_choked);
        // Eq 2: 1.205 * 7 = 8.435; Eq 3: 0.634 * 8.435 = 5.348 (paper: 0.764 * 7 = 5.348).
        assert!((a.rho_stagnation - 8.435).abs() < 1e-12);
        assert!((a.rho_exit / a.rho_stagnation - 0.634).abs() < 5e-4);
        // model-notes: about 313.3 m/s at 293 K (paper quotes 313.47).
        assert!(
            (a.exit_velocity - 313.25).abs() < 0.1,
            "{}",
            a.exit_velocity
        );
    }

    #[test]
    fn critical_ratio_of_air() {
        assert!((critical_pressure_ratio(1.4) - 1.8929).abs() < 1e-4);
    }

    #[test]
    fn unchoked_exit_is_continuous_at_the_critical_ratio() {
        // Just below and at the critical ratio the two branches must agree.
        let pc = critical_pressure_ratio(1.4);
        let pb = 0.1e6;
        let below = AirState::new(
            (pc - 1.0) * pb * (1.0 - 1e-9),
            pb,
            293.0,
            1.4,
            287.05,
            1.205,
        );
        let at = AirState::new(
            (pc - 1.0) * pb * (1.0 + 1e-9),
            pb,
            293.0,
            1.4,
            287.05,
            1.205,
        );
        assert!(!below.is_choked && at.is_choked);
        assert!((below.exit_velocity / at.exit_velocity - 1.0).abs() < 1e-6);
        assert!((below.rho_exit / at.rho_exit - 1.0).abs() < 1e-6);
    }
}
