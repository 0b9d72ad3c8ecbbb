/* test_shading.c - the lighting stage against hand values, analytic facts and the ground truth:
 * BRDF terms, the skewed and the microfacet sample densities, the std140 block, white furnace,
 * the three estimators (the spec's bias is measured and pinned down; the consistent and the
 * microfacet ones against the ground truth), point lights, the background, the row flip,
 * determinism over threads and over the per-alpha cache, and the tone map. */
#include "shading_fixtures.h"
#include "shading/lighting_trace.h"
#include "shading/brdf.h"
#include "post/tonemap.h"

#include <stddef.h>
#include <stdio.h>

/* ---- BRDF terms (brdf.h) against values worked out by hand ---- */
static void test_brdf_hand_values(void **state)
{
    (void)state;
    const double pi = 3.14159265358979;
    assert_near(sl_brdf_D(1.0f, 0.0f), 1.0 / pi, 1e-6);         /* (0+2)/(2 pi) */
    assert_near(sl_brdf_D(1.0f, 10.0f), 12.0 / (2 * pi), 1e-5);
    assert_near(sl_brdf_D(0.5f, 2.0f), 4.0 / (2 * pi) * 0.25, 1e-6);
    assert_near(sl_brdf_D(0.0f, 10.0f), 0.0, 1e-30);              /* floor 1e-30 ^ 10 underflows */
    assert_near(sl_brdf_D(0.0f, 0.0f), 1.0 / pi, 1e-6);           /* pow(0, 0) is pinned to 1 */
    vec3 ks = vec3s(0.04f);
    assert_near(sl_brdf_F(ks, 1.0f).x, 0.04, 1e-7);
    assert_near(sl_brdf_F(ks, 0.0f).x, 1.0, 1e-6);
    assert_near(sl_brdf_F(ks, 0.5f).x, 0.04 + 0.96 / 32.0, 1e-6);
    assert_near(sl_brdf_F(ks, nextafterf(1.0f, 2.0f)).x, 0.04f, 0.0); /* 1 - L.H < 0 clamps */
    assert_near(sl_brdf_G(0.5f, SL_GTERM_INV_LH2), 4.0, 1e-6);
    assert_near(sl_brdf_G(0.0f, SL_GTERM_INV_LH2), 1e6, 1.0);     /* L.H floored at 1e-3 */
    assert_near(sl_brdf_G(0.1f, SL_GTERM_ONE), 1.0, 0.0);
}

/* D is normalised: integral of D(H) (N.H) over the hemisphere = 1, by midpoint rule in
 * c = N.H (dw = dc dphi): (alpha+2) integral c^(alpha+1) dc = 1. */
static void test_brdf_D_normalised(void **state)
{
    (void)state;
    const float alphas[] = {0, 1, 10, 100, 1000};
    for (int a = 0; a < 5; a++) {
        double sum = 0;
        const int n = 200000;
        for (int i = 0; i < n; i++) {
            float c = ((float)i + 0.5f) / (float)n;
            sum += (double)sl_brdf_D(c, alphas[a]) * c * (2.0 * 3.14159265358979) / n;
        }
        assert_near(sum, 1.0, 2e-3);
    }
}

/* The skewed directions have the density (alpha+1)/(2 pi) (w.R)^alpha: mean of w.R over the
 * set = (alpha+1)/(alpha+2), the mean of L.x, L.y is 0, every w is unit and w.R = L.z. Read
 * through the trace, so the trace is checked as well. N = 1024: the midpoint rule in xi2
 * errs by O(1/N^2) for these smooth integrands; the radical inverse balances x and y to 1e-3. */
static void test_sample_density(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 8, 4, fx_const_one);
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    const float alphas[] = {0, 1, 10, 100};
    for (int a = 0; a < 4; a++) {
        vec3 v = fx_view_dir(0.6f, 0.3f);
        sl_lighting_uniforms *u =
            fx_uniforms(&env, NULL, (sl_lighting_options){.samples = 1024, .no_diffuse = true}, scale(v, 10.0f), 1, 1);
        sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.5f), alphas[a]);
        sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
        sl_error err;
        assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, &err));
        assert_int_equal(tr->sample_count, 1024);
        double mz = 0, mx = 0, my = 0;
        for (int k = 0; k < 1024; k++) {
            const sl_lighting_trace_sample *s = &tr->samples[k];
            mz += s->L.z / 1024.0;
            mx += s->L.x / 1024.0;
            my += s->L.y / 1024.0;
            assert_near(length(s->w), 1.0, 1e-6);
            assert_near(dot(s->w, tr->R), s->L.z, 1e-5);
        }
        assert_near(mz, (alphas[a] + 1.0) / (alphas[a] + 2.0), 1e-3);
        if (a == 1) { /* the printed trace has a line per sample and the result */
            FILE *f = tmpfile();
            assert_non_null(f);
            sl_lighting_trace_print(f, tr);
            long size = ftell(f);
            rewind(f);
            char line[1024];
            int lines = 0, total = 0;
            while (fgets(line, sizeof line, f)) {
                lines++;
                total += strstr(line, "total") != NULL;
            }
            fclose(f);
            assert_true(size > 1024 * 100);
            assert_true(lines > 1024);
            assert_int_equal(total, 1);
        }
        assert_near(mx, 0.0, 2e-3);
        assert_near(my, 0.0, 2e-3);
        free(u);
    }
    free(tr);
    sl_env_free(&env);
}

/* The std140 block: N at 0, the vec4 array at 16, pair k in [k/2].xy or .zw. */
static void test_hammersley_std140(void **state)
{
    (void)state;
    assert_int_equal(offsetof(sl_hammersley_block, hammersley), 16);
    assert_int_equal(sizeof(sl_hammersley_block), 16 + 16 * (SL_HAMMERSLEY_MAX / 2));
    sl_hammersley set;
    assert_true(sl_hammersley_build(&set, 5, NULL));
    sl_hammersley_block *b = malloc(sizeof *b);
    assert_non_null(b);
    sl_hammersley_pack_std140(&set, b);
    assert_near(b->N, 5.0, 0.0);
    /* radical inverse of 0..4: 0, 0.5, 0.25, 0.75, 0.125; v = (k + 0.5) / 5 */
    assert_near(b->hammersley[0].x, 0.0, 0.0);
    assert_near(b->hammersley[0].y, 0.1, 1e-7);
    assert_near(b->hammersley[0].z, 0.5, 0.0);
    assert_near(b->hammersley[0].w, 0.3, 1e-7);
    assert_near(b->hammersley[1].z, 0.75, 0.0);
    assert_near(b->hammersley[2].x, 0.125, 0.0);
    assert_near(b->hammersley[2].y, 0.9, 1e-7);
    assert_near(b->hammersley[2].z, 0.0, 0.0); /* unused half stays 0 */
    free(b);
}

static void test_options_resolve_and_names(void **state)
{
    (void)state;
    sl_lighting_options o = sl_lighting_options_resolve(&(sl_lighting_options){0});
    assert_int_equal(o.samples, 40);
    assert_int_equal(o.lod_rule, SL_LOD_SPEC_D4);
    assert_int_equal(o.gterm, SL_GTERM_INV_LH2);
    assert_int_equal(o.estimator, SL_ESTIMATOR_SPEC);
    assert_near(o.env_intensity, 1.0, 0.0);
    assert_false(o.distortion);
    for (int r = SL_LOD_NONE; r <= SL_LOD_PDF; r++) {
        sl_lod_rule back;
        assert_true(sl_lod_rule_parse(sl_lod_rule_name((sl_lod_rule)r), &back));
        assert_int_equal(back, r);
    }
    sl_estimator e;
    assert_true(sl_estimator_parse("consistent", &e));
    assert_int_equal(e, SL_ESTIMATOR_CONSISTENT);
    assert_true(sl_estimator_parse("mf", &e));
    assert_int_equal(e, SL_ESTIMATOR_MICROFACET);
    assert_string_equal(sl_estimator_name(SL_ESTIMATOR_MICROFACET), "mf");
    assert_false(sl_estimator_parse("microfacet", &e));
    sl_gterm g;
    assert_true(sl_gterm_parse("one", &g));
    assert_int_equal(g, SL_GTERM_ONE);
    assert_false(sl_lod_rule_parse("bogus", &(sl_lod_rule){0}));
    assert_string_equal(sl_lod_rule_name(SL_LOD_PDF), "pdf");

    /* uniforms refuse what the shader cannot run */
    sl_env env;
    fx_env(&env, 8, 4, fx_const_one);
    sl_lighting_uniforms *u = malloc(sizeof *u);
    sl_error err;
    sl_lighting_desc d = {.options = {.samples = 2000, .no_diffuse = true}, .env = &env, .width = 1, .height = 1};
    assert_false(sl_lighting_uniforms_init(u, &d, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    d.options.samples = 0;
    d.options.no_diffuse = false; /* diffuse on, no irradiance */
    assert_false(sl_lighting_uniforms_init(u, &d, &err));
    d.options.no_diffuse = true;
    d.light_count = SL_LIGHTING_MAX_LIGHTS + 1;
    assert_false(sl_lighting_uniforms_init(u, &d, &err));
    d.light_count = 0;
    d.options.estimator = (sl_estimator)(SL_ESTIMATOR_SPLITSUM + 1);
    assert_false(sl_lighting_uniforms_init(u, &d, &err));
    d.options.estimator = SL_ESTIMATOR_SPLITSUM; /* without its prefiltered chains and table */
    assert_false(sl_lighting_uniforms_init(u, &d, &err));
    d.options.estimator = SL_ESTIMATOR_MICROFACET;
    assert_true(sl_lighting_uniforms_init(u, &d, &err));
    assert_int_equal(u->uEstimator, 3); /* lighting.frag ESTIMATOR_MICROFACET */
    d.options.estimator = SL_ESTIMATOR_DEFAULT;
    d.options.lod_rule = (sl_lod_rule)(SL_LOD_PDF + 1);
    assert_false(sl_lighting_uniforms_init(u, &d, &err));
    d.options.lod_rule = SL_LOD_PDF;
    assert_true(sl_lighting_uniforms_init(u, &d, &err));
    assert_int_equal(u->uLodRule, 5); /* lighting.frag LOD_PDF */
    d.options.lod_rule = SL_LOD_DEFAULT;
    assert_true(sl_lighting_uniforms_init(u, &d, &err));
    assert_near(u->uLodBase, 0.5 * log2(8.0 * 4.0 / 40.0), 1e-6);
    assert_near(u->uEnvMaxLod, 3.0, 0.0); /* 8x4, 4x2, 2x1, 1x1 */
    assert_int_equal(u->uPointLights, 0);
    free(u);
    sl_env_free(&env);
}

/* White furnace, diffuse only: L = 1, Kd = 1 gives Kd/pi E = 1 for every irradiance method.
 * SH9 of a constant is exact (only l = 0) up to float rounding; BRUTE integrates a constant
 * exactly up to the quadrature's horizon texels (ground_truth.h: 4e-6 relative at 1024x512,
 * coarser here), MAP reads a constant image of E = pi. Tolerance 2e-3. */
static void test_white_furnace_diffuse(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 64, 32, fx_const_one);
    sl_irradiance irr[3];
    sl_error err;
    assert_true(sl_irradiance_sh9(&irr[0], &env, &err));
    assert_true(sl_irradiance_brute(&irr[1], &env, 32, 0, &err));
    sl_image e = {0};
    assert_true(sl_image_alloc(&e, 16, 8, 3, &err));
    for (int i = 0; i < 16 * 8 * 3; i++)
        e.data[i] = 3.14159265f;
    assert_true(sl_irradiance_from_image(&irr[2], &e, &err));
    sl_image_free(&e);
    const vec3 normals[] = {vec3(0, 0, 1), vec3(0, 0, -1), vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0.3f, -0.5f, 0.81f)};
    for (int m = 0; m < 3; m++) {
        sl_lighting_options o = {.irradiance = irr[m].method, .no_specular = true};
        for (int i = 0; i < 5; i++) {
            vec3 n = normalize(normals[i]);
            sl_lighting_uniforms *u = fx_uniforms(&env, &irr[m], o, scale(n, 10.0f), 1, 1);
            sl_gbuffer_texel t = fx_texel(n, vec3s(1.0f), vec3s(0.0f), 10.0f);
            vec3 c = fx_shade(u, t);
            assert_near(c.x, 1.0, 2e-3);
            assert_near(c.y, 1.0, 2e-3);
            assert_near(c.z, 1.0, 2e-3);
            free(u);
        }
        sl_irradiance_free(&irr[m]);
    }
    sl_env_free(&env);
}

/* White furnace, full BRDF: the TRUE integral is not 1 (docs/conventions.md, erratum 1): with Kd = 1, Ks = 0 and
 * alpha = 10 it averages 1.02 over a sphere (pixels weighted by N.V, orthographic) and reaches
 * 1.36 at the silhouette. Checked on the ground truth, then the shader (consistent estimator)
 * against it where the estimator converges (N.V = 1: the lobe's and the surface's hemispheres
 * coincide; alpha = 1: bounded weights D/p, see test_consistent_vs_truth). */
static void test_white_furnace_full(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 512, 256, fx_const_one);
    sl_ground_truth gt;
    sl_error err;
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    double sum = 0, wsum = 0, mx = 0;
    for (int i = 0; i < 100; i++) {
        float nv = ((float)i + 0.5f) / 100.0f;
        sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(1.0f), vec3s(0.0f), 10.0f);
        double total = fx_truth(&gt, vec3(0, 0, 1), fx_view_dir(nv, 0), t, true, true);
        sum += nv * total;
        wsum += nv;
        mx = total > mx ? total : mx;
    }
    assert_near(sum / wsum, 1.02, 0.005);
    assert_near(mx, 1.36, 0.02);

    sl_irradiance irr;
    assert_true(sl_irradiance_sh9(&irr, &env, &err));
    sl_lighting_uniforms *u = fx_uniforms(&env, &irr, (sl_lighting_options){.samples = 256,
        .estimator = SL_ESTIMATOR_CONSISTENT}, vec3(0, 0, 10), 1, 1);
    sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(1.0f), vec3s(0.0f), 1.0f);
    double truth = fx_truth(&gt, vec3(0, 0, 1), vec3(0, 0, 1), t, true, true);
    vec3 c = fx_shade(u, t);
    assert_near(c.x, truth, 2e-3);
    free(u);
    sl_irradiance_free(&irr);
    sl_ground_truth_free(&gt);
    sl_env_free(&env);
}

/* The consistent estimator against the ground truth, specular only, constant environment.
 * Tolerance, derived per case from the samples themselves (read through the trace): 4 s / sqrt(N),
 * s the standard deviation of the N per-sample terms (the Monte Carlo error bound for
 * independent samples; the Hammersley set does at least as well on these smooth integrands),
 * plus 1e-3 relative for the ground truth's quadrature. Cases where it holds: N.V = 1 and
 * alpha <= 2, where the weight D(H)/p(w) is bounded or square integrable. Elsewhere the
 * estimator is biased by what docs/lighting.md measures: p(w) = 0 on the wedge
 * w.R < 0 < w.N, and D/p has infinite variance at high alpha (the sampled lobe is narrower
 * than D's lobe seen in w). */
static void test_consistent_vs_truth(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 512, 256, fx_const_one);
    sl_ground_truth gt;
    sl_error err;
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    sl_env small;
    fx_env(&small, 64, 32, fx_const_one);
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    const float alphas[] = {0, 1, 2};
    const float kss[] = {0.04f, 1.0f};
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 2; k++) {
            vec3 n = vec3(0, 0, 1);
            sl_lighting_uniforms *u = fx_uniforms(&small, NULL, (sl_lighting_options){.samples = 64,
                .estimator = SL_ESTIMATOR_CONSISTENT, .no_diffuse = true}, vec3(0, 0, 10), 1, 1);
            sl_gbuffer_texel t = fx_texel(n, vec3s(0), vec3s(kss[k]), alphas[a]);
            sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
            assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, &err));
            double mean = 0, m2 = 0;
            int ns = tr->sample_count;
            for (int i = 0; i < ns; i++) {
                double c = tr->samples[i].wN > 0 ? tr->samples[i].c.x : 0.0;
                mean += c / ns;
                m2 += c * c / ns;
            }
            double s = sqrt(fmax(m2 - mean * mean, 0.0));
            double truth = fx_truth(&gt, n, n, t, false, true);
            double tol = 4.0 * s / sqrt((double)ns) + 1e-3 * truth;
            assert_near(tr->specular.x, truth, tol);
            free(u);
        }
    free(tr);
    sl_ground_truth_free(&gt);
    sl_env_free(&small);
    sl_env_free(&env);
}

static vec3 sky_gradient(vec3 d) { return vec3(1.0f + d.z, 0.5f + 0.25f * d.x, 2.0f - d.z); }

/* The specification's estimator (eq. (3), divide by D(H)) is biased (docs/conventions.md, erratum 7); pinned down:
 * (a) alpha = 0: D(H)/p(w) = (2/2pi)/(1/2pi) = 2 for every sample, so spec = consistent / 2
 *     exactly, in any environment and view;
 * (b) mirror limit at normal incidence: every w = R, L.H = 1, G = 1, so spec = F Li (w.N)/4 =
 *     Ks L / 4 while the truth is Ks L: a factor 1/4;
 * (c) over a sphere of a dielectric (Ks = 0.04, pixels weighted by N.V) it is darker than the
 *     truth, more so at low alpha (erratum 7): ratio about 0.45 at alpha 0, rising with alpha;
 *     measured 0.45, 0.53, 0.69, 0.89 for alpha 0, 1, 10, 100 (docs/lighting.md);
 * (d) per pixel it is not uniformly darker: at grazing view and high alpha it is brighter
 *     (the 1/(L.N) of eq. (3) is not cancelled), e.g. more than 2x at N.V = 0.1, alpha 100. */
static void test_spec_estimator_bias(void **state)
{
    (void)state;
    sl_env grad;
    fx_env(&grad, 64, 32, sky_gradient);
    /* (a) */
    for (int i = 0; i < 4; i++) {
        vec3 v = fx_view_dir(0.2f + 0.25f * (float)i, 0.7f * (float)i);
        sl_lighting_options o = {.no_diffuse = true};
        sl_lighting_uniforms *us = fx_uniforms(&grad, NULL, o, scale(v, 10.0f), 1, 1);
        o.estimator = SL_ESTIMATOR_CONSISTENT;
        sl_lighting_uniforms *uc = fx_uniforms(&grad, NULL, o, scale(v, 10.0f), 1, 1);
        sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.3f), 0.0f);
        vec3 s = fx_shade(us, t), c = fx_shade(uc, t);
        assert_near(2.0 * s.x, c.x, 1e-5 * c.x);
        assert_near(2.0 * s.z, c.z, 1e-5 * c.z);
        free(us);
        free(uc);
    }
    sl_env_free(&grad);

    sl_env env;
    fx_env(&env, 512, 256, fx_const_one);
    sl_ground_truth gt;
    sl_error err;
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    sl_env small;
    fx_env(&small, 64, 32, fx_const_one);
    /* (b) */
    {
        sl_lighting_uniforms *u = fx_uniforms(&small, NULL, (sl_lighting_options){.no_diffuse = true}, vec3(0, 0, 10), 1, 1);
        vec3 c = fx_shade(u, fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.5f), 1e6f));
        assert_near(c.x, 0.5 / 4.0, 1e-4);
        free(u);
    }
    /* (c) */
    const float alphas[] = {0, 1, 10, 100};
    double ratio[4];
    for (int a = 0; a < 4; a++) {
        double se = 0, st = 0;
        for (int i = 0; i < 20; i++) {
            float nv = ((float)i + 0.5f) / 20.0f;
            vec3 v = fx_view_dir(nv, 0);
            sl_lighting_uniforms *u =
                fx_uniforms(&small, NULL, (sl_lighting_options){.no_diffuse = true}, scale(v, 10.0f), 1, 1);
            sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.04f), alphas[a]);
            se += nv * fx_shade(u, t).x;
            st += nv * fx_truth(&gt, vec3(0, 0, 1), v, t, false, true);
            free(u);
        }
        ratio[a] = se / st;
        print_message("spec estimator / truth, sphere average, alpha %g: %.3f\n", (double)alphas[a], ratio[a]);
    }
    assert_true(ratio[0] < 0.55);
    assert_true(ratio[0] < ratio[1] && ratio[1] < ratio[2] && ratio[2] < ratio[3]);
    assert_true(ratio[3] < 1.0);
    /* (d) */
    {
        vec3 v = fx_view_dir(0.1f, 0);
        sl_lighting_uniforms *u = fx_uniforms(&small, NULL, (sl_lighting_options){.no_diffuse = true}, scale(v, 10.0f), 1, 1);
        sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0), vec3s(0.04f), 100.0f);
        double truth = fx_truth(&gt, vec3(0, 0, 1), v, t, false, true);
        assert_true(fx_shade(u, t).x > 2.0 * truth);
        free(u);
    }
    sl_ground_truth_free(&gt);
    sl_env_free(&small);
    sl_env_free(&env);
}

/* The microfacet estimator's samples, read through the trace (N = 1024, so the midpoint rule in
 * xi2 errs by O(1/N^2)): H has the density D(H) (N.H) about N, so the mean of N.H over the set is
 * (alpha+2)/(alpha+3) and the mean of H's local x, y is 0; every H is unit with H.N = its local z;
 * w = reflect(-V, H) is unit with L.H = V.H; D is (alpha+2)/(2 pi) (N.H)^alpha; and a drawn sample
 * contributes exactly when V.H > 0 and w.N > 0, with p(w) = D (N.H) / (4 V.H). Seen head-on
 * (V = N), w.N = 2 (N.H)^2 - 1 > 0 iff N.H > 1/sqrt(2), i.e. xi2 = (N.H)^(alpha+2) > 2^-(alpha+2)/2:
 * of the pairs xi2 = (k + 1/2)/1024 that is 1024 (1 - 2^-(alpha+2)/2) samples, to one (half of
 * them at alpha 0). The surface is tilted (N off +Z) so the frame is not the identity. */
static void test_microfacet_sample_density(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 8, 4, fx_const_one);
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    const float alphas[] = {0, 1, 10, 100};
    const vec3 n = normalize(vec3(0.3f, -0.2f, 0.9f));
    for (int a = 0; a < 4; a++)
        for (int plain = 0; plain < 2; plain++) {
            vec3 v = n;
            sl_lighting_uniforms *u = fx_uniforms(&env, NULL, (sl_lighting_options){.samples = 1024, .no_diffuse = true,
                .estimator = SL_ESTIMATOR_MICROFACET, .plain = plain}, scale(v, 10.0f), 1, 1);
            sl_gbuffer_texel t = fx_texel(n, vec3s(0), vec3s(0.5f), alphas[a]);
            sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
            sl_error err;
            assert_true(sl_lighting_trace_pixel(u, &gb, 0, 0, tr, &err));
            assert_true(tr->microfacet);
            assert_int_equal(tr->sample_count, 1024);
            assert_near(dot(tr->A, tr->Nenv), 0.0, 1e-6);
            assert_near(dot(tr->B, tr->Nenv), 0.0, 1e-6);
            double mz = 0, mx = 0, my = 0;
            int used = 0;
            for (int k = 0; k < 1024; k++) {
                const sl_lighting_trace_sample *s = &tr->samples[k];
                mz += s->L.z / 1024.0;
                mx += s->L.x / 1024.0;
                my += s->L.y / 1024.0;
                assert_near(length(s->H), 1.0, 1e-6);
                assert_near(dot(s->H, tr->Nenv), s->L.z, 2e-6);
                assert_near(length(s->w), 1.0, 1e-6);
                assert_near(dot(s->w, s->H), s->LdotH, 2e-6); /* L.H = V.H */
                assert_near(dot(tr->Venv, s->H), s->LdotH, 2e-6);
                double D = (alphas[a] + 2.0) / (2.0 * 3.14159265358979) * pow(s->NdotH, alphas[a]);
                assert_near(s->D, D, 1e-4 * D + 1e-30);
                if (s->LdotH > 0.0f && s->wN > 0.0f) {
                    used++;
                    assert_near(s->pdf, s->D * s->NdotH / (4.0 * s->LdotH), 1e-5 * s->pdf);
                    assert_true(isfinite(s->c.x) && s->c.x > 0.0f);
                } else {
                    assert_near(s->c.x, 0.0, 0.0);
                }
            }
            assert_near(mz, (alphas[a] + 2.0) / (alphas[a] + 3.0), 1e-3);
            assert_near(mx, 0.0, 2e-3);
            assert_near(my, 0.0, 2e-3);
            assert_near(used, 1024.0 * (1.0 - pow(2.0, -(alphas[a] + 2.0) / 2.0)), 1.0);
            free(u);
        }
    free(tr);
    sl_env_free(&env);
}

/* The microfacet estimator converges to the ground truth (specular only, lod 0 so that the
 * estimator alone is measured; the ground truth integrates the same environment texel by
 * texel): alpha 0, 1, 10, 100 x N.V 1, 0.6, 0.2 x Ks 0.04, 1, on a constant environment and on a
 * structured one (a gradient in every channel, 512x256 for both the shader and the truth).
 * Its weight G' (w.N)(V.H)/(N.H) is bounded by 2/(N.V) and every direction above the horizon is
 * drawn, so the relative error over these 48 cases must fall as N grows (RMS at N = 16, 64,
 * 256, 1024) and be small at N = 256. Measured (the print shows them): RMS 6.7e-2, 1.0e-2,
 * 4.9e-3, 8.1e-4; worst case 2.0e-2 at N = 256 (N.V 0.2, Ks 0.04: the Fresnel rise at the horizon)
 * and 3.5e-3 at N = 1024. Tolerances: each RMS below 0.6 of the previous; at N = 256 RMS 8e-3 and
 * worst 3e-2; at N = 1024 RMS 1.5e-3 and worst 6e-3. The consistent estimator does not get there
 * on these cases (RMS 9e-2 at N = 256, printed beside; docs/lighting.md says why). */
static void test_microfacet_vs_truth(void **state)
{
    (void)state;
    sl_env envs[2];
    fx_env(&envs[0], 512, 256, fx_const_one);
    fx_env(&envs[1], 512, 256, sky_gradient);
    const float alphas[] = {0, 1, 10, 100}, nvs[] = {1.0f, 0.6f, 0.2f}, kss[] = {0.04f, 1.0f};
    const int ns[] = {16, 64, 256, 1024};
    double sq[4] = {0}, worst[4] = {0}, sq_consistent = 0;
    int cases = 0;
    for (int e = 0; e < 2; e++) {
        sl_ground_truth gt;
        sl_error err;
        assert_true(sl_ground_truth_init(&gt, &envs[e], &err));
        for (int a = 0; a < 4; a++)
            for (int i = 0; i < 3; i++)
                for (int k = 0; k < 2; k++) {
                    vec3 n = vec3(0, 0, 1), v = fx_view_dir(nvs[i], 0.8f);
                    sl_gbuffer_texel t = fx_texel(n, vec3s(0), vec3s(kss[k]), alphas[a]);
                    double truth = fx_truth(&gt, n, v, t, false, true);
                    assert_true(truth > 0.0);
                    for (int j = 0; j < 4; j++) {
                        sl_lighting_options o = {.samples = ns[j], .no_diffuse = true, .lod_rule = SL_LOD_NONE,
                                                 .estimator = SL_ESTIMATOR_MICROFACET};
                        sl_lighting_uniforms *u = fx_uniforms(&envs[e], NULL, o, scale(v, 10.0f), 1, 1);
                        double rel = fabs(fx_shade(u, t).x - truth) / truth;
                        sq[j] += rel * rel;
                        worst[j] = fmax(worst[j], rel);
                        free(u);
                        if (j == 2) {
                            o.estimator = SL_ESTIMATOR_CONSISTENT;
                            u = fx_uniforms(&envs[e], NULL, o, scale(v, 10.0f), 1, 1);
                            double rc = (fx_shade(u, t).x - truth) / truth;
                            sq_consistent += rc * rc;
                            free(u);
                        }
                    }
                    cases++;
                }
        sl_ground_truth_free(&gt);
    }
    double rms[4];
    for (int j = 0; j < 4; j++) {
        rms[j] = sqrt(sq[j] / cases);
        print_message("microfacet vs truth, %d cases, N = %3d: RMS relative error %.3g, worst %.3g\n", cases, ns[j],
                      rms[j], worst[j]);
    }
    print_message("consistent vs truth, same cases, N = 256: RMS relative error %.3g\n", sqrt(sq_consistent / cases));
    for (int j = 1; j < 4; j++)
        assert_true(rms[j] < 0.6 * rms[j - 1]);
    assert_true(rms[2] < 8e-3 && worst[2] < 3e-2);
    assert_true(rms[3] < 1.5e-3 && worst[3] < 6e-3);
    sl_env_free(&envs[0]);
    sl_env_free(&envs[1]);
}

/* One point light straight above, eye on the axis: L = V = H = N, so L.H = 1, F = Ks, G term 1,
 * D = (alpha+2)/(2 pi), and radiance = (Kd/pi + Ks (alpha+2)/(8 pi)) color I / d^2. */
static void test_point_light_hand_value(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 8, 4, fx_const_one);
    sl_point_light light = {.position = vec3(0, 0, 2), .color = vec3(1.0f, 0.5f, 0.25f), .intensity = 8.0f};
    sl_lighting_uniforms *u = malloc(sizeof *u);
    sl_error err;
    sl_lighting_desc d = {.options = {.no_diffuse = false, .no_specular = false}, .env = &env, .eye = vec3(0, 0, 5),
                          .width = 1, .height = 1, .lights = &light, .light_count = 1};
    /* environment off: diffuse and specular IBL need the toggles, so zero the intensity path by
     * comparing with and without the light instead */
    sl_irradiance irr;
    assert_true(sl_irradiance_sh9(&irr, &env, &err));
    d.irradiance = &irr;
    assert_true(sl_lighting_uniforms_init(u, &d, &err));
    sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0.5f), vec3s(0.04f), 20.0f);
    vec3 with = fx_shade(u, t);
    d.options.no_point_lights = true;
    assert_true(sl_lighting_uniforms_init(u, &d, &err));
    vec3 without = fx_shade(u, t);
    const double pi = 3.14159265358979;
    double f = 0.5 / pi + 0.04 * 22.0 / (8.0 * pi);
    assert_near(with.x - without.x, f * 1.0 * 8.0 / 4.0, 1e-5);
    assert_near(with.y - without.y, f * 0.5 * 8.0 / 4.0, 1e-5);
    /* a light below the surface adds nothing */
    light.position = vec3(0, 0, -2);
    d.options.no_point_lights = false;
    assert_true(sl_lighting_uniforms_init(u, &d, &err));
    vec3 below = fx_shade(u, t);
    assert_near(below.x, without.x, 0.0);
    free(u);
    sl_irradiance_free(&irr);
    sl_env_free(&env);
}

/* Empty pixels show the environment at lod 0 in the view direction, times the intensity. */
static vec3 by_direction(vec3 d) { return vec3(1.0f + d.x, 1.0f + d.y, 1.0f + d.z); }
static void test_background(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 256, 128, by_direction);
    sl_camera cam = {.eye = vec3(0, 0, 0), .target = vec3(1, 0, 0), .up = vec3(0, 0, 1), .fovy_deg = 60,
                     .znear = 0.1f, .zfar = 10};
    fx_frame f;
    fx_frame_spheres(&f, &env, &cam, NULL, 0, 33, 33);
    sl_lighting_desc d = fx_frame_desc(&f, (sl_lighting_options){.no_diffuse = true, .env_intensity = 2.0f});
    sl_image out = {0};
    sl_lighting_stats st;
    fx_render(&d, &f.gb, 1, &out, &st);
    assert_int_equal(st.background, 33 * 33);
    /* centre pixel looks along +X: (1 + 1, 1, 1) * 2, to the bilinear filter's accuracy */
    float *p = sl_image_pixel(&out, 16, 16);
    assert_near(p[0], 4.0, 0.02);
    assert_near(p[1], 2.0, 0.02);
    assert_near(p[2], 2.0, 0.02);
    /* the top row of the image looks up (z > 0): row 0 = top after the flip */
    assert_true(sl_image_pixel(&out, 16, 0)[2] > 2.0f + 0.5f);
    assert_true(sl_image_pixel(&out, 16, 32)[2] < 2.0f - 0.5f);
    sl_image_free(&out);
    fx_frame_teardown(&f);
    sl_env_free(&env);
}

/* Pass with 1 and 2 threads: bitwise identical; the per-alpha cache (task) gives the same bits
 * as recomputing per pixel (task NULL); image row 0 is G-buffer row height-1. */
static void test_determinism(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 128, 64, sky_gradient);
    fx_frame f;
    fx_frame_setup(&f, &env, 96, 64, 5000.0f);
    sl_point_light light = {.position = vec3(2, -3, 3), .color = vec3s(1), .intensity = 10};
    sl_lighting_desc d = fx_frame_desc(&f, (sl_lighting_options){.samples = 20});
    d.lights = &light;
    d.light_count = 1;
    sl_lighting_uniforms *u = fx_uniforms_for(&d);
    sl_image a = {0};
    sl_lighting_stats sa;
    fx_assert_same_for_thread_counts(u, &f.gb, &a, &sa);
    assert_int_equal(sa.pixels, 96 * 64);
    assert_int_equal(sa.nonfinite, 0);
    assert_true(sa.background > 0 && sa.background < 96 * 64);
    for (int y = 0; y < 64; y += 7)
        for (int x = 0; x < 96; x += 5) {
            vec3 c = sl_lighting_shade(u, &f.gb, x, y, NULL, NULL);
            float *p = sl_image_pixel(&a, x, 63 - y);
            assert_memory_equal(&c.x, &p[0], sizeof(float));
            assert_memory_equal(&c.y, &p[1], sizeof(float));
            assert_memory_equal(&c.z, &p[2], sizeof(float));
        }
    sl_image_free(&a);
    free(u);
    fx_frame_teardown(&f);
    sl_env_free(&env);
}

/* ---- tone map ---- */
static void test_tonemap_values(void **state)
{
    (void)state;
    /* e C = 1 -> x = 1/2 */
    assert_near(sl_tonemap_value(1.0f, 1.0f, 1.0f, false), pow(0.5, 1 / 2.2), 1e-6);
    assert_near(sl_tonemap_value(0.01f, 100.0f, 1.0f, false), pow(0.5, 1 / 2.2), 1e-6);
    assert_near(sl_tonemap_value(1.0f, 1.0f, 2.0f, false), pow(0.5, 2 / 2.2), 1e-6);
    assert_near(sl_tonemap_value(1.0f, 1.0f, 1.0f, true), 1.055 * pow(0.5, 1 / 2.4) - 0.055, 1e-6);
    assert_near(sl_tonemap_value(1.0f, 1.0f, 2.0f, true), 1.055 * pow(0.25, 1 / 2.4) - 0.055, 1e-6);
    assert_near(sl_tonemap_value(3.0f, 1.0f, 1.0f, false), pow(0.75, 1 / 2.2), 1e-6);
    /* guards: negative, NaN -> 0; +Inf -> 1 */
    assert_near(sl_tonemap_value(-1.0f, 1.0f, 1.0f, false), 0.0, 0.0);
    assert_near(sl_tonemap_value(NAN, 1.0f, 1.0f, false), 0.0, 0.0);
    assert_near(sl_tonemap_value(INFINITY, 1.0f, 1.0f, false), 1.0, 0.0);
    assert_near(sl_tonemap_value(3e38f, 10000.0f, 1.0f, false), 1.0, 0.0);
    /* the curves */
    assert_near(sl_linear_to_srgb(0.0031308f), 0.04045, 1e-5);
    assert_near(sl_srgb_to_linear(0.04045f), 0.0031308, 1e-6);
    assert_near(sl_linear_to_srgb(1.0f), 1.0, 1e-6);
    assert_near(sl_srgb_to_linear(0.5f), 0.214041, 1e-5);
    assert_near(sl_gamma_to_linear(0.5f), pow(0.5, 2.2), 1e-6);
    assert_near(sl_linear_to_gamma(0.5f), pow(0.5, 1 / 2.2), 1e-6);
    for (int i = 0; i <= 100; i++) {
        float c = (float)i / 100.0f;
        assert_near(sl_srgb_to_linear(sl_linear_to_srgb(c)), c, 1e-5);
        assert_near(sl_gamma_to_linear(sl_linear_to_gamma(c)), c, 1e-5);
    }
}

static void test_tonemap_image(void **state)
{
    (void)state;
    sl_image in = {0}, out = {0};
    sl_error err;
    assert_true(sl_image_alloc(&in, 4, 2, 3, &err));
    const float vals[] = {0, 1e-4f, 0.1f, 1, 10, 1000, 30000, -2};
    for (int i = 0; i < 8; i++)
        for (int c = 0; c < 3; c++)
            in.data[3 * i + c] = vals[i];
    const float exposures[] = {0.1f, 1.0f, 10000.0f};
    for (int e = 0; e < 3; e++) {
        sl_tonemap_options o = {.exposure = exposures[e]};
        assert_true(sl_tonemap_image(&in, &out, &o, 0, &err));
        for (int i = 0; i < 8; i++) {
            float v = out.data[3 * i];
            assert_true(v >= 0.0f && v <= 1.0f);
            /* the display image holds the exact curve's 8-bit code (tonemap.h; test_tonemap) */
            int code = sl_unorm8(sl_tonemap_value(vals[i], exposures[e], 1.0f, false));
            assert_true(v == (float)code / 255.0f);
        }
        for (int i = 1; i < 7; i++) /* monotone over the increasing inputs */
            assert_true(out.data[3 * i] >= out.data[3 * (i - 1)]);
    }
    assert_false(sl_tonemap_image(&in, &out, &(sl_tonemap_options){.exposure = -1}, 0, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_true(sl_tonemap_image(&in, &in, NULL, 0, &err)); /* in place */
    sl_image_free(&in);
    sl_image_free(&out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_brdf_hand_values),
        cmocka_unit_test(test_brdf_D_normalised),
        cmocka_unit_test(test_sample_density),
        cmocka_unit_test(test_hammersley_std140),
        cmocka_unit_test(test_options_resolve_and_names),
        cmocka_unit_test(test_white_furnace_diffuse),
        cmocka_unit_test(test_white_furnace_full),
        cmocka_unit_test(test_consistent_vs_truth),
        cmocka_unit_test(test_spec_estimator_bias),
        cmocka_unit_test(test_microfacet_sample_density),
        cmocka_unit_test(test_microfacet_vs_truth),
        cmocka_unit_test(test_point_light_hand_value),
        cmocka_unit_test(test_background),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_tonemap_values),
        cmocka_unit_test(test_tonemap_image),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
