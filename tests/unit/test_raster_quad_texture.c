/* test_raster_quad_texture.c - texture(in, s, uv) (softlight/glsl.h): the implicit
 * level of detail, one lambda per 2x2 quad from the coarse derivatives of uv, as llvmpipe.
 * Apart from test_raster_quad.c because testutil.h brings ibl.h, whose textureLod (the
 * environment's) has the name of texture.h's. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "raster/texture.h"
#include "testutil.h"

enum { W = 64, H = 64 };

typedef struct {
    float d[8];
    float depth;
    int32_t tag, count, helper;
} qtexel;

static void vs_window(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *v)
{
    (void)uniforms;
    *clip = vec4(in->position.x / 32.0f - 1.0f, in->position.y / 32.0f - 1.0f, in->position.z, 1.0f);
    v[0] = v[1] = v[2] = 0.0f;
}

static void fill(qtexel *t)
{
    for (int i = 0; i < W * H; i++)
        t[i] = (qtexel){.d = {-7, -7, -7}, .depth = 1.0f, .tag = -1};
}

static void mark(qtexel *t, const sl_fragment_in *in)
{
    t->count++;
    t->helper += in->helper;
}

/* ---- texture(): the implicit level, one per quad ---- */

typedef struct {
    const sl_sampler2D *s;
    float scale; /* texels of level 0 per pixel in x */
} tex_uniforms;

/* a 64x64 checkerboard of single texels (0 and 1): its level 1 and above are 0.5 */
static void fs_tex(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    const tex_uniforms *u = uniforms;
    qtexel *t = texel;
    float x = in->frag_coord.x, y = in->frag_coord.y;
    vec2 uv = vec2(x * u->scale / 64.0f, y / 64.0f + x * x / 8192.0f); /* dv/dx grows along x */
    vec4 c = texture(in, u->s, uv);
    vec4 g = textureGrad(u->s, uv, dFdxCoarse(in, uv), dFdyCoarse(in, uv));
    t->d[0] = c.x;
    t->d[1] = g.x;
    t->d[2] = sl_texture_lambda_quad(u->s, dFdxCoarse(in, uv), dFdyCoarse(in, uv), 0.0f);
    mark(t, in);
}

static const sl_program prog_tex = {.vertex = vs_window, .fragment = fs_tex, .varying_count = 3,
                                    .derivatives = true};

static void test_texture_implicit_lod(void **state)
{
    (void)state;
    static float board[64 * 64];
    for (int i = 0; i < 64 * 64; i++)
        board[i] = (float)((i % 64 + i / 64) & 1);
    sl_texture *tex = NULL;
    sl_error err = {0};
    assert_true(sl_texture_create(SL_TEX_R32F, 64, 64, board, true, &tex, &err));
    sl_sampler2D s = {tex, sl_sampler_default()};
    s.state.min_filter = SL_NEAREST_MIPMAP_NEAREST;
    s.state.mag_filter = SL_NEAREST;
    static qtexel t[W * H];
    const float scales[2] = {4.0f, 1.0f};
    for (int k = 0; k < 2; k++) {
        tex_uniforms u = {&s, scales[k]};
        sl_program prog = prog_tex;
        fill(t);
        sl_raster *r = test_make_raster(2, 16, true, k == 1);
        vec3 p[3] = {{0, 0, 0}, {128, 0, 0}, {0, 128, 0}};
        uint32_t idx[3] = {0, 1, 2};
        sl_mesh m = {.vertex_count = 3, .triangle_count = 1, .positions = p, .indices = idx};
        assert_true(sl_raster_draw(r, &(sl_target){.width = W, .height = H, .texel_size = sizeof(qtexel), .texels = t, .depth_offset = SL_NO_DEPTH},
                                   &(sl_draw){.program = &prog, .fs_uniforms = &u, .mesh = &m}, &err));
        sl_raster_stats st = sl_raster_get_stats(r);
        sl_raster_destroy(r);
        assert_int_equal(st.quad_rounds, 2 * st.quads);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const qtexel *q = &t[y * W + x], *q0 = &t[(y & ~1) * W + (x & ~1)];
                assert_true(q->d[0] == q->d[1]);  /* texture() = textureGrad with the coarse derivatives */
                assert_true(q->d[2] == q0->d[2]); /* one lambda per quad */
                if (k == 0)                       /* 4 texels a pixel in u: rho >= 4, lambda >= 2: a mip, 0.5 */
                    assert_true(q->d[2] >= 2.0f && q->d[0] == 0.5f);
                else if (x < 16 && y < 16) /* about 1 texel a pixel: level 0, the texel itself */
                    assert_true(q->d[2] < 0.5f && (q->d[0] == 0.0f || q->d[0] == 1.0f));
            }
    }
    sl_texture_destroy(tex);
}

/* ---- helpers extrapolate the triangle's planes, 1/w included ---- */

/* position.z carries the vertex's clip w; the varying v = (x / 47.5) w, so v / w = x / 47.5 */
static void vs_persp(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *v)
{
    (void)uniforms;
    float w = in->position.z;
    *clip = vec4((in->position.x / 32.0f - 1.0f) * w, (in->position.y / 32.0f - 1.0f) * w, 0.0f, w);
    v[0] = in->position.x / 47.5f * w;
    v[1] = v[2] = 0.0f;
}

static void fs_persp(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    const sl_sampler2D *s = uniforms; /* a 64x64 texture */
    qtexel *t = texel;
    float v = in->varyings[0];
    t->d[0] = dFdxCoarse(in, v);
    t->d[1] = dFdyCoarse(in, v);
    t->d[2] = v;
    t->d[3] = sl_texture_lambda_quad(s, vec2(t->d[0], 0), vec2(t->d[1], 0), 0.0f); /* texture(s, vec2(v, 0)) */
    mark(t, in);
}

static const sl_program prog_persp = {.vertex = vs_persp, .fragment = fs_persp, .varying_count = 3,
                                      .derivatives = true};

/* A triangle (0, 0) w 1, (47.5, 0) w 4, (0, 47.5) w 4: 1/w = 1 - 0.75 (x + y) / 47.5 is smallest
 * (1/4) along the whole hypotenuse, so a helper beyond it has a 1/w below every vertex's. The
 * quad at (22, 24) has one live lane (centre sum x + y = 47) and three helpers (48, 48, 49): GL
 * runs them on the planes extrapolated (v = (x / 47.5) / (1/w)), and so must we: clamping the
 * helpers' 1/w to the vertices' range (what softlight did before) gives dFdx 0.1421 instead of
 * 0.2067, a lambda 0.54 lower. Hand-computed at the centres: lane 0 (22.5, 24.5): 1/w =
 * 0.2578947, v = 1.8367347; lane 1 (23.5, 24.5): 1/w = 0.2421053, v = 2.0434783; lane 2
 * (22.5, 25.5): 1/w = 0.2421053, v = 1.9565217. */
static void test_helpers_extrapolate(void **state)
{
    (void)state;
    static float zeros[64 * 64];
    sl_texture *tex = NULL;
    sl_error terr = {0};
    assert_true(sl_texture_create(SL_TEX_R32F, 64, 64, zeros, true, &tex, &terr));
    sl_sampler2D s = {tex, sl_sampler_default()};
    static qtexel t[W * H];
    for (int k = 0; k < 2; k++) { /* spans, then plain: the same values */
        fill(t);
        sl_raster *r = test_make_raster(1, 16, true, k == 1);
        vec3 p[3] = {{0, 0, 1}, {47.5f, 0, 4}, {0, 47.5f, 4}};
        uint32_t idx[3] = {0, 1, 2};
        sl_mesh m = {.vertex_count = 3, .triangle_count = 1, .positions = p, .indices = idx};
        sl_error err = {0};
        assert_true(sl_raster_draw(r, &(sl_target){.width = W, .height = H, .texel_size = sizeof(qtexel), .texels = t, .depth_offset = SL_NO_DEPTH},
                                   &(sl_draw){.program = &prog_persp, .fs_uniforms = &s, .mesh = &m}, &err));
        sl_raster_destroy(r);
        const qtexel *q = &t[24 * W + 22];
        assert_int_equal(q->count, 1);
        assert_int_equal(t[24 * W + 23].count, 0); /* lanes 1, 2, 3: helpers, nothing written */
        assert_int_equal(t[25 * W + 22].count, 0);
        assert_true(fabsf(q->d[2] - 1.8367347f) < 2e-6f);
        assert_true(fabsf(q->d[0] - (2.0434783f - 1.8367347f)) < 4e-6f);
        assert_true(fabsf(q->d[1] - (1.9565217f - 1.8367347f)) < 4e-6f);
        /* the quad's level for a 64-texel texture read at (v, 0): rho = 64 dFdx = 13.23159,
         * rho^2 = 175.0749 = 1.367773 * 2^7, lambda = 0.5 (7 + 0.367773) = 3.683886 (with the
         * helpers clamped it was 0.5 log2_fast((64 * 0.1422127)^2) = 3.15) */
        assert_true(fabsf(q->d[3] - 3.683886f) < 1e-4f);
    }
    sl_texture_destroy(tex);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_texture_implicit_lod),
                                       cmocka_unit_test(test_helpers_extrapolate)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
