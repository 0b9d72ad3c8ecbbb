/* lighting_trace.c - the trace of one pixel: run it through the pass's dispatch with a trace
 * (lighting_trace.h), and print what it recorded, sample by sample, for `softlight trace`. */

#include <math.h>
#include <string.h>

#include "lighting_trace.h"

bool sl_lighting_trace_pixel(const sl_lighting_uniforms *u, const sl_gbuffer *gb, int x, int y,
                             sl_lighting_trace *trace, sl_error *err)
{
    if (!gb || !gb->texels || x < 0 || y < 0 || x >= gb->width || y >= gb->height)
        return sl_fail(err, SL_ERR_RANGE, "trace: pixel %d,%d outside the %dx%d image", x, y, gb ? gb->width : 0,
                       gb ? gb->height : 0);
    memset(trace, 0, sizeof *trace);
    trace->x = x;
    trace->y = y;
    trace->extra = gb->extra != NULL;
    sl_lighting_shade(u, gb, x, gb->height - 1 - y, NULL, trace);
    /* each light's visibility as the shading looked it up: at the texel's position, with the
     * normal it shaded with */
    if (u->shadowMaps && trace->covered && !trace->program && u->uPointLights != 0) {
        trace->shadow_lights = u->uLightCount;
        for (int i = 0; i < u->uLightCount; i++)
            trace->light_visibility[i] = sl_shadow_point_visibility(u->shadowMaps, i, trace->texel.position, trace->N);
    }
    if (u->envLightShadows != 0 && trace->covered && !trace->program) {
        const sl_shadow_suns *m = u->envShadowMaps;
        trace->env_shadow_lights = u->uEnvLightCount;
        for (int j = 0; j < u->uEnvLightCount; j++) {
            int k = m->env_light_sun[j];
            trace->env_light_map[j] = (signed char)k;
            trace->env_light_visibility[j] = sl_shadow_sun_visibility(m, k, trace->texel.position, trace->N);
        }
    }
    if (u->skyMaps && trace->covered && !trace->program) {
        trace->sky_maps = u->skyMaps->count;
        trace->sky_visibility =
            sl_shadow_sky_visibility(u->skyMaps, trace->texel.position, trace->N, trace->sky_map_visibility);
    }
    return true;
}

static void print3(FILE *f, const char *name, vec3 v)
{
    fprintf(f, "  %-12s (%.6g, %.6g, %.6g)\n", name, (double)v.x, (double)v.y, (double)v.z);
}

/* Another program's trace: the texel it saw and what it returned. */
static void print_program(FILE *f, const sl_lighting_trace *t)
{
    fprintf(f, "lighting program %s\n", t->program);
    fprintf(f, "G-buffer texel%s\n", t->covered ? "" : " (no geometry: the program shades the background)");
    print3(f, "position", t->texel.position);
    print3(f, "normal", t->texel.normal);
    print3(f, "kd", t->texel.kd);
    print3(f, "ks", t->texel.ks);
    fprintf(f, "  %-12s %.6g\n  %-12s %.9g\n", "alpha", (double)t->texel.alpha, "depth", (double)t->texel.depth);
    if (t->extra)
        fprintf(f, "  %-12s %.6g\n", "occlusion", (double)t->extra_texel.occlusion);
    if (t->extra)
        print3(f, "emissive", t->extra_texel.emissive);
    fprintf(f, "result\n");
    print3(f, "returned", t->program_result);
    print3(f, "total", t->total);
    if (t->repaired)
        fprintf(f, "  a NaN/Inf was replaced by magenta (1, 0, 1)\n");
}

/* A sample whose contribution went to the part across the horizon (sky maps) says so after its sum. */
#define ACROSS(s) ((s)->across ? " across the horizon" : "")

/* A sample in an env-light map's glow (c times the map's visibility) says which, after that. */
static const char *glow_mark(const sl_lighting_trace_sample *s)
{
    static const char *const marks[] = {"", " in map 0's glow", " in map 1's glow", " in map 2's glow",
                                        " in map 3's glow"};
    _Static_assert(SL_SHADOW_SUN_MAX == 4, "a mark per map");
    return s->glow > 0 && s->glow <= SL_SHADOW_SUN_MAX ? marks[s->glow] : "";
}

/* Why a sample adds no BRDF term: below N's horizon, under the pixel's facet (the surface hides
 * it), or its microfacet faces away. */
static const char *unlit_reason(const sl_lighting_trace_sample *s)
{
    return s->wN <= 0.0f ? "below the horizon" : s->hidden ? "under the facet" : "facet faces away";
}

/* One MIS sample: its strategy's density, the other's, the power heuristic's weight, and what
 * it added (0 below the horizon, under the facet or for a facet facing away: unlit_reason). cv
 * (cvmis): every sample drawn adds the kernel's term too, K/p its kernel over its own density;
 * below the horizon that term alone. */
static void print_mis_sample(FILE *f, int k, const char *kind, const sl_lighting_trace_sample *s, bool cv)
{
    fprintf(f, "  %4d %-4s (%.5f,%.5f) (%+.5f,%+.5f,%+.5f) %+-8.4f", k, kind, (double)s->xi.x, (double)s->xi.y,
            (double)s->w.x, (double)s->w.y, (double)s->w.z, (double)s->wN);
    bool unlit = s->wN <= 0.0f || s->hidden || s->LdotH <= 0.0f || s->NdotH <= 0.0f;
    if (unlit && !(cv && s->pdf > 0.0f)) {
        fprintf(f, " %s: 0\n", unlit_reason(s));
        return;
    }
    if (unlit) {
        fprintf(f, " %-10.4g %-10.4g %-8.5f %s: the kernel's term alone, Li (%.4g,%.4g,%.4g) (%.4g,%.4g,%.4g)"
                   " sum (%.5g,%.5g,%.5g)%s%s\n       K/p %.6g\n",
                (double)s->pdf, (double)s->pdf_other, (double)s->mis,
                unlit_reason(s), (double)s->Li.x, (double)s->Li.y,
                (double)s->Li.z, (double)s->c.x, (double)s->c.y, (double)s->c.z, (double)s->sum.x, (double)s->sum.y,
                (double)s->sum.z, ACROSS(s), glow_mark(s), (double)s->cv_kp);
        return;
    }
    fprintf(f, " %-10.4g %-10.4g %-8.5f %-10.4g %-8.4g (%.4f,%.4f,%.4f) (%.4g,%.4g,%.4g) (%.4g,%.4g,%.4g)"
               " sum (%.5g,%.5g,%.5g)%s%s\n",
            (double)s->pdf, (double)s->pdf_other, (double)s->mis, (double)s->D, (double)s->G, (double)s->F.x,
            (double)s->F.y, (double)s->F.z, (double)s->Li.x, (double)s->Li.y, (double)s->Li.z, (double)s->c.x,
            (double)s->c.y, (double)s->c.z, (double)s->sum.x, (double)s->sum.y, (double)s->sum.z, ACROSS(s),
            glow_mark(s));
    if (cv)
        fprintf(f, "       K/p %.6g\n", (double)s->cv_kp);
}

/* The MIS estimator's samples: per pair k its BRDF sample, then its environment sample. */
static void print_mis(FILE *f, const sl_lighting_trace *t)
{
    fprintf(f,
            "specular samples (MIS, %d pairs: a BRDF sample drawn as the microfacet estimator's and an env "
            "sample from the environment distribution, power heuristic, level-0 texels, sum over both / N; %s)\n",
            t->sample_count, t->plain ? "plain port" : "batched path (the port's own loop)");
    fprintf(f, "  %4s %-4s %-17s %-26s %-8s %-10s %-10s %-8s %-10s %-8s %-26s %-26s %-26s\n", "k", "from", "xi", "w",
            "w.N", "p (own)", "p (other)", "weight", "D", "G", "F", "Li", "contribution");
    for (int k = 0; k < t->sample_count; k++) {
        print_mis_sample(f, k, "brdf", &t->samples[k], t->cv);
        print_mis_sample(f, k, "env", &t->env_samples[k], t->cv);
    }
}

void sl_lighting_trace_print(FILE *f, const sl_lighting_trace *t)
{
    if (t->program) {
        print_program(f, t);
        return;
    }
    fprintf(f, "pixel %d,%d (row 0 = top); gl_FragCoord (%.1f, %.1f)\n", t->x, t->y, (double)t->frag_coord.x,
            (double)t->frag_coord.y);
    if (!t->covered) {
        fprintf(f, "  no geometry (depth %.6g): environment at lod 0\n", (double)t->texel.depth);
        print3(f, "background", t->background);
        print3(f, "total", t->total);
        return;
    }
    fprintf(f, "G-buffer texel\n");
    print3(f, "position", t->texel.position);
    print3(f, "normal", t->texel.normal);
    print3(f, "kd", t->texel.kd);
    print3(f, "ks", t->texel.ks);
    fprintf(f, "  %-12s %.6g (used %.6g)\n  %-12s %.9g\n", "alpha", (double)t->texel.alpha, (double)t->alpha, "depth",
            (double)t->texel.depth);
    if (sl_lobe_is_ggx(t->alpha)) /* the lobe parameter's GGX range (raster/gbuffer.h) */
        fprintf(f, "  %-12s GGX, roughness r = %.6g, a^2 = %.6g (G: height-correlated Smith)\n", "lobe",
                (double)(-1.0f - t->alpha), (double)sl_ggx_a2(t->alpha));
    fprintf(f, "  %-12s estimator %s, lod %s%s%s\n", "sampling", sl_estimator_name((sl_estimator)t->estimator),
            sl_lod_rule_name((sl_lod_rule)t->lod_rule), t->distortion ? ", distortion" : "",
            t->set_own ? " (the GGX set's own; the Phong set's differ)" : "");
    fprintf(f, "frame (world)\n");
    print3(f, "V", t->V);
    print3(f, "N", t->N);
    fprintf(f, "  %-12s %s\n", "bent normal", t->bent ? "yes (N.V < 0.01)" : "no");
    fprintf(f, "frame (environment)\n");
    print3(f, "N", t->Nenv);
    print3(f, "V", t->Venv);
    fprintf(f, "  %-12s %.6g\n", "N.V", (double)t->NdotV);
    fprintf(f, "  %-12s (%.8f, %.8f)%s\n", "xi rotation", (double)t->rotation.x, (double)t->rotation.y,
            t->rotation.x == 0.0f && t->rotation.y == 0.0f ? " (off)" : "");
    print3(f, "R", t->R);
    print3(f, "A", t->A);
    print3(f, "B", t->B);
    const char *axis = t->microfacet ? "N" : "R";
    fprintf(f, "  %-12s %s (frame about %s)\n", "A axis", t->pole_frame ? "X (axis near a pole)" : "Z", axis);
    if (t->splitsum)
        fprintf(f,
                "%s (%s)\n  %-12s %.6g\n  %-12s %.6g\n  %-12s A %.6g (times Ks), B %.6g, t %.6g\n"
                "  %-12s (%.6g, %.6g, %.6g) (normalize(mix(N, R, t)))\n  %-12s (%.6g, %.6g, %.6g)\n",
                t->cv ? "control variate: the split sum's lookup" : "split sum: no samples",
                t->plain ? "plain port" : "batched path", "width r", (double)t->splitsum_width, "lod",
                (double)t->splitsum_lod, "table", (double)t->splitsum_ab.x, (double)t->splitsum_ab.y,
                (double)t->splitsum_ab.z, "lookup dir", (double)t->splitsum_dir.x, (double)t->splitsum_dir.y,
                (double)t->splitsum_dir.z, "prefiltered", (double)t->splitsum_prefiltered.x,
                (double)t->splitsum_prefiltered.y, (double)t->splitsum_prefiltered.z);
    if (t->cv)
        fprintf(f,
                "  %-12s levels %d and %d, shares %.6g and %.6g (0: a level that is not exact)\n"
                "  %-12s %.6g\n  %-12s (%.6g, %.6g, %.6g) (Ks A + B)\n"
                "  %-12s (%.6g, %.6g, %.6g) (beta E (ca C_a + cb C_b), times the intensity)\n"
                "  %-12s (%.6g, %.6g, %.6g) (1/N sum (F W - beta E K / p) Li: each sample's contribution"
                " below is its term, K/p its kernel over its density)\n",
                "exact part", t->cv_levels.la, t->cv_levels.lb, (double)t->cv_levels.ca, (double)t->cv_levels.cb,
                "beta", (double)t->cv_beta, "E", (double)t->cv_E.x, (double)t->cv_E.y, (double)t->cv_E.z, "closed part",
                (double)t->cv_closed.x, (double)t->cv_closed.y, (double)t->cv_closed.z, "correction",
                (double)t->cv_correction.x, (double)t->cv_correction.y, (double)t->cv_correction.z);
    if (t->mis)
        print_mis(f, t);
    else if (!t->splitsum || t->cv)
        fprintf(f, "specular samples (N = %d; %s; %s)\n", t->sample_count,
            !t->microfacet              ? "directions drawn about R"
            : sl_lobe_is_ggx(t->alpha) ? "microfacet estimator: H drawn from GGX's visible normals about N, w = "
                                         "reflect(-V, H), L.H = V.H, p(w) = D / (2 (N.V + sqrt((N.V)^2 (1 - a^2) + a^2)))"
                                       : "microfacet estimator: H drawn about N, w = reflect(-V, H), L.H = V.H",
            t->plain ? "plain port" : "batched path: lod and uv by core/fast_math.h, 4 partial sums");
    if (!t->mis)
        fprintf(f, "  %4s %-17s %-26s %-9s %-26s %-8s %-26s %-8s %-10s %-8s %-26s %-8s %-26s %-26s\n", "k", "xi",
            t->microfacet ? "H (about +Z)" : "L (skewed)", "p(w)", "w", "w.N", "H", t->microfacet ? "V.H" : "L.H", "D",
            "G", "F", "lod", "Li", "contribution");
    for (int k = 0; !t->mis && k < t->sample_count; k++) {
        const sl_lighting_trace_sample *s = &t->samples[k];
        fprintf(f, "  %4d (%.5f,%.5f) (%+.5f,%+.5f,%+.5f) %-9.4g (%+.5f,%+.5f,%+.5f) %+-8.4f", k, (double)s->xi.x,
                (double)s->xi.y, (double)s->L.x, (double)s->L.y, (double)s->L.z, (double)s->pdf, (double)s->w.x,
                (double)s->w.y, (double)s->w.z, (double)s->wN);
        if (t->microfacet && s->LdotH <= 0.0f) {
            fprintf(f, " V.H %+.5f <= 0 (facet faces away): 0\n", (double)s->LdotH);
            continue;
        }
        const bool unlit = s->wN <= 0.0f || s->hidden;
        if (unlit && !t->cv) {
            fprintf(f, " %s: 0\n", unlit_reason(s));
            continue;
        }
        if (unlit) { /* cv: the kernel reaches below the horizon and under the facet, the BRDF does not */
            fprintf(f, " %s: the kernel's term alone, lod %.4f Li (%.4g,%.4g,%.4g) (%.4g,%.4g,%.4g)"
                       " sum (%.5g,%.5g,%.5g)%s%s\n       K/p %.6g\n",
                    unlit_reason(s), (double)s->lod, (double)s->Li.x, (double)s->Li.y, (double)s->Li.z, (double)s->c.x,
                    (double)s->c.y, (double)s->c.z, (double)s->sum.x, (double)s->sum.y, (double)s->sum.z, ACROSS(s),
                    glow_mark(s), (double)s->cv_kp);
            continue;
        }
        fprintf(f,
                " (%+.5f,%+.5f,%+.5f) %-8.5f %-10.4g %-8.4g (%.4f,%.4f,%.4f) %-8.4f (%.4g,%.4g,%.4g) (%.4g,%.4g,%.4g)"
                " sum (%.5g,%.5g,%.5g)%s%s\n",
                (double)s->H.x, (double)s->H.y, (double)s->H.z, (double)s->LdotH, (double)s->D, (double)s->G,
                (double)s->F.x, (double)s->F.y, (double)s->F.z, (double)s->lod, (double)s->Li.x, (double)s->Li.y,
                (double)s->Li.z, (double)s->c.x, (double)s->c.y, (double)s->c.z, (double)s->sum.x,
                (double)s->sum.y, (double)s->sum.z, ACROSS(s), glow_mark(s));
        if (t->cv)
            fprintf(f, "       K/p %.6g\n", (double)s->cv_kp);
    }
    fprintf(f, "result\n");
    print3(f, "irradiance", t->irradiance);
    print3(f, "diffuse", t->diffuse);
    print3(f, "specular", t->specular);
    if (t->env_light_count > 0)
        fprintf(f, "  %-12s (%.6g, %.6g, %.6g): the exact part from %d env lights (in specular; the samples read the residual)\n",
                "env lights", (double)t->env_lights.x, (double)t->env_lights.y, (double)t->env_lights.z,
                t->env_light_count);
    if (t->env_lights_split > 0)
        fprintf(f, "  %-12s %d near the lobe's peak read over cells of their texel (at most %d cells)\n", "",
                t->env_lights_split, t->env_light_cells);
    for (int j = 0; j < t->env_shadow_lights; j++) {
        char name[32];
        snprintf(name, sizeof name, "env light %d", j);
        if (t->env_light_map[j] < 0)
            fprintf(f, "  %-12s no shadow map (outside the mapped clusters): visibility 1\n", name);
        else
            fprintf(f, "  %-12s shadow map %d: visibility %.4g\n", name, t->env_light_map[j],
                    (double)t->env_light_visibility[j]);
    }
    if (t->sky_maps > 0) {
        fprintf(f, "  %-12s %.6g (the sky visibility maps' V, in irradiance; each map's v:", "sky vis",
                (double)t->sky_visibility);
        for (int k = 0; k < t->sky_maps; k++)
            if (t->sky_map_visibility[k] < 0.0f)
                fprintf(f, " -");
            else
                fprintf(f, " %.2f", (double)t->sky_map_visibility[k]);
        fprintf(f, ")\n");
    }
    if (t->horizon)
        fprintf(f,
                "  %-12s (%.6g, %.6g, %.6g): the samples across the horizon from R, their luminous direction "
                "(%.5f, %.5f, %.5f) in map %d's cell, visibility %.4g: (%.6g, %.6g, %.6g) in specular, added after "
                "its occlusion\n",
                "across", (double)t->horizon_part.x, (double)t->horizon_part.y, (double)t->horizon_part.z,
                (double)t->horizon_dir.x, (double)t->horizon_dir.y, (double)t->horizon_dir.z, t->horizon_cell,
                (double)t->horizon_visibility, (double)t->horizon_visible.x, (double)t->horizon_visible.y,
                (double)t->horizon_visible.z);
    if (t->extra && !t->cone)
        fprintf(f, "  %-12s %.6g (scales diffuse and specular, not lights)\n", "occlusion", (double)t->occlusion);
    if (t->cone) { /* the ambient occlusion's cone (--ao-radius): each term its own factor */
        fprintf(f, "  %-12s %.6g (the material's times the AO; scales the diffuse, not lights)\n", "occlusion",
                (double)t->occlusion);
        fprintf(f, "  %-12s %.6g (the ambient occlusion alone: the cone's cosine-weighted share)\n", "ao", (double)t->ao);
        fprintf(f, "  %-12s (%.5f, %.5f, %.5f) (the visibility cone's axis, world space; cone half-angle %.2f deg)\n",
                "bent normal", (double)t->cone_axis.x, (double)t->cone_axis.y, (double)t->cone_axis.z,
                (double)(acosf(sqrtf(fmaxf(0.0f, 1.0f - t->ao))) * (180.0f / SL_PI)));
        fprintf(f, "  %-12s %.6g (scales the specular: the material's occlusion times the lobe's share in the cone%s)\n",
                "spec occl", (double)t->specular_occlusion, t->reflection ? ", joined with the reflection's" : "");
        if (t->cone_across > 0.0f)
            fprintf(f, "  %-12s %.6g (the share of the cone's occlusion across the horizon from R, left to the sky maps:"
                       " the cone's AO opened by it for the specular)\n",
                    "cone across", (double)t->cone_across);
        if (t->lobe_map >= 0.0f)
            fprintf(f, "  %-12s %.6g (the specular's factor before the sky map of R's cell, which lowered it to spec occl)\n",
                    "lobe map", (double)t->lobe_map);
    }
    if (t->reflection) { /* the reflection occlusion (--reflection-occlusion) */
        static const char *const member[SL_REFLECTION_MEMBERS] = {
            "texel",   "x+1",     "x-1",   "y+1",   "y-1",   "x+1,y+1", "x-1,y+1",
            "x+1,y-1", "x-1,y-1", "own+1", "own+2", "own+3", "own+4"};
        fprintf(f, "  %-12s %.6g (the share of open rays over the texel's block, each weighted by its cosine,"
                   " with the texel's own other rays own+1 .. own+4 where the block counts fewer than %d;"
                   " %d rays; ",
                "reflection", (double)t->reflection_visibility, SL_REFLECTION_LONE, t->reflection_count);
        if (t->cone) /* sl_reflection_specular_factor's weight */
            fprintf(f, "the rays alone weigh %.6g against the smaller factor:",
                    (double)sl_reflection_rays_weight((float)t->reflection_count));
        else
            fprintf(f, "scales the specular:");
        for (int m = 0; m < SL_REFLECTION_MEMBERS; m++)
            if (m >= SL_REFLECTION_BLOCK && !t->reflection_used[m] && t->reflection_rays[m] >= 0.0f)
                continue; /* an own ray not traced: the block counts enough */
            else if (t->reflection_used[m])
                fprintf(f, " %s %s %.3g", member[m],
                        t->reflection_rays[m] > 0.5f                 ? "open"
                        : t->reflection_rays[m] == SL_REFLECTION_INTO ? "into its surface"
                                                                      : "blocked",
                        (double)t->reflection_weights[m]);
            else if (t->reflection_rays[m] < 0.0f)
                fprintf(f, " %s below", member[m]);
            else
                fprintf(f, " %s -", member[m]);
        fprintf(f, ")\n");
        if (t->facet)
            fprintf(f, "  %-12s (%g, %g, %g) (the drawn triangle's normal, world space: the samples and rays under "
                       "its horizon are left out)\n",
                    "facet", (double)t->facet_normal.x, (double)t->facet_normal.y, (double)t->facet_normal.z);
    }
    print3(f, "lights", t->lights);
    for (int i = 0; i < t->shadow_lights; i++) {
        char name[32];
        snprintf(name, sizeof name, "light %d", i);
        fprintf(f, "  %-12s (%.6g, %.6g, %.6g): shadow-map visibility %.4g\n", name, (double)t->light[i].x,
                (double)t->light[i].y, (double)t->light[i].z, (double)t->light_visibility[i]);
    }
    if (t->extra)
        print3(f, "emissive", t->emissive);
    print3(f, "total", t->total);
    if (t->repaired)
        fprintf(f, "  a NaN/Inf was replaced by 0\n");
}
