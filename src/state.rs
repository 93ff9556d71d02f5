//! Simulation state: one [`ShotState`] per shot, plus ids.
//!
//! Shots are stored as an array of structs: the integrator copies the members of each
//! island into its own contiguous buffer for the window anyway (see `sim.rs`), so the
//! global array is touched once per window per shot.

use crate::Vec3;
use crate::flow::{JetField, Region};
use crate::forces::ShotBody;
use serde::Serialize;

/// Index of a shot in the run (0-based, in feed order).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct ShotId(pub u32);

/// Life cycle of a shot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ShotStatus {
    /// Flying (or resting) inside the domain; integrated.
    Active,
    /// Left the simulated domain (see [`Domain`]); no longer integrated.
    LeftDomain,
    /// Stopped because its state stopped being finite or its steps collapsed.
    Failed,
}

/// Box outside which a shot no longer matters and is dropped from the run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Domain {
    /// Largest distance from the world z axis, m.
    pub radius: f64,
    /// Largest height above the specimen, m.
    pub top: f64,
    /// Lowest height, m: below it a shot has passed a curved specimen for good
    /// ([`crate::contact::specimen::SpecimenShape::floor`]; `-inf` over the plane).
    pub bottom: f64,
}

impl Domain {
    /// Whether `pos` lies inside.
    #[inline]
    pub fn contains(&self, pos: &Vec3) -> bool {
        pos.x * pos.x + pos.y * pos.y <= self.radius * self.radius
            && pos.z <= self.top
            && pos.z >= self.bottom
    }
}

/// Everything the run keeps about one shot.
#[derive(Debug, Clone, PartialEq)]
pub struct ShotState {
    /// The shot's id.
    pub id: ShotId,
    /// Centre, m.
    pub pos: Vec3,
    /// Velocity, m/s.
    pub vel: Vec3,
    /// Angular velocity, rad/s (integrated only with the `friction` effect).
    pub omega: Vec3,
    /// Turbulent air-velocity fluctuation the shot sees (the current eddy), m/s.
    pub gust: Vec3,
    /// Time the current eddy ends, s (`-inf`: none).
    pub gust_until: f64,
    /// Eddies met so far (numbers the shot's random draws).
    pub gusts: u32,
    /// Radius and mass.
    pub body: ShotBody,
    /// Time the shot enters the run, s (0 for batch feeds).
    pub t_start: f64,
    /// Life-cycle status.
    pub status: ShotStatus,
    /// Jet region frozen for the current step.
    pub region: Region,
    /// Below the top of the jet's stagnation layer at the current step's start: the top is
    /// a located border, as the regions' are (`JetField::layer_margin`).
    pub in_layer: bool,
    /// In contact with the specimen.
    pub on_specimen: bool,
    /// Sliding on the specimen: a lone shot whose persistent specimen contact has settled
    /// moves in its plane, its overlap set by the static balance of its load (see
    /// [`crate::integrate::island`], `slide`), instead of stepping through the pressed
    /// contact's oscillation; with friction it rolls (the contact point held still).
    pub sliding: bool,
    /// Step-duration estimate of the current specimen contact (Hertz time), s.
    pub specimen_contact_time: f64,
    /// Onset time of the current specimen contact, s.
    pub specimen_onset: f64,
    /// Tsuji damping factor of the current specimen contact, set at every touch (the
    /// constant law's without a curve); read only when the restitution depends on the
    /// impact speed (`SpecimenContact::law_of`).
    pub specimen_damping: f64,
    /// In contact with the nozzle wall.
    pub on_wall: bool,
    /// Onset time of the current wall contact, s.
    pub wall_onset: f64,
    /// Tangential displacement of the current specimen contact, m (the `history`
    /// tangential law; zero otherwise and between contacts).
    pub specimen_xi: Vec3,
    /// Tangential displacement of the current wall contact, m (as `specimen_xi`).
    pub wall_xi: Vec3,
    /// Step-duration estimate of the current wall contact (Hertz time), s.
    pub wall_contact_time: f64,
    /// Next step size the error controller proposes, s.
    pub h_next: f64,
    /// Specimen contacts so far.
    pub hits: u32,
    /// Shot-shot contacts so far.
    pub collisions: u32,
    /// Nozzle-wall contacts so far.
    pub wall_contacts: u32,
    /// Accepted integrator steps that moved this shot.
    pub steps: u64,
    /// Steps from entering the run to the onset of the first specimen contact.
    pub steps_to_first_contact: Option<u64>,
    /// Steps taken during the first specimen contact.
    pub first_contact_steps: u64,
    /// Time (s) when the shot was stopped (left the domain or failed), if it was.
    pub t_stop: Option<f64>,
    /// A lone free-flying shot's last step when it ran past the window end (windows
    /// scheduler): `pos`, `vel` and `omega` are then its dense output at the window end,
    /// and the next window goes on from the step's exact end (see
    /// [`crate::integrate::island::advance_alone`]).
    pub ahead: Option<std::sync::Arc<crate::integrate::dopri::DenseStep>>,
    /// The fixed-step method's last force evaluation for this shot (acceleration, angular
    /// acceleration), at its current position with its half-step velocity: the first
    /// half-kick of its next step. Carried across windows, so that a window's start does
    /// not re-evaluate velocity-dependent forces (contact damping, drag, friction) with the
    /// full-step velocity: the steps are those of one global velocity Verlet, however the
    /// run is cut into windows. (The hybrid method carries it across a window end only
    /// while a contact lasts; each adaptive stretch clears it.)
    pub verlet_acc: Option<(Vec3, Vec3)>,
}

impl ShotState {
    /// A shot at rest or moving, entering the run at `t_start`.
    pub fn new(id: ShotId, pos: Vec3, vel: Vec3, body: ShotBody, t_start: f64) -> Self {
        ShotState {
            id,
            pos,
            vel,
            omega: Vec3::zeros(),
            gust: Vec3::zeros(),
            gust_until: f64::NEG_INFINITY,
            gusts: 0,
            body,
            t_start,
            status: ShotStatus::Active,
            region: Region::Outside,
            in_layer: false,
            on_specimen: false,
            sliding: false,
            specimen_contact_time: 0.0,
            specimen_onset: 0.0,
            specimen_damping: 0.0,
            on_wall: false,
            wall_onset: 0.0,
            specimen_xi: Vec3::zeros(),
            wall_xi: Vec3::zeros(),
            wall_contact_time: 0.0,
            h_next: 0.0,
            hits: 0,
            collisions: 0,
            wall_contacts: 0,
            steps: 0,
            steps_to_first_contact: None,
            first_contact_steps: 0,
            t_stop: None,
            ahead: None,
            verlet_acc: None,
        }
    }

    /// Sets the shot's jet region and its side of the stagnation layer's top for a
    /// centre at `pos` (an island's integrated position, not yet written back).
    #[inline]
    pub fn locate_at(&mut self, field: &JetField, pos: &Vec3) {
        self.region = field.region_of(&field.coords(pos));
        self.in_layer = field.in_layer(pos);
    }

    /// Sets the shot's jet region and its side of the stagnation layer's top for its
    /// own position.
    #[inline]
    pub fn locate(&mut self, field: &JetField) {
        let pos = self.pos;
        self.locate_at(field, &pos);
    }

    /// Whether the shot is still integrated.
    #[inline]
    pub fn is_active(&self) -> bool {
        self.status == ShotStatus::Active
    }
}
