//! FMI 2.0 co-simulation FMU of the SHPB specimen (`fractum_shpb.so`, model identifier
//! `fractum_shpb`). The bars (1D elastic wave models in Modelica, Python, Simulink...) give
//! the velocities of the two bar faces; the FMU returns the specimen's stresses and forces.
//!
//! A thin layer over `fractum::Simulation`: it checks the calling sequence, maps variables,
//! translates errors into fmi2Error with a sentence to the logger, and never lets a panic
//! cross the boundary. All 34 fmi2 functions are exported; those a co-simulation FMU of this
//! kind does not support return fmi2Error with a message.
//!
//! Split as the Modelica Association's Reference-FMUs split `fmi2Functions.c` from each
//! `model.c`: [`fmi2`] is the FMI layer, which knows no model, and [`shpb`] is the model
//! (variables, start values, how the specimen is built and stepped, what a saved state
//! holds), the only code that calls the `fractum` library. They meet at [`fmi2::Model`].

pub mod fmi2;
pub mod shpb;

pub use fmi2::*;
pub use shpb::{GUID, MODEL_IDENTIFIER, vr};

/// The model this library exports.
type FmuModel = shpb::Shpb;
