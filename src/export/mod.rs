//! Export stage: impact files (HDF5), ParaView views (VTK XML) and FE initial-condition
//! decks (Abaqus, LS-DYNA, CalculiX) from editable templates. Every deck and VTK mesh is
//! built from the one mesh model in `crate::mesh`.

pub mod hdf5;
