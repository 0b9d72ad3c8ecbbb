/* test_irradiance_span.c - sl_irradiance_eval_span (src/ibl/irradiance.c), the lighting pass's
 * batched lookup of the diffuse irradiance, against sl_irradiance_eval, the port's, bit for bit:
 * for every method (SH9, the brute-force and loaded lat-long maps, the octahedral and
 * dual-paraboloid maps), at the poles (N = +Z, -Z), on the lat-long seam (x < 0, y = +-0), on the
 * octahedral folds and the equator, at signed zeros, at non-unit and non-finite directions, and at
 * many random ones; spans of every length up to past the function's scratch (SL_IRRADIANCE_SPAN),
 * so vector loops, their remainders and the chunking all run. Also the batched lighting pass with
 * the diffuse term alone: every pixel the bits of the port's sum with sl_irradiance_eval. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ibl/ibl.h"
#include "shading/lighting_trace.h"
#include "shading_fixtures.h"
#include "testutil.h"

#define PI 3.14159265358979323846

/* A sky with a bright, coloured lobe and a dim ground: E differs in every channel and direction. */
static double lobed_sky(const double w[3], int ch)
{
    double d = w[0] * 0.48 + w[1] * -0.36 + w[2] * 0.8;
    double lobe = d > 0.0 ? pow(d, 20.0) * 50.0 : 0.0;
    return (w[2] > 0.0 ? 1.0 + w[2] : 0.15 + 0.05 * w[0]) * (1.0 - 0.2 * ch) + lobe * (1.0 + 0.5 * ch);
}

enum { DIRS = 600 };

/* The directions: the hard ones first, then random unit ones (a fixed LCG: reproducible). */
static int make_dirs(float *x, float *y, float *z)
{
    const float s = 0.70710678f, t = 1e-7f;
    const float hard[][3] = {
        {0, 0, 1}, {0, 0, -1}, {-0.0f, -0.0f, 1}, {-0.0f, 0, -1}, {0, -0.0f, -1},            /* poles */
        {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0},                                        /* equator */
        {-1, -0.0f, 0}, {-s, 0, s}, {-s, -0.0f, s}, {-s, 0, -s}, {-s, -0.0f, -s},            /* lat-long seam */
        {-s, t, s}, {-s, -t, s}, {s, 0, -s}, {0, s, -s}, {-0.0f, -s, -s}, {s, -0.0f, -s},    /* folds */
        {0.5f, 0.5f, -s}, {-0.5f, 0.5f, -s}, {s, s, 0}, {s, s, -0.0f}, {-s, -s, t}, {s, -s, -t}, /* diagonals */
        {0, 0, 1 - 1e-7f}, {t, t, -1}, {-t, 0, 1},                                          /* near the poles */
        {2, 0, 0}, {0.1f, 0.2f, -0.3f}, {0, 0, 0}, {NAN, 0, 0}, {0, INFINITY, 0}, {1, 1, NAN}, /* odd */
    };
    const int nh = (int)(sizeof hard / sizeof hard[0]);
    for (int i = 0; i < nh; i++) {
        x[i] = hard[i][0];
        y[i] = hard[i][1];
        z[i] = hard[i][2];
    }
    uint32_t r = 12345u;
    for (int i = nh; i < DIRS; i++) {
        float v[3];
        double l2;
        do {
            for (int c = 0; c < 3; c++) {
                r = r * 1664525u + 1013904223u;
                v[c] = (float)((double)(r >> 8) / 8388608.0 - 1.0);
            }
            l2 = (double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2];
        } while (l2 < 1e-4 || l2 > 1.0);
        float inv = (float)(1.0 / sqrt(l2));
        x[i] = v[0] * inv;
        y[i] = v[1] * inv;
        z[i] = v[2] * inv;
    }
    return nh;
}

/* The span lookup of x..z[from .. from + count) against the scalar one, bit for bit. */
static void check_span(const sl_irradiance *irr, const char *name, const float *x, const float *y, const float *z,
                       int from, int count)
{
    float er[DIRS], eg[DIRS], eb[DIRS];
    float want[3 * DIRS], got[3 * DIRS];
    sl_irradiance_eval_span(irr, count, x + from, y + from, z + from, er, eg, eb);
    for (int i = 0; i < count; i++) {
        vec3 e = sl_irradiance_eval(irr, vec3(x[from + i], y[from + i], z[from + i]));
        want[3 * i] = e.x;
        want[3 * i + 1] = e.y;
        want[3 * i + 2] = e.z;
        got[3 * i] = er[i];
        got[3 * i + 1] = eg[i];
        got[3 * i + 2] = eb[i];
    }
    assert_same_texels(want, got, (size_t)count, 3 * sizeof(float), 0, "%s: %d directions from %d", name, count, from);
}

static void check_method(const sl_irradiance *irr, const char *name)
{
    static float x[DIRS], y[DIRS], z[DIRS];
    int hard = make_dirs(x, y, z);
    check_span(irr, name, x, y, z, 0, DIRS); /* past SL_IRRADIANCE_SPAN: several chunks */
    check_span(irr, name, x, y, z, 0, hard);
    for (int n = 0; n <= 2 * SL_IRRADIANCE_SPAN + 3; n++) /* every length: remainders, chunk edges */
        check_span(irr, name, x, y, z, 7, n);
    check_span(irr, name, x, y, z, 1, 32); /* the batched path's span (lighting_internal.h SPAN) */
}

static void test_every_method(void **state)
{
    (void)state;
    sl_env env = test_make_env(128, 64, lobed_sky);
    sl_error err = {0};
    sl_irradiance irr;

    assert_true(sl_irradiance_sh9(&irr, &env, &err));
    check_method(&irr, "sh9");
    sl_irradiance_free(&irr);

    assert_true(sl_irradiance_brute(&irr, &env, 32, 0, &err));
    check_method(&irr, "brute");
    sl_irradiance_free(&irr);

    sl_image map;
    assert_true(sl_image_alloc(&map, 16, 8, 3, &err));
    for (int k = 0; k < 16 * 8 * 3; k++)
        map.data[k] = 0.1f + (float)((k * 37) % 101) * 0.01f;
    assert_true(sl_irradiance_from_image(&irr, &map, &err));
    check_method(&irr, "map");
    sl_irradiance_free(&irr);
    sl_image_free(&map);

    const sl_irradiance_method layouts[2] = {SL_IRRADIANCE_OCT, SL_IRRADIANCE_DP};
    const char *const names[2] = {"oct", "dp"};
    for (int l = 0; l < 2; l++) {
        for (int size = 3; size <= 33; size += 30) { /* the smallest map and a usual one */
            assert_true(
                sl_irradiance_map(&irr, &env, &(sl_irradiance_map_desc){.method = layouts[l], .size = size}, &err));
            check_method(&irr, names[l]);
            sl_irradiance_free(&irr);
        }
    }
    sl_env_free(&env);
}

static vec3 fx_sky(vec3 d)
{
    double w[3] = {d.x, d.y, d.z};
    return vec3((float)lobed_sky(w, 0), (float)lobed_sky(w, 1), (float)lobed_sky(w, 2));
}

/* The batched path (the pass's default) with the diffuse term alone, for every method: each
 * covered pixel of the pass (spans of 32 pixels, sl_irradiance_eval_span) has the bits of main()'s
 * sum with the port's irradiance(Nenv) (sl_irradiance_eval at the pixel's traced Nenv; the trace
 * computes Nenv as the pass does). The port itself (options.plain) forms Nenv by other
 * operations, a float rounding apart, so it is not the reference here. */
static void test_batched_diffuse(void **state)
{
    (void)state;
    sl_env env;
    fx_env(&env, 128, 64, fx_sky);
    fx_frame f;
    fx_frame_setup(&f, &env, 96, 64, 40.0f);
    sl_irradiance_free(&f.irr); /* SH9: replaced per method below */
    sl_error err = {0};
    sl_lighting_trace *trace = malloc(sizeof *trace);
    assert_non_null(trace);
    const sl_irradiance_method methods[] = {SL_IRRADIANCE_SH9, SL_IRRADIANCE_BRUTE, SL_IRRADIANCE_OCT,
                                            SL_IRRADIANCE_DP};
    for (size_t m = 0; m < sizeof methods / sizeof methods[0]; m++) {
        if (methods[m] == SL_IRRADIANCE_SH9)
            assert_true(sl_irradiance_sh9(&f.irr, &env, &err));
        else if (methods[m] == SL_IRRADIANCE_BRUTE)
            assert_true(sl_irradiance_brute(&f.irr, &env, 32, 0, &err));
        else
            assert_true(sl_irradiance_map(&f.irr, &env, &(sl_irradiance_map_desc){.method = methods[m]}, &err));
        sl_lighting_options o = {.samples = 8, .no_specular = true, .irradiance = methods[m]};
        sl_lighting_desc d = fx_frame_desc(&f, o);
        sl_lighting_uniforms *u = fx_uniforms_for(&d);
        sl_image img = {0};
        fx_render(&d, &f.gb, 1, &img, NULL);
        int covered = 0;
        for (int y = 0; y < img.height; y++)
            for (int x = 0; x < img.width; x++) {
                assert_true(sl_lighting_trace_pixel(u, &f.gb, x, y, trace, &err));
                if (!trace->covered)
                    continue;
                covered++;
                /* sl_shade_surface_color's operations with the diffuse term alone */
                vec3 E = sl_irradiance_eval(&f.irr, trace->Nenv);
                vec3 diffuse = scale(mul(scale(trace->texel.kd, 1.0f / SL_PI), E), u->uEnvIntensity);
                vec3 color = add(scale(add(vec3s(0.0f), diffuse), trace->occlusion), trace->emissive);
                assert_same_texels(&color, sl_image_pixel(&img, x, y), 1, sizeof color, 0,
                                   "diffuse alone, irradiance %s, pixel %d,%d", sl_irradiance_name(methods[m]), x, y);
            }
        print_message("%s: %d covered pixels checked\n", sl_irradiance_name(methods[m]), covered);
        assert_true(covered > img.width * img.height / 8);
        sl_image_free(&img);
        free(u);
        sl_irradiance_free(&f.irr);
    }
    free(trace);
    fx_frame_teardown(&f);
    sl_env_free(&env);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_method),
        cmocka_unit_test(test_batched_diffuse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
