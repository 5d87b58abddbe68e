"""An ideal linear retarder for Mitsuba 3, registered as the BSDF plugin "ideal_retarder": the
sheet prisma's `retarder` material describes, built from Mitsuba's own Mueller functions.

Mitsuba's `retarder` (src/bsdfs/retarder.cpp) differs from it off normal incidence in two ways:
  - it scales the retardance by |cos θ|, which prisma does not;
  - it takes the unprojected local x axis as the Stokes basis of its Mueller matrix
    (rotate_mueller_basis_collinear(M, forward, (1, 0, 0), stokes_basis(forward))), so that a
    ray tilted by θ toward the fast axis sees the plate turned by about θ: first order in θ.
    Measured on validation/scenes/stokes_polarizers.toml, a quarter-wave plate at 45° to the light's
    polarisation seen 0.6° off normal gives S1/S0 = ∓0.018 instead of 0 (translate.py's choice
    of plugin, `retarder_plugin`, shows it).
This plugin projects the fast axis (local U, the axis Mitsuba's retarder makes fast:
polarisation_conventions.py) onto the wavefront, as Mitsuba's `polarizer` does for its axes
after Korger et al. (2013), and keeps the retardance:
  forward = si.wi (radiance; -si.wi for importance), fast = normalize(U − (U·forward)·forward),
  M = rotate_mueller_basis_collinear(linear_retarder(delta), forward, fast, stokes_basis(forward)).
At normal incidence it is Mitsuba's `retarder` with theta = 0. In unpolarised variants it is
transparent, as Mitsuba's is.

Parameters:
  delta   float, degrees (default 90): the retardance; the component along local U leads.

Usage:
  import ideal_retarder  # registers "ideal_retarder" for the current variant
  {"type": "ideal_retarder", "delta": 90.0}
"""

import drjit as dr
import mitsuba as mi


class IdealRetarder(mi.BSDF):
    """See the module docstring."""

    def __init__(self, props):
        super().__init__(props)
        self.delta_deg = float(props.get("delta", 90.0))
        flags = mi.BSDFFlags.Null | mi.BSDFFlags.FrontSide | mi.BSDFFlags.BackSide
        self.m_flags = flags
        self.m_components = [flags]

    def mueller(self, forward):
        """The retarder's Mueller matrix between the implicit Stokes bases of `forward` (local)."""
        fast = mi.Vector3f(1.0, 0.0, 0.0)
        fast = dr.normalize(fast - dr.dot(fast, forward) * forward)
        m = mi.mueller.linear_retarder(mi.UnpolarizedSpectrum(dr.deg2rad(self.delta_deg)))
        return mi.mueller.rotate_mueller_basis_collinear(m, forward, fast, mi.mueller.stokes_basis(forward))

    def sample(self, ctx, si, sample1, sample2, active=True):
        bs = dr.zeros(mi.BSDFSample3f)
        bs.wo = -si.wi
        bs.pdf = mi.Float(1.0)
        bs.eta = mi.Float(1.0)
        bs.sampled_type = mi.UInt32(+mi.BSDFFlags.Null)
        bs.sampled_component = mi.UInt32(0)
        if mi.is_polarized:
            forward = si.wi if ctx.mode == mi.TransportMode.Radiance else -si.wi
            return bs, dr.select(active, self.mueller(forward), 0.0)
        return bs, dr.select(active, mi.Spectrum(1.0), 0.0)

    def eval(self, ctx, si, wo, active=True):
        return mi.Spectrum(0.0)

    def pdf(self, ctx, si, wo, active=True):
        return mi.Float(0.0)

    def eval_pdf(self, ctx, si, wo, active=True):
        return mi.Spectrum(0.0), mi.Float(0.0)

    def eval_null_transmission(self, si, active=True):
        if mi.is_polarized:
            return dr.select(active, self.mueller(si.wi), 0.0)
        return dr.select(active, mi.Spectrum(1.0), 0.0)

    def traverse(self, callback):
        pass

    def to_string(self):
        return f"IdealRetarder[delta = {self.delta_deg} deg]"


# The variant this module's class was built for (see translate.py, like whitted.VARIANT).
VARIANT = mi.variant()
mi.register_bsdf("ideal_retarder", lambda props: IdealRetarder(props))
