//! Flow stage: the compressed-air state and the jet field that drag and the lateral
//! force sample. Sampled only when a force model needs the air (drag or lateral force on).

pub mod air;
pub mod coupling;
pub mod jet;

pub use air::AirState;
pub use jet::{FlowSample, JetCoords, JetField, JetModel, Region};
