//! [`Beam`] lives in [`crate::polarization::beam`], below the film that accumulates beams and
//! the integrators that trace them; re-exported here so `integrator::Beam` keeps its name.

pub use crate::polarization::Beam;
