/* test_lighting_splitsum.c - the split-sum estimator's fast path (src/shading/lighting_splitsum.c),
 * and cv's batched path (the split sum as a control variate, lighting_batched.c), against the plain port (lighting.c's specular_splitsum, options.plain) over the options it
 * reads, on spheres that mix the Phong and GGX sets (so spans use both prefiltered chains), with
 * and without point lights, with the chains' compact texels and without; and its guarantees:
 * 1 and 2 threads, sl_lighting_shade per pixel, a row and the trace's total agree bit for bit. */
#include <stdio.h>

#include "core/fast_math.h"
#include "shading/lighting_internal.h"
#include "shading/splitsum_lut.h"
#include "ibl/env_dist.h"
#include "shading_fixtures.h"

/* A sharp environment: a gradient with a bright disc (200x), so uv and level errors show. */
static vec3 sky_with_sun(vec3 d)
{
    vec3 s = normalize(vec3(0.3f, -0.8f, 0.5f));
    vec3 c = vec3(1.0f + d.z, 0.5f + 0.25f * d.x, 2.0f - d.z);
    return dot(d, s) > 0.97f ? scale(c, 200.0f) : c;
}

typedef struct {
    sl_env env, phong, ggx;
    sl_splitsum_lut *lut;
    fx_frame f;
    sl_point_light lights[2];
} ss_fixture;

/* Five spheres, left to right GGX r 0.1 (metal), GGX r 0.5, Phong 80, Phong 1, GGX r 1, close
 * enough that rows cross from one set to the other inside a span. */
static void ss_setup(ss_fixture *s, int w, int h)
{
    sl_error err;
    fx_env(&s->env, 256, 128, sky_with_sun);
    assert_true(sl_env_prefilter(&s->phong, &s->env, &(sl_prefilter_desc){.ggx = false}, &err));
    assert_true(sl_env_prefilter(&s->ggx, &s->env, &(sl_prefilter_desc){.ggx = true}, &err));
    s->lut = malloc(sizeof *s->lut);
    assert_non_null(s->lut);
    sl_splitsum_lut_build(s->lut, 0);
    sl_camera cam = {.eye = vec3(0, -7, 1), .target = vec3(0, 0, 0), .up = vec3(0, 0, 1), .fovy_deg = 50,
                     .znear = 0.1f, .zfar = 100};
    sl_synthetic_sphere sp[5] = {
        {vec3(-2.4f, 0, 0), 0.62f, vec3s(0.0f), vec3(0.95f, 0.64f, 0.54f), sl_gbuffer_ggx_alpha(0.1f)},
        {vec3(-1.2f, 0, 0), 0.62f, vec3(0.2f, 0.2f, 0.2f), vec3s(0.04f), sl_gbuffer_ggx_alpha(0.5f)},
        {vec3(0, 0, 0), 0.62f, vec3(0.8f, 0.2f, 0.2f), vec3s(0.5f), 80.0f},
        {vec3(1.2f, 0, 0), 0.62f, vec3s(0.1f), vec3s(0.9f), 1.0f},
        {vec3(2.4f, 0, 0), 0.62f, vec3(0.2f, 0.2f, 0.2f), vec3s(0.04f), sl_gbuffer_ggx_alpha(1.0f)},
    };
    fx_frame_spheres(&s->f, &s->env, &cam, sp, 5, w, h);
    s->lights[0] = (sl_point_light){.position = vec3(-3, -4, 4), .color = vec3(1.0f, 0.9f, 0.7f), .intensity = 200};
    s->lights[1] = (sl_point_light){.position = vec3(3, -2, 0.5f), .color = vec3(0.3f, 0.5f, 1.0f), .intensity = 60};
}

static void ss_teardown(ss_fixture *s)
{
    fx_frame_teardown(&s->f);
    free(s->lut);
    sl_env_free(&s->phong);
    sl_env_free(&s->ggx);
    sl_env_free(&s->env);
}

static sl_lighting_desc ss_desc(const ss_fixture *s, sl_lighting_options o, int lights)
{
    o.estimator = SL_ESTIMATOR_SPLITSUM;
    sl_lighting_desc d = fx_frame_desc(&s->f, o);
    d.splitsum_phong = &s->phong;
    d.splitsum_ggx = &s->ggx;
    d.splitsum_lut = s->lut;
    d.lights = s->lights;
    d.light_count = lights;
    return d;
}

/* The chain's compact rows (sl_env.e5) dropped: the fast path then reads the chain's float
 * block, the port's texels. */
static void drop_e5(sl_env *chain)
{
    free(chain->e5);
    chain->e5 = NULL;
}

/* The fast path against the port. They differ by the fast path's compact texels (the
 * prefiltered chains' e5 rows, src/ibl/texel_e5.h: each channel within 1/511.5 = 2^-9 of its
 * texel's largest channel, so a dim channel beside a bright one moves by more than 2^-9 of
 * itself; test_e5_fetch_bound holds the pass to the format's bound), by the fast atan2 in R's uv
 * (2.4e-7 rad, moving the trilinear fetch by ~1e-5 of a texel), the table's coordinates computed
 * without the uv round trip, and Phong's D of the point lights through log2/exp2 (3e-7
 * relative). Measured with the compact texels over the variants here and test_fast_vs_port_extra's:
 * worst pixel 4.8e-3 relative, mean 4.0e-5 (printed; no_diffuse the largest, the specular then
 * the whole pixel); tolerances 1e-2 worst and 1e-4 mean, 2x and 2.5x that, of the order of the
 * batched path's own bounds against the port for the same texels (5e-3 worst, 3e-4 mean).
 * Without them (`compact` false: the float block) everything but the texels is compared:
 * measured 4.4e-6 worst, mean 2e-8; tolerances 1e-4 and 1e-6, 25x the measurement. */
static void fast_vs_port(bool compact)
{
    const double max_bound = compact ? 1e-2 : 1e-4, mean_bound = compact ? 1e-4 : 1e-6;
    ss_fixture s;
    ss_setup(&s, 160, 64);
    assert_non_null(s.phong.e5);
    assert_non_null(s.ggx.e5);
    if (!compact) {
        drop_e5(&s.phong);
        drop_e5(&s.ggx);
    }
    const struct {
        sl_lighting_options o;
        int lights;
    } variants[] = {
        {{0}, 0},
        {{0}, 2},
        {{.gterm = SL_GTERM_ONE}, 2},
        {{.no_diffuse = true, .env_rotation_deg = 70.0f, .env_intensity = 2.0f}, 0},
        {{.no_specular = true}, 2},
        {{.no_point_lights = true, .env_rotation_deg = -25.0f}, 2},
    };
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        sl_lighting_desc d = ss_desc(&s, variants[v].o, variants[v].lights);
        sl_lighting_uniforms *u = fx_uniforms_for(&d);
        assert_true(sl_shade_splitsum_fast(u)); /* the fast path is what the pass runs */
        free(u);
        sl_image a = {0}, b = {0};
        fx_render(&d, &s.f.gb, 1, &a, NULL);
        d.options.plain = true;
        u = fx_uniforms_for(&d);
        assert_false(sl_shade_splitsum_fast(u));
        free(u);
        fx_render(&d, &s.f.gb, 1, &b, NULL);
        double mx, mean;
        fx_image_rel_diff(&a, &b, &mx, &mean);
        print_message("variant %zu, %s texels: split-sum fast vs port: max rel %.3g, mean rel %.3g\n", v,
                      compact ? "compact" : "float", mx, mean);
        assert_true(mean < mean_bound);
        assert_true(mx < max_bound);
        sl_image_free(&a);
        sl_image_free(&b);
    }
    ss_teardown(&s);
}

static void test_fast_vs_port(void **state)
{
    (void)state;
    fast_vs_port(true);
}

static void test_fast_vs_port_float_texels(void **state)
{
    (void)state;
    fast_vs_port(false);
}

/* The fast path with the compact texels against itself on the float block: the only
 * difference is the texels, so it is bounded by the format's (test_lighting_fast's
 * test_e5_fetch_bound, the spec path's). A fetched radiance P is a trilinear blend (weights >= 0,
 * sum 1) of texels whose channels are each within M_t / 511.5 of the float ones (M_t <= the
 * texel's r + g + b), so each channel of P is within (P_r + P_g + P_b) / 511.5 of the float
 * fetch's; the specular is P_c (Ks_c A + B) I, whose factor's ratio between channels is at most
 * max Ks / min Ks (A, B >= 0), 1.76 for the fixture's metal. So, specular only, |a_c - b_c| <=
 * 1.76 (b_r + b_g + b_b) / 511.5 per pixel, plus float rounding (1e-6 of the sum). */
static void test_e5_fetch_bound(void **state)
{
    (void)state;
    ss_fixture s;
    ss_setup(&s, 160, 64);
    const sl_lighting_options variants[] = {
        {.no_diffuse = true, .no_point_lights = true},
        {.no_diffuse = true, .no_point_lights = true, .env_rotation_deg = 70.0f, .env_intensity = 2.0f},
    };
    double worst = 0.0; /* the largest |a_c - b_c| / ((b_r + b_g + b_b) / 511.5) */
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        sl_lighting_desc d = ss_desc(&s, variants[v], 0);
        sl_image a = {0}, b = {0};
        fx_render(&d, &s.f.gb, 1, &a, NULL);
        sl_env phong = s.phong, ggx = s.ggx; /* the same chains without their compact rows */
        phong.e5 = NULL;
        ggx.e5 = NULL;
        d.splitsum_phong = &phong;
        d.splitsum_ggx = &ggx;
        fx_render(&d, &s.f.gb, 1, &b, NULL);
        int differ = 0;
        for (int k = 0; k < a.width * a.height; k++) {
            const float *pa = a.data + 3 * k, *pb = b.data + 3 * k;
            double sum = (double)pb[0] + (double)pb[1] + (double)pb[2];
            for (int c = 0; c < 3; c++) {
                double diff = fabs((double)pa[c] - (double)pb[c]);
                differ += diff > 0.0;
                assert_true(diff <= 1.76 * sum / 511.5 + 1e-6 * sum);
                if (sum > 0.0)
                    worst = fmax(worst, diff / (sum / 511.5));
            }
        }
        assert_true(differ > 0); /* the compact rows were read */
        sl_image_free(&a);
        sl_image_free(&b);
    }
    print_message("compact vs float texels: worst %.3g of (r + g + b) / 511.5 (bound 1.76)\n", worst);
    ss_teardown(&s);
}

/* The fast path against the port with the G-buffer's extra plane (occlusion and emission, read
 * by load_stage in a loop of its own): a pattern of both over the image, the same bounds as
 * test_fast_vs_port with the compact texels (measured max rel 4.8e-3, mean 3.4e-5); without
 * diffuse the emission is dropped (it travels with the diffuse term). */
static void test_fast_vs_port_extra(void **state)
{
    (void)state;
    ss_fixture s;
    sl_error err;
    ss_setup(&s, 160, 64);
    sl_gbuffer *gb = &s.f.gb;
    assert_true(sl_gbuffer_use_extra(gb, true, 0, &err));
    for (int y = 0; y < gb->height; y++)
        for (int x = 0; x < gb->width; x++) {
            sl_gbuffer_extra *e = &gb->extra[y * gb->width + x];
            e->occlusion = 0.25f + 0.125f * (float)((x + y) % 7);
            e->emissive = vec3(0.5f * (float)(x % 3), 0.25f * (float)(y % 5), (x % 11) == 0 ? 4.0f : 0.0f);
            e->depth = sl_gbuffer_at(gb, x, y)->depth;
        }
    const sl_lighting_options opts[] = {{0}, {.no_diffuse = true}, {.no_specular = true}};
    for (size_t v = 0; v < sizeof opts / sizeof opts[0]; v++) {
        sl_lighting_desc d = ss_desc(&s, opts[v], 2);
        sl_image a = {0}, b = {0};
        fx_render(&d, gb, 1, &a, NULL);
        d.options.plain = true;
        fx_render(&d, gb, 1, &b, NULL);
        double mx, mean;
        fx_image_rel_diff(&a, &b, &mx, &mean);
        print_message("extra plane, variant %zu: split-sum fast vs port: max rel %.3g, mean rel %.3g\n", v, mx, mean);
        assert_true(mean < 1e-4);
        assert_true(mx < 1e-2);
        sl_image_free(&a);
        sl_image_free(&b);
    }
    ss_teardown(&s);
}

/* The same bits from the pass on 1 and 2 threads, from sl_lighting_shade per pixel (with and
 * without a task), from a whole row, and from the trace (whose total is what the pass wrote, and
 * which records a split-sum lookup and the point lights). With env lights the batched path
 * runs instead (their exact term is its loop). */
static void test_fast_determinism(void **state)
{
    (void)state;
    enum { W = 100, H = 40 };
    ss_fixture s;
    ss_setup(&s, W, H);
    sl_error err;
    sl_lighting_desc d = ss_desc(&s, (sl_lighting_options){0}, 2);
    sl_lighting_uniforms *u = fx_uniforms_for(&d);
    sl_image p = {0};
    sl_lighting_stats st;
    fx_assert_same_for_thread_counts(u, &s.f.gb, &p, &st);
    assert_true(st.background > 0 && st.background < (int64_t)W * H); /* both kinds of pixel */
    sl_lighting_task *task = sl_lighting_task_create(&err);
    assert_non_null(task);
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    int covered = 0;
    int lit = 0; /* pixels where the point lights add at least 1% */
    for (int y = 0; y < H; y += 2)
        for (int x = 0; x < W; x += 3) {
            const float *px = sl_image_pixel(&p, x, H - 1 - y);
            vec3 c = sl_lighting_shade(u, &s.f.gb, x, y, NULL, NULL);
            assert_memory_equal(&c, px, sizeof(float) * 3);
            c = sl_lighting_shade(u, &s.f.gb, x, y, task, NULL);
            assert_memory_equal(&c, px, sizeof(float) * 3);
            assert_true(sl_lighting_trace_pixel(u, &s.f.gb, x, H - 1 - y, tr, &err));
            assert_memory_equal(&tr->total, px, sizeof(float) * 3);
            if (tr->covered) {
                covered++;
                assert_true(tr->splitsum);
                assert_int_equal(tr->sample_count, 0);
                /* the trace's terms add up to what was written (no occlusion, no emission here) */
                vec3 sum = add(add(tr->diffuse, tr->specular), tr->lights);
                lit += tr->lights.x > 0.01f * tr->total.x;
                assert_float_equal(sum.x, tr->total.x, 1e-5f * (1.0f + fabsf(tr->total.x)));
            }
        }
    assert_true(covered > 30);
    assert_true(lit > 10);
    vec3 row[W];
    sl_lighting_shade_row(u, &s.f.gb, 0, H / 2, W, NULL, row);
    assert_memory_equal(row, sl_image_pixel(&p, 0, H - 1 - H / 2), sizeof row);
    free(tr);
    sl_lighting_task_destroy(task);
    sl_image_free(&p);
    free(u);
    /* env lights: the fast path steps aside */
    sl_env_lights el;
    assert_true(sl_env_lights_extract(&el, &s.env, 8, 0, &err));
    s.f.env_lights = &el;
    d = ss_desc(&s, (sl_lighting_options){.env_lights = 8}, 0);
    u = fx_uniforms_for(&d);
    assert_false(sl_shade_splitsum_fast(u));
    free(u);
    sl_env_lights_free(&el);
    ss_teardown(&s);
}

/* The batched path against the port with d's options and `estimator`, within what the batched
 * samples differ by (core/fast_math.h's lod, uv and, for the Phong kernel, log2 and exp2), as
 * test_lighting_fast bounds for mf; and `estimator` is not `plain_estimator` (so its kernel ran).
 * With `rotated` also with the set rotated per pixel, where both run the port's loop. */
static void batched_vs_port(ss_fixture *s, sl_lighting_desc d, sl_estimator estimator, sl_estimator plain_estimator,
                            bool rotated)
{
    const char *name = sl_estimator_name(estimator);
    d.options.estimator = estimator;
    sl_image a = {0}, b = {0}, c = {0};
    double mx, mean;
    for (int rotate = 0; rotate <= (rotated ? 1 : 0); rotate++) {
        d.options.rotate = rotate;
        d.options.plain = false;
        fx_render(&d, &s->f.gb, 1, &a, NULL);
        d.options.plain = true;
        fx_render(&d, &s->f.gb, 1, &b, NULL);
        fx_image_rel_diff(&a, &b, &mx, &mean);
        print_message("%s%s batched vs port: max rel %.3g, mean rel %.3g\n", name, rotate ? " rotated," : "", mx, mean);
        assert_true(mean < 1e-4);
        assert_true(mx < (rotate ? 1e-5 : 1e-2));
    }
    d.options.estimator = plain_estimator;
    fx_render(&d, &s->f.gb, 1, &c, NULL);
    fx_image_rel_diff(&b, &c, &mx, &mean);
    print_message("%s against %s: max rel %.3g, mean rel %.3g\n", name, sl_estimator_name(plain_estimator), mx, mean);
    assert_true(mx > 1e-2);
    sl_image_free(&a);
    sl_image_free(&b);
    sl_image_free(&c);
}

/* --estimator cv (lighting.c specular_cv): the batched path (the port's cv_setup, the chain's
 * reads at the fast lat-long map's uv, the microfacet samples through the batched stages, the
 * kernel's term in a loop of its own) against the port, on the five spheres. Measured: max rel
 * 2.9e-3, mean rel 7.5e-6; against mf's image a max rel of 0.41. */
static void test_cv_batched_vs_port(void **state)
{
    (void)state;
    ss_fixture s;
    ss_setup(&s, 160, 64);
    sl_lighting_options o = {.samples = 16, .lod_rule = SL_LOD_PDF, .distortion = true};
    batched_vs_port(&s, ss_desc(&s, o, 2), SL_ESTIMATOR_CV, SL_ESTIMATOR_MICROFACET, false);
    ss_teardown(&s);
}

/* --estimator cvmis (lighting.c specular_cv with mis): the batched path (cv_samples' closed part, mis's
 * pairs through mis_samples with the kernel's terms in loops of their own) against the port, also
 * with the set rotated per pixel; and it is not mis's image. Measured: max rel 6.1e-7, rotated
 * 1.8e-7; against mis's image (rotated too) a max rel of 0.24. */
static void test_cvmis_batched_vs_port(void **state)
{
    (void)state;
    ss_fixture s;
    ss_setup(&s, 160, 64);
    sl_error err;
    sl_env_dist dist;
    assert_true(sl_env_dist_build(&dist, &s.env, &err));
    sl_lighting_desc d = ss_desc(&s, (sl_lighting_options){.samples = 16}, 2);
    d.env_dist = &dist;
    batched_vs_port(&s, d, SL_ESTIMATOR_CV_MIS, SL_ESTIMATOR_MIS, true);
    sl_env_dist_free(&dist);
    ss_teardown(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cv_batched_vs_port),
        cmocka_unit_test(test_cvmis_batched_vs_port),
        cmocka_unit_test(test_fast_vs_port),
        cmocka_unit_test(test_fast_vs_port_float_texels),
        cmocka_unit_test(test_e5_fetch_bound),
        cmocka_unit_test(test_fast_vs_port_extra),
        cmocka_unit_test(test_fast_determinism),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
