//! Polarised light: Stokes vectors per wavelength lane ([`Stokes`]), the Mueller matrices of
//! the interactions prisma models ([`Mueller`]), and the reference frames they are written in
//! ([`frame`]). Conventions are stated here once; every other module follows them.
//!
//! # Stokes vectors and their frames
//! A Stokes vector (S0, S1, S2, S3) describes a beam travelling along a unit direction `f` (the
//! direction the *light* travels), in a frame given by a unit x axis perpendicular to `f`; the
//! y axis is `f × x`, so that (x, y, f) is right-handed. Looking back at the source (the
//! receiver's point of view), x points right and y up. Then
//! - S0 is the radiance;
//! - S1 = +S0 for light polarised along x, −S0 along y;
//! - S2 = +S0 for light polarised at +45°, counter-clockwise from x towards y;
//! - S3 = +S0 for light whose electric field turns **clockwise as seen by the receiver**
//!   ("right circular" in the optics convention of Born & Wolf and of Mitsuba 3's `stokes`
//!   output, whose signs prisma's output shares).
//!
//! Turning the frame's x axis by θ counter-clockwise about `f` changes the Stokes vector by
//! `S1' = cos 2θ·S1 + sin 2θ·S2`, `S2' = −sin 2θ·S1 + cos 2θ·S2` (a field at angle φ from the
//! old axis is at φ − θ from the new one); S0 and S3 do not change. [`frame::Rotation`] owns
//! this formula; its tests check it against the electric-field direction itself.
//!
//! # Complex amplitudes and the phase sign
//! Fields are written `E·e^{i(ωt − k·r)}` (the engineering time convention of Clarke's
//! *Stellar Polarimetry* and of Mitsuba's Fresnel code): an absorbing medium has index n − ik,
//! and an evanescent wave past the critical angle has cos θt = −i√(sin²θt − 1), so both decay.
//! An element whose Jones matrix is diagonal in its (x, y) frame, E' = (A_x E_x, A_y E_y), has
//! the Mueller matrix (see [`Mueller::from_jones_diagonal`])
//! ```text
//! | a  b  0   0 |     a = (|A_x|² + |A_y|²)/2,  b = (|A_x|² − |A_y|²)/2,
//! | b  a  0   0 |     w = A_x·conj(A_y) = w_re + i·w_im
//! | 0  0  w_re w_im |
//! | 0  0 −w_im w_re |
//! ```
//! With δ = arg A_y − arg A_x this is Mitsuba 3's `specular_reflection` form
//! (w_re = c·cos δ, w_im = −c·sin δ, c = |A_x A_y|). The sign of w_im ties S3 to the time
//! convention: with `e^{+iωt}`, A_y = i·A_x makes the field turn clockwise for the receiver,
//! and gives S3 = +S0 from S2 = +S0 through a 90° phase. Tests reconstruct the field E(t) and
//! check the sense of rotation against the sign of S3 (`mueller.rs`).
//!
//! # Interfaces
//! At a surface with normal n and a beam travelling along f, the s axis is `n × f`
//! (perpendicular to the plane of incidence) and p = f × s; Fresnel's r_s, r_p, t_s, t_p (Hecht's
//! signs) are the diagonal of the Jones matrix between the incident (s, p_in) and the outgoing
//! (s, p_out) frames. An ideal mirror is a perfect electric conductor: (r_s, r_p) = (−1, +1).
//! Diffuse surfaces depolarise; lights and the background emit unpolarised light.

pub mod beam;
pub mod detector;
pub mod frame;
pub mod mueller;
pub mod stokes;

pub use beam::Beam;
pub use detector::Detector;
pub use frame::Rotation;
pub use mueller::Mueller;
pub use stokes::Stokes;
