/* test_raster_quad.c - 2x2 quads, helper invocations, derivatives and discard (src/raster/quad.c,
 * tile.c's quad path, glsl.h's built-ins).
 *
 * Geometry is placed in window coordinates on a 64x64 target (clip = pos / 32 - 1, w = 1), so
 * attribute planes and pixel centres are exact dyadic numbers: the derivative of a linear ramp
 * must equal its slope exactly, and every expected value below is computed by hand (or, for the
 * lock-step results of chained derivatives, by the test with the same float operations in the
 * order a GPU's quad would do them). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raster/raster.h"
#include "testutil.h"

enum { W = 64, H = 64 };

typedef struct {
    float d[8];
    float depth;
    int32_t tag, count, helper;
} qtexel;

static const qtexel SENTINEL = {.d = {-7, -7, -7, -7, -7, -7, -7, -7}, .depth = 1.0f, .tag = -1};

/* window coordinates -> clip; varyings: 0.25 x + 3 (a ramp), x (the pixel centre's x), y */
static void vs_window(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *v)
{
    (void)uniforms;
    *clip = vec4(in->position.x / 32.0f - 1.0f, in->position.y / 32.0f - 1.0f, in->position.z, 1.0f);
    v[0] = 0.25f * in->position.x + 3.0f;
    v[1] = in->position.x;
    v[2] = in->position.y;
}

static void fill(qtexel *t)
{
    for (int i = 0; i < W * H; i++)
        t[i] = SENTINEL;
}

/* Draw triangle (a, b, c) (window coordinates, z as clip z) with `prog` into t. */
static sl_raster_stats draw_tri(sl_raster *r, const sl_program *prog, qtexel *t, bool depth, vec3 a, vec3 b, vec3 c)
{
    vec3 p[3] = {a, b, c};
    uint32_t idx[3] = {0, 1, 2};
    sl_mesh m = {.vertex_count = 3, .triangle_count = 1, .positions = p, .indices = idx};
    sl_target target = {.width = W, .height = H, .texel_size = sizeof(qtexel), .texels = t, .depth_offset = depth ? (long)offsetof(qtexel, depth) : SL_NO_DEPTH};
    sl_error err = {0};
    sl_raster_reset_stats(r);
    assert_true(sl_raster_draw(r, &target, &(sl_draw){.program = prog, .mesh = &m}, &err));
    return sl_raster_get_stats(r);
}

static void mark(qtexel *t, const sl_fragment_in *in)
{
    t->count++;
    t->helper += in->helper;
}

/* ---- derivatives of ramps, a quadratic, fine against coarse ---- */

static void fs_ramps(const void *u, const sl_fragment_in *in, void *texel)
{
    (void)u;
    qtexel *t = texel;
    float ramp = in->varyings[0];
    vec2 fc = vec2(3.0f * in->frag_coord.x, 0.5f * in->frag_coord.y); /* computed from gl_FragCoord */
    vec2 dfc = dFdx(in, fc);
    float x = in->varyings[1], y = in->varyings[2];
    t->d[0] = dFdx(in, ramp);
    t->d[1] = dFdy(in, ramp);
    t->d[2] = dfc.x + dFdy(in, fc).y; /* 3 + 0.5 */
    t->d[3] = dFdx(in, x * x);        /* a quadratic: the forward difference from the even column */
    t->d[4] = dFdxFine(in, x * y);
    t->d[5] = dFdxCoarse(in, x * y);
    t->d[6] = dFdyFine(in, x * y);
    t->d[7] = dFdyCoarse(in, x * y) + fwidth(in, vec3(ramp, 0, 0)).x * 1024.0f;
    mark(t, in);
}

static const sl_program prog_ramps = {.vertex = vs_window, .fragment = fs_ramps, .varying_count = 3,
                                      .derivatives = true};

static void test_derivatives_exact(void **state)
{
    (void)state;
    static qtexel t[W * H];
    for (int plain = 0; plain < 2; plain++) {
        fill(t);
        sl_raster *r = test_make_raster(2, 16, true, plain);
        sl_raster_stats st = draw_tri(r, &prog_ramps, t, false, vec3(0, 0, 0), vec3(64, 0, 0), vec3(0, 64, 0));
        sl_raster_destroy(r);
        int covered = 0, bad = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const qtexel *q = &t[y * W + x];
                if (x + y >= 63) { /* outside: the diagonal's centres x + y + 1 = 64 are on a right edge */
                    bad += q->count != 0 || q->tag != -1;
                    continue;
                }
                covered++;
                float xc = (float)x + 0.5f, yc = (float)y + 0.5f;
                float xe = (float)(x & ~1) + 0.5f, ye = (float)(y & ~1) + 0.5f;
                float quad_d = (xe + 1.0f) * (xe + 1.0f) - xe * xe;
                bool ok = q->d[0] == 0.25f && q->d[1] == 0.0f && q->d[2] == 3.5f && q->d[3] == quad_d &&
                          q->d[4] == yc && q->d[5] == ye && q->d[6] == xc &&
                          q->d[7] == xe + 0.25f * 1024.0f && q->count == 1 && q->helper == 0;
                if (!ok && bad++ < 3)
                    print_error("pixel %d,%d: %g %g %g %g %g %g %g %g count %d\n", x, y, (double)q->d[0],
                                (double)q->d[1], (double)q->d[2], (double)q->d[3], (double)q->d[4], (double)q->d[5],
                                (double)q->d[6], (double)q->d[7], q->count);
            }
        assert_int_equal(bad, 0);
        assert_int_equal(covered, 64 * 63 / 2);
        assert_int_equal(st.fragments_shaded, covered);
        /* each quad: the 4 lanes, every call reads varyings or gl_FragCoord: 2 rounds */
        assert_true(st.quads > 0);
        assert_int_equal(st.quad_rounds, 2 * st.quads);
        assert_int_equal(st.helper_invocations, 4 * st.quads - covered);
        /* the 32 quads on the diagonal cover only their lane 0 (x + y = 62): 3 helpers each */
        assert_int_equal(st.helper_invocations, 96);
    }
}

/* ---- a one-pixel-wide triangle: helpers carry the derivatives, write nothing ---- */

static void fs_sliver(const void *u, const sl_fragment_in *in, void *texel)
{
    (void)u;
    qtexel *t = texel;
    t->d[0] = dFdx(in, in->varyings[0]);
    t->d[1] = dFdx(in, 3.0f * in->frag_coord.x);
    t->d[2] = dFdy(in, in->varyings[0]);
    t->tag = 5;
    mark(t, in);
}

static const sl_program prog_sliver = {.vertex = vs_window, .fragment = fs_sliver, .varying_count = 3,
                                       .derivatives = true};

static void test_sliver_helpers(void **state)
{
    (void)state;
    static qtexel t[W * H];
    const int cols[2] = {10, 21}; /* an even column (helpers on its right) and an odd one (on its left) */
    for (int k = 0; k < 2; k++) {
        float cx = (float)cols[k] + 0.5f;
        fill(t);
        sl_raster *r = test_make_raster(1, 64, true, false);
        sl_raster_stats st =
            draw_tri(r, &prog_sliver, t, true, vec3(cx - 0.25f, 2, 0), vec3(cx + 0.25f, 2, 0), vec3(cx, 62, 0));
        sl_raster_destroy(r);
        int shaded = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const qtexel *q = &t[y * W + x];
                if (x != cols[k] || y < 2 || y > 61) {
                    assert_true(memcmp(q, &SENTINEL, sizeof *q) == 0); /* helpers wrote nothing */
                    continue;
                }
                shaded++;
                assert_int_equal(q->tag, 5);
                assert_int_equal(q->helper, 0);
                assert_near(q->d[0], 0.25, 1e-5); /* the plane's slope, extrapolated by the helper */
                assert_true(q->d[1] == 3.0f);     /* gl_FragCoord at the helper's centre: exact */
                assert_near(q->d[2], 0.0, 1e-5);
                assert_near(q->depth, 0.5, 1e-6);
            }
        assert_int_equal(shaded, 60);
        assert_int_equal(st.fragments_shaded, 60);
        assert_int_equal(st.quads, 30);
        assert_int_equal(st.helper_invocations, 60);
    }
}

/* ---- a derivative of a value computed from a derivative (2 levels) ---- */

/* texture-like: a level from a derivative, then a value fetched with it */
static float level_of(float d) { return floorf(log2f(d)); }

static void fs_chain(const void *u, const sl_fragment_in *in, void *texel)
{
    (void)u;
    qtexel *t = texel;
    float x = in->varyings[1], y = in->varyings[2];
    float a = x * x + y;
    float d1 = dFdx(in, a);
    float b = level_of(d1) * x + sinf(y);
    t->d[0] = d1;
    t->d[1] = b;
    t->d[2] = dFdx(in, b);
    t->d[3] = dFdy(in, b);
    mark(t, in);
}

static const sl_program prog_chain = {.vertex = vs_window, .fragment = fs_chain, .varying_count = 3,
                                      .derivatives = true};

static void test_chained_derivatives(void **state)
{
    (void)state;
    static qtexel t[W * H];
    fill(t);
    sl_raster *r = test_make_raster(2, 32, true, false);
    sl_raster_stats st = draw_tri(r, &prog_chain, t, false, vec3(0, 0, 0), vec3(64, 0, 0), vec3(0, 64, 0));
    sl_raster_destroy(r);
    int checked = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x + y < 63; x++) {
            /* the lock-step result, lane by lane in the quad of (x, y) */
            float a[4], d1[4], b[4];
            for (int l = 0; l < 4; l++) {
                float lx = (float)((x & ~1) + (l & 1)) + 0.5f, ly = (float)((y & ~1) + (l >> 1)) + 0.5f;
                a[l] = lx * lx + ly;
            }
            for (int l = 0; l < 4; l++)
                d1[l] = a[l | 1] - a[l & 2];
            for (int l = 0; l < 4; l++) {
                float lx = (float)((x & ~1) + (l & 1)) + 0.5f, ly = (float)((y & ~1) + (l >> 1)) + 0.5f;
                b[l] = level_of(d1[l]) * lx + sinf(ly);
            }
            int l = (x & 1) + 2 * (y & 1);
            const qtexel *q = &t[y * W + x];
            assert_true(q->d[0] == d1[l] && q->d[1] == b[l]);
            assert_true(q->d[2] == b[l | 1] - b[l & 2]);
            assert_true(q->d[3] == b[l | 2] - b[l & 1]);
            checked++;
        }
    assert_int_equal(checked, 64 * 63 / 2);
    /* round 1 gets a, round 2 b, round 3 confirms: 3 rounds a quad */
    assert_int_equal(st.quad_rounds, 3 * st.quads);
}

/* ---- discard ---- */

static void fs_far(const void *u, const sl_fragment_in *in, void *texel)
{
    (void)u;
    qtexel *t = texel;
    t->tag = 1;
    t->depth = in->frag_coord.z;
    mark(t, in);
}

/* discards the left half (pixel centre x < 32) */
static void fs_cut(const void *u, const sl_fragment_in *in, void *texel)
{
    (void)u;
    qtexel *t = texel;
    t->tag = 2; /* written before the discard: must not reach the target */
    t->depth = in->frag_coord.z;
    if (in->varyings[1] < 32.0f) {
        discard(in);
        return;
    }
    mark(t, in);
}

/* the same with a derivative: fwidth of the ramp is 0.25 everywhere */
static void fs_cut_deriv(const void *u, const sl_fragment_in *in, void *texel)
{
    (void)u;
    qtexel *t = texel;
    t->tag = 2;
    t->depth = in->frag_coord.z;
    t->d[0] = fwidth(in, in->varyings[0]);
    if (in->varyings[1] < 32.0f) {
        discard(in);
        return;
    }
    mark(t, in);
}

static const sl_program prog_far = {.vertex = vs_window, .fragment = fs_far, .varying_count = 3};
static const sl_program prog_cut = {.vertex = vs_window, .fragment = fs_cut, .varying_count = 3, .discards = true};
static const sl_program prog_cut_deriv = {.vertex = vs_window, .fragment = fs_cut_deriv, .varying_count = 3,
                                          .discards = true, .derivatives = true};

/* A discarding triangle at depth 0.25, then a non-discarding one behind it at 0.75: where
 * the first discarded, neither its texel nor its depth was written, so the one behind shows. */
static void test_discard(void **state)
{
    (void)state;
    static qtexel t[W * H];
    const sl_program *cut[2] = {&prog_cut, &prog_cut_deriv};
    for (int k = 0; k < 2; k++)
        for (int plain = 0; plain < 2; plain++) {
            fill(t);
            sl_raster *r = test_make_raster(2, 16, true, plain);
            sl_raster_stats s1 =
                draw_tri(r, cut[k], t, true, vec3(-64, -64, -0.5f), vec3(192, -64, -0.5f), vec3(-64, 192, -0.5f));
            sl_raster_stats s2 =
                draw_tri(r, &prog_far, t, true, vec3(-64, -64, 0.5f), vec3(192, -64, 0.5f), vec3(-64, 192, 0.5f));
            sl_raster_destroy(r);
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    const qtexel *q = &t[y * W + x];
                    if (x < 32) {
                        assert_int_equal(q->tag, 1);
                        assert_true(q->depth == 0.75f);
                        assert_true(q->d[0] == -7.0f);
                    } else {
                        assert_int_equal(q->tag, 2);
                        assert_true(q->depth == 0.25f);
                        assert_true(q->d[0] == (k ? 0.25f : -7.0f));
                    }
                    assert_int_equal(q->count, 1);
                }
            assert_int_equal(s1.fragments_shaded, W * H);
            assert_int_equal(s1.fragments_discarded, W * H / 2);
            assert_int_equal(s1.fragments_late_z, W * H / 2);
            /* the program that cannot discard keeps the early test: no late depth write, and
             * its occluded half never reaches the shader */
            assert_int_equal(s2.fragments_late_z, 0);
            assert_int_equal(s2.fragments_discarded, 0);
            assert_int_equal(s2.fragments_tested, W * H);
            assert_int_equal(s2.fragments_shaded, W * H / 2);
            assert_int_equal(s2.quads, 0);
        }
}

/* ---- stores outside the texel (sl_program.stores) ---- */

/* Stores into the plane its uniforms point to (an image store): one count a store. Round 1 of
 * the rounds sees fwidth 0 and keeps every lane; from round 2 on, the left half (x < 32) sees
 * the true 0.25 and discards. So a store in round 1 would leave counts where no texel is. */
static void fs_store(const void *u, const sl_fragment_in *in, void *texel)
{
    int32_t *plane = (int32_t *)u;
    qtexel *t = texel;
    t->tag = 3;
    if (fwidth(in, in->varyings[0]) > 0.0f && in->varyings[1] < 32.0f) {
        discard(in);
        return;
    }
    if (sl_fragment_stores(in))
        plane[in->y * W + in->x]++;
    mark(t, in);
}

static const sl_program prog_store = {.vertex = vs_window, .fragment = fs_store, .varying_count = 3,
                                      .derivatives = true, .discards = true, .stores = true};

/* Only the last round stores, once, and only for the lanes that keep their texel: none at the
 * discarded left half, none from a helper (the triangle's diagonal quads have some). */
static void test_stores(void **state)
{
    (void)state;
    static qtexel t[W * H];
    static int32_t plane[W * H];
    for (int plain = 0; plain < 2; plain++)
        for (int threads = 1; threads <= 2; threads++) {
            fill(t);
            memset(plane, 0, sizeof plane);
            sl_raster *r = test_make_raster(threads, 16, true, plain);
            vec3 p[3] = {vec3(0, 0, 0), vec3(64, 0, 0), vec3(0, 64, 0)};
            uint32_t idx[3] = {0, 1, 2};
            sl_mesh m = {.vertex_count = 3, .triangle_count = 1, .positions = p, .indices = idx};
            sl_target target = {.width = W, .height = H, .texel_size = sizeof(qtexel), .texels = t,
                                .depth_offset = SL_NO_DEPTH};
            sl_error err = {0};
            assert_true(sl_raster_draw(r, &target, &(sl_draw){.program = &prog_store, .fs_uniforms = plane, .mesh = &m},
                                       &err));
            sl_raster_stats st = sl_raster_get_stats(r);
            sl_raster_destroy(r);
            int kept = 0;
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    bool keep = x + y < 63 && x >= 32;
                    kept += keep;
                    if (plane[y * W + x] != (keep ? 1 : 0) || t[y * W + x].tag != (keep ? 3 : -1))
                        fail_msg("plain %d threads %d: pixel %d,%d stored %d times, tag %d", plain, threads, x, y,
                                 plane[y * W + x], t[y * W + x].tag);
                }
            assert_int_equal(kept, 32 * 31 / 2);
            /* the one call reads a varying: round 2 records what round 1 did (the fixed point),
             * then round 3 repeats it with stores on */
            assert_int_equal(st.quad_rounds, 3 * st.quads);
        }
}

/* ---- determinism: any thread count and tile size, plain or not ---- */

static void test_quads_deterministic(void **state)
{
    (void)state;
    static qtexel ref[W * H], out[W * H];
    const sl_program *progs[3] = {&prog_chain, &prog_cut_deriv, &prog_cut};
    for (int p = 0; p < 3; p++) {
        fill(ref);
        sl_raster *r = test_make_raster(1, 16, true, true);
        draw_tri(r, progs[p], ref, true, vec3(3.3f, 1.7f, 0.1f), vec3(61.2f, 20.4f, -0.3f), vec3(17.9f, 63.1f, 0.4f));
        draw_tri(r, progs[p], ref, true, vec3(60, 60, -0.2f), vec3(1, 40, 0.2f), vec3(40, 2, 0));
        sl_raster_destroy(r);
        const int cfg[][2] = {{2, 16}, {3, 32}, {1, 64}, {2, 256}};
        for (int k = 0; k < 4; k++)
            for (int plain = 0; plain < 2; plain++) {
                fill(out);
                r = test_make_raster(cfg[k][0], cfg[k][1], true, plain);
                draw_tri(r, progs[p], out, true, vec3(3.3f, 1.7f, 0.1f), vec3(61.2f, 20.4f, -0.3f),
                         vec3(17.9f, 63.1f, 0.4f));
                draw_tri(r, progs[p], out, true, vec3(60, 60, -0.2f), vec3(1, 40, 0.2f), vec3(40, 2, 0));
                sl_raster_destroy(r);
                assert_same_texels(ref, out, W * H, sizeof(qtexel), W, "program %d, threads %d, tile %d, plain %d", p,
                                   cfg[k][0], cfg[k][1], plain);
            }
    }
}

/* A quad form (or a multi-quad form) without derivatives = true is refused; derivative built-ins in a program
 * without the flag return 0, and discard does nothing. */
static void quad_form(const void *u, const sl_fragment_in in[4], void *const texel[4])
{
    (void)u;
    (void)in;
    (void)texel;
}

static void quads_form(const void *u, const sl_fragment_quads *q)
{
    (void)u;
    (void)q;
}

static void test_flags(void **state)
{
    (void)state;
    static qtexel t[W * H];
    sl_program bad = prog_far;
    bad.fragment_quad = quad_form;
    sl_raster *r = test_make_raster(1, 64, true, false);
    vec3 p[3] = {{0, 0, 0}, {64, 0, 0}, {0, 64, 0}};
    uint32_t idx[3] = {0, 1, 2};
    sl_mesh m = {.vertex_count = 3, .triangle_count = 1, .positions = p, .indices = idx};
    sl_error err = {0};
    assert_false(sl_raster_draw(r, &(sl_target){.width = W, .height = H, .texel_size = sizeof(qtexel), .texels = t, .depth_offset = SL_NO_DEPTH},
                                &(sl_draw){.program = &bad, .mesh = &m}, &err));
    assert_msg_contains(err, "fragment_quad");
    bad.fragment_quad = NULL;
    bad.fragment_quads = quads_form;
    err = (sl_error){0};
    assert_false(sl_raster_draw(r, &(sl_target){.width = W, .height = H, .texel_size = sizeof(qtexel), .texels = t, .depth_offset = SL_NO_DEPTH},
                                &(sl_draw){.program = &bad, .mesh = &m}, &err));
    assert_msg_contains(err, "fragment_quads");
    sl_program noflag = prog_cut_deriv;
    noflag.derivatives = noflag.discards = false;
    fill(t);
    sl_raster_stats st = draw_tri(r, &noflag, t, false, p[0], p[1], p[2]);
    sl_raster_destroy(r);
    assert_int_equal(st.quads, 0);
    assert_int_equal(st.fragments_discarded, 0);
    for (int y = 0; y < H; y++)
        for (int x = 0; x + y < 63; x++)
            assert_true(t[y * W + x].tag == 2 && t[y * W + x].d[0] == 0.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_derivatives_exact), cmocka_unit_test(test_sliver_helpers),
        cmocka_unit_test(test_chained_derivatives), cmocka_unit_test(test_discard), cmocka_unit_test(test_stores),
        cmocka_unit_test(test_quads_deterministic), cmocka_unit_test(test_flags),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
