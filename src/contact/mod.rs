//! Contact stage: which contacts a scene enabled, their geometry and their laws.
//!
//! * [`SpecimenContact`]: shot on the specimen (the plane `z = 0`, normal `+z`; or a bar,
//!   or a [`groove`]);
//! * [`WallContact`]: shot against the nozzle tube (bore, lips, outer surface);
//! * [`PairContact`]: shot on shot, candidates from the [`broad`] cell list;
//! * [`Friction`]: Coulomb friction at the contact points of all three (spins shots).
//!
//! Laws only evaluate forces at the state they are given; the integrator decides how
//! time is stepped and locates contact onsets (see `integrate::island`).

pub mod broad;
pub mod friction;
pub mod groove;
pub mod hertz;
pub mod involute;
pub mod pair;
pub mod restitution;
pub mod specimen;
pub mod table;
pub mod wall;

pub use friction::Friction;
pub use hertz::HertzLaw;
pub use pair::PairContact;
pub use specimen::SpecimenContact;
pub use wall::{Tube, WallContact, WallGeom};

/// The enabled contacts. A disabled contact is `None`: no test, no neighbour search.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSet {
    /// Shot-specimen contact.
    pub specimen: Option<SpecimenContact>,
    /// Shot-nozzle-wall contact.
    pub wall: Option<WallContact>,
    /// Shot-shot contact.
    pub pair: Option<PairContact>,
    /// Coulomb friction in the enabled contacts (and shot spin). `None`: frictionless
    /// contacts and no angular velocity in the integrated state.
    pub friction: Option<Friction>,
}

/// Effective mass `m_1 m_2 / (m_1 + m_2)`, kg.
#[inline]
pub fn effective_mass(m1: f64, m2: f64) -> f64 {
    m1 * m2 / (m1 + m2)
}
