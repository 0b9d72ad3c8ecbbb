/* test_texture.c - textures and samplers (src/raster/texture.h) against hand-computed values:
 * every format's decode, sRGB's 256 codes against the formula, mip chains of odd sizes (the
 * values llvmpipe's glGenerateMipmap gave for the same data), each wrap mode at and beyond the
 * edges, each filter, the min/mag switch, level selection from known derivatives with bias and
 * lod clamps, texelFetch and textureSize, files of every kind, and bad files.
 *
 * Level selection is checked on textures whose level l holds the value l everywhere (written
 * into the storage through texture_internal.h), so a sample reads back the level (or the blend
 * of two levels) the rules chose. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "raster/gbuffer_textured.h"
#include "raster/raster.h" /* SL_QUADS_MAX */
#include "raster/texture.h"
#include "raster/texture_internal.h"
#include "testutil.h"

static sl_sampler2D sampler(const sl_texture *t, sl_filter min, sl_filter mag, sl_wrap ws, sl_wrap wt)
{
    sl_sampler2D s = {t, sl_sampler_default()};
    s.state.min_filter = min;
    s.state.mag_filter = mag;
    s.state.wrap_s = ws;
    s.state.wrap_t = wt;
    return s;
}

static void assert_vec4(vec4 v, double x, double y, double z, double w, double tol)
{
    assert_near(v.x, x, tol);
    assert_near(v.y, y, tol);
    assert_near(v.z, z, tol);
    assert_near(v.w, w, tol);
}

/* ---- formats ---- */

static void test_every_format(void **state)
{
    (void)state;
    /* one texel of each format; GL fills missing channels with (0, 0, 1) */
    unsigned char b8[4] = {51, 102, 153, 204};
    uint16_t b16[4] = {0, 13107, 65535, 32768};
    float f32[4] = {-2.5f, 0.25f, 1e6f, 0.5f};
    const double u8[4] = {0.2, 0.4, 0.6, 0.8}, u16[4] = {0.0, 0.2, 1.0, 32768.0 / 65535.0};
    struct {
        sl_texture_format fmt;
        const void *data;
        int bytes;
        double expect[4];
    } cases[] = {
        {SL_TEX_R8, b8, 1, {u8[0], 0, 0, 1}},
        {SL_TEX_RG8, b8, 2, {u8[0], u8[1], 0, 1}},
        {SL_TEX_RGB8, b8, 3, {u8[0], u8[1], u8[2], 1}},
        {SL_TEX_RGBA8, b8, 4, {u8[0], u8[1], u8[2], u8[3]}},
        /* sRGB 51, 102, 153 by the formula: ((c/255 + 0.055) / 1.055)^2.4 */
        {SL_TEX_SRGB8, b8, 3, {0.0331048, 0.1328683, 0.3185468, 1}},
        {SL_TEX_SRGB8_ALPHA8, b8, 4, {0.0331048, 0.1328683, 0.3185468, u8[3]}},
        {SL_TEX_R16, b16, 2, {u16[0], 0, 0, 1}},
        {SL_TEX_RG16, b16, 4, {u16[0], u16[1], 0, 1}},
        {SL_TEX_RGB16, b16, 6, {u16[0], u16[1], u16[2], 1}},
        {SL_TEX_RGBA16, b16, 8, {u16[0], u16[1], u16[2], u16[3]}},
        {SL_TEX_R32F, f32, 4, {-2.5, 0, 0, 1}},
        {SL_TEX_RGB32F, f32, 12, {-2.5, 0.25, 1e6, 1}},
        {SL_TEX_RGBA32F, f32, 16, {-2.5, 0.25, 1e6, 0.5}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sl_texture *t;
        sl_error err = {0};
        assert_true(sl_texture_create(cases[i].fmt, 1, 1, cases[i].data, true, &t, &err));
        assert_int_equal(sl_texture_get_format(t), cases[i].fmt);
        assert_int_equal(sl_texture_format_bytes(cases[i].fmt), cases[i].bytes);
        assert_int_equal(sl_texture_bytes(t), (size_t)cases[i].bytes);
        assert_int_equal(sl_texture_levels(t), 1);
        sl_sampler2D s = sampler(t, SL_LINEAR_MIPMAP_LINEAR, SL_LINEAR, SL_REPEAT, SL_REPEAT);
        const double *e = cases[i].expect;
        assert_vec4(texelFetch(&s, ivec2(0, 0), 0), e[0], e[1], e[2], e[3], 1e-6 * fmax(1.0, fabs(e[2])));
        /* a 1x1 texture filters to its texel anywhere, at any level of detail */
        assert_vec4(textureLod(&s, vec2(-3.7f, 12.2f), 3.0f), e[0], e[1], e[2], e[3], 1e-6 * fmax(1.0, fabs(e[2])));
        sl_texture_destroy(t);
    }
    assert_string_equal(sl_texture_format_name(SL_TEX_SRGB8_ALPHA8), "SRGB8_ALPHA8");
}

static void test_srgb_all_codes(void **state)
{
    (void)state;
    unsigned char codes[256];
    for (int i = 0; i < 256; i++)
        codes[i] = (unsigned char)i;
    sl_texture *t;
    assert_true(sl_texture_create(SL_TEX_SRGB8, 256, 1, NULL, false, &t, NULL) == false); /* no data */
    /* an R-only table would do, but SRGB8 is RGB: the same code in all three */
    unsigned char rgb[256 * 3];
    for (int i = 0; i < 256; i++)
        rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = codes[i];
    assert_true(sl_texture_create(SL_TEX_SRGB8, 256, 1, rgb, false, &t, NULL));
    sl_sampler2D s = sampler(t, SL_NEAREST, SL_NEAREST, SL_REPEAT, SL_REPEAT);
    for (int i = 0; i < 256; i++) {
        double c = i / 255.0;
        double expect = c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
        vec4 v = texelFetch(&s, ivec2(i, 0), 0);
        /* the float nearest the double: one rounding, no more */
        assert_true(v.x == (float)expect && v.y == (float)expect && v.z == (float)expect);
    }
    assert_near(texelFetch(&s, ivec2(128, 0), 0).x, 0.21586, 5e-6); /* docs/conventions.md, erratum 8: not 0.2195 */
    sl_texture_destroy(t);
}

/* ---- mip chains ---- */

/* The 5x3 RGBA8 image the llvmpipe probe used (texel i: r = 17 i, g = 255 at i = 7, b = 60 (i
 * mod 5), a = 255 - 10 i), rows bottom first as uploaded. */
static void probe_image(unsigned char d[5 * 3 * 4])
{
    for (int i = 0; i < 15; i++) {
        d[4 * i] = (unsigned char)(i * 17);
        d[4 * i + 1] = (unsigned char)(i == 7 ? 255 : 0);
        d[4 * i + 2] = (unsigned char)((i % 5) * 60);
        d[4 * i + 3] = (unsigned char)(255 - i * 10);
    }
}

static void assert_texel8(const sl_texture *t, int l, int x, int y, int r, int g, int b, int a)
{
    const tex_level *lv = &t->level[l];
    const unsigned char *p = lv->texels + ((size_t)y * (size_t)lv->width + (size_t)x) * (size_t)t->texel_bytes;
    if (p[0] != r || p[1] != g || p[2] != b || p[3] != a) {
        print_error("level %d texel %d,%d: (%d,%d,%d,%d), expected (%d,%d,%d,%d)\n", l, x, y, p[0], p[1], p[2], p[3],
                    r, g, b, a);
        fail();
    }
}

static void test_mips_odd_sizes(void **state)
{
    (void)state;
    unsigned char d[60];
    probe_image(d);
    sl_texture *t;
    assert_true(sl_texture_create(SL_TEX_RGBA8, 5, 3, d, true, &t, NULL));
    assert_int_equal(sl_texture_levels(t), 3); /* 5x3 -> 2x1 -> 1x1 */
    sl_sampler2D s = sampler(t, SL_LINEAR_MIPMAP_LINEAR, SL_LINEAR, SL_REPEAT, SL_REPEAT);
    assert_true(textureSize(&s, 0).x == 5 && textureSize(&s, 0).y == 3);
    assert_true(textureSize(&s, 1).x == 2 && textureSize(&s, 1).y == 1);
    assert_true(textureSize(&s, 2).x == 1 && textureSize(&s, 2).y == 1);
    assert_true(textureSize(&s, 3).x == 0 && textureSize(&s, -1).y == 0);
    assert_int_equal(sl_texture_bytes(t), (15 + 2 + 1) * 4);
    /* Level 1 texel 0 samples level 0 at x = (0.5) 5/2 - 0.5 = 0.75, y = 0.5 * 3 - 0.5 = 1 (row
     * 1 exactly): r = 85 + 17 * 0.75 = 97.75 -> 98, b = 60 * 0.75 = 45, a = 205 - 7.5 -> 198;
     * texel 1 at x = 3.25: r = 85 + 17 * 3.25 = 140.25 -> 140, b = 195, a = 172.5 -> 173. Level 2
     * averages those two stored texels. llvmpipe gave exactly these bytes. */
    assert_texel8(t, 1, 0, 0, 98, 0, 45, 198);
    assert_texel8(t, 1, 1, 0, 140, 0, 195, 173);
    assert_texel8(t, 2, 0, 0, 119, 0, 120, 186);
    sl_texture_destroy(t);

    /* sRGB: filtered in linear, re-encoded with the exact curve. llvmpipe gave (98,0,52,198)
     * (141,0,197,173) (122,0,148,186): the same but texel 1's red, 0.75 dec(136) + 0.25 dec(153)
     * = 0.264288 -> 140.497 -> 140, which llvmpipe's approximate encoder rounds to 141 */
    assert_true(sl_texture_create(SL_TEX_SRGB8_ALPHA8, 5, 3, d, true, &t, NULL));
    assert_texel8(t, 1, 0, 0, 98, 0, 52, 198);
    assert_texel8(t, 1, 1, 0, 140, 0, 197, 173);
    /* level 2 from the stored 98 and 140: 121.29 -> 121 (llvmpipe, from its 141: 121.89 -> 122) */
    assert_texel8(t, 2, 0, 0, 121, 0, 148, 186);
    sl_texture_destroy(t);

    /* 2x2 sRGB black, red, green, white: red averages linear 0.5 -> exact encode 187.52 -> 188
     * (llvmpipe's approximate encoder gives 187); blue 0.25 -> 137 */
    unsigned char q[16] = {0, 0, 0, 255, 255, 0, 0, 255, 0, 255, 0, 255, 255, 255, 255, 255};
    assert_true(sl_texture_create(SL_TEX_SRGB8_ALPHA8, 2, 2, q, true, &t, NULL));
    assert_texel8(t, 1, 0, 0, 188, 188, 137, 255);
    sl_texture_destroy(t);

    /* 7x1 -> 3x1 -> 1x1: x = 7/6 - 1/2 = 0.667 -> 26.67 -> 27; 3; 5.333 -> 213.3 -> 213 (llvmpipe the same) */
    unsigned char r7[28] = {0};
    for (int i = 0; i < 7; i++) {
        r7[4 * i] = (unsigned char)(40 * i);
        r7[4 * i + 3] = 255;
    }
    assert_true(sl_texture_create(SL_TEX_RGBA8, 7, 1, r7, true, &t, NULL));
    assert_int_equal(sl_texture_levels(t), 3);
    assert_texel8(t, 1, 0, 0, 27, 0, 0, 255);
    assert_texel8(t, 1, 1, 0, 120, 0, 0, 255);
    assert_texel8(t, 1, 2, 0, 213, 0, 0, 255);
    assert_texel8(t, 2, 0, 0, 120, 0, 0, 255);
    sl_texture_destroy(t);

    /* float 3x1 -> 1x1 at x = 1: the middle texel exactly (not the mean of three) */
    float f3[3] = {1.0f, 10.0f, 100.0f};
    assert_true(sl_texture_create(SL_TEX_R32F, 3, 1, f3, true, &t, NULL));
    s = sampler(t, SL_NEAREST, SL_NEAREST, SL_REPEAT, SL_REPEAT);
    assert_true(texelFetch(&s, ivec2(0, 0), 1).x == 10.0f);
    sl_texture_destroy(t);

    /* even sizes: the 2x2 box; 16-bit keeps 16 bits (1 + 2 + 2 + 4 = 9 -> 9/4 rounds to 2) */
    uint16_t h4[4] = {1, 2, 2, 4};
    assert_true(sl_texture_create(SL_TEX_R16, 2, 2, h4, true, &t, NULL));
    uint16_t h;
    memcpy(&h, t->level[1].texels, 2);
    assert_int_equal(h, 2);
    sl_texture_destroy(t);
}

/* ---- wrap modes and filters ---- */

static void test_wrap_modes(void **state)
{
    (void)state;
    /* 4x1, values 0 1 2 3 across; level 0 only, so magnification and min NEAREST / LINEAR agree */
    float v[4] = {0, 1, 2, 3};
    sl_texture *t;
    assert_true(sl_texture_create(SL_TEX_R32F, 4, 1, v, false, &t, NULL));
    struct {
        float u;
        float repeat, clamp, mirror;
    } nearest[] = {
        /* x = 4u; texel floor(x), wrapped */
        {0.0f, 0, 0, 0},     {0.99f, 3, 3, 3},   {-0.1f, 3, 0, 0},  /* i = -1: mirror -> 0 */
        {1.1f, 0, 3, 3},     /* i = 4: repeat 0, mirror 3 */
        {1.6f, 2, 3, 1},     /* i = 6: mirror 7 - 6 = 1 */
        {-1.3f, 2, 0, 2},    /* i = -6: mod 4 = 2; mod 8 = 2 */
        {2.1f, 0, 3, 0},     /* i = 8: mirror period 8 */
        {-0.3f, 2, 0, 1},    /* i = -2: mod 8 = 6 -> 1 */
    };
    for (size_t i = 0; i < sizeof nearest / sizeof nearest[0]; i++) {
        sl_sampler2D r = sampler(t, SL_NEAREST, SL_NEAREST, SL_REPEAT, SL_REPEAT);
        sl_sampler2D c = sampler(t, SL_NEAREST, SL_NEAREST, SL_CLAMP_TO_EDGE, SL_REPEAT);
        sl_sampler2D m = sampler(t, SL_NEAREST, SL_NEAREST, SL_MIRRORED_REPEAT, SL_REPEAT);
        vec2 uv = vec2(nearest[i].u, 0.5f);
        assert_near(textureLod(&r, uv, 0).x, nearest[i].repeat, 0);
        assert_near(textureLod(&c, uv, 0).x, nearest[i].clamp, 0);
        assert_near(textureLod(&m, uv, 0).x, nearest[i].mirror, 0);
    }
    struct {
        float u;
        float repeat, clamp, mirror;
    } linear[] = {
        /* x = 4u - 0.5: texels floor(x) and the next, weight fract(x) */
        {0.125f, 0, 0, 0},    /* texel 0's centre */
        {0.25f, 0.5f, 0.5f, 0.5f},
        {0.0f, 1.5f, 0, 0},   /* x = -0.5: texels -1 and 0: repeat 3 and 0; mirror 0 and 0 */
        {1.0f, 1.5f, 3, 3},   /* x = 3.5: texels 3 and 4: repeat 3 and 0; mirror 3 and 3 */
        {-0.25f, 2.5f, 0, 0.5f}, /* x = -1.5: texels -2, -1: repeat 2, 3; mirror 1, 0 */
        {1.375f, 1, 3, 2},      /* x = 5: texel 5 alone: repeat 1; mirror 2 (and 6 -> 1 at weight 0) */
    };
    for (size_t i = 0; i < sizeof linear / sizeof linear[0]; i++) {
        sl_sampler2D r = sampler(t, SL_LINEAR, SL_LINEAR, SL_REPEAT, SL_REPEAT);
        sl_sampler2D c = sampler(t, SL_LINEAR, SL_LINEAR, SL_CLAMP_TO_EDGE, SL_REPEAT);
        sl_sampler2D m = sampler(t, SL_LINEAR, SL_LINEAR, SL_MIRRORED_REPEAT, SL_REPEAT);
        vec2 uv = vec2(linear[i].u, 0.5f);
        assert_near(textureLod(&r, uv, 0).x, linear[i].repeat, 1e-6);
        assert_near(textureLod(&c, uv, 0).x, linear[i].clamp, 1e-6);
        assert_near(textureLod(&m, uv, 0).x, linear[i].mirror, 1e-6);
    }
    sl_texture_destroy(t);

    /* the t axis wraps on its own: 1x4, values up the rows (row 0 = bottom = t near 0) */
    assert_true(sl_texture_create(SL_TEX_R32F, 1, 4, v, false, &t, NULL));
    sl_sampler2D s = sampler(t, SL_NEAREST, SL_NEAREST, SL_CLAMP_TO_EDGE, SL_MIRRORED_REPEAT);
    assert_near(textureLod(&s, vec2(5.0f, 0.1f), 0).x, 0, 0);
    assert_near(textureLod(&s, vec2(5.0f, 1.6f), 0).x, 1, 0);
    s.state.wrap_t = SL_REPEAT;
    assert_near(textureLod(&s, vec2(-5.0f, -0.1f), 0).x, 3, 0);
    s.state.wrap_t = SL_CLAMP_TO_EDGE;
    assert_near(textureLod(&s, vec2(0.5f, 7.0f), 0).x, 3, 0);
    /* NaN and huge coordinates: some texel, no crash */
    float nan = nanf("");
    vec4 any = textureLod(&s, vec2(nan, 1e30f), 0);
    assert_true(any.x >= 0 && any.x <= 3);
    s.state.min_filter = s.state.mag_filter = SL_LINEAR;
    s.state.wrap_s = s.state.wrap_t = SL_MIRRORED_REPEAT;
    any = textureLod(&s, vec2(-1e30f, nan), 0);
    assert_true(any.x >= 0 && any.x <= 3);
    sl_texture_destroy(t);
}

static void test_filters_and_mag_switch(void **state)
{
    (void)state;
    /* 2x2: 0 1 (bottom row), 2 4 (top) */
    float v[4] = {0, 1, 2, 4};
    sl_texture *t;
    assert_true(sl_texture_create(SL_TEX_R32F, 2, 2, v, true, &t, NULL));
    sl_sampler2D s = sampler(t, SL_NEAREST, SL_LINEAR, SL_CLAMP_TO_EDGE, SL_CLAMP_TO_EDGE);
    /* the centre: bilinear is the mean 7/4, nearest texel (1, 1) (x = y = 1 exactly) is 4 */
    assert_near(sl_texture_sample(&s, vec2(0.5f, 0.5f), 0.0f).x, 1.75, 1e-7);     /* lambda 0: magnified */
    assert_near(sl_texture_sample(&s, vec2(0.5f, 0.5f), 1e-6f).x, 4, 0);          /* lambda > 0: minified */
    assert_near(sl_texture_sample(&s, vec2(0.5f, 0.5f), -3.0f).x, 1.75, 1e-7);
    /* bilinear weights: (0.375, 0.625) is x = 0.25, y = 0.75: rows 0.25, 2.5 -> 0.25 + 0.75 (2.25) */
    assert_near(sl_texture_sample(&s, vec2(0.375f, 0.625f), 0.0f).x, 0.25 + 0.75 * 2.25, 1e-6);
    s.state.mag_filter = SL_NEAREST;
    assert_near(sl_texture_sample(&s, vec2(0.3f, 0.2f), -1.0f).x, 0, 0);
    assert_near(sl_texture_sample(&s, vec2(0.3f, 0.7f), -1.0f).x, 2, 0);
    /* min LINEAR stays on level 0 even far minified; level 1 (the mean) only with mipmaps */
    s.state.min_filter = SL_LINEAR;
    assert_near(sl_texture_sample(&s, vec2(0.5f, 0.5f), 5.0f).x, 1.75, 1e-7);
    s.state.min_filter = SL_NEAREST_MIPMAP_NEAREST;
    assert_near(sl_texture_sample(&s, vec2(0.1f, 0.1f), 5.0f).x, 1.75, 1e-7);
    sl_texture_destroy(t);

    /* GL's incompleteness: a mipmap filter on a texture made without mipmaps reads (0, 0, 0, 1) */
    assert_true(sl_texture_create(SL_TEX_R32F, 2, 2, v, false, &t, NULL));
    sl_sampler2D d = {t, sl_sampler_default()}; /* NEAREST_MIPMAP_LINEAR */
    assert_vec4(textureLod(&d, vec2(0.5f, 0.5f), 0), 0, 0, 0, 1, 0);
    assert_vec4(texelFetch(&d, ivec2(1, 1), 0), 0, 0, 0, 1, 0);
    d.state.min_filter = SL_LINEAR;
    assert_vec4(texelFetch(&d, ivec2(1, 1), 0), 4, 0, 0, 1, 0);
    sl_texture_destroy(t);
}

/* ---- level of detail ---- */

/* A 16x16 R32F texture (5 levels) whose level l holds l. */
static sl_texture *level_texture(void)
{
    float zero[256] = {0};
    sl_texture *t;
    assert_true(sl_texture_create(SL_TEX_R32F, 16, 16, zero, true, &t, NULL));
    for (int l = 0; l < t->levels; l++) {
        float *p = (float *)(void *)t->level[l].texels;
        for (int i = 0; i < t->level[l].width * t->level[l].height; i++)
            p[i] = (float)l;
    }
    sl_tex_plane_drop(t); /* the decoded plane was made from the levels as created: again from these */
    sl_tex_plane_build(t);
    return t;
}

static void test_lambda(void **state)
{
    (void)state;
    sl_texture *t = level_texture();
    sl_sampler2D s = sampler(t, SL_LINEAR_MIPMAP_LINEAR, SL_LINEAR, SL_REPEAT, SL_REPEAT);
    const float px = 1.0f / 16.0f; /* one texel of level 0 */
    /* powers of two are exact: rho = 4 -> 2 */
    assert_true(sl_texture_lambda(&s, vec2(4 * px, 0), vec2(0, px), 0) == 2.0f);
    /* rho is the longer of the two derivatives: (2, 0) and (0, 8) -> 3 */
    assert_true(sl_texture_lambda(&s, vec2(2 * px, 0), vec2(0, 8 * px), 0) == 3.0f);
    /* each is a length: (3, 4) -> 5, rho^2 = 25 = 1.5625 * 2^4: llvmpipe's log2 gives
     * 0.5 (4 + 0.5625) = 2.28125 (exact log2 5 = 2.3219) */
    assert_true(sl_texture_lambda(&s, vec2(3 * px, 4 * px), vec2(0, 0), 0) == 2.28125f);
    /* rho = 3: rho^2 = 9 = 1.125 * 2^3 -> 0.5 (3 + 0.125) = 1.5625 */
    float l3 = sl_texture_lambda(&s, vec2(3 * px, 0), vec2(0, 3 * px), 0);
    assert_true(l3 == 1.5625f);
    /* shader bias, sampler bias, clamps (max first, then min, as llvmpipe) */
    assert_true(sl_texture_lambda(&s, vec2(4 * px, 0), vec2(0, 0), 1.0f) == 3.0f);
    s.state.lod_bias = -0.5f;
    assert_true(sl_texture_lambda(&s, vec2(4 * px, 0), vec2(0, 0), 1.0f) == 2.5f);
    s.state.lod_bias = 0.0f;
    s.state.max_lod = 1.25f;
    assert_true(sl_texture_lambda(&s, vec2(4 * px, 0), vec2(0, 0), 0) == 1.25f);
    s.state.min_lod = 2.5f;
    s.state.max_lod = 1000.0f;
    assert_true(sl_texture_lambda(&s, vec2(4 * px, 0), vec2(0, 0), 0) == 2.5f);
    assert_true(sl_texture_lambda(&s, vec2(0, 0), vec2(0, 0), 0) == 2.5f);
    s.state.min_lod = -1000.0f;
    /* no derivative: log2 of 0 is -127 in llvmpipe's form -> -63.5, magnified; non-finite: the same */
    assert_true(sl_texture_lambda(&s, vec2(0, 0), vec2(0, 0), 0) == -63.5f);
    assert_true(sl_texture_lambda(&s, vec2(INFINITY, 0), vec2(0, 0), 0) == -63.5f);
    assert_true(sl_texture_lambda(&s, vec2(nanf(""), 0), vec2(0, 0), 0) == -63.5f);
    /* texture()'s lambda (a quad's implicit derivatives): the same rule for finite ones; a
     * non-finite rho (a helper lane's infinite or NaN uv) is not zeroed as textureGrad's is:
     * log2_fast(+inf) = 128 -> 64, clamped to the chain, the last level (llvmpipe, measured) */
    assert_true(sl_texture_lambda_quad(&s, vec2(3 * px, 4 * px), vec2(0, 0), 0) == 2.28125f);
    assert_true(sl_texture_lambda_quad(&s, vec2(3 * px, 0), vec2(0, 3 * px), 0.5f) == 2.0625f);
    assert_true(sl_texture_lambda_quad(&s, vec2(0, 0), vec2(0, 0), 0) == -63.5f);
    assert_true(sl_texture_lambda_quad(&s, vec2(INFINITY, 0), vec2(0, 0), 0) == 64.0f);
    assert_true(sl_texture_lambda_quad(&s, vec2(0, 0), vec2(0, nanf("")), 0) == 64.0f);
    assert_near(sl_texture_sample(&s, vec2(0.3f, 0.6f), sl_texture_lambda_quad(&s, vec2(INFINITY, 0), vec2(0, 0), 0)).x,
                4.0, 0.0); /* level 4, 1x1, holds 4 */
    s.state.max_lod = 1.25f; /* the sampler's clamp still applies */
    assert_true(sl_texture_lambda_quad(&s, vec2(INFINITY, 0), vec2(0, 0), 0) == 1.25f);
    s.state.max_lod = 1000.0f;
    /* textureGrad samples at that lambda: trilinear 1.5625 reads 1.5625 */
    assert_near(textureGrad(&s, vec2(0.3f, 0.6f), vec2(3 * px, 0), vec2(0, 3 * px)).x, 1.5625, 1e-6);
    sl_texture_destroy(t);
}

static void test_level_selection(void **state)
{
    (void)state;
    sl_texture *t = level_texture();
    vec2 uv = vec2(0.3f, 0.7f);
    struct {
        float lambda;
        float nearest, linear; /* *_MIPMAP_NEAREST and *_MIPMAP_LINEAR read */
    } cases[] = {
        {-1.0f, 0, 0},  {0.0f, 0, 0},     {0.25f, 0, 0.25f}, {0.5f, 0, 0.5f}, /* half to even: 0 */
        {0.75f, 1, 0.75f}, {1.5f, 2, 1.5f}, {2.5f, 2, 2.5f},  {3.5f, 4, 3.5f},
        {3.75f, 4, 3.75f}, {4.0f, 4, 4.0f}, {7.0f, 4, 4.0f}, /* clamped to the last level */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        for (int lin = 0; lin < 2; lin++) {
            sl_filter n = lin ? SL_LINEAR_MIPMAP_NEAREST : SL_NEAREST_MIPMAP_NEAREST;
            sl_filter l = lin ? SL_LINEAR_MIPMAP_LINEAR : SL_NEAREST_MIPMAP_LINEAR;
            sl_sampler2D sn = sampler(t, n, SL_LINEAR, SL_REPEAT, SL_REPEAT);
            sl_sampler2D sl = sampler(t, l, SL_LINEAR, SL_REPEAT, SL_REPEAT);
            assert_near(textureLod(&sn, uv, cases[i].lambda).x, cases[i].nearest, 0);
            assert_near(textureLod(&sl, uv, cases[i].lambda).x, cases[i].linear, 1e-6);
        }
    }
    /* textureLod takes the sampler's bias and clamps too */
    sl_sampler2D s = sampler(t, SL_NEAREST_MIPMAP_NEAREST, SL_NEAREST, SL_REPEAT, SL_REPEAT);
    s.state.lod_bias = 1.0f;
    assert_near(textureLod(&s, uv, 1.0f).x, 2, 0);
    s.state.max_lod = 1.0f;
    assert_near(textureLod(&s, uv, 3.0f).x, 1, 0);
    sl_texture_destroy(t);
}

static void test_texel_fetch_and_size(void **state)
{
    (void)state;
    sl_texture *t = level_texture();
    sl_sampler2D s = sampler(t, SL_NEAREST_MIPMAP_NEAREST, SL_NEAREST, SL_REPEAT, SL_REPEAT);
    for (int l = 0; l < 5; l++) {
        ivec2 size = textureSize(&s, l);
        assert_true(size.x == 16 >> l && size.y == 16 >> l);
        assert_vec4(texelFetch(&s, ivec2(size.x - 1, 0), l), l, 0, 0, 1, 0);
    }
    /* outside the level or the chain: zero, alpha too (llvmpipe's answer) */
    assert_vec4(texelFetch(&s, ivec2(16, 0), 0), 0, 0, 0, 0, 0);
    assert_vec4(texelFetch(&s, ivec2(-1, 3), 0), 0, 0, 0, 0, 0);
    assert_vec4(texelFetch(&s, ivec2(2, 0), 1 + 4), 0, 0, 0, 0, 0);
    assert_vec4(texelFetch(&s, ivec2(0, 0), -1), 0, 0, 0, 0, 0);
    sl_texture_destroy(t);
    /* a row is a row: texel (1, 2) of a 3x4 RGBA8 texture is byte 4 * (2 * 3 + 1) */
    unsigned char d[48];
    for (int i = 0; i < 48; i++)
        d[i] = (unsigned char)i;
    assert_true(sl_texture_create(SL_TEX_RGBA8, 3, 4, d, false, &t, NULL));
    s = sampler(t, SL_NEAREST, SL_NEAREST, SL_REPEAT, SL_REPEAT);
    assert_vec4(texelFetch(&s, ivec2(1, 2), 0), 28 / 255.0, 29 / 255.0, 30 / 255.0, 31 / 255.0, 1e-7);
    sl_texture_destroy(t);
}

/* ---- files ---- */

static void fetch_rgba8(const sl_texture *t, int x, int y, double e[4], const char *what)
{
    sl_sampler2D s = {t, sl_sampler_default()};
    vec4 v = texelFetch(&s, ivec2(x, y), 0);
    if (fabs((double)v.x - e[0]) > 1e-6 || fabs((double)v.y - e[1]) > 1e-6 || fabs((double)v.z - e[2]) > 1e-6 ||
        fabs((double)v.w - e[3]) > 1e-6) {
        print_error("%s texel %d,%d: (%g,%g,%g,%g) expected (%g,%g,%g,%g)\n", what, x, y, (double)v.x, (double)v.y,
                    (double)v.z, (double)v.w, e[0], e[1], e[2], e[3]);
        fail();
    }
}

static sl_texture *load(const char *name, bool srgb)
{
    char path[256];
    snprintf(path, sizeof path, "fuzz/corpus/fuzz_texture/%s", name);
    sl_texture *t;
    sl_error err = {0};
    if (!sl_texture_load(path, srgb, 0, &t, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
    return t;
}

static void test_load_files(void **state)
{
    (void)state;
    /* the seed files (fuzz/corpus/fuzz_texture, made by hand: see fuzz/fuzz_texture.c) */
    sl_texture *t = load("rgba_2x2.png", false); /* file rows: red, green / blue, grey 128 */
    assert_int_equal(sl_texture_get_format(t), SL_TEX_RGBA8);
    assert_int_equal(sl_texture_levels(t), 2);
    /* flipped: row 0 (bottom) is the file's last row */
    fetch_rgba8(t, 0, 0, (double[4]){0, 0, 1, 0}, "rgba");
    fetch_rgba8(t, 1, 0, (double[4]){128 / 255.0, 128 / 255.0, 128 / 255.0, 1}, "rgba");
    fetch_rgba8(t, 0, 1, (double[4]){1, 0, 0, 1}, "rgba");
    fetch_rgba8(t, 1, 1, (double[4]){0, 1, 0, 128 / 255.0}, "rgba");
    sl_texture_destroy(t);
    t = load("rgba_2x2.png", true);
    assert_int_equal(sl_texture_get_format(t), SL_TEX_SRGB8_ALPHA8);
    fetch_rgba8(t, 1, 1, (double[4]){0, 1, 0, 128 / 255.0}, "srgb alpha stays linear");
    fetch_rgba8(t, 1, 0, (double[4]){0.2158605, 0.2158605, 0.2158605, 1}, "srgb");
    sl_texture_destroy(t);

    t = load("grey_2x2.png", false); /* rows 0 128 / 255 64 */
    assert_int_equal(sl_texture_get_format(t), SL_TEX_R8);
    fetch_rgba8(t, 1, 0, (double[4]){64 / 255.0, 0, 0, 1}, "grey");
    sl_texture_destroy(t);
    t = load("grey_2x2.png", true); /* grey sRGB: replicated to SRGB8 */
    assert_int_equal(sl_texture_get_format(t), SL_TEX_SRGB8);
    fetch_rgba8(t, 1, 1, (double[4]){0.2158605, 0.2158605, 0.2158605, 1}, "grey srgb");
    sl_texture_destroy(t);
    t = load("grey_alpha_2x1.png", false); /* (128, 255) (64, 32) */
    assert_int_equal(sl_texture_get_format(t), SL_TEX_RG8);
    fetch_rgba8(t, 1, 0, (double[4]){64 / 255.0, 32 / 255.0, 0, 1}, "grey alpha");
    sl_texture_destroy(t);
    t = load("grey_alpha_2x1.png", true);
    assert_int_equal(sl_texture_get_format(t), SL_TEX_SRGB8_ALPHA8);
    fetch_rgba8(t, 0, 0, (double[4]){0.2158605, 0.2158605, 0.2158605, 1}, "grey alpha srgb");
    sl_texture_destroy(t);
    t = load("rgb_3x2.png", true); /* rows 0..8 / 100..108: texel (2, 0) is the file's 106 107 108 */
    assert_int_equal(sl_texture_get_format(t), SL_TEX_SRGB8);
    double c = 106 / 255.0;
    fetch_rgba8(t, 2, 0, (double[4]){pow((c + 0.055) / 1.055, 2.4), pow((107 / 255.0 + 0.055) / 1.055, 2.4),
                                     pow((108 / 255.0 + 0.055) / 1.055, 2.4), 1}, "rgb srgb");
    sl_texture_destroy(t);
    /* 16-bit: UNORM16 whatever srgb says */
    t = load("rgb16_2x1.png", true); /* (0, 32768, 65535) (1, 2, 3) */
    assert_int_equal(sl_texture_get_format(t), SL_TEX_RGB16);
    fetch_rgba8(t, 0, 0, (double[4]){0, 32768 / 65535.0, 1, 1}, "rgb16");
    fetch_rgba8(t, 1, 0, (double[4]){1 / 65535.0, 2 / 65535.0, 3 / 65535.0, 1}, "rgb16");
    sl_texture_destroy(t);
    t = load("grey16_1x1.png", false);
    assert_int_equal(sl_texture_get_format(t), SL_TEX_R16);
    fetch_rgba8(t, 0, 0, (double[4]){1000 / 65535.0, 0, 0, 1}, "grey16");
    sl_texture_destroy(t);
    /* JPEG: one 8x8 block of DC only, quantizer 1: pixel = 128 + DC / 8 = 128 + 576 / 8 = 200 */
    t = load("grey200_8x8.jpg", false);
    assert_int_equal(sl_texture_get_format(t), SL_TEX_R8);
    assert_int_equal(sl_texture_levels(t), 4);
    fetch_rgba8(t, 3, 5, (double[4]){200 / 255.0, 0, 0, 1}, "jpeg");
    sl_texture_destroy(t);
    /* colour JPEG: Y 200, Cb 128 - 10, Cr 128 + 20 -> R = Y + 1.402 (Cr - 128) = 228.04, G = Y -
     * 0.34414 (Cb - 128) - 0.71414 (Cr - 128) = 189.16, B = Y + 1.772 (Cb - 128) = 182.28; the
     * decoder's fixed-point conversion within a code */
    t = load("ycc_8x8.jpg", false);
    assert_int_equal(sl_texture_get_format(t), SL_TEX_RGB8);
    sl_sampler2D s = {t, sl_sampler_default()};
    vec4 v = texelFetch(&s, ivec2(0, 0), 0);
    assert_near(v.x * 255.0f, 228.04, 1.0);
    assert_near(v.y * 255.0f, 189.16, 1.0);
    assert_near(v.z * 255.0f, 182.28, 1.0);
    sl_texture_destroy(t);
    /* Radiance: (128, 64, 32, e 129) = (1, 0.5, 0.25) * 2^(129 - 136) * 128 ... = m 2^(e - 136) */
    t = load("tiny_2x1.hdr", true);
    assert_int_equal(sl_texture_get_format(t), SL_TEX_RGB32F);
    v = texelFetch(&(sl_sampler2D){t, sl_sampler_default()}, ivec2(0, 0), 0);
    assert_near(v.x, 128.0 / 128.0, 1e-7);
    assert_near(v.y, 64.0 / 128.0, 1e-7);
    assert_near(v.z, 32.0 / 128.0, 1e-7);
    sl_texture_destroy(t);
}

static void test_bad_files(void **state)
{
    (void)state;
    sl_texture *t = (sl_texture *)&t; /* must come back NULL */
    sl_error err = {0};
    assert_false(sl_texture_load(test_tmpfile("missing.png"), true, 0, &t, &err));
    assert_null(t);
    assert_int_equal(err.code, SL_ERR_IO);
    assert_msg_contains(err, "missing.png");

    const char *text = test_tmpfile("text.png");
    test_write_bytes(text, "not an image at all", 19);
    assert_false(sl_texture_load(text, true, 0, &t, &err));
    assert_msg_contains(err, "text.png: byte 0: not a PNG, JPEG, BMP, TGA or Radiance .hdr file");

    /* every truncation of a PNG, a JPEG and a .hdr: an error naming the file, never a texture
     * that is not whole, no crash (ASan and UBSan watch) */
    const char *files[] = {"rgba_2x2.png", "rgb16_2x1.png", "ycc_8x8.jpg", "tiny_2x1.hdr"};
    for (size_t f = 0; f < 4; f++) {
        char path[256];
        snprintf(path, sizeof path, "fuzz/corpus/fuzz_texture/%s", files[f]);
        unsigned char *bytes;
        size_t size;
        assert_true(sl_read_file(path, 1 << 20, &bytes, &size, &err));
        for (size_t n = 0; n < size; n++) {
            bool ok = sl_texture_load_memory(bytes, n, "cut", false, 0, &t, &err);
            if (ok) { /* a PNG cut after its image data (no IEND) still holds the whole image */
                assert_true(n > 40);
                sl_texture_destroy(t);
                continue;
            }
            assert_null(t);
            assert_true(strncmp(err.msg, "cut: ", 5) == 0);
        }
        free(bytes);
    }

    /* a JPEG Huffman table of more than 256 codes */
    assert_false(sl_texture_load("fuzz/corpus/fuzz_texture/dht_over_256.jpg", false, 0, &t, &err));
    assert_msg_contains(err, "dht_over_256.jpg: byte 92: corrupt JPEG: Bogus Huffman table definition");

    /* a scan naming a Huffman table no DHT defined, whose data then ends */
    assert_false(sl_texture_load("fuzz/corpus/fuzz_texture/sos_undefined_table.jpg", false, 0, &t, &err));
    assert_msg_contains(err, "sos_undefined_table.jpg: byte 138: corrupt JPEG: premature end of data segment");

    /* a PNG whose IHDR's CRC does not match */
    assert_false(sl_texture_load("fuzz/corpus/fuzz_texture/empty_idat.png", false, 0, &t, &err));
    assert_msg_contains(err, "empty_idat.png: byte 33: corrupt PNG: IHDR: CRC error");

    /* an absurd size declared by a header */
    assert_false(sl_texture_load("fuzz/corpus/fuzz_texture/huge_40000x40000.png", false, 0, &t, &err));
    assert_msg_contains(err, "huge_40000x40000.png: byte 16: PNG: image too large: 40000x40000 is over 32768 on a side");
    /* over the budget: the texture and its mips count (a 4096 x 4096 grey PNG: 16 MiB + 5.3 MiB
     * of levels + the decoder's share, three 16 MiB images) */
    sl_image img;
    assert_true(sl_image_alloc(&img, 4096, 4096, 1, NULL));
    const char *big = test_tmpfile("big.png");
    assert_true(sl_image_write_png(big, &img, NULL));
    sl_image_free(&img);
    assert_false(sl_texture_load(big, false, (size_t)40 << 20, &t, &err));
    assert_msg_contains(err, "big.png: byte 16: image 4096x4096 needs 70 MiB in memory");
    assert_true(sl_texture_load(big, false, (size_t)70 << 20, &t, &err));
    assert_int_equal(sl_texture_bytes(t), 22369621); /* 4^12 (1 + 1/4 + ...) = (4^13 - 1) / 3 */
    sl_texture_destroy(t);

    /* sizes the API refuses */
    unsigned char one[4] = {0};
    assert_false(sl_texture_create(SL_TEX_RGBA8, 0, 4, one, true, &t, &err));
    assert_int_equal(err.code, SL_ERR_RANGE);
    assert_false(sl_texture_create(SL_TEX_RGBA8, 40000, 1, one, true, &t, &err));
    assert_false(sl_texture_create((sl_texture_format)99, 1, 1, one, true, &t, &err));
    sl_texture_destroy(NULL);
}

/* ---- the fast fetch path against the plain one ---- */

/* A plain reference sampler (without sampler.c's per-format instances and its REPEAT masks):
 * a switch per texel (tex_texel), a remainder per wrap. The fast path must give its bits. */
static float ref_safe_coord(float x)
{
    const float limit = 16777216.0f;
    if (x >= -limit)
        return x <= limit ? x : limit;
    return x < 0.0f ? -limit : 0.0f;
}

static int ref_wrap(int i, int n, sl_wrap mode)
{
    if (i >= 0 && i < n)
        return i;
    if (mode == SL_REPEAT) {
        int r = i % n;
        return r < 0 ? r + n : r;
    }
    if (mode == SL_MIRRORED_REPEAT) {
        int r = i % (2 * n);
        if (r < 0)
            r += 2 * n;
        return r < n ? r : 2 * n - 1 - r;
    }
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

static vec4 ref_level(const sl_texture *t, int l, vec2 uv, bool linear, const sl_sampler_state *st)
{
    const tex_level *lv = &t->level[l];
    float x = uv.x * (float)lv->width, y = uv.y * (float)lv->height;
    if (!linear)
        return tex_texel(t, lv, ref_wrap((int)floorf(ref_safe_coord(x)), lv->width, st->wrap_s),
                         ref_wrap((int)floorf(ref_safe_coord(y)), lv->height, st->wrap_t));
    x = ref_safe_coord(x - 0.5f);
    y = ref_safe_coord(y - 0.5f);
    float fx = floorf(x), fy = floorf(y);
    int i = (int)fx, j = (int)fy;
    int i0 = ref_wrap(i, lv->width, st->wrap_s), i1 = ref_wrap(i + 1, lv->width, st->wrap_s);
    int j0 = ref_wrap(j, lv->height, st->wrap_t), j1 = ref_wrap(j + 1, lv->height, st->wrap_t);
    vec4 bottom = mix4(tex_texel(t, lv, i0, j0), tex_texel(t, lv, i1, j0), x - fx);
    vec4 top = mix4(tex_texel(t, lv, i0, j1), tex_texel(t, lv, i1, j1), x - fx);
    return mix4(bottom, top, y - fy);
}

static vec4 ref_sample(const sl_sampler2D *s, vec2 uv, float lambda)
{
    const sl_texture *t = s->texture;
    const sl_sampler_state *st = &s->state;
    if (!(lambda > 0.0f))
        return ref_level(t, 0, uv, st->mag_filter == SL_LINEAR, st);
    bool linear = st->min_filter == SL_LINEAR || st->min_filter == SL_LINEAR_MIPMAP_NEAREST ||
                  st->min_filter == SL_LINEAR_MIPMAP_LINEAR;
    int last = t->levels - 1;
    if (st->min_filter == SL_NEAREST || st->min_filter == SL_LINEAR)
        return ref_level(t, 0, uv, linear, st);
    if (st->min_filter == SL_NEAREST_MIPMAP_NEAREST || st->min_filter == SL_LINEAR_MIPMAP_NEAREST)
        return ref_level(t, lambda >= (float)last ? last : (int)rintf(lambda), uv, linear, st);
    if (lambda >= (float)last)
        return ref_level(t, last, uv, linear, st);
    float fl = floorf(lambda);
    return mix4(ref_level(t, (int)fl, uv, linear, st), ref_level(t, (int)fl + 1, uv, linear, st), lambda - fl);
}

static float rnd(float lo, float hi) { return lo + (hi - lo) * (float)rand() / (float)RAND_MAX; }

/* Every format, power-of-two and odd sizes, every filter and wrap pair, random positions (far
 * outside [0, 1] too) and levels: the fast path's bits are the plain path's, from the decoded
 * plane and from the stored bytes. */
/* Two ~150-byte JPEGs whose DC coefficients run out of any valid range: in a baseline file the DC
 * times its quantiser (254) would overflow an int, in a progressive one the DC shifted left by
 * the scan's successive-approximation bit would. Both are corrupt (bytes between markers, then
 * scan data that ends early): each must fail with an error naming the file. Under UBSan
 * (-fno-sanitize-recover) an integer overflow in the decoder aborts the test. */
static void test_jpeg_dc_overflow_files(void **state)
{
    (void)state;
    const char *files[] = {"dc_quant_overflow.jpg", "progressive_dc_shift_overflow.jpg"};
    for (size_t f = 0; f < 2; f++)
        for (int srgb = 0; srgb < 2; srgb++) {
            char path[256];
            snprintf(path, sizeof path, "fuzz/corpus/fuzz_texture/%s", files[f]);
            sl_texture *t = (sl_texture *)&t; /* must come back NULL */
            sl_error err = {0};
            assert_false(sl_texture_load(path, srgb, 0, &t, &err));
            assert_null(t);
            assert_int_equal(err.code, SL_ERR_FORMAT);
            assert_true(strncmp(err.msg, path, strlen(path)) == 0);
            assert_msg_contains(err, ": corrupt JPEG: ");
        }
}

static void test_fast_path_bits(void **state)
{
    (void)state;
    static const int sizes[][2] = {{16, 8}, {13, 7}, {1, 1}, {64, 3}};
    unsigned char *data = malloc(64 * 8 * 16);
    assert_non_null(data);
    srand(7);
    long checked = 0, checked4 = 0, checked_quads = 0;
    vec2 quad_uv[4];
    float mu[4 * SL_QUADS_MAX], mv[4 * SL_QUADS_MAX], mlambda[SL_QUADS_MAX];
    int mq = 0;
    for (int f = 0; f < SL_TEX_FORMAT_COUNT; f++) {
        assert_int_equal(tex_format_bytes((sl_texture_format)f), sl_texture_format_bytes((sl_texture_format)f));
        for (size_t i = 0; i < 64 * 8 * 16; i++)
            data[i] = (unsigned char)(rand() & 0xff);
        if (f >= SL_TEX_R32F) /* finite floats in [0, 1) */
            for (size_t i = 0; i < 64 * 8 * 4; i++) {
                float v = (float)(rand() & 0xffff) / 65536.0f;
                memcpy(data + 4 * i, &v, 4);
            }
        for (size_t z = 0; z < sizeof sizes / sizeof sizes[0]; z++) {
            sl_texture *t = NULL;
            sl_error err = {0};
            assert_true(sl_texture_create((sl_texture_format)f, sizes[z][0], sizes[z][1], data, true, &t, &err));
            /* small textures sample the decoded plane (RGBA32F stores one already); then the
             * stored bytes through the per-format instances, the plane dropped */
            assert_true(t->plane_storage != NULL || f == SL_TEX_RGBA32F);
            for (int pass = 0; pass < 2; pass++, sl_tex_plane_drop(t)) {
                for (int min = SL_NEAREST; min <= SL_LINEAR_MIPMAP_LINEAR; min++)
                    for (int w = 0; w < 9; w++) {
                        sl_sampler2D s = sampler(t, (sl_filter)min, min & 1 ? SL_LINEAR : SL_NEAREST,
                                                 (sl_wrap)(w % 3), (sl_wrap)(w / 3));
                        for (int k = 0; k < 200; k++) {
                            float range = k < 150 ? 3.0f : 1e6f;
                            vec2 uv = vec2(rnd(-range, range), rnd(-range, range));
                            float lambda = rnd(-1.0f, (float)sl_texture_levels(t) + 1.0f);
                            vec4 fast = sl_texture_sample(&s, uv, lambda), slow = ref_sample(&s, uv, lambda);
                            if (memcmp(&fast, &slow, sizeof fast) != 0)
                                fail_msg("%s %dx%d min %d wrap %d uv (%.9g, %.9g) lambda %.9g: (%.9g %.9g %.9g %.9g) "
                                         "against (%.9g %.9g %.9g %.9g)",
                                         sl_texture_format_name((sl_texture_format)f), sizes[z][0], sizes[z][1], min, w,
                                         (double)uv.x, (double)uv.y, (double)lambda, (double)fast.x, (double)fast.y,
                                         (double)fast.z, (double)fast.w, (double)slow.x, (double)slow.y,
                                         (double)slow.z, (double)slow.w);
                            checked++;
                            /* the quad form's four-lane sample: each lane the one-lane sample's bits */
                            quad_uv[k % 4] = uv;
                            if (k % 4 == 3) {
                                vec4 four[4];
                                sl_texture_sample4(&s, quad_uv, lambda, four);
                                for (int l = 0; l < 4; l++) {
                                    vec4 one = sl_texture_sample(&s, quad_uv[l], lambda);
                                    assert_memory_equal(&four[l], &one, sizeof one);
                                }
                                checked4++;
                                /* the multi-quad sample: this quad joins the call's (each quad its own
                                 * lambda), checked lane by lane when 16 are gathered or the run ends */
                                for (int l = 0; l < 4; l++) {
                                    mu[4 * mq + l] = quad_uv[l].x;
                                    mv[4 * mq + l] = quad_uv[l].y;
                                }
                                mlambda[mq++] = lambda;
                            }
                            if (mq == SL_QUADS_MAX || (k == 199 && mq > 0)) {
                                float r[4 * SL_QUADS_MAX], g[4 * SL_QUADS_MAX], b[4 * SL_QUADS_MAX], a[4 * SL_QUADS_MAX];
                                float *const rgba[4] = {r, g, b, a};
                                sl_texture_sample_quads(&s, mq, mu, mv, mlambda, rgba);
                                for (int j = 0; j < 4 * mq; j++) {
                                    vec4 many = vec4(r[j], g[j], b[j], a[j]);
                                    vec4 one = sl_texture_sample(&s, vec2(mu[j], mv[j]), mlambda[j / 4]);
                                    if (memcmp(&many, &one, sizeof one) != 0)
                                        fail_msg("%s %dx%d min %d wrap %d plane %d: multi-quad lane %d of %d differs",
                                                 sl_texture_format_name((sl_texture_format)f), sizes[z][0],
                                                 sizes[z][1], min, w, pass == 0, j, 4 * mq);
                                    checked_quads++;
                                }
                                mq = 0;
                            }
                        }
                    }
            }
            sl_texture_destroy(t);
        }
    }
    free(data);
    assert_true(checked == 2 * 13L * 4 * 6 * 9 * 200);
    assert_true(checked4 == checked / 4);
    assert_true(checked_quads == checked);
}

/* The multi-quad lambda (sl_texture_lambda_quads) against the quad's (sl_texture_lambda_quad of
 * the coarse differences), bit for bit: random quads from magnified to past the last level, a
 * sampler bias and lod clamps, and quads with an infinite or NaN lane (the last level). */
static void test_lambda_quads(void **state)
{
    (void)state;
    sl_texture *t = NULL;
    sl_error err = {0};
    unsigned char texels[64 * 32 * 4] = {0};
    assert_true(sl_texture_create(SL_TEX_RGBA8, 64, 32, texels, true, &t, &err));
    srand(11);
    long checked = 0;
    for (int cfg = 0; cfg < 3; cfg++) {
        sl_sampler2D s = sampler(t, SL_LINEAR_MIPMAP_LINEAR, SL_LINEAR, SL_REPEAT, SL_REPEAT);
        if (cfg == 1)
            s.state.lod_bias = 0.75f;
        if (cfg == 2) {
            s.state.min_lod = 0.5f;
            s.state.max_lod = 3.25f;
        }
        for (int round = 0; round < 50; round++) {
            float u[4 * SL_QUADS_MAX], v[4 * SL_QUADS_MAX], lambda[SL_QUADS_MAX];
            int n = 1 + round % SL_QUADS_MAX;
            for (int q = 0; q < n; q++) {
                float scale = powf(2.0f, rnd(-12.0f, 4.0f)), u0 = rnd(-2, 2), v0 = rnd(-2, 2);
                for (int l = 0; l < 4; l++) {
                    u[4 * q + l] = u0 + rnd(-scale, scale);
                    v[4 * q + l] = v0 + rnd(-scale, scale);
                }
            }
            if (round % 5 == 4) { /* a helper's non-finite input */
                u[1] = INFINITY;
                v[4 * (n - 1) + 2] = NAN;
            }
            sl_texture_lambda_quads(&s, n, u, v, 0.0f, lambda);
            for (int q = 0; q < n; q++) {
                const float *uq = u + 4 * q, *vq = v + 4 * q;
                float one = sl_texture_lambda_quad(&s, vec2(uq[1] - uq[0], vq[1] - vq[0]),
                                                   vec2(uq[2] - uq[0], vq[2] - vq[0]), 0.0f);
                assert_memory_equal(&lambda[q], &one, sizeof one);
                checked++;
            }
        }
    }
    sl_texture_destroy(t);
    assert_true(checked > 1000);
}

/* The textured G-buffer programs' three forms give the same bits: the multi-quad form (the span
 * path), the quad form (the span path with fragment_quads taken away) and the reference through
 * the generic rounds (the plain path). A sphere and a plane with every map slot bound (an sRGB kd
 * map, a normal map, an odd-sized RGBA mask map: REPEAT of a non-power of two, MIRRORED and CLAMP
 * wraps, nearest and bilinear filters), GGX with metallic-roughness and the extra plane, masked and
 * not, 1 and 2 threads. */
static void test_textured_program_forms(void **state)
{
    (void)state;
    enum { W = 97, H = 61 };
    sl_error err = {0};
    srand(5);
    unsigned char data[64 * 32 * 4];
    for (size_t i = 0; i < sizeof data; i++)
        data[i] = (unsigned char)(rand() & 0xff);
    sl_texture *kd = NULL, *nm = NULL, *mask = NULL, *kd2 = NULL;
    assert_true(sl_texture_create(SL_TEX_SRGB8, 64, 32, data, true, &kd, &err));
    assert_true(sl_texture_create(SL_TEX_RGB8, 64, 32, data + 3, true, &kd2, &err));
    assert_true(sl_texture_create(SL_TEX_RGB8, 16, 16, data + 7, true, &nm, &err));
    assert_true(sl_texture_create(SL_TEX_RGBA8, 13, 7, data + 100, true, &mask, &err));
    sl_mesh sphere, plane;
    assert_true(sl_mesh_sphere(&sphere, 24, 12, &err));
    assert_true(sl_mesh_plane(&plane, &err));
    mat4 vp = mat4_mul(perspective(radians(50.0f), (float)W / (float)H, 0.5f, 40.0f),
                       lookAt(vec3(0.4f, -3.5f, 1.2f), vec3(0, 0, 0), vec3(0, 0, 1)));
    mat4 models[2] = {mat4_scale(vec3(1.2f, 1.2f, 1.2f)),
                      mat4_mul(mat4_translate(vec3(0, 0, -1.2f)), mat4_scale(vec3(12, 12, 1)))};
    sl_gbuffer_tex_uniforms u[2];
    for (int o = 0; o < 2; o++) {
        sl_gbuffer_tex_uniforms *x = &u[o];
        memset(x, 0, sizeof *x);
        x->uModel = models[o];
        x->uViewProj = vp;
        x->uNormalMatrix = transpose(inverse(mat3_from_mat4(models[o])));
        x->uModel3 = mat3_from_mat4(models[o]);
        x->uKd = vec3(0.9f, 0.7f, 0.5f);
        x->uKs = vec3(0.04f, 0.05f, 0.06f);
        x->uAlpha = 40.0f;
        x->uRoughness = o == 0 ? 0.6f : -1.0f;
        x->uMetallic = o == 0 ? 0.8f : -1.0f;
        x->uOcclusionStrength = 0.5f;
        x->uEmissive = vec3(0.1f, 0.2f, 0.3f);
        x->uAlphaCutoff = 0.4f;
        sl_sampler2D *smp[SL_MAP_COUNT] = {&x->uKdMap, &x->uKsMap, &x->uAlphaMap, &x->uNormalMap, &x->uMaskMap,
                                           &x->uMetallicRoughnessMap, &x->uOcclusionMap, &x->uEmissiveMap};
        vec4 *st[SL_MAP_COUNT] = {&x->uKdMapST, &x->uKsMapST, &x->uAlphaMapST, &x->uNormalMapST, &x->uMaskMapST,
                                  &x->uMetallicRoughnessMapST, &x->uOcclusionMapST, &x->uEmissiveMapST};
        const sl_texture *tex[SL_MAP_COUNT] = {kd, kd, nm, nm, mask, mask, nm, kd};
        for (int slot = 0; slot < SL_MAP_COUNT; slot++) {
            *smp[slot] = sampler(tex[slot], slot == 2 ? SL_LINEAR : slot == 6 ? SL_NEAREST_MIPMAP_NEAREST
                                                                             : SL_LINEAR_MIPMAP_LINEAR,
                                 slot == 3 ? SL_NEAREST : SL_LINEAR, (sl_wrap)(slot % 3), (sl_wrap)((slot + 1) % 3));
            *st[slot] = vec4(1.0f + (float)slot, 2.5f - 0.25f * (float)slot, 0.1f * (float)slot, -0.2f);
        }
        x->uMaps = (1 << SL_MAP_COUNT) - 1;
    }
    sl_gbuffer gb[3] = {{0}, {0}, {0}};
    /* shared 1: the occlusion slot samples the metallic-roughness slot's texture with its sampler
     * and uv transform (glTF's packed image): the multi-quad form fetches it once (same_fetch).
     * shared 2, also: the normal slot samples another texture of the kd map's size with its sampler
     * and uv transform: the multi-quad form reads it with the kd slot's plan (same_plan) */
    for (int shared = 0; shared < 3; shared++)
    for (int masked = 0; masked < 2; masked++)
        for (int threads = 1; threads <= 2; threads++) {
            for (int o = 0; o < 2 && shared; o++) {
                u[o].uOcclusionMap = u[o].uMetallicRoughnessMap;
                u[o].uOcclusionMapST = u[o].uMetallicRoughnessMapST;
            }
            for (int o = 0; o < 2 && shared == 2; o++) {
                u[o].uNormalMap = (sl_sampler2D){kd2, u[o].uKdMap.state};
                u[o].uNormalMapST = u[o].uKdMapST;
                assert_true(sl_texture_same_plan(&u[o].uKdMap, &u[o].uNormalMap));
            }
            const sl_program *base = masked ? &sl_gbuffer_tex_masked_program : &sl_gbuffer_tex_program;
            sl_program quad = *base;
            quad.fragment_quads = NULL;
            /* and the tiles copy their depth back: what the program's own depth writes
             * (writes_depth) must give in the other two */
            assert_true(quad.writes_depth);
            quad.writes_depth = false;
            const sl_program *progs[3] = {base, &quad, base};
            for (int k = 0; k < 3; k++) {
                for (int o = 0; o < 2; o++) {
                    u[o].uMaps = masked ? (u[o].uMaps | SL_GBUFFER_MAP_CUTOFF) : (u[o].uMaps & ~SL_GBUFFER_MAP_CUTOFF);
                    u[o].extra = NULL;
                }
                assert_true(sl_gbuffer_resize(&gb[k], W, H, &err));
                assert_true(sl_gbuffer_use_extra(&gb[k], true, 0, &err));
                sl_gbuffer_clear(&gb[k], 0);
                u[0].extra = gb[k].extra;
                u[0].extra_width = W;
                sl_draw draws[2] = {{.program = progs[k], .vs_uniforms = &u[0], .fs_uniforms = &u[0], .mesh = &sphere},
                                    {.program = progs[k], .vs_uniforms = &u[1], .fs_uniforms = &u[1], .mesh = &plane}};
                sl_raster *r = sl_raster_create(
                    &(sl_raster_desc){.threads = threads, .tile_size = 32, .stats = true, .plain = k == 2}, &err);
                assert_non_null(r);
                sl_target tg = sl_gbuffer_target(&gb[k]);
                assert_true(sl_raster_draw_list(r, &tg, draws, 2, &err));
                sl_raster_stats stats = sl_raster_get_stats(r);
                sl_raster_destroy(r);
                sl_gbuffer_extra_resolve(&gb[k]); /* the tile hooks resolved it already: idempotent */
                assert_true(stats.quads > 500);
                assert_true(!masked || stats.fragments_discarded > 100);
                if (k < 2)
                    assert_int_equal(stats.quad_rounds, stats.quads);
            }
            for (int k = 1; k < 3; k++) {
                if (memcmp(gb[0].texels, gb[k].texels, (size_t)W * H * sizeof *gb[0].texels) != 0)
                    fail_msg("shared %d masked %d threads %d: the multi-quad form's texels differ from the %s", shared,
                             masked, threads,
                             k == 1 ? "quad form's" : "rounds'");
                /* the rounds too when masked: a lane of the rounds may pass the cutoff in a round
                 * and discard in the next; its extra texel must not stay (sl_program.stores) */
                if (memcmp(gb[0].extra, gb[k].extra, (size_t)W * H * sizeof *gb[0].extra) != 0)
                    fail_msg("shared %d masked %d threads %d: the extra plane differs from the %s", shared, masked,
                             threads,
                             k == 1 ? "quad form's" : "rounds'");
            }
        }
    for (int k = 0; k < 3; k++)
        sl_gbuffer_free(&gb[k]);
    sl_mesh_free(&sphere);
    sl_mesh_free(&plane);
    sl_texture_destroy(kd);
    sl_texture_destroy(kd2);
    sl_texture_destroy(nm);
    sl_texture_destroy(mask);
}

/* A fetch plan shared (sl_texture_plan_quads, sl_texture_fetch_quads): textures of one size under
 * one sampler state take each other's plans, and a fetch through another texture's plan gives
 * that texture's own multi-quad sample, bit for bit; a different size, sampler state or storage
 * (no decoded plane) does not count as the same plan. */
static void test_shared_plan(void **state)
{
    (void)state;
    unsigned char data[32 * 16 * 4 + 16]; /* and the offsets below */
    srand(11);
    for (size_t i = 0; i < sizeof data; i++)
        data[i] = (unsigned char)(rand() & 0xff);
    sl_texture *a = NULL, *b = NULL, *small = NULL, *bytes = NULL;
    sl_error err = {0};
    assert_true(sl_texture_create(SL_TEX_SRGB8, 32, 16, data, true, &a, &err));
    assert_true(sl_texture_create(SL_TEX_RGBA8, 32, 16, data + 5, true, &b, &err));
    assert_true(sl_texture_create(SL_TEX_RGBA8, 16, 16, data, true, &small, &err));
    assert_true(sl_texture_create(SL_TEX_RGBA8, 32, 16, data + 9, true, &bytes, &err));
    sl_tex_plane_drop(bytes);
    long checked = 0;
    for (int min = SL_NEAREST; min <= SL_LINEAR_MIPMAP_LINEAR; min++)
        for (int w = 0; w < 9; w++) {
            sl_filter mag = min & 1 ? SL_LINEAR : SL_NEAREST;
            sl_wrap ws = (sl_wrap)(w % 3), wt = (sl_wrap)(w / 3);
            sl_sampler2D sa = sampler(a, (sl_filter)min, mag, ws, wt), sb = sampler(b, (sl_filter)min, mag, ws, wt);
            sl_sampler2D ssmall = sampler(small, (sl_filter)min, mag, ws, wt);
            sl_sampler2D sbytes = sampler(bytes, (sl_filter)min, mag, ws, wt);
            sl_sampler2D swrap = sampler(b, (sl_filter)min, mag, (sl_wrap)((w + 1) % 3), wt);
            sl_sampler2D sbias = sb;
            sbias.state.lod_bias = 0.5f;
            assert_true(sl_texture_same_plan(&sa, &sb));
            assert_true(sl_texture_same_plan(&sb, &sa));
            assert_false(sl_texture_same_plan(&sa, &ssmall));
            assert_false(sl_texture_same_plan(&sa, &sbytes));
            assert_false(sl_texture_same_plan(&sa, &swrap));
            assert_false(sl_texture_same_plan(&sa, &sbias));
            for (int round = 0; round < 20; round++) {
                int n = 1 + round % SL_QUADS_MAX;
                float u[4 * SL_QUADS_MAX], v[4 * SL_QUADS_MAX], lambda[SL_QUADS_MAX];
                for (int q = 0; q < n; q++) {
                    float u0 = rnd(-2.0f, 3.0f), v0 = rnd(-2.0f, 3.0f), d = rnd(0.0f, 0.2f);
                    for (int l = 0; l < 4; l++) {
                        u[4 * q + l] = u0 + d * (float)(l & 1);
                        v[4 * q + l] = v0 + d * (float)(l >> 1);
                    }
                }
                sl_texture_lambda_quads(&sa, n, u, v, 0.0f, lambda);
                sl_texture_quads_plan plan;
                sl_texture_plan_quads(&sa, n, u, v, lambda, &plan);
                float r[2][4 * SL_QUADS_MAX], g[2][4 * SL_QUADS_MAX], bl[2][4 * SL_QUADS_MAX], al[2][4 * SL_QUADS_MAX];
                float *const shared[4] = {r[0], g[0], bl[0], al[0]}, *const own[4] = {r[1], g[1], bl[1], al[1]};
                sl_texture_fetch_quads(&sb, &plan, shared);
                sl_texture_sample_quads(&sb, n, u, v, lambda, own);
                for (int c = 0; c < 4; c++)
                    assert_memory_equal(shared[c], own[c], (size_t)(4 * n) * sizeof(float));
                checked += 4 * n;
            }
        }
    assert_true(checked > 10000);
    sl_texture_destroy(a);
    sl_texture_destroy(b);
    sl_texture_destroy(small);
    sl_texture_destroy(bytes);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_format),
        cmocka_unit_test(test_srgb_all_codes),
        cmocka_unit_test(test_mips_odd_sizes),
        cmocka_unit_test(test_wrap_modes),
        cmocka_unit_test(test_filters_and_mag_switch),
        cmocka_unit_test(test_lambda),
        cmocka_unit_test(test_level_selection),
        cmocka_unit_test(test_texel_fetch_and_size),
        cmocka_unit_test(test_load_files),
        cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_jpeg_dc_overflow_files),
        cmocka_unit_test(test_fast_path_bits),
        cmocka_unit_test(test_lambda_quads),
        cmocka_unit_test(test_textured_program_forms),
        cmocka_unit_test(test_shared_plan),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
