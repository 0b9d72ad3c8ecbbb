/* test_splitsum.c - the split-sum estimator (--estimator splitsum): the BRDF table's entries
 * against closed forms, the prefiltered chain of a constant environment, a shaded pixel under
 * a constant environment against the ground truth's white-furnace albedo, and the wide lobes
 * under a lit environment: their widest level against a finely sampled build, their shading
 * against the ground truth, and --estimator cv (the split sum as a control variate): the white
 * furnace and its convergence to the ground truth (src/ibl/prefilter.c, src/shading/splitsum_lut.c,
 * lighting.c's specular_splitsum and specular_cv). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "shading_fixtures.h"
#include "shading/splitsum_lut.h"

/* A + B is the albedo with Ks = 1 (F = 1). At N.V = 1:
 *  - GGX: the directional albedo of docs/conventions.md, erratum 11 (0.99569, 0.91581,
 *    0.62689, 1 - ln 2 at r 0.25 .. 1);
 *  - the Phong set with G' = 1 (--g one): f = D / 4, and by hand
 *    integral of D(H)/4 (N.L) dL = (alpha + 2^(-alpha/2)) / (alpha + 4)
 *    (dL = 4 (V.H) dH, N.L = 2 (N.H)^2 - 1 > 0 for N.H > 2^-1/2).
 * 256 Hammersley samples (the table's count) leave at most 0.3% here. */
static void test_albedo_closed_forms(void **state)
{
    (void)state;
    const float r[] = {0.25f, 0.5f, 0.75f, 1.0f};
    const double ggx[] = {0.99569, 0.91581, 0.62689, 0.30685};
    for (int i = 0; i < 4; i++) {
        vec2 ab = sl_splitsum_albedo(SL_SPLITSUM_GGX, 1.0f, r[i], SL_SPLITSUM_LUT_SAMPLES);
        double got = (double)ab.x + (double)ab.y;
        printf("GGX r %.2f: A + B %.5f, expected %.5f\n", (double)r[i], got, ggx[i]);
        assert_true(fabs(got - ggx[i]) < 3e-3 * ggx[i]);
    }
    const float rp[] = {0.3f, 0.6f, 1.0f};
    for (int i = 0; i < 3; i++) {
        double a = (double)fminf(sl_ggx_phong_equivalent(rp[i]), 1e7f);
        double want = (a + pow(2.0, -a / 2.0)) / (a + 4.0);
        vec2 ab = sl_splitsum_albedo(SL_SPLITSUM_PHONG_ONE, 1.0f, rp[i], SL_SPLITSUM_LUT_SAMPLES);
        double got = (double)ab.x + (double)ab.y;
        printf("Phong alpha %.4g (g one): A + B %.5f, expected %.5f\n", a, got, want);
        assert_true(fabs(got - want) < 3e-3 * want);
    }
    /* the width of a Phong exponent inverts the equal-peak exponent of a width */
    assert_float_equal(sl_splitsum_width(sl_ggx_phong_equivalent(0.5f)), 0.5f, 1e-5f);
    assert_float_equal(sl_splitsum_width(sl_ggx_alpha_of_roughness(0.3f)), 0.3f, 1e-6f);
}

static vec3 const_two(vec3 d)
{
    (void)d;
    return vec3s(2.0f);
}

/* A constant environment L = 2: every level of both chains is 2 (a weighted mean of a constant,
 * to float rounding), and a shaded pixel's specular is 2 (Ks A + B), which the ground truth's
 * exact integral of the same BRDF matches to within the table's interpolation and sampling: 1%
 * (measured: at most 0.44% over these cases). The map is 256x128: on 64x32 the truth's own
 * quadrature is 2.5% off at r = 0.3 (texels wider than the lobe, docs/conventions.md, erratum 11). */
static void test_constant_environment(void **state)
{
    (void)state;
    sl_env env, phong, ggx;
    sl_error err;
    fx_env(&env, 256, 128, const_two);
    assert_true(sl_env_prefilter(&phong, &env, &(sl_prefilter_desc){.ggx = false}, &err));
    assert_true(sl_env_prefilter(&ggx, &env, &(sl_prefilter_desc){.ggx = true}, &err));
    assert_int_equal(phong.level_count, SL_PREFILTER_LEVELS);
    for (int k = 0; k < phong.level_count; k++) {
        size_t n = (size_t)phong.levels[k].width * (size_t)phong.levels[k].height;
        assert_int_equal(phong.levels[k].width, 256 >> k);
        for (size_t t = 0; t < n; t++) {
            assert_float_equal(phong.levels[k].texels[t].y, 2.0f, 1e-5f);
            assert_float_equal(ggx.levels[k].texels[t].y, 2.0f, 1e-5f);
        }
    }
    sl_splitsum_lut *lut = malloc(sizeof *lut);
    assert_non_null(lut);
    sl_splitsum_lut_build(lut, 0);
    sl_ground_truth gt;
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    const float nvs[] = {1.0f, 0.7f, 0.3f};
    const float alphas[] = {sl_ggx_alpha_of_roughness(0.3f), sl_ggx_alpha_of_roughness(0.7f), 20.0f, 200.0f};
    for (int plain = 0; plain < 2; plain++)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 4; j++) {
                vec3 v = fx_view_dir(nvs[i], 0.3f);
                sl_lighting_desc d = {
                    .options = {.estimator = SL_ESTIMATOR_SPLITSUM, .no_diffuse = true, .plain = plain},
                    .env = &env, .eye = scale(v, 10.0f), .inv_view_proj = mat4_identity(), .width = 1, .height = 1,
                    .splitsum_phong = &phong, .splitsum_ggx = &ggx, .splitsum_lut = lut};
                sl_lighting_uniforms *u = fx_uniforms_for(&d);
                sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3s(0.0f), vec3s(0.04f), alphas[j]);
                vec3 c = fx_shade(u, t);
                sl_gt_query q = {.n = vec3(0, 0, 1), .v = v, .kd = t.kd, .ks = t.ks, .alpha = alphas[j] < 0 ? 0 : alphas[j],
                                 .ggx = alphas[j] < 0, .roughness = -1.0 - (double)alphas[j], .g = SL_GT_G_INV_LH2,
                                 .intensity = 1.0};
                sl_gt_result res;
                assert_true(sl_ground_truth_shade(&gt, &q, &res, &err));
                double truth = res.specular[0];
                printf("%s N.V %.1f alpha %g: split sum %.5f, truth %.5f (%+.2f%%)\n", plain ? "plain" : "batched",
                       (double)nvs[i], (double)alphas[j], (double)c.x, truth, 100.0 * ((double)c.x / truth - 1.0));
                assert_true(fabs((double)c.x - truth) < 0.01 * truth);
                free(u);
            }
    sl_ground_truth_free(&gt);
    free(lut);
    sl_env_free(&phong);
    sl_env_free(&ggx);
    sl_env_free(&env);
}

/* A studio-like environment: a dim sky over a darker ground and a bright soft box (a cosine
 * power lobe about 25 degrees wide), so a rough lobe's mean depends on where it points. */
static vec3 soft_box(vec3 d)
{
    vec3 s = normalize(vec3(-0.6f, -0.7f, 0.4f));
    float c = fmaxf(dot(d, s), 0.0f);
    float c2 = c * c, c4 = c2 * c2;
    float sky = d.z > 0.0f ? 0.4f + 0.3f * d.z : 0.15f;
    return vec3s(sky + 12.0f * c4 * c4);
}

/* The two widest levels (r = 0.8, 1) against a chain prefiltered with the most samples at every
 * level: the same integral, so what differs is the default build's sampling error, which a rough
 * sphere shows as blotches and row-to-row streaks. RMS over a level relative to its mean:
 * at most 0.35% with the sample count doubling per level (prefilter.c, 512 and 1024 samples
 * there); 64 samples at every level left 10% at r = 1. */
static void test_widest_level_sampling(void **state)
{
    (void)state;
    sl_env env, def, fine;
    sl_error err;
    fx_env(&env, 256, 128, soft_box);
    for (int ggx = 0; ggx < 2; ggx++) {
        assert_true(sl_env_prefilter(&def, &env, &(sl_prefilter_desc){.ggx = ggx}, &err));
        assert_true(sl_env_prefilter(&fine, &env, &(sl_prefilter_desc){.ggx = ggx, .samples = SL_HAMMERSLEY_MAX}, &err));
        for (int k = def.level_count - 2; k < def.level_count; k++) {
            const sl_env_level *a = &def.levels[k], *b = &fine.levels[k];
            size_t n = (size_t)a->width * (size_t)a->height;
            double se = 0.0, sum = 0.0;
            for (size_t t = 0; t < n; t++) {
                double e = (double)a->texels[t].x - (double)b->texels[t].x;
                se += e * e;
                sum += (double)b->texels[t].x;
            }
            double rel = sqrt(se / (double)n) / (sum / (double)n);
            printf("%s chain, level %d (r = %.1f): RMS against %d samples %.3f%% of the mean\n", ggx ? "GGX" : "Phong",
                   k, (double)sl_prefilter_width(k, def.level_count), SL_HAMMERSLEY_MAX, 100.0 * rel);
            assert_true(rel < 0.005);
        }
        sl_env_free(&def);
        sl_env_free(&fine);
    }
    sl_env_free(&env);
}

/* Rough lobes (Phong alpha 1 and 4, GGX r 0.8 and 1) under soft_box against the ground truth, at
 * N.V 1, 0.7, 0.4 and three view azimuths (the soft box in front, beside, behind), on a
 * 1024x512 map (the shipped maps' size: the chain's levels are the map's mip sizes): the lobe as
 * the prefilter weights it (G' (N.w), prefilter.c) read towards its centroid (the table's t,
 * splitsum_lut.h). Measured: within 1.9% at normal view (the table and F's variation), mean
 * |error| 10.8% over all cases, worst 39% (N.V 0.4: the chain's lobe is round, the true one is
 * not; 6.5% and 25% with the whole shift to the centroid, which does worse on ggx.json's
 * mid-rough spheres, splitsum_lut.c). Karis' form (N.w weights, the lookup along R, 64 samples at every level) gave 6.0% at
 * normal view, a mean of 45% and a worst of 238% (a grazing lookup along R into the dark side). */
static void test_wide_lobes_against_truth(void **state)
{
    (void)state;
    sl_env env, phong, ggx;
    sl_error err;
    fx_env(&env, 1024, 512, soft_box);
    assert_true(sl_env_prefilter(&phong, &env, &(sl_prefilter_desc){.ggx = false}, &err));
    assert_true(sl_env_prefilter(&ggx, &env, &(sl_prefilter_desc){.ggx = true}, &err));
    sl_splitsum_lut *lut = malloc(sizeof *lut);
    assert_non_null(lut);
    sl_splitsum_lut_build(lut, 0);
    sl_ground_truth gt;
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    const float nvs[] = {1.0f, 0.7f, 0.4f};
    const float phis[] = {-2.3f, -0.6f, 0.9f};
    const float alphas[] = {1.0f, 4.0f, sl_ggx_alpha_of_roughness(0.8f), sl_ggx_alpha_of_roughness(1.0f)};
    double sum = 0.0, worst = 0.0, worst_normal = 0.0;
    int cases = 0;
    /* the normal tilted 50 degrees off the pole (the chain's coarse levels are poor exactly at
     * the pole: their first row is r = 1's 8x4 level's 22 degrees away); v from fx_view_dir's
     * frame about +Z turned with it about Y */
    const float ct = cosf(0.87f), st = sinf(0.87f);
    const vec3 n = vec3(st, 0.0f, ct);
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 4; j++) {
                vec3 v0 = fx_view_dir(nvs[i], phis[k]);
                vec3 v = vec3(ct * v0.x + st * v0.z, v0.y, -st * v0.x + ct * v0.z);
                sl_lighting_desc d = {
                    .options = {.estimator = SL_ESTIMATOR_SPLITSUM, .no_diffuse = true},
                    .env = &env, .eye = scale(v, 10.0f), .inv_view_proj = mat4_identity(), .width = 1, .height = 1,
                    .splitsum_phong = &phong, .splitsum_ggx = &ggx, .splitsum_lut = lut};
                sl_lighting_uniforms *u = fx_uniforms_for(&d);
                sl_gbuffer_texel t = fx_texel(n, vec3s(0.0f), vec3s(0.9f), alphas[j]);
                vec3 c = fx_shade(u, t);
                sl_gt_query q = {.n = n, .v = v, .kd = t.kd, .ks = t.ks, .alpha = alphas[j] < 0 ? 0 : alphas[j],
                                 .ggx = alphas[j] < 0, .roughness = -1.0 - (double)alphas[j], .g = SL_GT_G_INV_LH2,
                                 .intensity = 1.0};
                sl_gt_result res;
                assert_true(sl_ground_truth_shade(&gt, &q, &res, &err));
                double e = fabs((double)c.x / res.specular[0] - 1.0);
                printf("N.V %.1f phi %+.1f alpha %g: split sum %.5f, truth %.5f (%.1f%%)\n", (double)nvs[i],
                       (double)phis[k], (double)alphas[j], (double)c.x, res.specular[0], 100.0 * e);
                sum += e;
                worst = fmax(worst, e);
                if (nvs[i] == 1.0f)
                    worst_normal = fmax(worst_normal, e);
                cases++;
                free(u);
            }
    printf("wide lobes: mean |error| %.2f%%, worst %.2f%%, worst at normal view %.2f%%\n", 100.0 * sum / cases,
           100.0 * worst, 100.0 * worst_normal);
    assert_true(worst_normal < 0.03);
    assert_true(sum / cases < 0.15);
    sl_ground_truth_free(&gt);
    free(lut);
    sl_env_free(&phong);
    sl_env_free(&ggx);
    sl_env_free(&env);
}

/* One pixel's specular term at normal n seen from v (the shading of test_constant_environment). */
static vec3 shade_one(sl_env *env, sl_env *phong, sl_env *ggx, sl_splitsum_lut *lut, sl_lighting_options o, vec3 n,
                      vec3 v, float ks, float alpha)
{
    o.no_diffuse = true;
    sl_lighting_desc d = {.options = o, .env = env, .eye = scale(v, 10.0f), .inv_view_proj = mat4_identity(),
                          .width = 1, .height = 1, .splitsum_phong = phong, .splitsum_ggx = ggx, .splitsum_lut = lut};
    sl_lighting_uniforms *u = fx_uniforms_for(&d);
    vec3 c = fx_shade(u, fx_texel(n, vec3s(0.0f), vec3s(ks), alpha));
    free(u);
    return c;
}

/* --estimator cv under a constant environment (the white furnace): every sample reads Lbar, so
 * the correction is 0 and cv equals the split sum, which equals the ground truth's albedo
 * (test_constant_environment). Both paths, N = 16, rough to sharp lobes, N.V 1 .. 0.3. */
static void test_cv_white_furnace(void **state)
{
    (void)state;
    sl_env env, phong, ggx;
    sl_error err;
    fx_env(&env, 256, 128, const_two);
    assert_true(sl_env_prefilter(&phong, &env, &(sl_prefilter_desc){.ggx = false}, &err));
    assert_true(sl_env_prefilter(&ggx, &env, &(sl_prefilter_desc){.ggx = true}, &err));
    sl_splitsum_lut *lut = malloc(sizeof *lut);
    assert_non_null(lut);
    sl_splitsum_lut_build(lut, 0);
    const float nvs[] = {1.0f, 0.7f, 0.3f};
    const float alphas[] = {1.0f, 200.0f, sl_ggx_alpha_of_roughness(0.3f), sl_ggx_alpha_of_roughness(1.0f)};
    for (int plain = 0; plain < 2; plain++)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 4; j++) {
                vec3 v = fx_view_dir(nvs[i], 0.3f);
                sl_lighting_options o = {.estimator = SL_ESTIMATOR_CV, .samples = 16, .lod_rule = SL_LOD_PDF, .plain = plain};
                vec3 cv = shade_one(&env, &phong, &ggx, lut, o, vec3(0, 0, 1), v, 0.5f, alphas[j]);
                o.estimator = SL_ESTIMATOR_SPLITSUM;
                vec3 ss = shade_one(&env, &phong, &ggx, lut, o, vec3(0, 0, 1), v, 0.5f, alphas[j]);
                assert_true(fabsf(cv.x - ss.x) <= 1e-5f * ss.x);
            }
    free(lut);
    sl_env_free(&phong);
    sl_env_free(&ggx);
    sl_env_free(&env);
}

/* --estimator cv converges to the ground truth as N grows: soft_box (256x128), lod none (the
 * samples read level 0, as the truth does, up to its bilinear filter), the mean |error| over rough
 * and medium lobes and three views. Measured: 29.0%, 6.6%, 1.4%, 0.53% at N = 4, 16, 64, 256. */
static void test_cv_converges(void **state)
{
    (void)state;
    sl_env env, phong, ggx;
    sl_error err;
    fx_env(&env, 256, 128, soft_box);
    assert_true(sl_env_prefilter(&phong, &env, &(sl_prefilter_desc){.ggx = false}, &err));
    assert_true(sl_env_prefilter(&ggx, &env, &(sl_prefilter_desc){.ggx = true}, &err));
    sl_splitsum_lut *lut = malloc(sizeof *lut);
    assert_non_null(lut);
    sl_splitsum_lut_build(lut, 0);
    sl_ground_truth gt;
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    const float ct = cosf(0.87f), st = sinf(0.87f);
    const vec3 n = vec3(st, 0.0f, ct);
    const float nvs[] = {0.9f, 0.6f, 0.35f};
    const float alphas[] = {1.0f, 20.0f, sl_ggx_alpha_of_roughness(0.5f), sl_ggx_alpha_of_roughness(0.9f)};
    const int ns[] = {4, 16, 64, 256};
    double errs[4] = {0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++) {
            vec3 v0 = fx_view_dir(nvs[i], 0.9f);
            vec3 v = vec3(ct * v0.x + st * v0.z, v0.y, -st * v0.x + ct * v0.z);
            sl_gt_query q = {.n = n, .v = v, .kd = vec3s(0.0f), .ks = vec3s(0.9f), .alpha = alphas[j] < 0 ? 0 : alphas[j],
                             .ggx = alphas[j] < 0, .roughness = -1.0 - (double)alphas[j], .g = SL_GT_G_INV_LH2,
                             .intensity = 1.0};
            sl_gt_result res;
            assert_true(sl_ground_truth_shade(&gt, &q, &res, &err));
            for (int k = 0; k < 4; k++) {
                sl_lighting_options o = {.estimator = SL_ESTIMATOR_CV, .samples = ns[k], .lod_rule = SL_LOD_NONE};
                vec3 c = shade_one(&env, &phong, &ggx, lut, o, n, v, 0.9f, alphas[j]);
                errs[k] += fabs((double)c.x / res.specular[0] - 1.0) / 12.0;
            }
        }
    for (int k = 0; k < 4; k++)
        printf("cv N = %d: mean |error| against the truth %.2f%%\n", ns[k], 100.0 * errs[k]);
    for (int k = 1; k < 4; k++)
        assert_true(errs[k] < 0.6 * errs[k - 1]);
    assert_true(errs[3] < 0.01);
    sl_ground_truth_free(&gt);
    free(lut);
    sl_env_free(&phong);
    sl_env_free(&ggx);
    sl_env_free(&env);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_albedo_closed_forms),
        cmocka_unit_test(test_constant_environment),
        cmocka_unit_test(test_widest_level_sampling),
        cmocka_unit_test(test_wide_lobes_against_truth),
        cmocka_unit_test(test_cv_white_furnace),
        cmocka_unit_test(test_cv_converges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
