/* test_raster_interp.c - perspective-correct varyings and window depth, against ray casting.
 *
 * A textured parallelogram recedes from just behind the eye (so the near plane clips it
 * and the clipped vertices' varyings are tested too) to 12 units away. For every pixel
 * centre the analytic texture coordinate is found by intersecting the pixel's ray with
 * the plane (double precision) and expressing the hit in the parallelogram's edge basis;
 * the window depth follows from the hit's eye-space z through the projection.
 * test_clipped_floor does the same for world positions on scenes/textured.json's floor. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raster/raster.h"
#include "testutil.h"

typedef struct {
    float u, v, depth, inv_w;
    uint32_t count;
} probe_texel;

typedef struct {
    mat4 mvp;
} uniforms;

static void vs_textured(const void *u, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    *clip = mat4_mul_vec4(((const uniforms *)u)->mvp, vec4_from3(in->position, 1.0f));
    varyings[0] = in->texcoord.x;
    varyings[1] = in->texcoord.y;
}

static void fs_probe(const void *u, const sl_fragment_in *in, void *texel)
{
    (void)u;
    probe_texel *t = texel;
    t->u = in->varyings[0];
    t->v = in->varyings[1];
    t->depth = in->frag_coord.z;
    t->inv_w = in->frag_coord.w;
    t->count++;
}

static void test_perspective(void **state)
{
    (void)state;
    enum { W = 64, H = 64 };
    const double fovy = 60.0, n = 0.5, f = 20.0;
    /* P0, P1 at z = +0.5 (behind the eye: w = -0.5), P3 at z = -12; P2 = P1 + P3 - P0 */
    const vec3 pos[] = {{-3, -2, 0.5f}, {3, -2, 0.5f}, {3, 2, -12}, {-3, 2, -12}};
    const vec2 tc[] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
    sl_mesh mesh = {.vertex_count = 4, .triangle_count = 2, .positions = (vec3 *)pos, .texcoords = (vec2 *)tc,
                    .indices = (uint32_t *)idx};
    uniforms u = {perspective(radians((float)fovy), 1.0f, (float)n, (float)f)};
    sl_program prog = {.vertex = vs_textured, .fragment = fs_probe, .varying_count = 2};
    probe_texel *tex = calloc(W * H, sizeof *tex);
    assert_non_null(tex);
    for (int i = 0; i < W * H; i++)
        tex[i].depth = 1.0f;
    sl_target target = {.width = W, .height = H, .texel_size = sizeof *tex, .texels = tex, .depth_offset = (long)offsetof(probe_texel, depth)};
    sl_error err = {0};
    sl_raster *r = sl_raster_create(&(sl_raster_desc){.threads = 2, .tile_size = 16, .stats = true}, &err);
    assert_non_null(r);
    const sl_draw draw = {.program = &prog, .vs_uniforms = &u, .fs_uniforms = &u, .mesh = &mesh, .cull = SL_CULL_NONE};
    assert_true(sl_raster_draw(r, &target, &draw, &err));
    assert_int_equal(sl_raster_get_stats(r).triangles_clipped, 2);

    const double t = tan(fovy * 3.14159265358979 / 360.0);
    const double P0[3] = {-3, -2, 0.5}, EU[3] = {6, 0, 0}, EV[3] = {0, 4, -12.5};
    const double N[3] = {EU[1] * EV[2] - EU[2] * EV[1], EU[2] * EV[0] - EU[0] * EV[2], EU[0] * EV[1] - EU[1] * EV[0]};
    double max_uv = 0, max_depth = 0, max_w = 0;
    int checked = 0, coverage_wrong = 0;
    /* The analytic v along the centre column is far from linear: screen-space (affine)
     * interpolation would be off by much more than the tolerance. */
    double v_lo = -1, v_mid = -1, v_hi = -1;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double d[3] = {((x + 0.5) / W * 2 - 1) * t, ((y + 0.5) / H * 2 - 1) * t, -1};
            double s = (P0[0] * N[0] + P0[1] * N[1] + P0[2] * N[2]) / (d[0] * N[0] + d[1] * N[1] + d[2] * N[2]);
            double hit[3] = {s * d[0], s * d[1], s * d[2]};
            double au = (hit[0] - P0[0]) / EU[0], av = (hit[1] - P0[1]) / EV[1];
            double ze = hit[2];
            double zndc = ((f + n) / (n - f) * ze + 2 * f * n / (n - f)) / -ze;
            double depth = zndc * 0.5 + 0.5;
            double margin = fmin(fmin(au, 1 - au), fmin(fmin(av, 1 - av), s - n));
            const probe_texel *p = &tex[y * W + x];
            if (x == W / 2) {
                if (y == 20) v_lo = av;
                if (y == 40) v_mid = av;
                if (y == 60) v_hi = av;
            }
            if (fabs(margin) > 1e-3 && p->count != (margin > 0 ? 1u : 0u)) {
                print_error("pixel (%d,%d): covered %u, ray cast margin %g\n", x, y, p->count, margin);
                coverage_wrong++;
            }
            if (p->count != 1)
                continue;
            checked++;
            double e = fmax(fabs(p->u - au), fabs(p->v - av));
            if (e > max_uv) {
                max_uv = e;
                if (e > 5e-6)
                    print_error("pixel (%d,%d): uv (%.6f, %.6f), analytic (%.6f, %.6f)\n", x, y, (double)p->u,
                                (double)p->v, au, av);
            }
            max_depth = fmax(max_depth, fabs(p->depth - depth));
            max_w = fmax(max_w, fabs(p->inv_w * s - 1.0)); /* gl_FragCoord.w = 1/w_clip = 1/s */
        }
    print_message("perspective: %d pixels, max |uv error| %.3g, max |depth error| %.3g, max rel 1/w error %.3g\n",
                  checked, max_uv, max_depth, max_w);
    assert_int_equal(coverage_wrong, 0);
    assert_true(checked > W * H / 3);
    /* The planes are built on the exact window positions in double (setup.c) and evaluated in
     * float: measured uv 5.0e-7, depth 7.3e-8, 1/w 3.4e-7 of itself; the bounds are 10x that.
     * Built on the positions snapped to 1/256 pixel (a shift of up to 1/512 pixel times the
     * gradient) they were 6.5e-5, 3.7e-6 and 7.4e-5: each fails its bound. */
    assert_true(max_uv < 5e-6);
    assert_true(max_depth < 1e-6);
    assert_true(max_w < 5e-6);
    /* v at rows 20, 40, 60: the middle differs from the mean of the ends by far more than 2e-4 */
    assert_true(fabs(v_mid - 0.5 * (v_lo + v_hi)) > 0.02);
    sl_raster_destroy(r);
    free(tex);
}

/* World position of a floor crossing the near plane, far to the horizon, against the
 * analytic ray-plane hit: scenes/textured.json's floor and camera (an 80-unit floor, near 0.05,
 * far 200) at 320x180. Near-clipping cuts each of its two triangles into a polygon whose cut
 * vertices have 1/w = 20 and lie at the guard band (16000 pixels off screen), while the pixels
 * at the horizon have 1/w = 0.012: the attribute planes must be built on the exact window
 * positions and anchored near the pixels (setup.c). Built on the snapped positions about vertex
 * 0 in float, the horizon's positions would be off by up to 4.0e-3 of their distance (0.34 units
 * at 82); as built, 3.1e-6 (mean 3.2e-7); llvmpipe's float rounding is 5.8e-7 (docs/gl.md
 * "Clipped triangles"). */
typedef struct {
    vec3 pos;
    float depth;
    uint32_t count;
} floor_texel;

static void vs_world(const void *u, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    *clip = mat4_mul_vec4(((const uniforms *)u)->mvp, vec4_from3(in->position, 1.0f));
    varyings[0] = in->position.x;
    varyings[1] = in->position.y;
    varyings[2] = in->position.z;
}

static void fs_world(const void *u, const sl_fragment_in *in, void *texel)
{
    (void)u;
    floor_texel *t = texel;
    t->pos = vec3(in->varyings[0], in->varyings[1], in->varyings[2]);
    t->depth = in->frag_coord.z;
    t->count++;
}

static void test_clipped_floor(void **state)
{
    (void)state;
    enum { W = 320, H = 180 };
    const double eye[3] = {0.6, -6.5, 1.7}, target[3] = {0.4, 2, 0.8}, fovy = 45;
    const vec3 pos[] = {{-80, -80, 0}, {80, -80, 0}, {80, 80, 0}, {-80, 80, 0}};
    const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
    sl_mesh mesh = {.vertex_count = 4, .triangle_count = 2, .positions = (vec3 *)pos, .indices = (uint32_t *)idx};
    mat4 view = lookAt(vec3((float)eye[0], (float)eye[1], (float)eye[2]),
                       vec3((float)target[0], (float)target[1], (float)target[2]), vec3(0, 0, 1));
    uniforms u = {mat4_mul(perspective(radians((float)fovy), (float)W / (float)H, 0.05f, 200.0f), view)};
    sl_program prog = {.vertex = vs_world, .fragment = fs_world, .varying_count = 3};
    floor_texel *tex = calloc(W * H, sizeof *tex);
    assert_non_null(tex);
    for (int i = 0; i < W * H; i++)
        tex[i].depth = 1.0f;
    sl_target tg = {.width = W, .height = H, .texel_size = sizeof *tex, .texels = tex, .depth_offset = (long)offsetof(floor_texel, depth)};
    sl_error err = {0};
    sl_raster *r = sl_raster_create(&(sl_raster_desc){.threads = 2, .tile_size = 32, .stats = true}, &err);
    assert_non_null(r);
    const sl_draw draw = {.program = &prog, .vs_uniforms = &u, .fs_uniforms = &u, .mesh = &mesh, .cull = SL_CULL_NONE};
    assert_true(sl_raster_draw(r, &tg, &draw, &err));
    assert_int_equal(sl_raster_get_stats(r).triangles_clipped, 2);

    /* the camera's basis in double: forward f, side s = f x up, up' = s x f */
    double f[3] = {target[0] - eye[0], target[1] - eye[1], target[2] - eye[2]};
    double fl = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int k = 0; k < 3; k++)
        f[k] /= fl;
    double sd[3] = {f[1], -f[0], 0}; /* f x (0, 0, 1) */
    double sl = sqrt(sd[0] * sd[0] + sd[1] * sd[1]);
    sd[0] /= sl;
    sd[1] /= sl;
    const double up[3] = {sd[1] * f[2] - sd[2] * f[1], sd[2] * f[0] - sd[0] * f[2], sd[0] * f[1] - sd[1] * f[0]};
    const double t = tan(fovy * 3.14159265358979 / 360.0), aspect = (double)W / H;
    double worst = 0, sum = 0;
    int checked = 0, coverage_wrong = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double nx = ((x + 0.5) / W * 2 - 1) * t * aspect, ny = ((y + 0.5) / H * 2 - 1) * t;
            double d[3];
            for (int k = 0; k < 3; k++)
                d[k] = f[k] + sd[k] * nx + up[k] * ny;
            const floor_texel *p = &tex[y * W + x];
            /* rays at least 1e-3 below the horizon hit the floor (within 80 units: all but the
             * sky); rays near it are left out of the coverage check */
            if (d[2] > -1e-3) {
                if (d[2] > 1e-3 && p->count != 0)
                    coverage_wrong++;
                continue;
            }
            double s = -eye[2] / d[2];
            double hx = eye[0] + s * d[0], hy = eye[1] + s * d[1];
            if (fabs(hx) > 79 || fabs(hy) > 79)
                continue; /* beyond the floor's edge, or close to it */
            if (p->count != 1) {
                coverage_wrong++;
                continue;
            }
            double dist = s * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            double e = fmax(fmax(fabs(p->pos.x - hx), fabs(p->pos.y - hy)), fabs((double)p->pos.z)) / dist;
            if (e > worst) {
                worst = e;
                if (e > 1e-5)
                    print_error("pixel (%d,%d): position (%.5f, %.5f), analytic (%.5f, %.5f), %.1f away\n", x, y,
                                (double)p->pos.x, (double)p->pos.y, hx, hy, dist);
            }
            sum += e;
            checked++;
        }
    print_message("clipped floor: %d pixels, max error %.3g of the distance, mean %.3g\n", checked, worst,
                  sum / checked);
    assert_int_equal(coverage_wrong, 0);
    assert_true(checked > W * H / 2);
    /* float vertex and fragment stages: the clip coordinates carry about 1e-7 of 80 units, the
     * horizon's 1/w plane about 1e-7 of its terms; 1e-5 is 3x the measured 3.1e-6 and 400 times
     * below the old error */
    assert_true(worst < 1e-5);
    sl_raster_destroy(r);
    free(tex);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_perspective),
        cmocka_unit_test(test_clipped_floor),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
