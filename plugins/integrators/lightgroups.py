"""``lightgroups``: a path tracer that splits the image into one layer per group of lights.

The same estimator as Mitsuba's ``path`` (unidirectional path tracing with next-event
estimation, multiple importance sampling by the power heuristic, Russian roulette), written
in Dr.Jit, that also adds every contribution to the layer of the light it came from:

* next-event estimation: the emitter the scene sampled (``ds.emitter``);
* a BSDF-sampled ray that hits an area light, or escapes to the environment: the emitter
  hit (``si.emitter(scene)``, the environment map for a ray that hits nothing);
* emission seen directly by the camera: that emitter.

So all layers come from one set of paths (one render, not one per light), and they sum to
the beauty image (up to float rounding: the beauty is accumulated separately). Each layer
is an AOV of three channels ``<group>.R``, ``<group>.G``, ``<group>.B`` in linear sRGB;
the beauty is the film's own channels as with ``path``.

Parameters
----------

====================  ========  =======  ====  ===================================================
parameter             type      default  unit  description
====================  ========  =======  ====  ===================================================
``groups``            string    --       --    required: ``name=id1,id2;name2=id3``: the groups,
                                               each a name (letters, digits, ``_``, ``-``) and the
                                               emitters in it; every emitter of the scene in exactly
                                               one group. An emitter is named by its ``id``, an
                                               emitter without one by ``emitter<k>`` (k: its index
                                               in ``scene.emitters()``), an environment emitter
                                               without one by ``environment``
``max_depth``         integer   -1       --    longest path (vertices): 1 shows the emitters
                                               seen directly, 2 direct light, -1 no limit
``rr_depth``          integer   5        --    depth from which Russian roulette may stop a
                                               path, >= 1
``hide_emitters``     boolean   false    --    emitters seen directly (area lights, environment)
                                               are not shown
``band_wavelengths``  string    --       nm    spectral variants: spectral layers, the
                                               channels ``<group>.band000``, ... instead of
                                               R, G, B: hat bands at these evenly spaced
                                               centres, as ``spectrace render --film
                                               spectral`` makes (see below)
====================  ========  =======  ====  ===================================================

Formula
-------

The estimate of the pixel's radiance along a path x0 (camera), x1, ..., with throughput
beta_k = prod f cos / pdf (divided by the Russian roulette probabilities) is

    L = sum_k beta_k [ w_bsdf L_e(x_k) + w_em f(x_k) L_e(y) cos / p_em(y) ]

with power-heuristic weights w (1 for delta lights and delta BSDF lobes), and the layer of
group g is the same sum restricted to the terms whose emitter belongs to g:
L = sum_g L_g exactly, term by term.

Colour of the layers: in RGB variants the layer is the path's RGB radiance. In spectral
variants each sample carries its own wavelengths; since Mitsuba's film stores AOVs as
given, the layer is converted to linear sRGB in the integrator, as the film converts the
beauty: the radiance times the sensor's wavelength weight (1 / ``mi.pdf_rgb_spectrum``,
the weight of Mitsuba's sensors without an ``srf``; the render refuses films with a
sensor response), then ``mi.spectrum_to_srgb`` (CIE 1931 XYZ -> linear sRGB) on the
sample's wavelengths. Mono variants: R = G = B = the
luminance. Polarized variants are refused (the throughput would be a Mueller matrix).

Spectral layers (``band_wavelengths`` c_0 < ... < c_{N-1}, spacing d): channel j of a
group's layer is the estimate of integral L(l) hat_j(l) dl, hat_j(l) = max(0, 1 - |l - c_j|
/ d) on [c_0, c_{N-1}] (half hats at the ends; the bands of
:mod:`spectrace.spectral_film`), from the sample's wavelengths and their weight:
mean over the wavelengths of L w hat_j. Mitsuba 3.9's ``specfilm`` writes its bands over
the integrator's AOVs, so these layers go on the RGB film as AOVs (its wavelength
sampling, 360-830 nm); ``spectrace.spectral_film.film_to_bands`` turns them into band
averages.

Reconstruction filter
---------------------

The film's filter is *importance sampled* (Ernst et al. 2006; pbrt-v4's and Cycles' way),
not splatted as Mitsuba's own render loop does: each sample's position in its pixel is
drawn from the filter f itself (each axis from |f|, tabulated at ``FILTER_NODES`` points,
:func:`sample_filter`) with weight f / pdf, and the sample goes to its own pixel only.
Splatting adds every channel of every sample into each pixel of the filter's footprint
(5 x 5 for hdrfilm's default ``gaussian``), so with 8 layers (24 more channels) the film
would cost more than the paths. Both estimate the same filtered image, int f(x - p) L(x)
dx / int f; with filter importance sampling the pixels' noise is also independent, as
denoisers want. A ``box`` filter is sampled exactly as Mitsuba does (uniformly in the
pixel), so the beauty equals ``path``'s with the same seed up to float rounding; with
another filter it equals ``path``'s within Monte Carlo noise. Films that develop their
own samples (``specfilm``), ``sample_border`` and the scalar variants use Mitsuba's render
loop.

Details:

* The emitter -> group lookup: an ``EmitterPtr`` is, in the JIT variants, the emitter's
  index in Mitsuba's instance registry; ``dr.reinterpret_array(mi.UInt32, ptr)`` gives it
  (0 for no emitter), and a gather from a table indexed by it gives the group. It works
  alike for Mitsuba's C++ emitters and for emitters written in Python (spectrace's
  ``pointlight``, ``spotlight``, ``ieslight``), which every emitter sample of theirs names in
  ``ds.emitter``. The table is built from ``scene.emitters()`` when the kernel is traced.
* The samples are drawn in the order of Mitsuba's ``path`` (light sample, BSDF sample,
  roulette), with its Russian roulette (from depth ``rr_depth``, survival probability
  min(max throughput * eta^2, 0.95)) and its alpha (a path is valid once it hits a surface
  that is not a null BSDF, or sees the environment).
* A scene whose integrator is ``lightgroups`` renders its layers with ``spectrace render``
  as with ``--light-groups``.
* A scene of the ``local`` integrator gets its layers from ``local`` itself
  (:class:`LocalLightGroups`, made by ``spectrace render --light-groups``): its loop over
  the lights adds each light's term to the light's group, the emission seen directly goes
  to the emitter's group, and the ambient term and fog colour form the last layer,
  ``ambient``.
* A scene of the ``illuminance`` integrator gets per-light lux layers from
  ``illuminance`` (:class:`IlluminanceLightGroups`): each light's lux (exact for delta
  lights) and its MIS companion go to the light's group, the interreflected light to
  one more layer, ``indirect``; R = G = B = the lux.

Sources
-------

Veach (1997), *Robust Monte Carlo Methods for Light Transport Simulation*, PhD thesis,
Stanford, ch. 9 (MIS, power heuristic); Ernst, Stamminger and Greiner (2006), "Filter
importance sampling", IEEE Symposium on Interactive Ray Tracing, 125-132, and Pharr, Jakob
and Humphreys (2023), *Physically Based Rendering*, 4th ed., sec. 8.8.3 (filter importance
sampling); Jakob, Speierer, Roussel et al. (2022), Mitsuba 3:
its ``path`` (C++) and ``prb`` (Python) integrators, whose sampling decisions this one
repeats in the same order, so its beauty equals ``path``'s in expectation (and, with the
same seed and a box filter, up to float rounding in the scenes tested).

Example
-------

Two groups, the key and fill lights dimmable separately, the sky its own layer::

    <integrator type="lightgroups">
        <string name="groups" value="key=lamp1,lamp2;fill=lamp3;sky=environment"/>
        <integer name="max_depth" value="6"/>
    </integrator>

``spectrace render SCENE.xml --light-groups`` builds it from the scene's ``path`` or
``direct`` integrator (see :mod:`spectrace.lightgroups`).
"""

from __future__ import annotations

import math

import drjit as dr
import mitsuba as mi
from spectrace.plugins import params

from spectrace import lightgroups
from spectrace.errors import ParameterError

PLUGIN = "lightgroups"
#: Russian roulette keeps a path with at most this probability (Mitsuba's ``path``).
RR_MAX_PROBABILITY = 0.95
#: The channel of band j of a spectral layer: ``<group>.band000``.
BAND_CHANNEL = "band{:03d}"
#: The layer of a ``local`` scene's ambient term (:class:`LocalLightGroups`).
AMBIENT_GROUP = "ambient"
#: The layer of an ``illuminance`` scene's interreflected light (:class:`IlluminanceLightGroups`).
INDIRECT_GROUP = "indirect"
#: ``max_depth`` -1: no limit (Mitsuba's convention: 2^32 - 1 vertices).
UNLIMITED_DEPTH = 0xFFFFFFFF
#: At most this many samples in one kernel (Mitsuba's limit: 2^32 - 1 lanes).
WAVEFRONT_LIMIT = 0xFFFFFFFF
#: Nodes of the tabulated reconstruction filter that filter importance sampling draws from.
FILTER_NODES = 1025


_FILTER_TABLES: dict = {}


def sample_filter(rfilter, u):
    """(offset, weight): filter importance sampling of a pixel's reconstruction filter f
    (separable, radius r). Each axis of ``offset`` (in [-r, r], from the pixel centre) is
    drawn from the 1D distribution proportional to |f|, tabulated at FILTER_NODES points
    and linearly interpolated (``mi.ContinuousDistribution``), from one coordinate of the
    uniform sample ``u``; ``weight`` = f(x) f(y) / (pdf(x) pdf(y)), constant up to the
    table's interpolation and negative in a negative lobe (Lanczos, Mitchell)."""
    key = (mi.variant(), str(rfilter))  # the filter's type and parameters
    if key not in _FILTER_TABLES:
        r = float(rfilter.radius())
        f = dr.abs(rfilter.eval(dr.linspace(mi.Float, -r, r, FILTER_NODES)))
        dr.eval(f)
        _FILTER_TABLES[key] = mi.ContinuousDistribution(mi.ScalarVector2f(-r, r), f)
    table = _FILTER_TABLES[key]
    x, pdf_x = table.sample_pdf(u.x)
    y, pdf_y = table.sample_pdf(u.y)
    weight = rfilter.eval(x) * rfilter.eval(y) / (pdf_x * pdf_y)
    return mi.Vector2f(x, y), dr.select(dr.isfinite(weight), weight, 0.0)


def _mis_weight(pdf_a, pdf_b):
    """Power heuristic pdf_a^2 / (pdf_a^2 + pdf_b^2), 0 where it is not finite."""
    a2 = dr.square(pdf_a)
    w = a2 / (a2 + dr.square(pdf_b))
    return dr.select(dr.isfinite(w), w, 0.0)


class LightGroups(mi.SamplingIntegrator):
    """Path tracer with one AOV layer per light group; see the module docstring."""

    def __init__(self, props):
        super().__init__(props)  # reads hide_emitters
        if mi.is_polarized:
            raise ParameterError(f"{PLUGIN}: polarized variants are not supported (variant "
                             f"{mi.variant()}); use the unpolarized one")
        params.read_bool(props, PLUGIN, "hide_emitters", False)  # type check only
        max_depth = params.read_int(props, PLUGIN, "max_depth", -1, minimum=-1)
        self.max_depth = UNLIMITED_DEPTH if max_depth == -1 else max_depth
        self.rr_depth = params.read_int(props, PLUGIN, "rr_depth", 5, minimum=1)
        text = params.read_string(props, PLUGIN, "groups", params.REQUIRED)
        try:
            self.groups = lightgroups.parse_groups(text)
        except ValueError as e:
            raise ParameterError(f"{PLUGIN}: parameter 'groups': {e}") from None
        self.names = list(self.groups)
        self.bands = None  # band centres (nm) of spectral layers
        text = params.read_string(props, PLUGIN, "band_wavelengths", None)
        if text is not None:
            self.bands = self._band_centres(text)

    @staticmethod
    def _band_centres(text: str) -> list[float]:
        where = f"{PLUGIN}: parameter 'band_wavelengths'"
        if not mi.is_spectral:
            raise ParameterError(f"{where} needs a spectral variant (got {mi.variant()})")
        try:
            c = [float(v) for v in text.replace(",", " ").split()]
        except ValueError:
            raise ParameterError(f"{where} must be numbers in nm (got {text!r})") from None
        steps = [b - a for a, b in zip(c, c[1:], strict=False)]
        if len(c) < 2 or not all(math.isfinite(v) and v > 0 for v in c) or not all(
                abs(d - steps[0]) <= 1e-6 * steps[0] and d > 0 for d in steps):
            raise ParameterError(f"{where} must be 2 or more evenly spaced increasing "
                             f"wavelengths in nm (got {text!r})")
        return c

    def aov_names(self):
        if self.bands is not None:
            return [f"{name}.{BAND_CHANNEL.format(j)}" for name in self.names
                    for j in range(len(self.bands))]
        return [f"{name}.{c}" for name in self.names for c in "RGB"]

    def to_string(self):
        return (f"LightGroups[max_depth={self.max_depth}, rr_depth={self.rr_depth}, "
                f"groups={self.names}]")

    # -- the emitter -> group lookup -------------------------------------------------

    def _group_table(self, scene):
        """UInt32 table: an emitter's registry index (its ``EmitterPtr`` reinterpreted)
        -> its group's index. Unlisted emitters are an error."""
        index = lightgroups.emitter_group_indices(scene, self.groups)  # in emitters() order
        ids = [int(dr.reinterpret_array(mi.UInt32, mi.EmitterPtr(e))[0])
               for e in scene.emitters()]
        table = [len(self.names)] * (max(ids, default=0) + 1)
        for i, g in zip(ids, index, strict=True):
            table[i] = g
        return mi.UInt32(table)

    # -- Mitsuba interface -----------------------------------------------------------

    def render(self, scene, sensor=0, seed=0, spp=0, develop=True, evaluate=True):
        """Mitsuba's ``SamplingIntegrator.render`` (the same wavefront, sampler calls and
        film), except that a film's reconstruction filter other than ``box`` is importance
        sampled instead of splatted (see "Reconstruction filter" in the module docstring).
        Films that develop their own samples (``specfilm``), ``sample_border`` and the
        scalar variants go to Mitsuba's own ``render``."""
        if isinstance(sensor, int):
            sensor = scene.sensors()[sensor]
        film = sensor.film()
        if (not dr.is_jit_v(mi.Float) or film.sample_border()
                or mi.has_flag(film.flags(), mi.FilmFlags.Special)):
            return super().render(scene, sensor, seed, spp, develop, evaluate)
        n_channels = film.prepare(self.aov_names())
        sampler = sensor.sampler()
        if spp:
            sampler.set_sample_count(spp)
        spp = sampler.sample_count()
        size = film.crop_size()
        pixels = int(size[0]) * int(size[1])
        per_pass = spp
        while pixels * per_pass > WAVEFRONT_LIMIT:  # Mitsuba's 2^32 samples per kernel
            per_pass = next(d for d in range(per_pass - 1, 0, -1) if spp % d == 0)
        sampler.set_samples_per_wavefront(per_pass)
        sampler.seed(seed, pixels * per_pass)
        block = mi.ImageBlock(size, film.crop_offset(), n_channels)  # one pixel a sample
        idx = dr.arange(mi.UInt32, pixels * per_pass)
        shift = per_pass.bit_length() - 1
        if per_pass == 1 << shift:
            idx >>= dr.opaque(mi.UInt32, shift)
        else:
            idx //= dr.opaque(mi.UInt32, per_pass)
        pos = mi.Vector2i()
        pos.y = mi.Int32(idx // int(size[0]))
        pos.x = mi.Int32(idx) - int(size[0]) * pos.y
        pos += mi.Vector2i(film.crop_offset())
        for i in range(spp // per_pass):
            self._render_sample(scene, sensor, sampler, block, mi.Vector2f(pos),
                                1.0 / math.sqrt(spp))
            if i + 1 < spp // per_pass:
                sampler.advance()
                sampler.schedule_state()
                dr.eval(block.tensor())
        film.put_block(block)
        result = None
        if develop:
            result = film.develop()
            dr.schedule(result)
        else:
            film.schedule_storage()
        if evaluate:
            dr.eval()
            dr.sync_thread()
        return result if develop else mi.TensorXf()

    def _render_sample(self, scene, sensor, sampler, block, pos, diff_scale):
        """One sample per wavefront lane, in the order of Mitsuba's ``render_sample``."""
        film = sensor.film()
        rfilter = film.rfilter()
        u = sampler.next_2d()
        if rfilter.is_box_filter():  # uniform in the pixel, as Mitsuba's render
            offset, weight = u, mi.Float(1.0)
        else:
            offset, weight = sample_filter(rfilter, u)
            offset += 0.5
        scale = 1.0 / mi.ScalarVector2f(film.crop_size())
        adjusted = (pos + offset - mi.ScalarVector2f(film.crop_offset())) * scale
        aperture = sampler.next_2d() if sensor.needs_aperture_sample() else mi.Point2f(0.5)
        time = mi.Float(sensor.shutter_open())
        if sensor.shutter_open_time() > 0.0:
            time += sampler.next_1d() * sensor.shutter_open_time()
        wavelength = sampler.next_1d() if mi.is_spectral else mi.Float(0.0)
        ray, ray_weight = sensor.sample_ray_differential(time, wavelength, adjusted, aperture)
        if ray.has_differentials:
            ray.scale_differential(diff_scale)
        L, valid, aovs = self.sample(scene, sampler, ray, None, True)  # no media (as path)
        L = ray_weight * L
        if mi.is_spectral:
            rgb = mi.spectrum_to_srgb(L, ray.wavelengths, True)
        elif mi.is_monochromatic:
            rgb = mi.Color3f(L[0])
        else:
            rgb = L
        values = [rgb[0], rgb[1], rgb[2]]
        if mi.has_flag(film.flags(), mi.FilmFlags.Alpha):
            values.append(dr.select(valid, 1.0, 0.0))
        values = [weight * v for v in (*values, 1.0, *aovs)]  # the last base channel: W
        block.put(pos + 0.5, values)


    def sample(self, scene, sampler, ray, medium=None, active=True):
        n_groups = len(self.names)
        zero = [mi.Spectrum(0.0) for _ in range(n_groups)]
        active = mi.Bool(active)
        if self.max_depth == 0:
            return mi.Spectrum(0.0), mi.Bool(False), self._layers(zero, ray, active)
        table = self._group_table(scene)

        def group_of(emitter, mask):
            return dr.gather(mi.UInt32, table, dr.reinterpret_array(mi.UInt32, emitter), mask)

        def add(Lg, gid, value):
            return [Lg[g] + dr.select(gid == g, value, 0.0) for g in range(n_groups)]

        bsdf_ctx = mi.BSDFContext()
        ray = mi.Ray3f(ray)
        max_depth = mi.UInt32(self.max_depth)
        rr_depth = mi.UInt32(self.rr_depth)
        pi = scene.ray_intersect_preliminary(ray, coherent=True, active=active)
        if self.hide_emitters:  # skip the area emitters a camera ray meets first
            skip = pi.is_valid() & (pi.shape.emitter() != None) & active  # noqa: E711
            si_skip = pi.compute_surface_interaction(ray, mi.RayFlags.Minimal, skip)
            pi_after = self.skip_area_emitters(scene, si_skip.spawn_ray(ray.d), True, skip)
            pi[skip] = pi_after
        valid_ray = mi.Bool(not self.hide_emitters and scene.environment() is not None)

        state = (sampler, ray, pi, mi.UInt32(0), mi.Spectrum(0.0), zero, mi.Spectrum(1.0),
                 mi.Float(1.0), active, valid_ray & active,
                 dr.zeros(mi.SurfaceInteraction3f), mi.Float(1.0), mi.Bool(True))

        def cond(sampler, ray, pi, depth, L, Lg, beta, eta, active, *rest):
            return active

        def body(sampler, ray, pi, depth, L, Lg, beta, eta, active, valid_ray,
                 si_prev, bsdf_pdf_prev, bsdf_delta_prev):
            active_next = mi.Bool(active)
            si = pi.compute_surface_interaction(ray, ray_flags=mi.RayFlags.All, active=active)
            bsdf = si.bsdf(ray)

            # emission of the surface or environment reached (MIS against NEE)
            if self.hide_emitters:
                active_next &= ~((depth == 0) & ~si.is_valid())
            ds = mi.DirectionSample3f(scene, si=si, ref=si_prev)
            em_pdf = scene.pdf_emitter_direction(si_prev, ds, ~bsdf_delta_prev & active_next)
            mis = _mis_weight(bsdf_pdf_prev, dr.select(bsdf_delta_prev, 0.0, em_pdf))
            Le = beta * mis * ds.emitter.eval(si, active_next & (bsdf_pdf_prev > 0.0))
            Le = dr.select(active_next, Le, 0.0)
            L = L + Le
            Lg = add(Lg, group_of(ds.emitter, active_next), Le)

            # next-event estimation
            active_next &= (depth + 1 < max_depth) & si.is_valid()
            active_em = active_next & mi.has_flag(bsdf.flags(), mi.BSDFFlags.Smooth)
            ds, em_weight = scene.sample_emitter_direction(si, sampler.next_2d(), True,
                                                           active_em)
            active_em &= ds.pdf != 0.0
            wo = si.to_local(ds.d)
            bsdf_value, bsdf_pdf = bsdf.eval_pdf(bsdf_ctx, si, wo, active_em)
            mis_em = dr.select(ds.delta, 1.0, _mis_weight(ds.pdf, bsdf_pdf))
            Ld = dr.select(active_em, beta * mis_em * bsdf_value * em_weight, 0.0)
            L = L + Ld
            Lg = add(Lg, group_of(ds.emitter, active_em), Ld)

            # BSDF sampling
            bs, bsdf_weight = bsdf.sample(bsdf_ctx, si, sampler.next_1d(), sampler.next_2d(),
                                          active_next)
            ray = si.spawn_ray(si.to_world(bs.wo))
            eta = eta * dr.select(active_next, bs.eta, 1.0)
            beta = beta * bsdf_weight
            valid_ray |= active & si.is_valid() & ~mi.has_flag(bs.sampled_type,
                                                               mi.BSDFFlags.Null)
            si_prev = dr.detach(si, True)
            bsdf_pdf_prev = bs.pdf
            bsdf_delta_prev = mi.has_flag(bs.sampled_type, mi.BSDFFlags.Delta)

            # Russian roulette (as Mitsuba's path: from depth rr_depth, counted after this
            # vertex), and no further vertex once the throughput is 0
            depth = dr.select(si.is_valid(), depth + 1, depth)
            beta_max = dr.max(beta)
            rr_prob = dr.minimum(beta_max * dr.square(eta), RR_MAX_PROBABILITY)
            rr_active = depth >= rr_depth
            beta = dr.select(rr_active, beta * dr.rcp(rr_prob), beta)
            rr_continue = sampler.next_1d() < rr_prob
            active = active_next & (~rr_active | rr_continue) & (beta_max != 0.0)
            pi = scene.ray_intersect_preliminary(ray, coherent=False, active=active)
            return (sampler, ray, pi, depth, L, Lg, beta, eta, active, valid_ray,
                    si_prev, bsdf_pdf_prev, bsdf_delta_prev)

        state = dr.while_loop(state, cond, body, max_iterations=self.max_depth,
                              label=PLUGIN)
        L, Lg, valid_ray = state[4], state[5], state[9]
        return (dr.select(valid_ray, L, 0.0), valid_ray,
                self._layers([dr.select(valid_ray, x, 0.0) for x in Lg], ray, active, scene))

    def _layers(self, Lg, ray, active, scene):
        """The AOV floats: linear sRGB or band values of each group's radiance (see the
        docstring)."""
        out = []
        if mi.is_spectral:  # the sensor's wavelength weight, which the film applies to L
            srf = scene.sensors()[0].film().sensor_response_function()
            if srf is None:
                pdf = mi.pdf_rgb_spectrum(ray.wavelengths)
            else:
                si = dr.zeros(mi.SurfaceInteraction3f, dr.width(ray.wavelengths))
                si.wavelengths = ray.wavelengths
                pdf = srf.pdf_spectrum(si, active)
            weight = dr.select(pdf > 0.0, dr.rcp(pdf), 0.0)
        if self.bands is not None:
            return [v for L in Lg for v in self._band_values(L * weight, ray.wavelengths)]
        for L in Lg:
            if mi.is_spectral:
                rgb = mi.spectrum_to_srgb(L * weight, ray.wavelengths, active)
            elif mi.is_monochromatic:
                rgb = mi.Color3f(L[0], L[0], L[0])
            else:
                rgb = L
            out += [rgb[0], rgb[1], rgb[2]]
        return out

    def _band_values(self, L, wavelengths):
        """specfilm's channels of the weighted radiance L: the mean over the sample's
        wavelengths of L hat_j, hat_j the band's response (peak 1, half hats at the ends)."""
        c0, step = self.bands[0], self.bands[1] - self.bands[0]
        lo, hi = self.bands[0], self.bands[-1]
        out = []
        for j in range(len(self.bands)):
            total = mi.Float(0.0)
            for i in range(len(wavelengths)):
                lam = wavelengths[i]
                hat = dr.maximum(1.0 - dr.abs(lam - (c0 + j * step)) / step, 0.0)
                hat = dr.select((lam >= lo) & (lam <= hi), hat, 0.0)
                total += L[i] * hat
            out.append(total / len(wavelengths))
        return out


class LocalLightGroups(LightGroups):
    """The layers of a scene's ``local`` integrator (not a plugin of its own:
    :func:`spectrace.lightgroups.integrator_for` makes it around the scene's ``local``).

    ``local`` sums its lights in one symbolic loop; with ``light_group_of`` set on it, that
    loop also adds each light's term to the light's group. Here the emission seen directly
    goes to the group of the emitter seen, both are multiplied by the fog fraction as
    ``local`` does, and what remains of the beauty (the ``ambient`` term, the fog colour)
    is the last layer, :data:`AMBIENT_GROUP`; so the layers sum to the beauty."""

    def __init__(self, local, groups: dict, band_wavelengths=None):
        props = mi.Properties(PLUGIN)
        props["groups"] = lightgroups.format_groups(groups)
        props["hide_emitters"] = bool(local.hide_emitters)
        if band_wavelengths is not None:
            props["band_wavelengths"] = ",".join(repr(float(w)) for w in band_wavelengths)
        super().__init__(props)
        if AMBIENT_GROUP in self.groups:
            raise ParameterError(f"{PLUGIN}: light group {AMBIENT_GROUP!r} is reserved for "
                                 "the ambient term of the local integrator")
        self.local = local
        self.names = [*self.groups, AMBIENT_GROUP]

    def to_string(self):
        return f"LocalLightGroups[{self.local.to_string()}, groups={self.names}]"

    def sample(self, scene, sampler, ray, medium=None, active=True):
        local, n_groups = self.local, len(self.groups)
        local.light_group_of = mi.UInt32(lightgroups.emitter_group_indices(scene, self.groups))
        local.light_group_count = n_groups
        try:
            L, valid, _ = local.sample(scene, sampler, ray, medium, active)
            Lg = list(local.light_layers)
        finally:
            local.light_group_of = None
        active = mi.Bool(active)
        si = scene.ray_intersect(ray, mi.RayFlags.Minimal, coherent=True, active=active)
        hit = active & si.is_valid()
        Lg = [dr.select(hit, x, 0.0) for x in Lg] or [mi.Spectrum(0.0)] * n_groups
        if not local.hide_emitters:  # the emitter seen directly: its group
            table = self._group_table(scene)
            emitter = si.emitter(scene, active)
            gid = dr.gather(mi.UInt32, table, dr.reinterpret_array(mi.UInt32, emitter), active)
            Le = emitter.eval(si, active)
            Lg = [x + dr.select(gid == g, Le, 0.0) for g, x in enumerate(Lg)]
        if local.fog != "none":
            f = local.fog_fraction(dr.select(hit, si.t, dr.largest(mi.Float)))
            Lg = [f * x for x in Lg]
        ambient = L - sum(Lg[1:], Lg[0])  # the ambient term and the fog colour
        return L, valid, self._layers([*Lg, ambient], ray, active, scene)


class IlluminanceLightGroups(LightGroups):
    """Per-light lux of a scene's ``illuminance`` integrator (not a plugin of its own:
    :func:`spectrace.lightgroups.integrator_for` makes it around the scene's
    ``illuminance``).

    Its loop over the lights adds each light's lux to the light's group (see the
    ``illuminance`` page); the interreflected light is the last layer,
    :data:`INDIRECT_GROUP`. A layer's R, G and B are all its lux, so the layers sum to the
    ``lux`` channel (the beauty is ``illuminance``'s: its grey preview, ``lux``,
    ``measured``)."""

    def __init__(self, illuminance, groups: dict):
        props = mi.Properties(PLUGIN)
        props["groups"] = lightgroups.format_groups(groups)
        super().__init__(props)
        if INDIRECT_GROUP in self.groups:
            raise ParameterError(f"{PLUGIN}: light group {INDIRECT_GROUP!r} is reserved for "
                                 "the interreflected light of the illuminance integrator")
        self.illuminance = illuminance
        self.names = [*self.groups, INDIRECT_GROUP]

    def aov_names(self):
        return [*self.illuminance.aov_names(), *super().aov_names()]

    def to_string(self):
        return f"IlluminanceLightGroups[{self.illuminance.to_string()}, groups={self.names}]"

    def sample(self, scene, sampler, ray, medium=None, active=True):
        illuminance = self.illuminance
        illuminance.light_group_of = mi.UInt32(
            lightgroups.emitter_group_indices(scene, self.groups))
        illuminance.light_group_count = len(self.groups)
        illuminance.light_group_by_pointer = self._group_table(scene)
        try:
            preview, measured, aovs = illuminance.sample(scene, sampler, ray, medium, active)
            Eg = list(illuminance.light_lux)
        finally:
            illuminance.light_group_of = illuminance.light_group_by_pointer = None
        layers = [v for E in Eg for v in [dr.select(measured, E, 0.0)] * 3]
        return preview, measured, [*aovs, *layers]


mi.register_integrator(PLUGIN, lambda props: LightGroups(props))
