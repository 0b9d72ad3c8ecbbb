/* shading_fixtures.h - shared set-up for the lighting-stage tests (test_shading.c, test_hardcases.c,
 * test_lighting_fast.c, test_env_lights.c): environments made to order, one-texel G-buffers placed
 * at a chosen N.V, a frame to light (synthetic spheres + G-buffer + irradiance, fx_frame), its
 * uniforms and a checked pass (fx_render), the "1 and 2 threads give the same bits" check
 * (fx_assert_same_for_thread_counts), the ground truth for one texel, and image statistics.
 * Header-only (static inline functions): each test executable is one translation unit. */
#ifndef SHADING_FIXTURES_H
#define SHADING_FIXTURES_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ibl/env_lights.h"
#include "ibl/ground_truth.h"
#include "ibl/ibl.h"
#include "shading/lighting.h"
#include "shading/synthetic.h"
#include "testutil.h"

/* An environment of w x h texels with radiance f(direction of the texel centre). */
typedef vec3 fx_radiance_fn(vec3 d);
static inline vec3 fx_const_one(vec3 d)
{
    (void)d;
    return vec3s(1.0f);
}

static inline void fx_env(sl_env *env, int w, int h, fx_radiance_fn *f)
{
    sl_image img = {0};
    sl_error err;
    assert_true(sl_image_alloc(&img, w, h, 3, &err));
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            vec3 c = f(sl_uv_to_dir(vec2(((float)x + 0.5f) / (float)w, ((float)y + 0.5f) / (float)h)));
            float *p = sl_image_pixel(&img, x, y);
            p[0] = c.x;
            p[1] = c.y;
            p[2] = c.z;
        }
    if (!sl_env_build(env, &img, 0, &err))
        fail_msg("sl_env_build: %s", err.msg);
    sl_image_free(&img);
}

/* Uniforms for desc, on the heap (about 9 KB; free them); the test fails with the reason if
 * sl_lighting_uniforms_init refuses desc. */
static inline sl_lighting_uniforms *fx_uniforms_for(const sl_lighting_desc *desc)
{
    sl_lighting_uniforms *u = malloc(sizeof *u);
    assert_non_null(u);
    sl_error err;
    if (!sl_lighting_uniforms_init(u, desc, &err))
        fail_msg("uniforms: %s", err.msg);
    return u;
}

/* Uniforms for a 1x1 (or w x h) frame with the given options and no view matrix. */
static inline sl_lighting_uniforms *fx_uniforms(const sl_env *env, const sl_irradiance *irr, sl_lighting_options opt,
                                         vec3 eye, int w, int h)
{
    sl_lighting_desc d = {.options = opt, .env = env, .irradiance = irr, .eye = eye,
                          .inv_view_proj = mat4_identity(), .width = w, .height = h};
    return fx_uniforms_for(&d);
}

/* A surface at the origin with normal +Z seen from a direction at N.V = nv (in the xz plane,
 * rotated by phi about Z), eye at distance 10. */
static inline vec3 fx_view_dir(float nv, float phi)
{
    float s = sqrtf(fmaxf(0.0f, 1.0f - nv * nv));
    return vec3(s * cosf(phi), s * sinf(phi), nv);
}

static inline sl_gbuffer_texel fx_texel(vec3 normal, vec3 kd, vec3 ks, float alpha)
{
    return (sl_gbuffer_texel){.position = vec3(0, 0, 0), .normal = normal, .kd = kd, .ks = ks, .alpha = alpha,
                              .depth = 0.5f};
}

/* Shade one texel through sl_lighting_shade (1x1 G-buffer, no task). */
static inline vec3 fx_shade(const sl_lighting_uniforms *u, sl_gbuffer_texel t)
{
    sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t};
    return sl_lighting_shade(u, &gb, 0, 0, NULL, NULL);
}

/* Ground truth (src/ibl/ground_truth.h) for the same texel: returns diffuse + specular as
 * requested, channel 0. */
static inline double fx_truth(const sl_ground_truth *gt, vec3 n, vec3 v, sl_gbuffer_texel t, bool diffuse, bool specular)
{
    sl_gt_query q = {.n = n, .v = v, .kd = t.kd, .ks = t.ks, .alpha = t.alpha, .g = SL_GT_G_INV_LH2,
                     .rotation = 0.0, .intensity = 1.0};
    sl_gt_result r;
    sl_error err;
    if (!sl_ground_truth_shade(gt, &q, &r, &err))
        fail_msg("ground truth: %s", err.msg);
    return (diffuse ? r.diffuse[0] : 0.0) + (specular ? r.specular[0] : 0.0);
}

static inline bool fx_finite3(vec3 v) { return isfinite(v.x) && isfinite(v.y) && isfinite(v.z); }

static inline double fx_luminance(const float *p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

/* Per-pixel relative difference of two radiance images' luminance, floor 1e-3 of the larger:
 * the largest and the mean over every pixel. */
static inline void fx_image_rel_diff(const sl_image *a, const sl_image *b, double *max_rel, double *mean_rel)
{
    size_t n = (size_t)a->width * (size_t)a->height;
    double mx = 0.0, sum = 0.0;
    for (size_t i = 0; i < n; i++) {
        double la = fx_luminance(a->data + 3 * i), lb = fx_luminance(b->data + 3 * i);
        double r = fabs(la - lb) / fmax(fmax(fabs(la), fabs(lb)), 1e-3);
        mx = fmax(mx, r);
        sum += r;
    }
    *max_rel = mx;
    *mean_rel = sum / (double)n;
}

static inline int fx_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Isolated speckles: pixels whose 3x3 neighbourhood lies wholly in `mask` (1 = count it) and
 * whose luminance is below lo x or above hi x the neighbourhood's median. Prints each one. */
static inline int fx_count_speckles(const sl_image *img, const unsigned char *mask, double lo, double hi)
{
    int bad = 0;
    for (int y = 1; y + 1 < img->height; y++)
        for (int x = 1; x + 1 < img->width; x++) {
            double v[9];
            int n = 0;
            bool inside = true;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    inside = inside && mask[(y + dy) * img->width + x + dx];
                    v[n++] = fx_luminance(sl_image_pixel(img, x + dx, y + dy));
                }
            if (!inside)
                continue;
            double c = v[4];
            qsort(v, 9, sizeof v[0], fx_cmp_double);
            double med = v[4];
            if (med > 1e-6 && (c < lo * med || c > hi * med)) {
                if (bad < 10)
                    print_message("speckle at %d,%d: luminance %.5g, 3x3 median %.5g\n", x, y, c, med);
                bad++;
            }
        }
    return bad;
}

/* Coverage of a G-buffer in image orientation (row 0 = top), 1 = covered. */
static inline unsigned char *fx_image_mask(const sl_gbuffer *gb)
{
    unsigned char *m = calloc((size_t)gb->width * (size_t)gb->height, 1);
    assert_non_null(m);
    for (int y = 0; y < gb->height; y++)
        for (int x = 0; x < gb->width; x++)
            m[(gb->height - 1 - y) * gb->width + x] = sl_gbuffer_covered(sl_gbuffer_at(gb, x, y));
    return m;
}

/* ---- a frame to light ---- */

/* What the image tests light: a G-buffer of synthetic spheres, the camera's eye and inverse
 * view-projection, the environment (borrowed: tests build it in many ways) and its SH9 irradiance.
 * env_lights (NULL unless a test sets it) goes into fx_frame_desc. */
typedef struct {
    const sl_env *env;
    sl_irradiance irr;
    sl_gbuffer gb;
    mat4 inv_view_proj;
    vec3 eye;
    const sl_env_lights *env_lights;
} fx_frame;

/* count spheres seen by cam at w x h under env. */
static inline void fx_frame_spheres(fx_frame *f, const sl_env *env, const sl_camera *cam, const sl_synthetic_sphere *s,
                                    int count, int w, int h)
{
    memset(f, 0, sizeof *f);
    f->env = env;
    f->eye = cam->eye;
    sl_error err;
    if (!sl_irradiance_sh9(&f->irr, env, &err))
        fail_msg("irradiance: %s", err.msg);
    if (!sl_gbuffer_synthetic_spheres(&f->gb, w, h, cam, s, count, &f->inv_view_proj, 0, &err))
        fail_msg("synthetic: %s", err.msg);
}

/* The usual frame: three spheres (rough dielectric, glossy, metal with exponent metal_alpha) in
 * front of a camera on -Y. */
static inline void fx_frame_setup(fx_frame *f, const sl_env *env, int w, int h, float metal_alpha)
{
    sl_camera cam = {.eye = vec3(0, -6, 1), .target = vec3(0, 0, 0), .up = vec3(0, 0, 1), .fovy_deg = 40,
                     .znear = 0.1f, .zfar = 100};
    sl_synthetic_sphere s[3] = {
        {vec3(-1.6f, 0, 0), 0.8f, vec3(0.8f, 0.2f, 0.2f), vec3s(0.04f), 1.0f},
        {vec3(0, 0, 0), 0.8f, vec3(0.2f, 0.2f, 0.2f), vec3s(0.04f), 80.0f},
        {vec3(1.6f, 0, 0), 0.8f, vec3s(0.0f), vec3(0.95f, 0.64f, 0.54f), metal_alpha},
    };
    fx_frame_spheres(f, env, &cam, s, 3, w, h);
}

static inline void fx_frame_teardown(fx_frame *f)
{
    sl_gbuffer_free(&f->gb);
    sl_irradiance_free(&f->irr);
}

/* The frame's lighting description with options o; a test adds point lights or swaps the env.
 * The irradiance is always given: the uniforms ignore it when o.no_diffuse is set. */
static inline sl_lighting_desc fx_frame_desc(const fx_frame *f, sl_lighting_options o)
{
    return (sl_lighting_desc){.options = o, .env = f->env, .irradiance = &f->irr, .eye = f->eye,
                              .inv_view_proj = f->inv_view_proj, .width = f->gb.width, .height = f->gb.height,
                              .env_lights = f->env_lights};
}

/* Light gb with desc on `threads` threads into out (allocated on first use): no pixel repaired
 * (stats.nonfinite == 0) and every value finite. stats may be NULL. */
static inline void fx_render(const sl_lighting_desc *desc, const sl_gbuffer *gb, int threads, sl_image *out,
                             sl_lighting_stats *stats)
{
    sl_lighting_uniforms *u = fx_uniforms_for(desc);
    sl_lighting_stats st;
    sl_error err;
    if (!sl_lighting_pass(u, &st, gb, out, threads, &err))
        fail_msg("lighting pass: %s", err.msg);
    assert_int_equal(st.nonfinite, 0);
    size_t n = (size_t)gb->width * (size_t)gb->height * 3;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(out->data[i]))
            fail_msg("value %zu of the image is %g", i, (double)out->data[i]);
    if (stats)
        *stats = st;
    free(u);
}

/* fx_render of the frame with options o, one thread. */
static inline void fx_frame_render(const fx_frame *f, sl_lighting_options o, sl_image *out)
{
    sl_lighting_desc d = fx_frame_desc(f, o);
    fx_render(&d, &f->gb, 1, out, NULL);
}

/* The pass is bitwise identical for any thread count (lighting.h): run it with 1 and with 2
 * threads and assert the same bits in every pixel (reporting the first that differs) and the
 * same counters. out and stats (may be NULL) get the 1-thread result. */
static inline void fx_assert_same_for_thread_counts(const sl_lighting_uniforms *u, const sl_gbuffer *gb, sl_image *out,
                                                    sl_lighting_stats *stats)
{
    sl_image two = {0};
    sl_lighting_stats s1, s2;
    sl_error err;
    if (!sl_lighting_pass(u, &s1, gb, out, 1, &err) || !sl_lighting_pass(u, &s2, gb, &two, 2, &err))
        fail_msg("lighting pass: %s", err.msg);
    assert_same_image(out, &two, "lighting pass, 1 thread against 2");
    assert_same_texels(&s1, &s2, 1, sizeof s1, 0, "lighting counters, 1 thread against 2");
    sl_image_free(&two);
    if (stats)
        *stats = s1;
}

#endif
