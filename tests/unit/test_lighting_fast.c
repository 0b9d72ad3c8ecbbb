/* test_lighting_fast.c - the lighting pass's batched fast path and the per-pixel rotation:
 * the fast transcendentals against double precision, the batched path against the plain port
 * (options.plain) over every option and all three estimators, the gathered fetch against the texel-by-texel one (bit for
 * bit), the Cranley-Patterson hash against hand values (the same values the GLSL computes:
 * tests/cli/gl_shading.sh renders with rotation on through both), rotation off leaving results
 * unchanged, and averaging rotated frames converging to the ground truth. */
#include "raster/gbuffer.h"
#include "shading_fixtures.h"
#include "core/fast_math.h"
#include "ibl/texture_lod.h"
#include "shading/lighting_trace.h"
#include "shading/lighting_internal.h"
#include "shading/splitsum_lut.h"
#include "ibl/env_dist.h"

#include <stdio.h>

static vec3 sky_gradient(vec3 d) { return vec3(1.0f + d.z, 0.5f + 0.25f * d.x, 2.0f - d.z); }

/* A sharper environment: a bright disc (a "sun", 200x) on the gradient, so lod and uv errors show. */
static vec3 sky_with_sun(vec3 d)
{
    vec3 s = normalize(vec3(0.3f, -0.8f, 0.5f));
    vec3 c = sky_gradient(d);
    return dot(d, s) > 0.97f ? scale(c, 200.0f) : c;
}

/* ---- core/fast_math.h and the fast lat-long map against double precision ---- */
static void test_fast_math(void **state)
{
    (void)state;
    const double pi = 3.14159265358979323846;
    double e_atan = 0, e_log = 0, e_exp = 0, e_u = 0, e_v = 0;
    for (int i = 0; i < 200000; i++) {
        double a = -pi + 2.0 * pi * (i + 0.5) / 200000.0;
        for (int s = 0; s < 3; s++) { /* unit circle, tiny and huge radii */
            double r = s == 0 ? 1.0 : (s == 1 ? 1e-20 : 1e20);
            float x = (float)(r * cos(a)), y = (float)(r * sin(a));
            double d = fabs((double)sl_fast_atan2(y, x) - atan2((double)y, (double)x));
            d = d > pi ? 2.0 * pi - d : d; /* +-pi are the same angle */
            e_atan = fmax(e_atan, d);
        }
        /* the lat-long map of a unit direction against its double-precision definition */
        double th = pi * (i + 0.5) / 200000.0, ph = 7.0 * a;
        float dx = (float)(sin(th) * cos(ph)), dy = (float)(sin(th) * sin(ph)), dz = (float)cos(th);
        float u, v;
        sl_fast_dir_to_uv(dx, dy, dz, &u, &v);
        assert_true(u >= 0.0f && u < 1.0f && v >= 0.0f && v <= 1.0f);
        double ut = 0.5 - atan2((double)dy, (double)dx) / (2.0 * pi);
        double du = fabs(u - (ut >= 1.0 ? ut - 1.0 : ut));
        e_u = fmax(e_u, du > 0.5 ? 1.0 - du : du);
        e_v = fmax(e_v, fabs(v - atan2(hypot((double)dx, (double)dy), (double)dz) / pi));
    }
    for (float x = 1e-30f; x <= 1.0f; x *= 1.0001f) {
        double t = log2((double)x);
        /* absolute near 0, relative (3 ulp of the result) elsewhere */
        e_log = fmax(e_log, fabs(sl_fast_log2(x) - t) / fmax(1.0, fabs(t)));
    }
    for (float x = -126.0f; x <= 127.0f; x += 0.001f) {
        double t = exp2((double)x);
        e_exp = fmax(e_exp, fabs(sl_fast_exp2(x) - t) / t);
    }
    for (float x = -1000.0f; x <= 1000.0f; x += 0.37f)
        assert_near(sl_fast_floor(x), floorf(x), 0.0);
    assert_near(sl_fast_floor(-0.5f), -1.0, 0.0);
    assert_near(sl_fast_floor(-1.0f), -1.0, 0.0);
    assert_near(sl_fast_atan2(0.0f, 0.0f), 0.0, 0.0);
    print_message("fast math max errors: atan2 %.3g rad, log2 %.3g (rel), exp2 %.3g (rel), u %.3g, v %.3g\n",
                  e_atan, e_log, e_exp, e_u, e_v);
    assert_true(e_atan < 3e-7);
    assert_true(e_log < 3e-7);
    assert_true(e_exp < 2e-7);
    assert_true(e_u < 1e-7);
    assert_true(e_v < 2e-7);
}

/* ---- the Cranley-Patterson hash: values worked out by an independent implementation (Python,
 * 32-bit masks), and the same in lighting.frag ---- */
static void test_hash_hand_values(void **state)
{
    (void)state;
    assert_int_equal(sl_lighting_hash(0u), 0u);
    assert_int_equal(sl_lighting_hash(1u), 0x688990c0u);
    assert_int_equal(sl_lighting_hash(2u), 0xd1132181u);
    assert_int_equal(sl_lighting_hash(0xffffffffu), 0x6768824au);
    assert_int_equal(sl_lighting_hash(12345u), 0x912efcf7u);
    const struct {
        int x, y;
        uint32_t frame;
        uint32_t a, b; /* the two 24-bit values */
    } cases[] = {
        {0, 0, 0, 9719733u, 3351763u},     {1, 0, 0, 2018948u, 13029390u}, {0, 1, 0, 13007976u, 505115u},
        {639, 359, 7, 9137824u, 2759128u}, {5, 3, 1, 12793030u, 5587191u},
    };
    for (int i = 0; i < 5; i++) {
        vec2 r = sl_lighting_pixel_rotation(cases[i].x, cases[i].y, cases[i].frame);
        assert_near(r.x, (double)cases[i].a / 16777216.0, 0.0);
        assert_near(r.y, (double)cases[i].b / 16777216.0, 0.0);
    }
}

/* Render variant o of f through the batched path and the port (o.plain) and hold them to
 * test_batched_vs_plain's bounds (mean relative 3e-4, worst pixel 0.5%); `what` names the case
 * in the message. The batched image is left in *batched (freed by the caller) when it is not NULL. */
static void assert_batched_matches_plain(fx_frame *f, sl_lighting_options o, const char *what, size_t v,
                                         sl_image *batched)
{
    sl_image a = {0}, b = {0};
    fx_frame_render(f, o, &a);
    o.plain = true;
    fx_frame_render(f, o, &b);
    double mx, mean;
    fx_image_rel_diff(&a, &b, &mx, &mean);
    print_message("%s variant %zu: batched vs plain: max rel %.3g, mean rel %.3g\n", what, v, mx, mean);
    assert_true(mean < 3e-4);
    assert_true(mx < 5e-3);
    if (batched)
        *batched = a;
    else
        sl_image_free(&a);
    sl_image_free(&b);
}

/* The batched path against the plain port, option by option, on three spheres (rough,
 * glossy, a metal of alpha 5000) under a smooth sky and under a sky with a 200x sun. The two
 * differ by the batched fetch's compact texels (src/ibl/texel_e5.h: each channel within 1/511.5
 * of its texel's max channel; test_e5_fetch_bound below holds the pass to that), by the fast
 * functions' rounding (1e-7 .. 3e-7, above) moving a sample's lod and texel position, and by
 * the order of the sum. Measured with the compact texels: mean 3e-5 .. 2e-4 (no_diffuse
 * doubles the specular share), worst pixel 0.4% (a dim channel beside bright ones in the same
 * texels); with float texels they were 2e-8 .. 5e-6 and 6e-4. Tolerances 3e-4 mean and 0.5%
 * worst pixel, far inside the GL comparison's (p99 5%). */
static void test_batched_vs_plain(void **state)
{
    (void)state;
    sl_env envs[2];
    fx_env(&envs[0], 128, 64, sky_gradient);
    fx_env(&envs[1], 256, 128, sky_with_sun);
    const sl_lighting_options variants[] = {
        {.samples = 20},
        {.samples = 40, .lod_rule = SL_LOD_SPEC},
        {.samples = 33, .lod_rule = SL_LOD_GEMS, .distortion = true},
        {.samples = 40, .lod_rule = SL_LOD_NONE},
        {.samples = 40, .distortion = true, .gterm = SL_GTERM_ONE},
        {.samples = 40, .estimator = SL_ESTIMATOR_CONSISTENT},
        {.samples = 70, .rotate = true, .frame = 3},
        {.samples = 40, .rotate = true, .frame = 9, .estimator = SL_ESTIMATOR_CONSISTENT, .lod_rule = SL_LOD_GEMS},
        {.samples = 40, .no_diffuse = true, .env_rotation_deg = 70.0f, .env_intensity = 2.0f},
        /* the pdf rule (Gems' level without its +1) with the density of each estimator's draws */
        {.samples = 40, .lod_rule = SL_LOD_PDF},
        {.samples = 33, .estimator = SL_ESTIMATOR_CONSISTENT, .lod_rule = SL_LOD_PDF, .distortion = true},
        {.samples = 40, .rotate = true, .frame = 5, .estimator = SL_ESTIMATOR_CONSISTENT, .lod_rule = SL_LOD_PDF},
        /* the microfacet estimator: every lod rule, distortion, G = 1, rotation on and off */
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_SPEC, .distortion = true},
        {.samples = 33, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_GEMS, .distortion = true},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_NONE, .gterm = SL_GTERM_ONE},
        {.samples = 70, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true, .frame = 3},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true, .frame = 9, .lod_rule = SL_LOD_GEMS},
        {.samples = 24, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true, .lod_rule = SL_LOD_SPEC, .distortion = true},
        {.samples = 16, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true, .lod_rule = SL_LOD_NONE},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .no_diffuse = true, .env_rotation_deg = 70.0f},
        {.samples = 32, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_PDF, .distortion = true},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_PDF, .gterm = SL_GTERM_ONE},
        {.samples = 24, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true, .frame = 2, .lod_rule = SL_LOD_PDF,
         .distortion = true},
    };
    for (int e = 0; e < 2; e++) {
        fx_frame f;
        fx_frame_setup(&f, &envs[e], 96, 64, 5000.0f);
        for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++)
            assert_batched_matches_plain(&f, variants[v], e == 0 ? "env 0" : "env 1", v, NULL);
        fx_frame_teardown(&f);
    }
    sl_env_free(&envs[0]);
    sl_env_free(&envs[1]);
}

/* With the ambient occlusion's visibility cone the batched path keeps its vector sum, each
 * term times its own occlusion (the specular by the same shade_spec_occlusion as the port): it
 * must agree with the port as closely as without the cone (test_batched_vs_plain's bounds), with
 * AO from 0 to 1 (both ends included) and bent normals leaning every way. A cone applied to the
 * wrong term, or the sum scaled twice, moves pixels by tens of percent. The AO-0 pixels are
 * black in both, so they do not weigh on the relative error; the darkened ones do. */
static void test_batched_vs_plain_cone(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 256, 128, sky_with_sun);
    fx_frame f;
    fx_frame_setup(&f, &env, 96, 64, 5000.0f);
    f.gb.cone = malloc((size_t)f.gb.width * (size_t)f.gb.height * sizeof *f.gb.cone);
    assert_non_null(f.gb.cone);
    for (int y = 0; y < f.gb.height; y++)
        for (int x = 0; x < f.gb.width; x++) {
            vec3 b = normalize(vec3(sinf(0.37f * (float)x), cosf(0.23f * (float)y), 0.6f));
            float ao = (float)((x * 7 + y * 13) % 11) / 10.0f;
            f.gb.cone[(size_t)y * (size_t)f.gb.width + (size_t)x] = (sl_vec4){b.x, b.y, b.z, ao};
        }
    const sl_lighting_options variants[] = {
        {.samples = 40},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true, .frame = 3},
        {.samples = 40, .no_diffuse = true, .env_rotation_deg = 70.0f, .env_intensity = 2.0f},
        {.samples = 40, .no_specular = true},
    };
    sl_image none = {0};
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        sl_image a = {0};
        assert_batched_matches_plain(&f, variants[v], "cone", v, &a);
        if (v == 0) { /* the cone does darken: the same frame without it differs */
            sl_vec4 *cone = f.gb.cone;
            f.gb.cone = NULL;
            fx_frame_render(&f, variants[0], &none);
            f.gb.cone = cone;
            double mx, mean;
            fx_image_rel_diff(&a, &none, &mx, &mean);
            assert_true(mean > 0.05);
        }
        sl_image_free(&a);
    }
    sl_image_free(&none);
    fx_frame_teardown(&f);
    sl_env_free(&env);
}

/* A row of spheres' setting: the sky with a 200x sun (*env) and its 8 brightest texels as env
 * lights (*el), seen by the camera returned, 7 units down -Y and 1 up. */
static sl_camera sunny_row(sl_env *env, sl_env_lights *el)
{
    fx_env(env, 256, 128, sky_with_sun);
    sl_error err;
    if (!sl_env_lights_extract(el, env, 8, 0, &err))
        fail_msg("extract: %s", err.msg);
    return (sl_camera){.eye = vec3(0, -7, 1), .target = vec3(0, 0, 0), .up = vec3(0, 0, 1), .fovy_deg = 50,
                       .znear = 0.1f, .zfar = 100};
}

/* A row of GGX spheres, r = 0.1, 0.3, 0.6, 1, and a Phong one (alpha 80), for sunny_row's camera. */
static const sl_synthetic_sphere ggx_row[5] = {
    {{-2.4f, 0, 0}, 0.55f, {0.0f, 0.0f, 0.0f}, {0.95f, 0.64f, 0.54f}, -1.1f},
    {{-1.2f, 0, 0}, 0.55f, {0.2f, 0.2f, 0.2f}, {0.04f, 0.04f, 0.04f}, -1.3f},
    {{0, 0, 0}, 0.55f, {0.8f, 0.2f, 0.2f}, {0.5f, 0.5f, 0.5f}, -1.6f},
    {{1.2f, 0, 0}, 0.55f, {0.1f, 0.1f, 0.1f}, {0.9f, 0.9f, 0.9f}, -2.0f},
    {{2.4f, 0, 0}, 0.55f, {0.2f, 0.2f, 0.2f}, {0.04f, 0.04f, 0.04f}, 80.0f},
};

/* GGX lobes (lobe parameter <= -1, brdf.h) through both paths: the batched path's own GGX
 * pieces (per-roughness tables, the rotated GGX lobe, the weights with 4 Vis, the spec-rule lod
 * from GGX's D, the env lights' GGX loop) against the port, on spheres r = 0.1, 0.3, 0.6, 1
 * plus a Phong sphere in the same frame (tables of both sets in one task). Same tolerances as
 * test_batched_vs_plain (measured worst 3.3e-3, mean 2e-5). Not r = 0.05 with rotation and the consistent
 * estimator: there the port's sin(acos(c)) and the batched sqrt(1 - c^2) round c = 0.99999
 * differently enough for D / pdf, 1e4 wide, to move one pixel by 0.6%. */
static void test_batched_vs_plain_ggx(void **state)
{
    (void)state;
    sl_env env;
    sl_env_lights el;
    const sl_camera cam = sunny_row(&env, &el);
    const sl_lighting_options variants[] = {
        {.samples = 40},
        {.samples = 40, .lod_rule = SL_LOD_SPEC, .distortion = true},
        {.samples = 33, .estimator = SL_ESTIMATOR_CONSISTENT, .lod_rule = SL_LOD_PDF},
        {.samples = 40, .rotate = true, .frame = 4},
        {.samples = 40, .rotate = true, .frame = 9, .estimator = SL_ESTIMATOR_CONSISTENT, .lod_rule = SL_LOD_GEMS},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_PDF},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_SPEC_D4, .distortion = true},
        {.samples = 70, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true, .frame = 3, .lod_rule = SL_LOD_PDF},
        {.samples = 24, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true, .lod_rule = SL_LOD_SPEC},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .env_lights = 8, .lod_rule = SL_LOD_PDF},
        {.samples = 40, .env_lights = 8, .env_rotation_deg = 70.0f},
    };
    fx_frame f;
    fx_frame_spheres(&f, &env, &cam, ggx_row, 5, 128, 48);
    f.env_lights = &el;
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++)
        assert_batched_matches_plain(&f, variants[v], "GGX", v, NULL);
    fx_frame_teardown(&f);
    sl_env_lights_free(&el);
    sl_env_free(&env);
}

/* A frame whose GGX set samples otherwise than its Phong set (options.ggx: a scene of both
 * sets): in either path each pixel gets the bits of a frame that samples every pixel its set's
 * way, the GGX spheres those of the microfacet estimator's frame (its frame about N, its lod
 * rule and distortion), the Phong sphere the recipe's; the paths agree as in
 * test_batched_vs_plain. Checked on ggx_row without env lights, with them for both sets, and with
 * them for the GGX set alone (options.env_lights_ggx_only), where the Phong sphere has the bits of
 * the recipe without env lights. */
static void test_lobe_set_sampling(void **state)
{
    (void)state;
    sl_env env;
    sl_env_lights el;
    const sl_camera cam = sunny_row(&env, &el);
    fx_frame f;
    fx_frame_spheres(&f, &env, &cam, ggx_row, 5, 320, 120);
    f.env_lights = &el;
    const sl_lobe_sampling mf = {SL_ESTIMATOR_MICROFACET, SL_LOD_PDF, true};
    /* case 0: no env lights; 1: 8 env lights for both sets; 2: 8 for the GGX set alone, whose
     * Phong pixels are then the recipe's without lights */
    for (int kase = 0; kase < 3; kase++) {
        const int lights = kase > 0 ? 8 : 0;
        const sl_lighting_options both = {.samples = 24, .env_lights = lights, .ggx = mf,
                                          .env_lights_ggx_only = kase == 2};
        const sl_lighting_options all_mf = {.samples = 24, .env_lights = lights, .estimator = mf.estimator,
                                            .lod_rule = mf.lod_rule, .distortion = mf.distortion};
        const sl_lighting_options all_spec = {.samples = 24, .env_lights = kase == 1 ? 8 : 0};
        for (int plain = 0; plain < 2; plain++) {
            sl_image a = {0}, g = {0}, p = {0};
            sl_lighting_options o[3] = {both, all_mf, all_spec};
            for (int k = 0; k < 3; k++)
                o[k].plain = plain;
            fx_frame_render(&f, o[0], &a);
            fx_frame_render(&f, o[1], &g);
            fx_frame_render(&f, o[2], &p);
            int ggx = 0, phong = 0, differ = 0, same = 0;
            for (int y = 0; y < f.gb.height; y++)
                for (int x = 0; x < f.gb.width; x++) {
                    const sl_gbuffer_texel *t = sl_gbuffer_at(&f.gb, x, f.gb.height - 1 - y); /* row 0 = top */
                    if (t->depth >= 1.0f)
                        continue;
                    const bool is_ggx = sl_lobe_is_ggx(t->alpha);
                    const size_t i = 3 * ((size_t)y * (size_t)f.gb.width + (size_t)x);
                    const sl_image *want = is_ggx ? &g : &p;
                    ggx += is_ggx;
                    phong += !is_ggx;
                    differ += memcmp(&a.data[i], &want->data[i], 3 * sizeof(float)) != 0;
                    same += memcmp(&g.data[i], &p.data[i], 3 * sizeof(float)) == 0;
                }
            print_message("lobe sets, case %d, %s: %d GGX and %d Phong pixels, %d not their set's bits, %d "
                          "alike under both estimators\n",
                          kase, plain ? "plain" : "batched", ggx, phong, differ, same);
            assert_true(ggx > 1000 && phong > 200);
            assert_int_equal(differ, 0);
            assert_true(same < (ggx + phong) / 100); /* a pixel that took the other set's estimator shows */
            sl_image_free(&a);
            sl_image_free(&g);
            sl_image_free(&p);
        }
        assert_batched_matches_plain(&f, both, "lobe sets", (size_t)kase, NULL);
    }
    /* a GGX set drawing MIS's pairs where the frame draws single samples shares no sample set:
     * refused with one line, as either way round */
    sl_lighting_uniforms *u = malloc(sizeof *u);
    assert_non_null(u);
    sl_error err;
    const sl_lighting_options pairs[2] = {{.samples = 24, .ggx = {SL_ESTIMATOR_MIS, SL_LOD_NONE, false}},
                                          {.samples = 24, .estimator = SL_ESTIMATOR_CV_MIS, .ggx = mf}};
    for (int k = 0; k < 2; k++) {
        sl_lighting_desc d = fx_frame_desc(&f, pairs[k]);
        assert_false(sl_lighting_uniforms_init(u, &d, &err));
        assert_non_null(strstr(err.msg, "draw different sample sets"));
    }
    free(u);
    fx_frame_teardown(&f);
    sl_env_lights_free(&el);
    sl_env_free(&env);
}

/* The facet plane (sl_gbuffer.facet) with reflection occlusion on: every estimator leaves the
 * directions under the pixel's facet out, sample by sample, and so do the env lights
 * (lighting_internal.h shade_facet_hides). On GGX and Phong spheres whose facets lean FACET_LEAN
 * degrees from the shading normal (as a normal map or a coarse mesh's normals lean, each pixel its
 * own azimuth), both paths agree within test_batched_vs_plain's bounds for every sampling
 * estimator; the light under the facets is gone, no pixel brighter and the spheres' specular
 * darker (measured: 1.7% to 6% of it); and a
 * facet that is the shading normal itself, whose horizon the estimators already stop at, or a
 * zero facet (no plane at the texel), gives the bits of the frame without the plane. */
#define FACET_LEAN 35.0f

/* What the control variates and MIS read besides the frame: the prefiltered chains, the table
 * and the environment's distribution. */
typedef struct {
    sl_env phong, ggx;
    sl_splitsum_lut *lut;
    sl_env_dist dist;
} cv_chains;

/* fx_frame_render with reflection occlusion on (its plane is the frame's) and the chains */
static void render_reflecting(const fx_frame *f, const cv_chains *c, sl_lighting_options o, sl_image *out)
{
    sl_lighting_desc d = fx_frame_desc(f, o);
    d.reflection_distance = 7.0f;
    d.splitsum_phong = &c->phong;
    d.splitsum_ggx = &c->ggx;
    d.splitsum_lut = c->lut;
    d.env_dist = &c->dist;
    fx_render(&d, &f->gb, 1, out, NULL);
}

static void test_facet_hides(void **state)
{
    (void)state;
    sl_env env;
    sl_env_lights el;
    const sl_camera cam = sunny_row(&env, &el);
    sl_error err;
    cv_chains chains;
    assert_true(sl_env_prefilter(&chains.phong, &env, &(sl_prefilter_desc){.ggx = false}, &err));
    assert_true(sl_env_prefilter(&chains.ggx, &env, &(sl_prefilter_desc){.ggx = true}, &err));
    chains.lut = malloc(sizeof *chains.lut);
    assert_non_null(chains.lut);
    sl_splitsum_lut_build(chains.lut, 0);
    assert_true(sl_env_dist_build(&chains.dist, &env, &err));
    sl_synthetic_sphere sp[4] = {
        {vec3(-1.8f, 0, 0), 0.75f, vec3s(0.0f), vec3(0.95f, 0.64f, 0.54f), sl_gbuffer_ggx_alpha(0.15f)},
        {vec3(-0.6f, 0, 0), 0.55f, vec3(0.2f, 0.2f, 0.2f), vec3s(0.04f), sl_gbuffer_ggx_alpha(0.5f)},
        {vec3(0.6f, 0, 0), 0.55f, vec3(0.2f, 0.2f, 0.2f), vec3s(0.5f), 80.0f},
        {vec3(1.8f, 0, 0), 0.75f, vec3s(0.0f), vec3s(0.9f), 2000.0f},
    };
    fx_frame f;
    fx_frame_spheres(&f, &env, &cam, sp, 4, 128, 48);
    f.env_lights = &el;
    const size_t n = (size_t)f.gb.width * (size_t)f.gb.height;
    f.gb.reflection = malloc(n * sizeof *f.gb.reflection);
    assert_non_null(f.gb.reflection);
    for (size_t i = 0; i < n; i++)
        f.gb.reflection[i] = vec2(1.0f, 5.0f); /* open over five rays: the factor is 1 */
    assert_true(sl_gbuffer_use_facet(&f.gb, true, &err));
    const float c = cosf(FACET_LEAN * SL_PI / 180.0f), s = sinf(FACET_LEAN * SL_PI / 180.0f);
    const sl_lighting_options variants[] = {
        {.samples = 40},
        {.samples = 40, .estimator = SL_ESTIMATOR_CONSISTENT},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_PDF, .distortion = true},
        {.samples = 40, .estimator = SL_ESTIMATOR_MICROFACET, .env_lights = 8, .lod_rule = SL_LOD_PDF},
        {.samples = 32, .estimator = SL_ESTIMATOR_CV, .lod_rule = SL_LOD_PDF, .distortion = true},
        {.samples = 32, .estimator = SL_ESTIMATOR_MIS},
        {.samples = 16, .estimator = SL_ESTIMATOR_CV_MIS},
    };
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        sl_image leaned = {0}, open = {0}, same = {0}, zero = {0};
        sl_lighting_options spec_only = variants[v];
        spec_only.no_diffuse = true;
        for (size_t i = 0; i < n; i++) { /* leaned FACET_LEAN from N, each pixel towards its own azimuth */
            vec3 N = f.gb.texels[i].normal;
            vec3 a = normalize(cross(fabsf(N.z) < 0.9f ? vec3(0, 0, 1) : vec3(1, 0, 0), N));
            vec3 b = cross(N, a);
            float phi = 2.0f * SL_PI * (float)(i % 7) / 7.0f;
            f.gb.facet[i] = add(scale(N, c), scale(add(scale(a, cosf(phi)), scale(b, sinf(phi))), s));
        }
        sl_image plain = {0};
        render_reflecting(&f, &chains, spec_only, &leaned);
        sl_lighting_options o = spec_only;
        o.plain = true;
        render_reflecting(&f, &chains, o, &plain);
        double mx, mean;
        fx_image_rel_diff(&leaned, &plain, &mx, &mean);
        print_message("facet variant %zu: batched vs plain: max rel %.3g, mean rel %.3g\n", v, mx, mean);
        assert_true(mean < 3e-4 && mx < 5e-3);
        sl_image_free(&plain);
        sl_vec3 *facet = f.gb.facet;
        f.gb.facet = NULL;
        render_reflecting(&f, &chains, spec_only, &open);
        f.gb.facet = facet;
        for (size_t i = 0; i < n; i++) /* the normal the shader uses, bent at the silhouette */
            f.gb.facet[i] = sl_shade_facing_normal(f.gb.texels[i].normal, normalize(sub(f.eye, f.gb.texels[i].position)));
        render_reflecting(&f, &chains, spec_only, &same);
        memset(f.gb.facet, 0, n * sizeof *f.gb.facet);
        render_reflecting(&f, &chains, spec_only, &zero);
        double sum_leaned = 0.0, sum_open = 0.0;
        for (size_t k = 0; k < 3 * n; k++) {
            assert_true(leaned.data[k] <= open.data[k] * 1.0001f + 1e-6f);
            if (sl_gbuffer_covered(&f.gb.texels[k / 3])) { /* the specular: the frames are --specular-only */
                sum_leaned += leaned.data[k];
                sum_open += open.data[k];
            }
        }
        print_message("facet variant %zu: the leaned facets keep %.4f of the frame\n", v, sum_leaned / sum_open);
        assert_true(sum_leaned < 0.995 * sum_open && sum_leaned > 0.5 * sum_open);
        assert_memory_equal(same.data, open.data, 3 * n * sizeof *open.data);
        assert_memory_equal(zero.data, open.data, 3 * n * sizeof *open.data);
        sl_image_free(&leaned);
        sl_image_free(&open);
        sl_image_free(&same);
        sl_image_free(&zero);
    }
    fx_frame_teardown(&f);
    free(chains.lut);
    sl_env_dist_free(&chains.dist);
    sl_env_free(&chains.phong);
    sl_env_free(&chains.ggx);
    sl_env_lights_free(&el);
    sl_env_free(&env);
}

/* The vectorized fetch gathers from the environment's single block (sl_env.block); without a
 * block the same filter runs texel by texel. Same operations: the images are bitwise equal. */
static void test_block_fetch_bitwise(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 96, 40, sky_with_sun); /* not a power of two: odd level sizes */
    assert_non_null(env.block);
    /* the float texels' fetch (the compact one is test_e5_fetch_bound's): without sl_env.e5 the
     * pass reads the float pair rows */
    free(env.e5);
    env.e5 = NULL;
    assert_true(env.levels[0].texels == env.block);
    sl_env loose = {.level_count = env.level_count};
    for (int l = 0; l < env.level_count; l++) {
        size_t n = (size_t)env.levels[l].width * (size_t)env.levels[l].height;
        if (l > 0) /* level after level in the block */
            assert_true(env.levels[l].texels ==
                        env.levels[l - 1].texels + (size_t)env.levels[l - 1].width * (size_t)env.levels[l - 1].height);
        loose.levels[l] = (sl_env_level){env.levels[l].width, env.levels[l].height, malloc(n * sizeof(vec3))};
        assert_non_null(loose.levels[l].texels);
        memcpy(loose.levels[l].texels, env.levels[l].texels, n * sizeof(vec3));
    }
    fx_frame f;
    fx_frame_setup(&f, &env, 64, 48, 300.0f);
    const sl_lighting_options variants[] = {
        {.samples = 24},
        {.samples = 24, .rotate = true, .lod_rule = SL_LOD_GEMS},
        {.samples = 24, .estimator = SL_ESTIMATOR_MICROFACET, .lod_rule = SL_LOD_GEMS},
        {.samples = 24, .estimator = SL_ESTIMATOR_MICROFACET, .rotate = true},
    };
    for (int v = 0; v < 4; v++) {
        sl_image a = {0}, b = {0};
        sl_lighting_options o = variants[v];
        o.no_diffuse = true;
        fx_frame_render(&f, o, &a);
        sl_lighting_desc d = fx_frame_desc(&f, o);
        d.env = &loose;
        fx_render(&d, &f.gb, 1, &b, NULL);
        assert_memory_equal(a.data, b.data, sizeof(float) * 64 * 48 * 3);
        sl_image_free(&a);
        sl_image_free(&b);
    }
    sl_env_free(&loose);
    fx_frame_teardown(&f);
    sl_env_free(&env);
}

/* The batched pass with the compact texels (sl_env.e5) against the same pass on the float
 * pair rows: the only difference is the texels, so it is bounded by the format's. A fetched
 * radiance is a trilinear blend (weights >= 0, sum 1) of texels whose channels are each within
 * M_t / 511.5 of the float ones, so each of its channels is within (r + g + b) / 511.5 of the
 * float fetch's value; the pixel's specular is a sum of such radiances times F weight >= 0 per
 * channel, whose ratio between channels is at most max Ks / min Ks (F = Ks + (1 - Ks) m5), 1.76
 * for the fixture's metal. So |a_c - b_c| <= 1.76 (b_r + b_g + b_b) / 511.5 per pixel (specular
 * only), plus float rounding of the two computations (1e-6 of the sum). */
static void test_e5_fetch_bound(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 128, 64, sky_with_sun);
    assert_non_null(env.e5);
    fx_frame f;
    fx_frame_setup(&f, &env, 96, 64, 5000.0f);
    const sl_lighting_options variants[] = {
        {.samples = 40, .no_diffuse = true},
        {.samples = 24, .no_diffuse = true, .rotate = true, .lod_rule = SL_LOD_GEMS, .distortion = true},
        {.samples = 40, .no_diffuse = true, .estimator = SL_ESTIMATOR_MICROFACET},
    };
    uint32_t *e5 = env.e5;
    for (size_t v = 0; v < sizeof variants / sizeof variants[0]; v++) {
        sl_image a = {0}, b = {0};
        env.e5 = e5;
        fx_frame_render(&f, variants[v], &a);
        env.e5 = NULL;
        fx_frame_render(&f, variants[v], &b);
        double worst = 0.0;
        for (int i = 0; i < 96 * 64; i++) {
            const float *pa = a.data + 3 * i, *pb = b.data + 3 * i;
            double sum = (double)pb[0] + (double)pb[1] + (double)pb[2];
            for (int c = 0; c < 3; c++) {
                double d = fabs((double)pa[c] - (double)pb[c]);
                if (d > 1.76 * sum / 511.5 + 1e-6 * sum + 1e-30)
                    fail_msg("variant %zu pixel %d channel %d: %.9g against %.9g", v, i, c, (double)pa[c],
                             (double)pb[c]);
                worst = sum > 0.0 ? fmax(worst, d / sum) : worst;
            }
        }
        print_message("variant %zu: compact against float texels: worst |difference| / sum %.3g\n", v, worst);
        assert_true(worst > 0.0); /* the compact texels were read */
        sl_image_free(&a);
        sl_image_free(&b);
    }
    env.e5 = e5;
    fx_frame_teardown(&f);
    sl_env_free(&env);
}

/* Rotation off: the frame number changes nothing (both paths), so rotation off is the previous
 * result bit for bit. Rotation on: every frame differs, the pass equals per-pixel shading
 * (sl_lighting_shade without a task), and 1 and 2 threads agree. */
static void test_rotation_off_and_determinism(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 128, 64, sky_with_sun);
    sl_error err;
    fx_frame f;
    fx_frame_setup(&f, &env, 80, 48, 1000.0f);
    const sl_gbuffer *gb = &f.gb;
    const size_t bytes = sizeof(float) * 80 * 48 * 3;
    for (int plain = 0; plain < 2; plain++) {
        sl_image a = {0}, b = {0}, c = {0};
        fx_frame_render(&f, (sl_lighting_options){.samples = 16, .plain = plain}, &a);
        fx_frame_render(&f, (sl_lighting_options){.samples = 16, .plain = plain, .frame = 77}, &b);
        assert_memory_equal(a.data, b.data, bytes);
        fx_frame_render(&f, (sl_lighting_options){.samples = 16, .plain = plain, .rotate = true}, &b);
        fx_frame_render(&f, (sl_lighting_options){.samples = 16, .plain = plain, .rotate = true, .frame = 1}, &c);
        assert_true(memcmp(a.data, b.data, bytes) != 0);
        assert_true(memcmp(b.data, c.data, bytes) != 0);
        sl_image_free(&a);
        sl_image_free(&b);
        sl_image_free(&c);
    }
    /* rotation on: pass (1 and 2 threads) = sl_lighting_shade per pixel = the trace's total */
    sl_lighting_desc d = fx_frame_desc(&f, (sl_lighting_options){.samples = 24, .rotate = true, .frame = 5});
    sl_lighting_uniforms *u = fx_uniforms_for(&d);
    sl_image p1 = {0};
    fx_assert_same_for_thread_counts(u, gb, &p1, NULL);
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    for (int y = 0; y < 48; y += 5)
        for (int x = 0; x < 80; x += 7) {
            vec3 c = sl_lighting_shade(u, gb, x, y, NULL, NULL);
            const float *p = sl_image_pixel(&p1, x, 47 - y);
            assert_memory_equal(&c, p, sizeof(float) * 3);
            assert_true(sl_lighting_trace_pixel(u, gb, x, 47 - y, tr, &err));
            assert_memory_equal(&tr->total, p, sizeof(float) * 3);
            if (tr->covered) {
                vec2 r = sl_lighting_pixel_rotation(x, y, 5);
                assert_near(tr->rotation.x, r.x, 0.0);
                assert_near(tr->rotation.y, r.y, 0.0);
            }
        }
    vec3 row[80]; /* a whole row at once (the viewer's call) = the pass */
    sl_lighting_shade_row(u, gb, 0, 20, 80, NULL, row);
    assert_memory_equal(row, sl_image_pixel(&p1, 0, 47 - 20), sizeof row);
    free(tr);
    free(u);
    sl_image_free(&p1);
    fx_frame_teardown(&f);
    sl_env_free(&env);
}

/* The microfacet estimator keeps the batched path's guarantees: the pass with 1 and 2 threads,
 * sl_lighting_shade per pixel without a task (no per-alpha table: the samples recomputed by the
 * same functions), a whole row, and the trace's total agree bit for bit, with rotation off and
 * on; rotation off ignores the frame number; and the spec-estimator tables a task holds for the
 * same alpha do not leak into it (the same task shades both, in turn). */
static void test_microfacet_determinism(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 128, 64, sky_with_sun);
    sl_error err;
    fx_frame f;
    fx_frame_setup(&f, &env, 80, 48, 1000.0f);
    const sl_gbuffer *gb = &f.gb;
    const size_t bytes = sizeof(float) * 80 * 48 * 3;
    sl_lighting_trace *tr = malloc(sizeof *tr);
    assert_non_null(tr);
    for (int rot = 0; rot < 2; rot++) {
        sl_lighting_desc d = fx_frame_desc(&f, (sl_lighting_options){.samples = 24, .rotate = rot, .frame = 5,
                                                  .lod_rule = SL_LOD_GEMS, .estimator = SL_ESTIMATOR_MICROFACET});
        sl_lighting_uniforms *u = fx_uniforms_for(&d);
        d.options.estimator = SL_ESTIMATOR_SPEC;
        sl_lighting_uniforms *us = fx_uniforms_for(&d);
        sl_image p1 = {0}, p2 = {0};
        fx_assert_same_for_thread_counts(u, gb, &p1, NULL);
        sl_lighting_task *task = sl_lighting_task_create(&err);
        assert_non_null(task);
        for (int y = 0; y < 48; y += 5)
            for (int x = 0; x < 80; x += 7) {
                vec3 c = sl_lighting_shade(u, gb, x, y, NULL, NULL);
                const float *p = sl_image_pixel(&p1, x, 47 - y);
                assert_memory_equal(&c, p, sizeof(float) * 3);
                /* one task, the two estimators in turn: the tables must not mix */
                vec3 s1 = sl_lighting_shade(us, gb, x, y, task, NULL);
                sl_lighting_task_reset(task);
                vec3 m1 = sl_lighting_shade(u, gb, x, y, task, NULL);
                assert_memory_equal(&m1, p, sizeof(float) * 3);
                sl_lighting_task_reset(task);
                vec3 s2 = sl_lighting_shade(us, gb, x, y, NULL, NULL);
                assert_memory_equal(&s1, &s2, sizeof(float) * 3);
                assert_true(sl_lighting_trace_pixel(u, gb, x, 47 - y, tr, &err));
                assert_memory_equal(&tr->total, p, sizeof(float) * 3);
                if (tr->covered)
                    assert_true(tr->microfacet);
            }
        vec3 row[80];
        sl_lighting_shade_row(u, gb, 0, 20, 80, NULL, row);
        assert_memory_equal(row, sl_image_pixel(&p1, 0, 47 - 20), sizeof row);
        if (!rot) { /* rotation off: the frame number changes nothing */
            d.options.estimator = SL_ESTIMATOR_MICROFACET;
            d.options.frame = 77;
            assert_true(sl_lighting_uniforms_init(u, &d, &err));
            assert_true(sl_lighting_pass(u, NULL, gb, &p2, 2, &err));
            assert_memory_equal(p1.data, p2.data, bytes);
        }
        sl_lighting_task_destroy(task);
        sl_image_free(&p1);
        sl_image_free(&p2);
        free(u);
        free(us);
    }
    free(tr);
    fx_frame_teardown(&f);
    sl_env_free(&env);
}

/* sl_lighting_accumulate: the running mean of frames 1, 2, 6 (and 0, 4, 8) is their mean. */
static void test_accumulate(void **state)
{
    (void)state;
    sl_image f = {0}, mean = {0}, small = {0};
    sl_error err;
    assert_true(sl_image_alloc(&f, 3, 2, 3, &err));
    const float a[3] = {1, 2, 6}, b[3] = {0, 4, 8};
    for (int k = 0; k < 3; k++) {
        for (int i = 0; i < 18; i++)
            f.data[i] = i % 2 ? a[k] : b[k];
        assert_true(sl_lighting_accumulate(&mean, &f, k, &err));
    }
    for (int i = 0; i < 18; i++)
        assert_near(mean.data[i], i % 2 ? 3.0 : 4.0, 1e-6);
    assert_true(sl_image_alloc(&small, 2, 2, 3, &err));
    assert_false(sl_lighting_accumulate(&mean, &small, 3, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_false(sl_lighting_accumulate(&mean, &f, -1, &err));
    sl_image_free(&f);
    sl_image_free(&mean);
    sl_image_free(&small);
}

/* Progressive refinement: on a synthetic sphere (specular only, consistent estimator, alpha 1,
 * lod 0, pixels with N.V > 0.9, where the estimator converges: docs/lighting.md) with N = 4,
 * the RMS error against the ground truth of (a) the plain Hammersley set, (b) one rotated
 * frame, (c) the mean of K = 16 rotated frames. (b) trades (a)'s structured error for noise;
 * averaging K frames divides the noise by sqrt(K) = 4 down to what is left of the bias (the
 * estimator's, and bilinear filtering against the truth's piecewise-constant texels), so (c)
 * must be below half of (b) and below (a). Measured: 0.042, 0.083, 0.035. */
static void test_rotation_converges(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 64, 32, sky_gradient);
    sl_ground_truth gt;
    sl_error err;
    assert_true(sl_ground_truth_init(&gt, &env, &err));
    sl_camera cam = {.eye = vec3(0, -3.2f, 0.4f), .target = vec3(0, 0, 0), .up = vec3(0, 0, 1), .fovy_deg = 40,
                     .znear = 0.1f, .zfar = 100};
    sl_synthetic_sphere s = {vec3(0, 0, 0), 1.0f, vec3s(0.0f), vec3s(0.9f), 1.0f};
    const int W = 64, H = 64;
    const float NV_MIN = 0.9f;
    fx_frame f;
    fx_frame_spheres(&f, &env, &cam, &s, 1, W, H);
    const sl_gbuffer *gb = &f.gb;
    /* the truth, per covered pixel (image orientation: row 0 = top) */
    double *truth = calloc((size_t)W * H, sizeof *truth);
    assert_non_null(truth);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(gb, x, y);
            if (!sl_gbuffer_covered(t))
                continue;
            vec3 v = normalize(sub(cam.eye, t->position));
            sl_gbuffer_texel q = *t;
            if (dot(t->normal, v) > NV_MIN) /* where the estimator converges (see above) */
                truth[(H - 1 - y) * W + x] = fx_truth(&gt, t->normal, v, q, false, true);
        }
    sl_lighting_options o = {.samples = 4, .no_diffuse = true, .estimator = SL_ESTIMATOR_CONSISTENT, .lod_rule = SL_LOD_NONE};
    sl_image plain = {0}, one = {0}, mean = {0}, frame = {0};
    fx_frame_render(&f, o, &plain);
    o.rotate = true;
    const int K = 16;
    for (int k = 0; k < K; k++) {
        o.frame = (uint32_t)k;
        fx_frame_render(&f, o, &frame);
        if (k == 0)
            fx_frame_render(&f, o, &one);
        assert_true(sl_lighting_accumulate(&mean, &frame, k, &err));
    }
    double e_plain = 0, e_one = 0, e_mean = 0;
    int count = 0;
    for (int i = 0; i < W * H; i++) {
        if (truth[i] <= 0.0)
            continue;
        e_plain += pow(plain.data[3 * i] - truth[i], 2);
        e_one += pow(one.data[3 * i] - truth[i], 2);
        e_mean += pow(mean.data[3 * i] - truth[i], 2);
        count++;
    }
    assert_true(count > 200);
    e_plain = sqrt(e_plain / count);
    e_one = sqrt(e_one / count);
    e_mean = sqrt(e_mean / count);
    print_message("RMS error vs ground truth, N = 4: Hammersley %.4g, one rotated frame %.4g, mean of %d rotated "
                  "frames %.4g\n",
                  e_plain, e_one, K, e_mean);
    assert_true(e_mean < 0.5 * e_one);
    assert_true(e_mean < e_plain);
    free(truth);
    sl_image_free(&plain);
    sl_image_free(&one);
    sl_image_free(&mean);
    sl_image_free(&frame);
    fx_frame_teardown(&f);
    sl_ground_truth_free(&gt);
    sl_env_free(&env);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fast_math),
        cmocka_unit_test(test_hash_hand_values),
        cmocka_unit_test(test_batched_vs_plain),
        cmocka_unit_test(test_batched_vs_plain_ggx),
        cmocka_unit_test(test_lobe_set_sampling),
        cmocka_unit_test(test_batched_vs_plain_cone),
        cmocka_unit_test(test_facet_hides),
        cmocka_unit_test(test_block_fetch_bitwise),
        cmocka_unit_test(test_e5_fetch_bound),
        cmocka_unit_test(test_rotation_off_and_determinism),
        cmocka_unit_test(test_microfacet_determinism),
        cmocka_unit_test(test_accumulate),
        cmocka_unit_test(test_rotation_converges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
