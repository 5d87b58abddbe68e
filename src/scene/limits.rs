//! The ranges a scene's values must lie in, so that everything that loads renders without
//! overflow or panic (scenes/README.md, "Limits", states them for users).
//!
//! The renderer computes in f32 (largest finite value ≈ 3.4·10³⁸). The checks apply to the
//! values as they are used, after every transform: a spectrum after its `scale` and tabulation,
//! a mesh vertex after `scale`, `rotate_deg` and `position`, a prism after its construction, an
//! index of refraction at every whole nanometre of 360–830 nm.
//!
//! Why these numbers:
//! - **Coordinates within ±10¹⁰ scene units, lengths within [10⁻¹⁰, 10¹⁰].** The watertight
//!   triangle test forms products of three coordinate differences (distance × edge function),
//!   and the sphere test squares distances; with differences below 4·10¹⁰ the largest product
//!   stays below 10³⁵, and a radius of 10⁻¹⁰ still squares to a normal f32. Outside these, a
//!   sphere of radius 10²⁰ was silently never hit (r² overflowed) and prism or mesh vertices
//!   overflowed to infinity.
//! - **Emission (background, light radiance and intensity) at most 10¹⁵ per nm.** Turning a
//!   sample into XYZ divides by the wavelength pdf (≥ 2.3·10⁻⁴ per nm) and weights by the
//!   colour-matching functions (≤ 1.8) over ∫ȳ = 106.9 nm: a factor below 80, then ≤ 3.3 to
//!   linear sRGB, which leaves a margin of 10²¹ for radiance gains in glass. A background of
//!   10³⁶ gave NaN pixels.
//! - **Indices of refraction in [10⁻², 10²].** Radiance gains n² leaving glass towards a camera
//!   inside it, and (1 − R)/n² ≈ 4/n entering a medium of n ≪ 1 at normal incidence; both stay
//!   below 10⁴ per interface.
//!
//! - **Coatings: at most 64 layers, each 0 < d ≤ 100 µm thick.** The transfer matrices grow
//!   like e^{|Im β|} only in absorbing or evanescent layers, and coating layers are real
//!   indices; the bound is physical rather than numerical: layers are treated as coherent, and
//!   beyond some 100 µm (the coherence length of light a few nm wide in the visible is tens of
//!   µm) interference fringes become finer than any sampled wavelength grid resolves, so a
//!   thicker "layer" is a slab that belongs in the geometry. 64 layers cover real dielectric
//!   mirrors and filters (tens of layers) while bounding the per-hit cost, and the layer array
//!   is fixed-size on the stack ([`crate::material::MAX_COATING_LAYERS`]).
//!
//! - **Not checked: precision far from the origin.** Positions are f32 in world coordinates,
//!   spaced M·2⁻²³ at distance M (1 unit at 10⁷), and spawned rays are offset by a few such
//!   spacings ([`crate::geometry::offset`]), so a shape small against that spacing renders
//!   wrongly and silently: a camera inside a radius-1 glass sphere (n = 1.5) at
//!   (10⁷, 10⁷, 10⁷) sees 2.20 × the background instead of n² = 2.25 (issue 37), as its
//!   internal reflections leave through the sphere. A fix that would hold is camera-relative
//!   coordinates (translating the scene by the camera position in f64 at build), which moves
//!   every render's bits and the validation references with them; until then scenes/README.md
//!   ("Limits") tells users to keep the scene near the origin.
//!
//! What the limits cannot bound (a point light a hair's breadth from a surface, I/d²; radiance
//! gains stacking over hundreds of one-sided glass exits) is caught after the render by
//! [`crate::film::Film::check_finite`], which names the pixel.

/// Largest accepted image side, in pixels.
pub const MAX_RESOLUTION: u32 = 32_768;
/// Largest accepted sample count per pixel.
pub const MAX_SPP: u32 = 1 << 20;
/// Most spectral bands an output may hold (`--spectral-bands`).
pub const MAX_SPECTRAL_BANDS: u32 = 1024;
/// Longest text of a part header's names (scene file, version, commit), in bytes.
pub const MAX_HEADER_TEXT: usize = 4096;
/// Largest accepted recursion depth (deep Whitted chains recurse on the thread stack).
pub const MAX_DEPTH: u32 = 4096;
/// Largest magnitude of a coordinate (positions, edges, mesh vertices after their transform),
/// in scene units.
pub const MAX_COORDINATE: f32 = 1e10;
/// Smallest length (sphere radius, prism sides) and smallest mesh scale factor.
pub const MIN_LENGTH: f32 = 1e-10;
/// Largest emitted radiance (W·m⁻²·sr⁻¹·nm⁻¹) or intensity (W·sr⁻¹·nm⁻¹) at any wavelength.
pub const MAX_EMISSION: f32 = 1e15;
/// Smallest index of refraction at any wavelength of 360–830 nm.
pub const MIN_IOR: f32 = 1e-2;
/// Largest index of refraction at any wavelength of 360–830 nm.
pub const MAX_IOR: f32 = 1e2;
/// Smallest `prune_below` with which any `max_depth` is accepted. Russian roulette below
/// `prune_below` keeps the expected number of branches at each depth below about
/// (total throughput)/`prune_below`; with 10⁻⁴ the nested-glass reproducer of issue 16 renders
/// in milliseconds at depth 4096, where pruning at 10⁻¹⁰ took a minute at depth 32.
pub const MIN_PRUNE_BELOW_DEEP: f32 = 1e-4;
/// Largest `max_depth` with pruning off or weaker than [`MIN_PRUNE_BELOW_DEEP`]: every dielectric
/// hit may keep both branches, so a camera sample can cost up to 2^max_depth rays (about 10⁶
/// here; the reproducer took 1 s at depth 16, 40 s at 24 and hours beyond).
pub const MAX_DEPTH_UNPRUNED: u32 = 20;
/// Largest coating layer thickness, in nm (100 µm; see the module documentation).
pub const MAX_COATING_THICKNESS_NM: f32 = 1e5;
