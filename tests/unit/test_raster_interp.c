/* test_raster_interp.c - perspective-correct varyings and window depth, against ray casting.
 *
 * A textured parallelogram recedes from just behind the eye (so the near plane clips it
 * and the clipped vertices' varyings are tested too) to 12 units away. For every pixel
 * centre the analytic texture coordinate is found by intersecting the pixel's ray with
 * the plane (double precision) and expressing the hit in the parallelogram's edge basis;
 * the window depth follows from the hit's eye-space z through the projection. */
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
    sl_target target = {W, H, sizeof *tex, tex, (long)offsetof(probe_texel, depth)};
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
                if (e > 2e-4)
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
    assert_true(max_uv < 2e-4);
    /* Depth is float z/w interpolated over vertices snapped to 1/256 pixel: a shift of up to
     * 1/512 pixel times a depth gradient near 1e-3 per pixel (close to the near plane), plus
     * float rounding, stays below 1e-5. uv: float planes of u/w, v/w and 1/w, about 1e-4. */
    assert_true(max_depth < 1e-5);
    assert_true(max_w < 1e-4);
    /* v at rows 20, 40, 60: the middle differs from the mean of the ends by far more than 2e-4 */
    assert_true(fabs(v_mid - 0.5 * (v_lo + v_hi)) > 0.02);
    sl_raster_destroy(r);
    free(tex);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_perspective),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
