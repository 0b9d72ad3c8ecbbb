/* test_hardcases.c - the numerical hard cases of the lighting shader (docs/conventions.md
 * "Errata", docs/lighting.md "Hard cases"), each its own test: finite values always, the ground truth where one exists,
 * and for whole images no isolated black or white speckles (luminance below 0.2x or above 5x
 * the 3x3 median). The microfacet estimator has its own frame (about N) and skips, so it meets
 * each case again (test_microfacet_*). */
#include "shading_fixtures.h"
#include "shading/lighting_trace.h"
#include "shading/brdf.h"
#include "post/tonemap.h"

#include <float.h>
#include <stdio.h>

/* Shared: a constant environment (shader) and its ground truth (512x256, fine enough for the
 * lobes used here). */
typedef struct {
    sl_env env, big;
    sl_ground_truth gt;
} furnace;

static int furnace_setup(void **state)
{
    furnace *f = calloc(1, sizeof *f);
    fx_env(&f->env, 64, 32, fx_const_one);
    fx_env(&f->big, 512, 256, fx_const_one);
    sl_error err;
    if (!sl_ground_truth_init(&f->gt, &f->big, &err))
        return -1;
    *state = f;
    return 0;
}

static int furnace_teardown(void **state)
{
    furnace *f = *state;
    sl_ground_truth_free(&f->gt);
    sl_env_free(&f->env);
    sl_env_free(&f->big);
    free(f);
    return 0;
}

static sl_lighting_options consistent(int n)
{
    return (sl_lighting_options){.samples = n, .estimator = SL_ESTIMATOR_CONSISTENT, .no_diffuse = true};
}

/* R parallel to +Z or -Z: Z x R vanishes, the frame switches to X x R. The surface is seen
 * head-on, so the consistent estimator converges (alpha 1) and must meet the truth; the spec
 * estimator must be finite and positive. A direction a hair off the pole uses the Z frame and
 * must agree with the pole within the sampling noise (1%). */
static void test_reflection_along_z(void **state)
{
    furnace *f = *state;
    const vec3 normals[] = {vec3(0, 0, 1), vec3(0, 0, -1)};
    for (int i = 0; i < 2; i++) {
        vec3 n = normals[i];
        sl_lighting_uniforms *u = fx_uniforms(&f->env, NULL, consistent(256), scale(n, 10.0f), 1, 1);
        sl_gbuffer_texel t = fx_texel(n, vec3s(0), vec3s(0.5f), 1.0f);
        vec3 c = fx_shade(u, t);
        assert_true(fx_finite3(c));
        assert_near(c.x, fx_truth(&f->gt, n, n, t, false, true), 5e-3);
        /* a hair off the pole: |R.xy|^2 = 4e-6 > POLE_EPS = 1e-6 */
        vec3 n2 = normalize(vec3(0.002f, 0, n.z));
        sl_lighting_uniforms *u2 = fx_uniforms(&f->env, NULL, consistent(256), scale(n2, 10.0f), 1, 1);
        sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
        t.normal = n2;
        sl_lighting_trace *tr = malloc(sizeof *tr);
        assert_true(sl_lighting_trace_pixel(u2, &gb, 0, 0, tr, NULL));
        assert_false(tr->pole_frame);
        assert_near(tr->total.x, c.x, 0.01 * c.x);
        t.normal = n;
        assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, NULL));
        assert_true(tr->pole_frame);
        assert_near(length(tr->A), 1.0, 1e-6);
        assert_near(dot(tr->A, tr->R), 0.0, 1e-6);
        free(tr);
        free(u);
        free(u2);
        /* spec estimator, default options */
        sl_lighting_uniforms *us = fx_uniforms(&f->env, NULL, (sl_lighting_options){.no_diffuse = true},
                                               scale(n, 10.0f), 1, 1);
        vec3 s = fx_shade(us, fx_texel(n, vec3s(0), vec3s(0.5f), 50.0f));
        assert_true(fx_finite3(s) && s.x > 0.0f);
        free(us);
    }
}

/* N.V <= 0 (interpolated normals facing away): the normal is bent to N.V = 0.01 (a zero
 * normal becomes V). Values stay finite and non-negative, N = -V shades like N = V (bent all
 * the way), and the pass counts the bent normals. */
static void test_normal_facing_away(void **state)
{
    furnace *f = *state;
    sl_irradiance irr;
    sl_error err;
    assert_true(sl_irradiance_sh9(&irr, &f->env, &err));
    vec3 eye = vec3(0, 0, 10);
    sl_lighting_uniforms *u = fx_uniforms(&f->env, &irr, (sl_lighting_options){0}, eye, 4, 1);
    sl_gbuffer_texel t[4] = {
        fx_texel(vec3(1, 0, 0), vec3s(0.5f), vec3s(0.04f), 10.0f),                /* N.V = 0 */
        fx_texel(normalize(vec3(1, 0, -0.5f)), vec3s(0.5f), vec3s(0.04f), 10.0f), /* N.V < 0 */
        fx_texel(vec3(0, 0, -1), vec3s(0.5f), vec3s(0.04f), 10.0f),               /* N = -V */
        fx_texel(vec3(0, 0, 0), vec3s(0.5f), vec3s(0.04f), 10.0f),                /* zero normal */
    };
    sl_gbuffer gb = {.width = 4, .height = 1, .texels = t};
    sl_image out = {0};
    sl_lighting_stats st;
    assert_true(sl_lighting_pass(u, &st, &gb, &out, 1, &err));
    for (int i = 0; i < 4; i++) {
        float *p = sl_image_pixel(&out, i, 0);
        assert_true(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]));
        assert_true(p[0] >= 0.0f && p[1] >= 0.0f && p[2] >= 0.0f);
    }
    assert_int_equal(st.bent_normals, 3); /* the zero normal is not "bent": it becomes V */
    assert_int_equal(st.nonfinite, 0);
    vec3 facing = fx_shade(u, fx_texel(vec3(0, 0, 1), vec3s(0.5f), vec3s(0.04f), 10.0f));
    assert_near(sl_image_pixel(&out, 2, 0)[0], facing.x, 1e-6);
    assert_near(sl_image_pixel(&out, 3, 0)[0], facing.x, 1e-6);
    sl_image_free(&out);
    free(u);
    sl_irradiance_free(&irr);
}

/* Samples below the horizon (w.N <= 0) contribute exactly 0: at grazing view with alpha 0,
 * about half the lobe lies below. Checked sample by sample in the trace. */
static void test_samples_below_horizon(void **state)
{
    furnace *f = *state;
    vec3 v = fx_view_dir(0.02f, 0.4f);
    sl_lighting_uniforms *u = fx_uniforms(&f->env, NULL, (sl_lighting_options){.no_diffuse = true}, scale(v, 10.0f), 1, 1);
    sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.04f), 0.0f);
    sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, NULL));
    int below = 0;
    vec3 prev = vec3s(0);
    for (int k = 0; k < tr->sample_count; k++) {
        const sl_lighting_trace_sample *s = &tr->samples[k];
        if (s->wN <= 0.0f) {
            below++;
            assert_near(s->c.x, 0.0, 0.0);
            assert_near(s->sum.x, prev.x, 0.0); /* the running sum did not move */
        } else {
            assert_true(s->c.x >= 0.0f && isfinite(s->c.x));
            prev = s->sum;
        }
    }
    assert_true(below > tr->sample_count / 4);
    assert_true(isfinite(tr->total.x) && tr->total.x > 0.0f);
    free(tr);
    free(u);
}

/* alpha = 0 (uniform lobe) and 1e6 (pow underflow; lod < 0 clamps to 0), and beyond (clamped to
 * 1e7). At alpha 1e6 head-on every sample is w = R, so the spec estimator gives exactly
 * Ks L / 4 (test_shading's bias (b)) and every lod is 0. */
static void test_alpha_extremes(void **state)
{
    furnace *f = *state;
    const float alphas[] = {0.0f, 1e6f, 1e20f, INFINITY};
    for (int i = 0; i < 4; i++) {
        vec3 v = fx_view_dir(i == 0 ? 0.5f : 1.0f, 0);
        sl_lighting_uniforms *u = fx_uniforms(&f->env, NULL, (sl_lighting_options){.no_diffuse = true}, scale(v, 10.0f), 1, 1);
        sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.5f), alphas[i]);
        sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
        sl_lighting_trace *tr = malloc(sizeof *tr);
        assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, NULL));
        assert_true(fx_finite3(tr->total));
        assert_false(tr->repaired);
        for (int k = 0; k < tr->sample_count; k++) {
            if (tr->samples[k].wN <= 0.0f)
                continue;
            assert_true(tr->samples[k].lod >= 0.0f && tr->samples[k].lod <= u->uEnvMaxLod);
            if (i > 0)
                assert_near(tr->samples[k].lod, 0.0, 0.0);
        }
        if (i == 0) {
            double truth = fx_truth(&f->gt, vec3(0, 0, 1), v, t, false, true);
            assert_true(tr->total.x > 0.3 * truth && tr->total.x < truth); /* spec bias: about 1/2 */
        } else {
            assert_near(tr->total.x, 0.5 / 4.0, 1e-4);
        }
        free(tr);
        free(u);
    }
}

static sl_lighting_options microfacet(int n)
{
    return (sl_lighting_options){.samples = n, .estimator = SL_ESTIMATOR_MICROFACET, .no_diffuse = true};
}

/* The microfacet estimator's frame is about N: N parallel to +-Z takes the X x N frame (both
 * paths); seen head-on it meets the ground truth (alpha 1, N = 256; tolerance 1e-3, measured
 * 2e-5 in test_shading), and a hair off the pole agrees with the pole (1e-3). R parallel to +Z
 * with N tilted by 30 degrees (the spec estimators' pole case) is an ordinary frame here: it
 * must meet the truth as well (alpha 10; tolerance 1%, measured 5e-4). */
static void test_microfacet_poles(void **state)
{
    furnace *f = *state;
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    const vec3 normals[] = {vec3(0, 0, 1), vec3(0, 0, -1)};
    for (int i = 0; i < 2; i++)
        for (int plain = 0; plain < 2; plain++) {
            vec3 n = normals[i];
            sl_lighting_options o = microfacet(256);
            o.plain = plain;
            sl_lighting_uniforms *u = fx_uniforms(&f->env, NULL, o, scale(n, 10.0f), 1, 1);
            sl_gbuffer_texel t = fx_texel(n, vec3s(0), vec3s(0.5f), 1.0f);
            sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
            assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, NULL));
            assert_true(tr->pole_frame && tr->microfacet);
            assert_near(dot(tr->A, n), 0.0, 1e-6);
            assert_near(length(tr->B), 1.0, 1e-6);
            double truth = fx_truth(&f->gt, n, n, t, false, true);
            print_message("mf, N = %+.0f Z head-on: %.4g vs truth %.4g\n", (double)n.z, (double)tr->total.x, truth);
            assert_near(tr->total.x, truth, 1e-3 * truth);
            vec3 n2 = normalize(vec3(0.002f, 0, n.z)); /* |N.xy|^2 = 4e-6 > POLE_EPS */
            sl_lighting_uniforms *u2 = fx_uniforms(&f->env, NULL, o, scale(n2, 10.0f), 1, 1);
            t.normal = n2;
            vec3 c2 = fx_shade(u2, t);
            assert_near(c2.x, tr->total.x, 1e-3 * tr->total.x);
            free(u);
            free(u2);
        }
    /* R = +Z: V is +Z mirrored about the tilted N */
    vec3 n = vec3(0.5f, 0, 0.8660254f), v = normalize(sub(scale(n, 2.0f * n.z), vec3(0, 0, 1)));
    sl_lighting_uniforms *u = fx_uniforms(&f->env, NULL, microfacet(256), add(vec3(0, 0, 0), scale(v, 10.0f)), 1, 1);
    sl_gbuffer_texel t = fx_texel(n, vec3s(0), vec3s(0.5f), 10.0f);
    sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
    assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, NULL));
    assert_false(tr->pole_frame);
    assert_near(tr->R.z, 1.0, 1e-5);
    double truth = fx_truth(&f->gt, n, v, t, false, true);
    print_message("mf, R = +Z: %.4g vs truth %.4g\n", (double)tr->total.x, truth);
    assert_near(tr->total.x, truth, 1e-2 * truth);
    free(u);
    free(tr);
}

/* The microfacet estimator at the extremes: alpha 0 (uniform facets) meets the truth at an
 * oblique view (N = 256; measured 2e-3, tolerance 1%); alpha 1e6 is a mirror: every H is N to
 * float precision, so w = R, V.H = N.V, and the term is G' (w.N)(V.H)/(N.H) F L = F(N.V) L for
 * G' = 1/(V.H)^2 and (N.V)^2 F(N.V) L for G' = 1, exactly what the truth's integral tends to
 * (D concentrates at N, and dw = 4 (V.H) dH); alpha 1e20 and infinity clamp to 1e7 and stay
 * finite; every lod is in range, and 0 for the mirror (its density is huge). */
static void test_microfacet_alpha_extremes(void **state)
{
    furnace *f = *state;
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    const float alphas[] = {0.0f, 1e6f, 1e20f, INFINITY};
    for (int i = 0; i < 4; i++)
        for (int g = 0; g < 2; g++) {
            vec3 v = fx_view_dir(0.5f, 0.3f);
            sl_lighting_options o = microfacet(256);
            o.lod_rule = SL_LOD_GEMS;
            o.gterm = g ? SL_GTERM_ONE : SL_GTERM_INV_LH2;
            sl_lighting_uniforms *u = fx_uniforms(&f->env, NULL, o, scale(v, 10.0f), 1, 1);
            sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.5f), alphas[i]);
            sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
            assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, NULL));
            assert_true(fx_finite3(tr->total));
            assert_false(tr->repaired);
            for (int k = 0; k < tr->sample_count; k++) {
                const sl_lighting_trace_sample *s = &tr->samples[k];
                assert_true(isfinite(s->D) && isfinite(s->pdf) && isfinite(s->c.x));
                if (s->wN <= 0.0f || s->LdotH <= 0.0f)
                    continue;
                assert_true(s->lod >= 0.0f && s->lod <= u->uEnvMaxLod);
                if (i > 0)
                    assert_near(s->lod, 0.0, 0.0);
            }
            if (i == 0) {
                sl_gt_query q = {.n = vec3(0, 0, 1), .v = v, .ks = t.ks, .alpha = 0.0, .intensity = 1.0,
                                 .g = g ? SL_GT_G_ONE : SL_GT_G_INV_LH2};
                sl_gt_result r;
                assert_true(sl_ground_truth_shade(&f->gt, &q, &r, NULL));
                print_message("mf, alpha 0, N.V 0.5, G %s: %.4g vs truth %.4g\n", g ? "one" : "inv-lh2",
                              (double)tr->total.x, r.specular[0]);
                assert_near(tr->total.x, r.specular[0], 1e-2 * r.specular[0]);
            } else {
                double F = 0.5 + 0.5 * pow(1.0 - 0.5, 5.0); /* F(V.H = N.V = 0.5), Ks = 0.5 */
                assert_near(tr->total.x, g ? 0.25 * F : F, 1e-4);
            }
            free(u);
        }
    free(tr);
}

/* Grazing and below the horizon: N.V = 0.01 (and 0, and facing away: bent to 0.01) with alpha
 * 0 and 100. Facets that reflect below the horizon (w.N <= 0; V.H <= 0 implies it, as w.N =
 * 2 (V.H)(N.H) - N.V) add exactly 0 and do not move the running sum; the rest add finite,
 * non-negative terms (bounded by 2/(N.V) F L); the pass counts the skipped samples. At N.V
 * = 0.01 most facets are skipped, which is what the density says (w.N > 0 needs N.H >
 * N.V / (2 V.H)), not a failure. */
static void test_microfacet_grazing(void **state)
{
    furnace *f = *state;
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    const float nvs[] = {0.01f, 0.0f, -0.3f};
    const float alphas[] = {0.0f, 100.0f};
    for (int i = 0; i < 3; i++)
        for (int a = 0; a < 2; a++)
            for (int plain = 0; plain < 2; plain++) {
                vec3 v = nvs[i] >= 0.0f ? fx_view_dir(nvs[i], 0.4f) : normalize(vec3(0.9f, 0.2f, nvs[i]));
                sl_lighting_options o = microfacet(64);
                o.plain = plain;
                sl_lighting_uniforms *u = fx_uniforms(&f->env, NULL, o, scale(v, 10.0f), 1, 1);
                sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.04f), alphas[a]);
                sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
                assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, NULL));
                assert_true(fx_finite3(tr->total) && tr->total.x > 0.0f);
                int skipped = 0;
                vec3 prev = vec3s(0);
                for (int k = 0; k < tr->sample_count; k++) {
                    const sl_lighting_trace_sample *s = &tr->samples[k];
                    if (s->wN <= 0.0f || s->LdotH <= 0.0f) {
                        skipped++;
                        assert_near(s->c.x, 0.0, 0.0);
                        assert_near(s->sum.x, prev.x, 0.0);
                    } else {
                        assert_true(isfinite(s->c.x) && s->c.x >= 0.0f);
                        assert_true(s->c.x <= 2.0f / tr->NdotV * 1.0001f); /* F <= 1, L = 1 */
                        prev = s->sum;
                    }
                }
                assert_true(skipped > 0);
                /* the pass counts them */
                sl_image out = {0};
                sl_lighting_stats st;
                sl_error err;
                assert_true(sl_lighting_pass(u, &st, &gb, &out, 1, &err));
                assert_int_equal(st.below_horizon, skipped);
                assert_int_equal(st.nonfinite, 0);
                assert_memory_equal(out.data, &tr->total, sizeof(float) * 3);
                sl_image_free(&out);
                free(u);
            }
    free(tr);
}

/* D(H) = 0 (pow underflow far from N): log2(0) would be -inf; the lod clamps to the last
 * level for every rule, and the distortion floor keeps the poles finite. */
static void test_lod_guards(void **state)
{
    furnace *f = *state;
    for (int rule = SL_LOD_SPEC; rule <= SL_LOD_PDF; rule++)
        for (int dist = 0; dist < 2; dist++) {
            sl_lighting_uniforms *u = fx_uniforms(&f->env, NULL, (sl_lighting_options){.lod_rule = (sl_lod_rule)rule,
                .distortion = dist, .no_diffuse = true}, vec3(0, 0, 10), 1, 1);
            float D0 = sl_brdf_D(0.0f, 10.0f);
            assert_near(D0, 0.0, 0.0);
            /* the density rules (gems, pdf) read p(w); the specification's read D */
            bool density = rule == SL_LOD_GEMS || rule == SL_LOD_PDF;
            float pdf0 = density ? 0.0f : 1.0f;
            assert_near(sl_lighting_mip_level(u, D0, pdf0, vec3(1, 0, 0)), u->uEnvMaxLod, 0.0);
            assert_near(sl_lighting_mip_level(u, NAN, NAN, vec3(1, 0, 0)), u->uEnvMaxLod, 0.0);
            /* huge density: below level 0, clamps to 0 */
            assert_near(sl_lighting_mip_level(u, 1e30f, 1e30f, vec3(1, 0, 0)), 0.0, 0.0);
            /* exactly at a pole, with and without distortion: finite, in range */
            float lp = sl_lighting_mip_level(u, 1.0f, 1.0f, vec3(0, 0, 1));
            assert_true(lp >= 0.0f && lp <= u->uEnvMaxLod);
            if (dist) /* the pole's texels are smallest: a coarser level than the equator */
                assert_true(lp > sl_lighting_mip_level(u, 1.0f, 1.0f, vec3(1, 0, 0)));
            free(u);
        }
    sl_lighting_uniforms *u = fx_uniforms(&f->env, NULL, (sl_lighting_options){.lod_rule = SL_LOD_NONE,
        .no_diffuse = true}, vec3(0, 0, 10), 1, 1);
    assert_near(sl_lighting_mip_level(u, 0.0f, 0.0f, vec3(1, 0, 0)), 0.0, 0.0);
    free(u);
    /* the rules' formulas, by hand: 64x32 env, N = 40, D = 16 */
    u = fx_uniforms(&f->env, NULL, (sl_lighting_options){.lod_rule = SL_LOD_SPEC, .no_diffuse = true},
                    vec3(0, 0, 10), 1, 1);
    double base = 0.5 * log2(64.0 * 32.0 / 40.0);
    assert_near(sl_lighting_mip_level(u, 16.0f, 1.0f, vec3(1, 0, 0)), base - 2.0, 1e-5);
    free(u);
    u = fx_uniforms(&f->env, NULL, (sl_lighting_options){.no_diffuse = true}, vec3(0, 0, 10), 1, 1);
    assert_near(sl_lighting_mip_level(u, 16.0f, 1.0f, vec3(1, 0, 0)), base - 1.0, 1e-5);
    free(u);
    u = fx_uniforms(&f->env, NULL, (sl_lighting_options){.lod_rule = SL_LOD_GEMS, .no_diffuse = true},
                    vec3(0, 0, 10), 1, 1);
    /* 1/2 log2(Omega_s / Omega_p) + 1 with Omega_s = 1/(N p), Omega_p = 4 pi / (W H), p = 0.5 */
    double gems = 0.5 * log2((1.0 / (40.0 * 0.5)) / (4.0 * 3.14159265358979 / (64.0 * 32.0))) + 1.0;
    assert_near(sl_lighting_mip_level(u, 1.0f, 0.5f, vec3(1, 0, 0)), gems, 1e-5);
    free(u);
    /* pdf: the same without the +1; at the equator with the distortion, d = pi/2 */
    u = fx_uniforms(&f->env, NULL, (sl_lighting_options){.lod_rule = SL_LOD_PDF, .no_diffuse = true},
                    vec3(0, 0, 10), 1, 1);
    assert_near(sl_lighting_mip_level(u, 1.0f, 0.5f, vec3(1, 0, 0)), gems - 1.0, 1e-5);
    free(u);
    u = fx_uniforms(&f->env, NULL, (sl_lighting_options){.lod_rule = SL_LOD_PDF, .distortion = true,
                    .no_diffuse = true}, vec3(0, 0, 10), 1, 1);
    double pdf_dist = gems - 1.0 - 0.5 * log2(3.14159265358979 / 2.0);
    assert_near(sl_lighting_mip_level(u, 1.0f, 0.5f, vec3(1, 0, 0)), pdf_dist, 1e-5);
    free(u);
}

/* L.H -> 0 inside 1/(L.H)^2, pow of a slightly negative base, acos of a value just above 1. */
static void test_brdf_and_map_guards(void **state)
{
    (void)state;
    assert_true(isfinite(sl_brdf_G(0.0f, SL_GTERM_INV_LH2)));
    assert_true(isfinite(sl_brdf_G(-1e-20f, SL_GTERM_INV_LH2)));
    vec3 F = sl_brdf_F(vec3s(0.2f), 1.0f + 1e-6f);
    assert_near(F.x, 0.2f, 0.0);
    vec3 Fneg = sl_brdf_F(vec3s(0.2f), -1e-7f); /* can only happen through rounding */
    assert_true(fx_finite3(Fneg) && Fneg.x <= 1.0f + 1e-6f);
    vec2 uv = sl_dir_to_uv(vec3(0, 0, nextafterf(1.0f, 2.0f)));
    assert_near(uv.y, 0.0, 0.0);
    uv = sl_dir_to_uv(vec3(0, 0, -nextafterf(1.0f, 2.0f)));
    assert_near(uv.y, 1.0, 1e-7);
    assert_true(isfinite(sl_brdf_D(nextafterf(1.0f, 2.0f), 1e7f)));
}

/* Directions exactly at the poles and on the u seam: finite lookups, and the shading of a
 * near-mirror is continuous across the seam (R = (-1, -e, 0) vs (-1, +e, 0)) in an environment
 * that is smooth on the sphere. */
static vec3 smooth_env(vec3 d) { return vec3(1.5f + d.x, 1.5f + d.y, 1.5f + 0.5f * d.z); }
static void test_poles_and_seam(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 128, 64, smooth_env);
    const vec3 dirs[] = {vec3(0, 0, 1), vec3(0, 0, -1), vec3(-1, 0, 0), vec3(-1, -0.0f, 0), vec3(-1, 1e-7f, 0)};
    for (int i = 0; i < 5; i++) {
        vec3 c = textureLod(&env, sl_dir_to_uv(dirs[i]), 0.0f);
        assert_true(fx_finite3(c));
        vec3 want = smooth_env(dirs[i]);
        assert_near(c.x, want.x, 0.05);
        assert_near(c.z, want.z, 0.05);
    }
    vec3 side[2];
    for (int s = 0; s < 2; s++) {
        vec3 n = normalize(vec3(-1, s ? 1e-4f : -1e-4f, 0));
        sl_lighting_uniforms *u = fx_uniforms(&env, NULL, (sl_lighting_options){.no_diffuse = true}, scale(n, 10.0f), 1, 1);
        side[s] = fx_shade(u, fx_texel(n, vec3s(0), vec3s(1.0f), 2000.0f));
        assert_true(fx_finite3(side[s]));
        free(u);
    }
    assert_near(side[0].x, side[1].x, 1e-3 * side[0].x);
    assert_near(side[0].y, side[1].y, 1e-3 * side[0].y);
    /* a surface looking straight up or down: R exactly at the poles */
    for (int s = 0; s < 2; s++) {
        vec3 n = vec3(0, 0, s ? 1.0f : -1.0f);
        sl_lighting_uniforms *u = fx_uniforms(&env, NULL, (sl_lighting_options){.no_diffuse = true}, scale(n, 10.0f), 1, 1);
        vec3 c = fx_shade(u, fx_texel(n, vec3s(0), vec3s(1.0f), 2000.0f));
        assert_true(fx_finite3(c));
        assert_near(c.z, smooth_env(n).z / 4.0, 0.02); /* mirror head-on: Ks L / 4 (spec estimator) */
        free(u);
    }
    sl_env_free(&env);
}

/* Non-finite G-buffer input never leaves the shader: replaced by 0 and counted. */
static void test_nonfinite_guard(void **state)
{
    furnace *f = *state;
    sl_irradiance irr;
    sl_error err;
    assert_true(sl_irradiance_sh9(&irr, &f->env, &err));
    sl_lighting_uniforms *u = fx_uniforms(&f->env, &irr, (sl_lighting_options){0}, vec3(0, 0, 10), 4, 1);
    sl_gbuffer_texel t[4] = {
        fx_texel(vec3(0, 0, 1), vec3s(0.5f), vec3s(0.04f), 10.0f),
        fx_texel(vec3(0, 0, 1), vec3(INFINITY, 0, 0), vec3s(0.04f), 10.0f),
        fx_texel(vec3(NAN, 0, 1), vec3s(0.5f), vec3s(0.04f), 10.0f),
        fx_texel(vec3(0, 0, 1), vec3s(0.5f), vec3s(0.04f), NAN),
    };
    t[0].position = vec3(NAN, 0, 0);
    sl_gbuffer gb = {.width = 4, .height = 1, .texels = t};
    sl_image out = {0};
    sl_lighting_stats st;
    assert_true(sl_lighting_pass(u, &st, &gb, &out, 1, &err));
    for (int i = 0; i < 4 * 3; i++)
        assert_true(isfinite(out.data[i]));
    assert_near(out.data[0], 0.0, 0.0);
    assert_near(out.data[3], 0.0, 0.0);
    assert_int_equal(st.nonfinite, 3); /* NaN position, Inf kd, NaN alpha; a NaN normal becomes V */
    sl_image_free(&out);
    free(u);
    sl_irradiance_free(&irr);
}

/* A smooth sky: brighter and bluer upward, a darker ground. */
static vec3 sky_like(vec3 d)
{
    float up = 0.5f + 0.5f * d.z;
    return vec3(0.3f + 0.7f * up, 0.4f + 0.8f * up, 0.6f + 1.2f * up);
}

/* Render the three-sphere scene under `env` and check: no NaN/Inf, pass stats; returns the
 * number of speckles. metal_alpha 5000 is a near mirror: it shows a small bright light source as
 * the tiny highlight it really is, which the speckle test cannot tell from a bad pixel; scenes
 * with a sun use a glossy 200 instead. */
static int render_finite(const sl_env *env, sl_lighting_options opt, float metal_alpha, const char *what)
{
    fx_frame f;
    fx_frame_setup(&f, env, 64, 64, metal_alpha);
    sl_lighting_desc d = fx_frame_desc(&f, opt);
    sl_image out = {0};
    fx_render(&d, &f.gb, 2, &out, NULL); /* no pixel repaired, every value finite */
    for (int i = 0; i < 64 * 64 * 3; i++)
        assert_true(out.data[i] >= 0.0f);
    unsigned char *mask = fx_image_mask(&f.gb);
    int speckles = fx_count_speckles(&out, mask, 0.2, 5.0);
    if (speckles)
        print_message("%s: %d speckles\n", what, speckles);
    free(mask);
    sl_image_free(&out);
    fx_frame_teardown(&f);
    return speckles;
}

/* render_finite, and no speckles */
static void render_and_check(const sl_env *env, sl_lighting_options opt, float metal_alpha, const char *what)
{
    assert_int_equal(render_finite(env, opt, metal_alpha, what), 0);
}

static void test_image_smooth_sky(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 256, 128, sky_like);
    render_and_check(&env, (sl_lighting_options){0}, 5000.0f, "sky, defaults");
    render_and_check(&env, (sl_lighting_options){.estimator = SL_ESTIMATOR_CONSISTENT, .distortion = true},
                     5000.0f, "sky, consistent + distortion");
    render_and_check(&env, (sl_lighting_options){.lod_rule = SL_LOD_GEMS}, 5000.0f, "sky, gems");
    render_and_check(&env, (sl_lighting_options){.lod_rule = SL_LOD_PDF, .distortion = true}, 5000.0f,
                     "sky, pdf+dist");
    render_and_check(&env, (sl_lighting_options){.estimator = SL_ESTIMATOR_MICROFACET}, 5000.0f, "sky, mf");
    render_and_check(&env, (sl_lighting_options){.estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_GEMS,
        .distortion = true, .rotate = true}, 5000.0f, "sky, mf gems+dist, rotated");
    sl_env_free(&env);
}

/* A 1x1 environment (one level: every lod clamps to 0, uLodBase < 0) and a non-power-of-two
 * 37x19 one (odd mip sizes). The constant 37x19 must also meet the ground truth head-on. */
static void test_tiny_and_npot_env(void **state)
{
    furnace *f = *state;
    sl_env one;
    fx_env(&one, 1, 1, fx_const_one);
    assert_int_equal(one.level_count, 1);
    render_and_check(&one, (sl_lighting_options){0}, 5000.0f, "1x1 env");
    sl_env npot;
    fx_env(&npot, 37, 19, sky_like);
    render_and_check(&npot, (sl_lighting_options){0}, 5000.0f, "37x19 env");
    render_and_check(&one, (sl_lighting_options){.estimator = SL_ESTIMATOR_MICROFACET}, 5000.0f, "1x1 env, mf");
    render_and_check(&npot, (sl_lighting_options){.estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_GEMS},
                     5000.0f, "37x19 env, mf");
    sl_env_free(&npot);
    fx_env(&npot, 37, 19, fx_const_one);
    sl_lighting_uniforms *u = fx_uniforms(&npot, NULL, consistent(128), vec3(0, 0, 10), 1, 1);
    sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.3f), 1.0f);
    assert_near(fx_shade(u, t).x, fx_truth(&f->gt, vec3(0, 0, 1), vec3(0, 0, 1), t, false, true), 5e-3);
    free(u);
    sl_env_free(&npot);
    sl_env_free(&one);
}

/* A sun 30000 times brighter than the sky (the city environment's case): finite, no speckles,
 * and the tone map at exposure 0.1 and 10000 stays in [0, 1] without NaN. */
static vec3 sky_with_sun(vec3 d)
{
    vec3 sun = normalize(vec3(0.3f, -0.8f, 0.5f));
    float s = dot(d, sun) > 0.9995f ? 30000.0f : 0.0f;
    return add(sky_like(d), vec3s(s));
}
static void test_sun_and_exposure(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 512, 256, sky_with_sun);
    render_and_check(&env, (sl_lighting_options){0}, 200.0f, "sun, defaults");
    render_and_check(&env, (sl_lighting_options){.estimator = SL_ESTIMATOR_CONSISTENT}, 200.0f, "sun, consistent");
    render_and_check(&env, (sl_lighting_options){.estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_GEMS,
        .distortion = true}, 200.0f, "sun, mf");
    /* pdf (no +1) filters each sample one level finer: at N = 40 a few pixels of the glossy
     * sphere catch the sun where their neighbours miss it (2 of 64x64 measured), the aliasing
     * Gems' +1 blurs away (docs/lighting.md "Mip level"). Finite and in range is the hard case. */
    render_finite(&env, (sl_lighting_options){.estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_PDF,
        .distortion = true}, 200.0f, "sun, mf pdf+dist");
    /* tone map the sun image itself at both ends of the exposure range */
    sl_image img = {0};
    sl_error err;
    assert_true(sl_image_alloc(&img, 512, 256, 3, &err));
    for (int i = 0; i < 512 * 256; i++) {
        vec3 c = env.levels[0].texels[i];
        img.data[3 * i] = c.x;
        img.data[3 * i + 1] = c.y;
        img.data[3 * i + 2] = c.z;
    }
    const float exposures[] = {0.1f, 10000.0f};
    for (int e = 0; e < 2; e++)
        for (int exact = 0; exact < 2; exact++) {
            sl_image out = {0};
            assert_true(sl_tonemap_image(&img, &out, &(sl_tonemap_options){.exposure = exposures[e],
                .contrast = 1.3f, .exact_srgb = exact}, 0, &err));
            float lo = 1, hi = 0;
            for (int i = 0; i < 512 * 256 * 3; i++) {
                assert_true(out.data[i] >= 0.0f && out.data[i] <= 1.0f);
                lo = fminf(lo, out.data[i]);
                hi = fmaxf(hi, out.data[i]);
            }
            if (e == 1)
                assert_true(lo > 0.99f); /* everything saturates at e = 10000 */
            else
                assert_true(hi > 0.99f && lo < 0.5f); /* only the sun saturates at e = 0.1 */
            sl_image_free(&out);
        }
    sl_image_free(&img);
    sl_env_free(&env);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_reflection_along_z, furnace_setup, furnace_teardown),
        cmocka_unit_test_setup_teardown(test_normal_facing_away, furnace_setup, furnace_teardown),
        cmocka_unit_test_setup_teardown(test_samples_below_horizon, furnace_setup, furnace_teardown),
        cmocka_unit_test_setup_teardown(test_alpha_extremes, furnace_setup, furnace_teardown),
        cmocka_unit_test_setup_teardown(test_microfacet_poles, furnace_setup, furnace_teardown),
        cmocka_unit_test_setup_teardown(test_microfacet_alpha_extremes, furnace_setup, furnace_teardown),
        cmocka_unit_test_setup_teardown(test_microfacet_grazing, furnace_setup, furnace_teardown),
        cmocka_unit_test_setup_teardown(test_lod_guards, furnace_setup, furnace_teardown),
        cmocka_unit_test(test_brdf_and_map_guards),
        cmocka_unit_test(test_poles_and_seam),
        cmocka_unit_test_setup_teardown(test_nonfinite_guard, furnace_setup, furnace_teardown),
        cmocka_unit_test(test_image_smooth_sky),
        cmocka_unit_test_setup_teardown(test_tiny_and_npot_env, furnace_setup, furnace_teardown),
        cmocka_unit_test(test_sun_and_exposure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
