"""A Whitted integrator for Mitsuba 3, registered as the plugin "whitted": the quantity prisma
computes, built only from Mitsuba's own intersection, BSDFs and emitters.

Along a camera path:
- a ray that hits an area emitter adds its radiance (Mitsuba's area emitters are one-sided, as
  prisma's quad lights are); a ray that escapes adds the background (the `constant` emitter);
- a delta BSDF (mirror, dielectric) is followed by sampling it. For the dielectric Mitsuba picks
  reflection or refraction with probability equal to its Fresnel reflectance and returns weight 1
  (times the η² radiance scaling on refraction), so one sampled branch is prisma's two-branch sum
  in expectation. At most `max_depth` such bounces (prisma's `max_depth`);
- at the first non-delta surface (a diffuse one) the path ends with direct light from every
  emitter that is not infinite, one light sample each, occlusion tested with `scene.ray_test`, so
  mirrors, glass and the quads of lights block shadow rays as in prisma. The background never
  lights a diffuse surface (in Whitted's model it is not a light).

In polarised variants (mi.Spectrum is a Mueller matrix) it does what Mitsuba's `path.cpp` does:
every BSDF value, sampled or evaluated, is turned from its local frames into the implicit world
Stokes frames with `si.to_world_mueller(value, -wo, si.wi)` (light arrives along -wo and leaves
along wi), and the throughput is the product of those Mueller matrices with the newest on the
right, so that `throughput * emitted` is the Stokes vector reaching the camera along the ray
(in the frame stokes_basis(-ray.d)). Emitters are unpolarised; the diffuse BSDF depolarises.
Wrap it in Mitsuba's `stokes` integrator to get the Stokes channels in the camera's frame. In
unpolarised variants `to_world_mueller` is the identity and the products are plain, so both
modes run the same code.

Parameters:
  max_depth   int, default 16: maximum number of specular bounces, prisma's `max_depth`.

Usage:
  import whitted  # registers the plugin
  {"type": "whitted", "max_depth": 8}
"""

import drjit as dr
import mitsuba as mi


class Whitted(mi.SamplingIntegrator):
    """See the module docstring."""

    def __init__(self, props):
        super().__init__(props)
        self.max_depth = int(props.get("max_depth", 16))
        if self.max_depth < 0:
            raise ValueError("whitted: max_depth must be >= 0")

    def direct_light(self, scene, sampler, si, bsdf, active):
        """Direct light reflected toward -ray at `si` from every non-infinite emitter."""
        ctx = mi.BSDFContext()
        result = mi.Spectrum(0.0)
        for emitter in scene.emitters():
            if mi.has_flag(emitter.flags(), mi.EmitterFlags.Infinite):
                continue
            # `spec` is the emitted radiance (or intensity) over the sampling pdf in solid angle:
            # I/d² for a point light, L·cos θ_light·A/d² for a uniformly sampled rectangle; zero
            # when the sampled point faces away.
            ds, spec = emitter.sample_direction(si, sampler.next_2d(active), active)
            lit = active & (ds.pdf > 0.0)
            lit &= ~scene.ray_test(si.spawn_ray_to(ds.p), lit)
            # Mitsuba's BSDF value includes the foreshortening |cos θ| (twosided diffuse: ρ/π·cos θ
            # on the side the view ray arrives on, zero across the surface).
            wo = si.to_local(ds.d)
            f = si.to_world_mueller(bsdf.eval(ctx, si, wo, lit), -wo, si.wi)
            result += dr.select(lit, f * spec, 0.0)
        return result

    @dr.syntax
    def sample(self, scene, sampler, ray, medium=None, active=True):
        ctx = mi.BSDFContext()
        ray = mi.Ray3f(ray)
        active = mi.Bool(active)
        radiance = mi.Spectrum(0.0)
        throughput = mi.Spectrum(1.0)
        bounces = mi.UInt32(0)

        while dr.hint(active, max_iterations=self.max_depth + 1, label="Whitted"):
            si = scene.ray_intersect(ray, active)
            # An area emitter hit from its emitting side, or the background for an escaping ray
            # (si.emitter returns the scene's environment emitter for invalid interactions).
            radiance += throughput * si.emitter(scene, active).eval(si, active)
            active &= si.is_valid()

            bsdf = si.bsdf(ray)
            delta = mi.has_flag(bsdf.flags(), mi.BSDFFlags.Delta)

            # Diffuse (any non-delta BSDF): direct light, then the path ends.
            diffuse = active & ~delta
            radiance += throughput * self.direct_light(scene, sampler, si, bsdf, diffuse)

            # Specular: follow the sampled delta lobe while bounces remain.
            specular = active & delta & (bounces < self.max_depth)
            bs, weight = bsdf.sample(ctx, si, sampler.next_1d(specular), sampler.next_2d(specular), specular)
            weight = si.to_world_mueller(weight, -bs.wo, si.wi)
            # The newest interaction on the right (a Mueller product in polarised variants).
            throughput = dr.select(specular, throughput * weight, throughput)
            ray[specular] = si.spawn_ray(si.to_world(bs.wo))
            bounces[specular] += 1
            active = specular & dr.any(mi.unpolarized_spectrum(throughput) != 0.0)

        return radiance, mi.Bool(True), []

    def aov_names(self):
        return []

    def to_string(self):
        return f"Whitted[max_depth={self.max_depth}]"


# The variant this module's class was built for (see translate.whitted_integrator).
VARIANT = mi.variant()
mi.register_integrator("whitted", lambda props: Whitted(props))
