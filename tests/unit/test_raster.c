/* test_raster.c - the rasterization pipeline against hand-derived and analytic coverage:
 * fill rule, watertightness, clipping, bad geometry, stats. Perspective correctness and
 * determinism are in test_raster_interp.c, the G-buffer in test_raster_gbuffer.c.
 *
 * Most tests use a coverage-count target: a uint32 per pixel, depth test off, and a
 * fragment shader that increments it, so "covered exactly once" is a plain check.
 * Target sizes are powers of two so that window -> NDC -> window is exact in float and
 * vertices given in window coordinates land exactly where the comments say. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raster/raster.h"
#include "testutil.h"

/* ---- coverage-count harness ---- */

typedef struct {
    float width, height; /* vertices are given in window coordinates (pixels) */
} window_uniforms;

/* Window coordinates in, clip coordinates out (w = 1, z from the vertex). */
static void vs_window(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    const window_uniforms *u = uniforms;
    (void)varyings;
    *clip = vec4(in->position.x / u->width * 2.0f - 1.0f, in->position.y / u->height * 2.0f - 1.0f, in->position.z, 1.0f);
}

/* Clip coordinates in directly: position.xyz and w = texcoord.x (tests of clipping). */
static void vs_clip(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    (void)uniforms;
    (void)varyings;
    *clip = vec4(in->position.x, in->position.y, in->position.z, in->texcoord.x);
}

typedef struct {
    mat4 mvp;
} mvp_uniforms;

static void vs_mvp(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    const mvp_uniforms *u = uniforms;
    (void)varyings;
    *clip = mat4_mul_vec4(u->mvp, vec4_from3(in->position, 1.0f));
}

static void fs_count(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    (void)uniforms;
    (void)in;
    (*(uint32_t *)texel)++;
}

/* Records front_facing: 1 = front, 2 = back. */
static void fs_facing(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    (void)uniforms;
    *(uint32_t *)texel = in->front_facing ? 1u : 2u;
}

static const sl_program prog_window = {.vertex = vs_window, .fragment = fs_count, .varying_count = 0};
static const sl_program prog_clip = {.vertex = vs_clip, .fragment = fs_count, .varying_count = 0};
static const sl_program prog_mvp = {.vertex = vs_mvp, .fragment = fs_count, .varying_count = 0};

typedef struct {
    int w, h;
    uint32_t *count;
    sl_target target;
} count_target;

static void ct_init(count_target *c, int w, int h)
{
    c->w = w;
    c->h = h;
    c->count = calloc((size_t)w * (size_t)h, sizeof *c->count);
    assert_non_null(c->count);
    c->target = (sl_target){.width = w, .height = h, .texel_size = sizeof(uint32_t), .texels = c->count, .depth_offset = SL_NO_DEPTH};
}

static void ct_free(count_target *c) { free(c->count); }
static uint32_t ct_at(const count_target *c, int x, int y) { return c->count[(size_t)y * (size_t)c->w + (size_t)x]; }

static void draw(sl_raster *r, count_target *c, const sl_program *p, const void *u, const vec3 *pos,
                 const vec2 *tc, int nv, const uint32_t *idx, int nt, sl_cull_mode cull)
{
    sl_mesh m = {.vertex_count = nv, .triangle_count = nt, .positions = (vec3 *)pos, .texcoords = (vec2 *)tc,
                 .indices = (uint32_t *)idx};
    sl_error err = {0};
    bool ok = sl_raster_draw(
        r, &c->target, &(sl_draw){.program = p, .vs_uniforms = u, .fs_uniforms = u, .mesh = &m, .cull = cull}, &err);
    if (!ok)
        print_error("sl_raster_draw: %s\n", err.msg);
    assert_true(ok);
}

/* Print a coverage map when a check fails (row 0 at the bottom, printed last). */
static void ct_dump(const count_target *c)
{
    for (int y = c->h - 1; y >= 0; y--) {
        for (int x = 0; x < c->w; x++)
            print_error("%c", ct_at(c, x, y) < 10 ? (char)('0' + ct_at(c, x, y)) : '+');
        print_error("\n");
    }
}

/* Compare against an expected map given by a predicate; report every mismatch. */
static int ct_mismatches(const count_target *c, uint32_t (*expect)(int x, int y))
{
    int bad = 0;
    for (int y = 0; y < c->h; y++)
        for (int x = 0; x < c->w; x++)
            if (ct_at(c, x, y) != expect(x, y)) {
                if (bad < 10)
                    print_error("pixel (%d,%d): covered %u times, expected %u\n", x, y, ct_at(c, x, y), expect(x, y));
                bad++;
            }
    if (bad)
        ct_dump(c);
    return bad;
}

/* Deterministic jitter: xorshift32 mapped to [0, 1). */
static float rnd(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return (float)(*s >> 8) / 16777216.0f;
}

/* ---- fill rule ---- */

/* Right triangle (0,0) (4,0) (0,4), counter-clockwise. Pixel centres (x+.5, y+.5) on the
 * hypotenuse x + y = 4 are those with x + y = 3. The hypotenuse runs (4,0) -> (0,4): dy > 0,
 * a right edge, so those centres are NOT covered. The legs pass through no centre.
 * Covered: x + y <= 2 (six pixels). */
static uint32_t expect_corner(int x, int y) { return x + y <= 2 ? 1u : 0u; }

/* Square [0.5, 4.5]^2 split along its diagonal, every edge through pixel centres:
 * left edge x = 0.5 (column 0) is a left edge: covered; right edge x = 4.5 (column 4) is
 * not; the horizontal edge with the interior above it, y = 0.5 (row 0), is the inclusive
 * one (llvmpipe's rule, setup.c): covered; y = 4.5 (row 4) is not. So columns 0..3,
 * rows 0..3, each exactly once. */
static uint32_t expect_square(int x, int y) { return x <= 3 && y <= 3 ? 1u : 0u; }

/* Lower-right half (0.5,0.5) (4.5,0.5) (4.5,4.5): its diagonal (4.5,4.5) -> (0.5,0.5) goes
 * down (dy < 0): a left edge, so the diagonal centres (k, k) belong to this half; its bottom
 * edge (0.5,0.5) -> (4.5,0.5) goes right (dy = 0, dx > 0: covered), the right edge is not.
 * Covered: x <= 3, x >= y. */
static uint32_t expect_lower(int x, int y) { return x <= 3 && x >= y ? 1u : 0u; }
/* Upper-left half (0.5,0.5) (4.5,4.5) (0.5,4.5): the diagonal (0.5,.5) -> (4.5,4.5) is a right
 * edge (excluded), the top edge (4.5,4.5) -> (0.5,4.5) goes left (dy = 0, dx < 0: excluded),
 * the left edge (0.5,4.5) -> (0.5,0.5) is covered. Covered: x < y <= 3. */
static uint32_t expect_upper(int x, int y) { return x < y && y <= 3 ? 1u : 0u; }

static void test_fill_rule(void **state)
{
    (void)state;
    window_uniforms u = {8, 8};
    sl_raster *r = test_make_raster(1, 16, false, false);
    count_target c;

    ct_init(&c, 8, 8);
    const vec3 corner[] = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}};
    draw(r, &c, &prog_window, &u, corner, NULL, 3, (const uint32_t[]){0, 1, 2}, 1, SL_CULL_NONE);
    assert_int_equal(ct_mismatches(&c, expect_corner), 0);
    /* The same triangle given clockwise is a back face: identical coverage, and culled with SL_CULL_BACK. */
    memset(c.count, 0, 64 * sizeof(uint32_t));
    draw(r, &c, &prog_window, &u, corner, NULL, 3, (const uint32_t[]){0, 2, 1}, 1, SL_CULL_NONE);
    assert_int_equal(ct_mismatches(&c, expect_corner), 0);
    memset(c.count, 0, 64 * sizeof(uint32_t));
    draw(r, &c, &prog_window, &u, corner, NULL, 3, (const uint32_t[]){0, 2, 1}, 1, SL_CULL_BACK);
    for (int i = 0; i < 64; i++)
        assert_int_equal(c.count[i], 0);
    ct_free(&c);

    const vec3 sq[] = {{0.5f, 0.5f, 0}, {4.5f, 0.5f, 0}, {4.5f, 4.5f, 0}, {0.5f, 4.5f, 0}};
    ct_init(&c, 8, 8);
    draw(r, &c, &prog_window, &u, sq, NULL, 4, (const uint32_t[]){0, 1, 2, 0, 2, 3}, 2, SL_CULL_BACK);
    assert_int_equal(ct_mismatches(&c, expect_square), 0);
    memset(c.count, 0, 64 * sizeof(uint32_t));
    draw(r, &c, &prog_window, &u, sq, NULL, 4, (const uint32_t[]){0, 1, 2}, 1, SL_CULL_BACK);
    assert_int_equal(ct_mismatches(&c, expect_lower), 0);
    memset(c.count, 0, 64 * sizeof(uint32_t));
    draw(r, &c, &prog_window, &u, sq, NULL, 4, (const uint32_t[]){0, 2, 3}, 1, SL_CULL_BACK);
    assert_int_equal(ct_mismatches(&c, expect_upper), 0);
    ct_free(&c);

    /* gl_FrontFacing: counter-clockwise in window coordinates is front. */
    ct_init(&c, 8, 8);
    sl_program facing = {.vertex = vs_window, .fragment = fs_facing, .varying_count = 0};
    draw(r, &c, &facing, &u, corner, NULL, 3, (const uint32_t[]){0, 1, 2}, 1, SL_CULL_NONE);
    assert_int_equal(ct_at(&c, 0, 0), 1);
    draw(r, &c, &facing, &u, corner, NULL, 3, (const uint32_t[]){0, 2, 1}, 1, SL_CULL_NONE);
    assert_int_equal(ct_at(&c, 0, 0), 2);
    ct_free(&c);
    sl_raster_destroy(r);
}

/* Sub-pixel precision: a vertex 1/256 pixel to either side of a pixel centre decides it.
 * Triangle (2.5 + d, 0) (8, 0) (8, 8): its left edge is nearly vertical; pixel (2, 0)'s
 * centre (2.5, 0.5) lies inside only when the edge passes left of it. */
static void test_subpixel(void **state)
{
    (void)state;
    window_uniforms u = {16, 16};
    sl_raster *r = test_make_raster(1, 16, false, false);
    const float d[] = {-1.0f / 256.0f, 1.0f / 256.0f};
    const uint32_t expect[] = {1, 0};
    for (int i = 0; i < 2; i++) {
        count_target c;
        ct_init(&c, 16, 16);
        const vec3 p[] = {{2.5f + d[i], 0, 0}, {12, 0, 0}, {2.5f + d[i], 12, 0}};
        draw(r, &c, &prog_window, &u, p, NULL, 3, (const uint32_t[]){0, 1, 2}, 1, SL_CULL_BACK);
        if (ct_at(&c, 2, 0) != expect[i])
            print_error("offset %g/256: pixel (2,0) covered %u, expected %u\n", (double)(d[i] * 256.0f), ct_at(&c, 2, 0),
                        expect[i]);
        assert_int_equal(ct_at(&c, 2, 0), expect[i]);
        assert_int_equal(ct_at(&c, 3, 0), 1);
        assert_int_equal(ct_at(&c, 1, 0), 0);
        ct_free(&c);
    }
    sl_raster_destroy(r);
}

/* ---- watertightness ---- */

/* A full-screen grid of jittered vertices (each moved up to 0.18 of a cell, about a pixel,
 * so cells stay convex; diagonals of random direction), its border vertices outside the
 * screen: every pixel exactly once. The test first checks every triangle is
 * counter-clockwise, so an overlap cannot come from the mesh itself. */
static void test_watertight_grid(void **state)
{
    (void)state;
    enum { W = 128, H = 64, N = 23 };
    window_uniforms u = {W, H};
    vec3 pos[(N + 1) * (N + 1)];
    uint32_t idx[N * N * 6];
    uint32_t seed = 12345;
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            float x = (float)i * W / N, y = (float)j * H / N;
            if (i == 0) x = -0.7f;
            else if (i == N) x = W + 0.3f;
            else x += (rnd(&seed) - 0.5f) * 0.36f * W / N;
            if (j == 0) y = -0.2f;
            else if (j == N) y = H + 0.9f;
            else y += (rnd(&seed) - 0.5f) * 0.36f * H / N;
            pos[j * (N + 1) + i] = vec3(x, y, 0);
        }
    int nt = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            uint32_t a = (uint32_t)(j * (N + 1) + i), b = a + 1, c = a + N + 1, d = c + 1;
            if (rnd(&seed) < 0.5f) {
                uint32_t t[6] = {a, b, d, a, d, c};
                memcpy(&idx[6 * nt], t, sizeof t);
            } else {
                uint32_t t[6] = {a, b, c, b, d, c};
                memcpy(&idx[6 * nt], t, sizeof t);
            }
            nt++;
        }
    for (int t = 0; t < 2 * nt; t++) {
        vec3 a = pos[idx[3 * t]], b = pos[idx[3 * t + 1]], c = pos[idx[3 * t + 2]];
        assert_true((double)(b.x - a.x) * (c.y - a.y) - (double)(c.x - a.x) * (b.y - a.y) > 0.0);
    }
    const int tiles[] = {16, 32};
    for (int k = 0; k < 2; k++) {
        sl_raster *r = test_make_raster(2, tiles[k], false, false);
        count_target c;
        ct_init(&c, W, H);
        draw(r, &c, &prog_window, &u, pos, NULL, (N + 1) * (N + 1), idx, 2 * nt, SL_CULL_BACK);
        int bad = 0;
        for (int i = 0; i < W * H; i++)
            bad += c.count[i] != 1;
        if (bad) {
            print_error("tile %d: %d of %d pixels not covered exactly once\n", tiles[k], bad, W * H);
            ct_dump(&c);
        }
        assert_int_equal(bad, 0);
        ct_free(&c);
        sl_raster_destroy(r);
    }
}

/* A fan of 37 triangles around one jittered vertex: inside the rim polygon every pixel
 * is covered exactly once, nothing anywhere twice. */
static void test_watertight_fan(void **state)
{
    (void)state;
    enum { W = 64, H = 64, N = 37 };
    window_uniforms u = {W, H};
    vec3 pos[N + 1];
    uint32_t idx[3 * N];
    const float cx = 31.77f, cy = 32.13f, rad = 27.3f;
    pos[0] = vec3(cx, cy, 0);
    for (int i = 0; i < N; i++) {
        double a = 2.0 * 3.14159265358979 * i / N;
        pos[i + 1] = vec3(cx + rad * (float)cos(a), cy + rad * (float)sin(a), 0);
        idx[3 * i] = 0;
        idx[3 * i + 1] = (uint32_t)(i + 1);
        idx[3 * i + 2] = (uint32_t)((i + 1) % N + 1);
    }
    sl_raster *r = test_make_raster(2, 16, false, false);
    count_target c;
    ct_init(&c, W, H);
    draw(r, &c, &prog_window, &u, pos, NULL, N + 1, idx, N, SL_CULL_BACK);
    /* the rim polygon contains the disc of radius rad*cos(pi/N); stay a pixel inside it */
    double inner = rad * cos(3.14159265358979 / N) - 1.0;
    int holes = 0, doubles = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double dx = x + 0.5 - cx, dy = y + 0.5 - cy;
            uint32_t n = ct_at(&c, x, y);
            doubles += n > 1;
            holes += dx * dx + dy * dy < inner * inner && n != 1;
        }
    if (holes || doubles) {
        print_error("fan: %d holes, %d pixels covered twice\n", holes, doubles);
        ct_dump(&c);
    }
    assert_int_equal(holes + doubles, 0);
    ct_free(&c);
    sl_raster_destroy(r);
}

/* UV sphere, counter-clockwise seen from outside, poles as single vertices. */
static void make_sphere(int slices, int stacks, vec3 **pos, uint32_t **idx, int *nv, int *nt)
{
    *nv = slices * (stacks - 1) + 2;
    *nt = 2 * slices * (stacks - 1);
    *pos = malloc((size_t)*nv * sizeof **pos);
    *idx = malloc((size_t)*nt * 3 * sizeof **idx);
    assert_non_null(*pos);
    assert_non_null(*idx);
    for (int j = 1; j < stacks; j++)
        for (int i = 0; i < slices; i++) {
            double th = 3.14159265358979 * j / stacks, ph = 2.0 * 3.14159265358979 * i / slices;
            (*pos)[(j - 1) * slices + i] = vec3(sin(th) * cos(ph), sin(th) * sin(ph), cos(th));
        }
    uint32_t north = (uint32_t)(*nv - 2), south = (uint32_t)(*nv - 1);
    (*pos)[north] = vec3(0, 0, 1);
    (*pos)[south] = vec3(0, 0, -1);
    uint32_t *t = *idx;
    for (int i = 0; i < slices; i++) {
        uint32_t a = (uint32_t)i, b = (uint32_t)((i + 1) % slices);
        *t++ = north, *t++ = a, *t++ = b;
        uint32_t la = (uint32_t)((stacks - 2) * slices) + a, lb = (uint32_t)((stacks - 2) * slices) + b;
        *t++ = south, *t++ = lb, *t++ = la;
    }
    for (int j = 0; j < stacks - 2; j++)
        for (int i = 0; i < slices; i++) {
            uint32_t a = (uint32_t)(j * slices + i), b = (uint32_t)(j * slices + (i + 1) % slices);
            uint32_t c = a + (uint32_t)slices, d = b + (uint32_t)slices;
            *t++ = a, *t++ = c, *t++ = d;
            *t++ = a, *t++ = d, *t++ = b;
        }
}

/* A closed, convex, finely tessellated sphere in perspective: every ray through a pixel
 * centre crosses the surface an even number of times, so with both faces drawn each
 * pixel is covered 0 or 2 times, and with back faces culled 0 or 1 times; pixels well
 * inside the silhouette must be covered (no holes). */
static void test_watertight_sphere(void **state)
{
    (void)state;
    enum { W = 128, H = 128 };
    vec3 *pos;
    uint32_t *idx;
    int nv, nt;
    make_sphere(96, 48, &pos, &idx, &nv, &nt);
    mvp_uniforms u;
    vec3 eye = vec3(0.3f, -3.1f, 0.7f);
    u.mvp = mat4_mul(perspective(radians(45.0f), 1.0f, 0.5f, 10.0f), lookAt(eye, vec3(0.01f, 0.02f, 0.0f), vec3(0, 0, 1)));
    sl_raster *r = test_make_raster(2, 32, false, false);
    for (int pass = 0; pass < 2; pass++) {
        count_target c;
        ct_init(&c, W, H);
        draw(r, &c, &prog_mvp, &u, pos, NULL, nv, idx, nt, pass ? SL_CULL_BACK : SL_CULL_NONE);
        uint32_t full = pass ? 1u : 2u;
        /* The projected centre, and the silhouette's radius (distance d, radius 1: half-angle asin(1/d))
         * shrunk by the tessellation (cos(pi/48)) and a pixel. */
        vec4 cc = mat4_mul_vec4(u.mvp, vec4(0, 0, 0, 1));
        double sx = (cc.x / cc.w * 0.5 + 0.5) * W, sy = (cc.y / cc.w * 0.5 + 0.5) * H;
        double dist = length(eye);
        double ang = asin(cos(3.14159265358979 / 48) / dist);
        double rad = tan(ang) / tan(radians(45.0f) * 0.5) * (H / 2.0) - 2.0;
        int odd = 0, holes = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                uint32_t n = ct_at(&c, x, y);
                odd += n != 0 && n != full;
                double dx = x + 0.5 - sx, dy = y + 0.5 - sy;
                holes += dx * dx + dy * dy < rad * rad && n != full;
            }
        if (odd || holes) {
            print_error("sphere (%s): %d pixels covered neither 0 nor %u times, %d holes\n",
                        pass ? "culled" : "both faces", odd, full, holes);
            ct_dump(&c);
        }
        assert_int_equal(odd + holes, 0);
        ct_free(&c);
    }
    sl_raster_destroy(r);
    free(pos);
    free(idx);
}

/* ---- clipping ---- */

/* A triangle crossing the near plane, against ray casting in double: a pixel is covered
 * iff the ray through its centre hits the triangle beyond the near plane. Pixels within
 * 1e-3 (barycentric or depth) of an edge are not judged. */
static void test_clip_near(void **state)
{
    (void)state;
    enum { W = 64, H = 64 };
    const double fovy = 60.0, znear = 1.0, zfar = 50.0;
    /* eye space (camera at the origin looking down -Z): one vertex behind the eye, one
     * between the eye and the near plane, one in front */
    const vec3 p[] = {{-1.5f, -1.0f, -6.0f}, {2.0f, -0.5f, 2.0f}, {-0.3f, 1.2f, -0.4f}};
    mvp_uniforms u = {perspective(radians((float)fovy), 1.0f, (float)znear, (float)zfar)};
    sl_raster *r = test_make_raster(2, 16, true, false);
    count_target c;
    ct_init(&c, W, H);
    draw(r, &c, &prog_mvp, &u, p, NULL, 3, (const uint32_t[]){0, 1, 2}, 1, SL_CULL_NONE);
    sl_raster_stats st = sl_raster_get_stats(r);
    assert_int_equal(st.triangles_clipped, 1);
    double t = tan(fovy * 3.14159265358979 / 360.0);
    int judged = 0, wrong = 0, any = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double dx = ((x + 0.5) / W * 2 - 1) * t, dy = ((y + 0.5) / H * 2 - 1) * t, dz = -1;
            /* Moller-Trumbore in double */
            double e1[3] = {p[1].x - p[0].x, p[1].y - p[0].y, p[1].z - p[0].z};
            double e2[3] = {p[2].x - p[0].x, p[2].y - p[0].y, p[2].z - p[0].z};
            double pv[3] = {dy * e2[2] - dz * e2[1], dz * e2[0] - dx * e2[2], dx * e2[1] - dy * e2[0]};
            double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
            double tv[3] = {-p[0].x, -p[0].y, -p[0].z};
            double bu = (tv[0] * pv[0] + tv[1] * pv[1] + tv[2] * pv[2]) / det;
            double qv[3] = {tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2], tv[0] * e1[1] - tv[1] * e1[0]};
            double bv = (dx * qv[0] + dy * qv[1] + dz * qv[2]) / det;
            double s = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det; /* hit = s * d, eye z = -s */
            double m = fmin(fmin(bu, bv), 1 - bu - bv), margin = fmin(m, s - znear);
            uint32_t n = ct_at(&c, x, y);
            any += n != 0;
            if (n > 1) wrong++;
            if (fabs(margin) < 1e-3)
                continue;
            judged++;
            uint32_t expect = margin > 0 ? 1u : 0u;
            if (n != expect) {
                if (wrong < 5)
                    print_error("pixel (%d,%d): covered %u, ray cast says %u (margin %g)\n", x, y, n, expect, margin);
                wrong++;
            }
        }
    if (wrong)
        ct_dump(&c);
    assert_int_equal(wrong, 0);
    assert_true(any > 100); /* the visible part is large: the check is not vacuous */
    assert_true(judged > W * H / 2);
    ct_free(&c);
    sl_raster_destroy(r);
}

/* Wholly behind the eye (w < 0 at every vertex): nothing. Without clipping, dividing by
 * w < 0 would mirror it into view (these positions project inside the screen). */
static void test_clip_behind(void **state)
{
    (void)state;
    mvp_uniforms u = {perspective(radians(60.0f), 1.0f, 0.1f, 100.0f)};
    const vec3 p[] = {{-1, -1, 3}, {1, -1, 3}, {0, 1, 2}};
    sl_raster *r = test_make_raster(2, 16, true, false);
    count_target c;
    ct_init(&c, 32, 32);
    draw(r, &c, &prog_mvp, &u, p, NULL, 3, (const uint32_t[]){0, 1, 2, 0, 2, 1}, 2, SL_CULL_NONE);
    for (int i = 0; i < 32 * 32; i++)
        assert_int_equal(c.count[i], 0);
    /* Also beyond the far plane. */
    const vec3 q[] = {{-50, -50, -200}, {50, -50, -200}, {0, 50, -200}};
    draw(r, &c, &prog_mvp, &u, q, NULL, 3, (const uint32_t[]){0, 1, 2}, 1, SL_CULL_NONE);
    for (int i = 0; i < 32 * 32; i++)
        assert_int_equal(c.count[i], 0);
    sl_raster_stats st = sl_raster_get_stats(r);
    assert_int_equal(st.triangles_in, 3);
    assert_int_equal(st.fragments_shaded, 0);
    ct_free(&c);
    sl_raster_destroy(r);
}

/* Enormous triangles cover the screen exactly once: (a) clip coordinates up to 3e6, far
 * past the guard band; (b) the screen square with two corners scaled by w = 1e7; (c) in
 * eye space, a 20000-unit triangle on the tilted plane z = -5 - 0.1 y with two vertices
 * behind the eye (w = -95) and one beyond the far plane: every ray of the 60-degree
 * frustum meets the plane at distance about 5, well inside the triangle. */
static void test_clip_enormous(void **state)
{
    (void)state;
    enum { W = 96, H = 64 };
    /* position = clip xyz, texcoord.x = clip w */
    const vec3 p[] = {{-1e6f, -1e6f, 0}, {3e6f, -1e6f, 0}, {-1e6f, 3e6f, 0},
                      {-1, -1, 0}, {1e7f, -1e7f, 0}, {1e7f, 1e7f, 0}, {-1, 1, 0}};
    const vec2 w[] = {{1, 0}, {1, 0}, {1, 0}, {1, 0}, {1e7f, 0}, {1e7f, 0}, {1, 0}};
    const uint32_t tris[][6] = {{0, 1, 2}, {3, 4, 5, 3, 5, 6}};
    const int ntris[] = {1, 2};
    const vec3 eye_space[] = {{-1e4f, -1000, 95}, {1e4f, -1000, 95}, {0, 1000, -105}};
    mvp_uniforms u = {perspective(radians(60.0f), (float)W / H, 1.0f, 50.0f)};
    sl_raster *r = test_make_raster(2, 32, true, false);
    for (int k = 0; k < 3; k++) {
        count_target c;
        ct_init(&c, W, H);
        if (k < 2)
            draw(r, &c, &prog_clip, NULL, p, w, 7, tris[k], ntris[k], SL_CULL_NONE);
        else
            draw(r, &c, &prog_mvp, &u, eye_space, NULL, 3, (const uint32_t[]){0, 1, 2}, 1, SL_CULL_NONE);
        int bad = 0;
        for (int i = 0; i < W * H; i++)
            bad += c.count[i] != 1;
        if (bad) {
            print_error("case %d: %d pixels not covered exactly once\n", k, bad);
            ct_dump(&c);
        }
        assert_int_equal(bad, 0);
        ct_free(&c);
    }
    sl_raster_stats st = sl_raster_get_stats(r);
    assert_int_equal(st.triangles_clipped, 2); /* (a) by the guard band, (c) by near and far */
    sl_raster_destroy(r);
}

/* A jittered 64x64 grid on the tilted plane z = -5 - 0.1 y, cut by the near plane at
 * distance 5 right through the middle of the view: many triangles are clipped and share
 * their cut edges. No pixel twice; every pixel whose ray meets the plane beyond the near
 * plane (by a margin of 1e-3) exactly once, every one in front of it never. */
static void test_clip_watertight(void **state)
{
    (void)state;
    enum { W = 64, H = 64, N = 64 };
    vec3 *pos = malloc((N + 1) * (N + 1) * sizeof *pos);
    uint32_t *idx = malloc(N * N * 6 * sizeof *idx);
    assert_non_null(pos);
    assert_non_null(idx);
    uint32_t seed = 777;
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            float x = -8.0f + 16.0f * (float)i / N + (rnd(&seed) - 0.5f) * 0.06f;
            float y = -8.0f + 16.0f * (float)j / N + (rnd(&seed) - 0.5f) * 0.06f;
            pos[j * (N + 1) + i] = vec3(x, y, -5.0f - 0.1f * y);
        }
    for (int j = 0, t = 0; j < N; j++)
        for (int i = 0; i < N; i++, t++) {
            uint32_t a = (uint32_t)(j * (N + 1) + i), b = a + 1, c = a + N + 1, d = c + 1;
            uint32_t q[6] = {a, b, d, a, d, c};
            memcpy(&idx[6 * t], q, sizeof q);
        }
    const double znear = 5.0, tf = tan(30.0 * 3.14159265358979 / 180.0);
    mvp_uniforms u = {perspective(radians(60.0f), 1.0f, (float)znear, 100.0f)};
    sl_raster *r = test_make_raster(2, 16, true, false);
    count_target c;
    ct_init(&c, W, H);
    draw(r, &c, &prog_mvp, &u, pos, NULL, (N + 1) * (N + 1), idx, 2 * N * N, SL_CULL_NONE);
    assert_true(sl_raster_get_stats(r).triangles_clipped > 20);
    int wrong = 0, covered = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            /* ray (dx, dy, -1) meets z = -5 - 0.1 y at distance s = 5 / (1 - 0.1 dy) */
            double dy = ((y + 0.5) / H * 2 - 1) * tf, s = 5.0 / (1.0 - 0.1 * dy);
            uint32_t n = ct_at(&c, x, y);
            covered += n == 1;
            if (n > 1 || (fabs(s - znear) > 1e-3 && n != (s > znear ? 1u : 0u))) {
                if (wrong < 5)
                    print_error("pixel (%d,%d): covered %u, hit distance %g, near %g\n", x, y, n, s, znear);
                wrong++;
            }
        }
    if (wrong)
        ct_dump(&c);
    assert_int_equal(wrong, 0);
    assert_true(covered > W * H / 3);
    ct_free(&c);
    sl_raster_destroy(r);
    free(pos);
    free(idx);
}

/* Slivers: a fan of 660 triangles, 0.1 pixel tall at their base, from an apex 20000
 * pixels to the left (outside the guard band: clipped there) to a base beyond the right
 * edge. Their union covers the screen; every pixel exactly once. */
static void test_clip_slivers(void **state)
{
    (void)state;
    enum { W = 64, H = 64, N = 660 };
    window_uniforms u = {W, H};
    vec3 *pos = malloc((N + 2) * sizeof *pos);
    uint32_t *idx = malloc(3 * N * sizeof *idx);
    assert_non_null(pos);
    assert_non_null(idx);
    pos[0] = vec3(-20000.0f, 32.0f, 0);
    for (int i = 0; i <= N; i++)
        pos[i + 1] = vec3(W + 1.0f, -1.0f + (float)(H + 2) * (float)i / N, 0);
    for (int i = 0; i < N; i++) {
        idx[3 * i] = 0;
        idx[3 * i + 1] = (uint32_t)(i + 1);
        idx[3 * i + 2] = (uint32_t)(i + 2);
    }
    sl_raster *r = test_make_raster(2, 16, true, false);
    count_target c;
    ct_init(&c, W, H);
    draw(r, &c, &prog_window, &u, pos, NULL, N + 2, idx, N, SL_CULL_BACK);
    sl_raster_stats st = sl_raster_get_stats(r);
    assert_int_equal(st.triangles_clipped, N); /* every sliver left the guard band */
    int bad = 0;
    for (int i = 0; i < W * H; i++)
        bad += c.count[i] != 1;
    if (bad) {
        print_error("slivers: %d pixels not covered exactly once\n", bad);
        ct_dump(&c);
    }
    assert_int_equal(bad, 0);
    ct_free(&c);
    sl_raster_destroy(r);
    free(pos);
    free(idx);
}

/* ---- bad geometry ---- */

/* NaN and Inf positions, a repeated vertex, collinear vertices: dropped at setup; the
 * good triangles beside them draw exactly as they do alone. An index out of range is an
 * error, not a crash. */
static void test_bad_geometry(void **state)
{
    (void)state;
    window_uniforms u = {32, 32};
    const vec3 p[] = {{2, 2, 0}, {30, 3, 0}, {5, 29, 0}, {NAN, 4, 0}, {4, INFINITY, 0}, {-INFINITY, 3, 0},
                      {10, 10, 0}, {20, 20, 0}, {30, 30, 0}};
    const uint32_t all[] = {0, 3, 1, 4, 0, 2, 0, 1, 2, 5, 1, 2, 6, 7, 8, 0, 0, 1, 3, 4, 5};
    sl_raster *r = test_make_raster(2, 16, true, false);
    count_target alone, mixed;
    ct_init(&alone, 32, 32);
    ct_init(&mixed, 32, 32);
    draw(r, &alone, &prog_window, &u, p, NULL, 9, (const uint32_t[]){0, 1, 2}, 1, SL_CULL_NONE);
    sl_raster_reset_stats(r);
    draw(r, &mixed, &prog_window, &u, p, NULL, 9, all, 7, SL_CULL_NONE);
    sl_raster_stats st = sl_raster_get_stats(r);
    assert_int_equal(memcmp(alone.count, mixed.count, 32 * 32 * sizeof(uint32_t)), 0);
    assert_int_equal(st.triangles_in, 7);
    assert_int_equal(st.triangles_binned, 1);
    assert_int_equal(st.triangles_dropped + st.triangles_culled, 6);

    const vec3 nan3[] = {{NAN, NAN, NAN}, {NAN, 0, 0}, {0, NAN, 0}};
    draw(r, &mixed, &prog_window, &u, nan3, NULL, 3, (const uint32_t[]){0, 1, 2}, 1, SL_CULL_NONE);
    assert_int_equal(memcmp(alone.count, mixed.count, 32 * 32 * sizeof(uint32_t)), 0);

    sl_mesh m = {.vertex_count = 3, .triangle_count = 1, .positions = (vec3 *)p, .indices = (uint32_t[]){0, 1, 7}};
    sl_error err = {0};
    const sl_draw dw = {.program = &prog_window, .vs_uniforms = &u, .fs_uniforms = &u, .mesh = &m};
    assert_false(sl_raster_draw(r, &mixed.target, &dw, &err));
    assert_non_null(strstr(err.msg, "index 2"));
    sl_target bad_target = mixed.target;
    bad_target.depth_offset = 2;
    m.indices = (uint32_t[]){0, 1, 2};
    assert_false(sl_raster_draw(r, &bad_target, &dw, &err));
    assert_null(sl_raster_create(&(sl_raster_desc){.tile_size = 48}, &err));
    ct_free(&alone);
    ct_free(&mixed);
    sl_raster_destroy(r);
}

/* NaN varyings are bad geometry too: no NaN reaches a fragment shader. */
static void vs_nan_varying(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    vs_window(uniforms, in, clip, varyings);
    varyings[0] = in->index == 1 ? NAN : 1.0f;
}

static void test_bad_varyings(void **state)
{
    (void)state;
    window_uniforms u = {16, 16};
    sl_raster *r = test_make_raster(1, 16, false, false);
    count_target c;
    ct_init(&c, 16, 16);
    sl_program p = {.vertex = vs_nan_varying, .fragment = fs_count, .varying_count = 1};
    const vec3 v[] = {{0, 0, 0}, {16, 0, 0}, {0, 16, 0}, {16, 16, 0}};
    draw(r, &c, &p, &u, v, NULL, 4, (const uint32_t[]){0, 1, 2, 0, 3, 2}, 2, SL_CULL_NONE);
    /* only the second triangle (no vertex 1) draws: pixels strictly above the diagonal x = y */
    int bad = 0;
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 16; x++)
            bad += ct_at(&c, x, y) != (x < y ? 1u : 0u);
    assert_int_equal(bad, 0);
    ct_free(&c);
    sl_raster_destroy(r);
}

/* ---- stats ---- */

static void test_stats(void **state)
{
    (void)state;
    window_uniforms u = {64, 64};
    const vec3 p[] = {{0, 0, 0}, {64, 0, 0}, {64, 64, 0}, {0, 64, 0}};
    const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
    count_target c;
    ct_init(&c, 64, 64);
    sl_raster *r = test_make_raster(2, 16, true, false);
    draw(r, &c, &prog_window, &u, p, NULL, 4, idx, 2, SL_CULL_BACK);
    sl_raster_stats st = sl_raster_get_stats(r);
    assert_int_equal(st.triangles_in, 2);
    assert_int_equal(st.triangles_binned, 2);
    assert_int_equal(st.fragments_shaded, 64 * 64);
    assert_int_equal(st.fragments_tested, 64 * 64);
    /* 16 tiles of 16x16; the diagonal crosses the 4 on it, each other tile is inside one triangle */
    assert_int_equal(st.bin_entries, 12 + 2 * 4);
    assert_int_equal(st.tiles_full, 12);
    sl_raster_destroy(r);
    r = test_make_raster(2, 16, false, false);
    draw(r, &c, &prog_window, &u, p, NULL, 4, idx, 2, SL_CULL_BACK);
    st = sl_raster_get_stats(r);
    assert_int_equal(st.triangles_in + st.fragments_shaded + st.bin_entries, 0);
    for (int i = 0; i < 64 * 64; i++)
        assert_int_equal(c.count[i], 2);
    ct_free(&c);
    sl_raster_destroy(r);
}

/* Many small draws: two parallel regions per draw (the index check and the vertex stage)
 * would spend a scene of many tiny objects in forks and barriers (300,000 boxes: 32 s with 2
 * threads against 1.3 s with one on a loaded machine). A list opens a few regions whatever its
 * number of draws, a small draw none but the tile pass; and the result is
 * the same as drawing one by one, with any thread count, on either path. */
static void test_many_small_draws(void **state)
{
    (void)state;
    enum { N = 3000, S = 64 };
    window_uniforms u = {S, S};
    /* N one-triangle draws: triangle i covers a 4x4 corner of cell i % 256 of a 16x16 grid */
    vec3 *pos = malloc(3 * N * sizeof *pos);
    uint32_t *idx = malloc(3 * N * sizeof *idx);
    sl_mesh *meshes = calloc(N, sizeof *meshes);
    sl_draw *draws = calloc(N, sizeof *draws);
    assert_true(pos && idx && meshes && draws);
    for (int i = 0; i < N; i++) {
        float x = (float)(4 * (i % 16)), y = (float)(4 * ((i / 16) % 16));
        pos[3 * i] = vec3(x, y, 0);
        pos[3 * i + 1] = vec3(x + 4, y, 0);
        pos[3 * i + 2] = vec3(x, y + 4, 0);
        for (int k = 0; k < 3; k++)
            idx[3 * i + k] = (uint32_t)k;
        meshes[i] = (sl_mesh){.vertex_count = 3, .triangle_count = 1, .positions = pos + 3 * i, .indices = idx + 3 * i};
        draws[i] = (sl_draw){.program = &prog_window, .vs_uniforms = &u, .mesh = &meshes[i]};
    }
    count_target ref, c;
    ct_init(&ref, S, S);
    ct_init(&c, S, S);
    sl_target tref = {.width = S, .height = S, .texel_size = sizeof(uint32_t), .texels = ref.count, .depth_offset = SL_NO_DEPTH}, tc = tref;
    tc.texels = c.count;
    sl_error err = {0};
    sl_raster *r = test_make_raster(1, 16, false, false);
    for (int i = 0; i < N; i++)
        assert_true(sl_raster_draw(r, &tref, &draws[i], &err));
    sl_raster_destroy(r);
    for (int plain = 0; plain < 2; plain++) {
        for (int threads = 4; threads >= 1; threads /= 2) {
            memset(c.count, 0, (size_t)S * S * sizeof *c.count);
            r = sl_raster_create(&(sl_raster_desc){.threads = threads, .tile_size = 16, .stats = true,
                                                   .plain = plain},
                                 &err);
            assert_non_null(r);
            assert_true(sl_raster_draw_list(r, &tc, draws, N, &err));
            sl_raster_stats st = sl_raster_get_stats(r);
            assert_same_texels(ref.count, c.count, (size_t)S * S, sizeof(uint32_t), S,
                               "%d draws as a list, %d threads, plain %d, against one by one", N, threads, plain);
            assert_int_equal(st.triangles_in, N);
            /* the index check, the vertex stage, setup and the tile pass: one each */
            if (threads == 2 && plain == 0)
                printf("%d draws as a list, 2 threads: %lld parallel regions\n", N, st.parallel_regions);
            if (threads > 1 && st.parallel_regions > 4) {
                print_error("%d draws opened %lld parallel regions (at most 4)\n", N, st.parallel_regions);
                fail();
            }
            /* one small draw: only its tile pass is parallel */
            sl_raster_reset_stats(r);
            assert_true(sl_raster_draw(r, &tc, &draws[0], &err));
            st = sl_raster_get_stats(r);
            assert_true(st.parallel_regions <= 1);
            sl_raster_destroy(r);
        }
    }
    /* a bad index in draw 1234 is still named, with the last bad index of that draw */
    uint32_t bad[3] = {7, 1, 9};
    meshes[1234].indices = bad;
    meshes[2000].indices = bad;
    r = test_make_raster(2, 16, false, false);
    assert_false(sl_raster_draw_list(r, &tc, draws, N, &err));
    assert_non_null(strstr(err.msg, "draw 1234: raster: index 2 is 9, mesh has 3 vertices"));
    sl_raster_destroy(r);
    ct_free(&ref);
    ct_free(&c);
    free(pos);
    free(idx);
    free(meshes);
    free(draws);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fill_rule),         cmocka_unit_test(test_subpixel),
        cmocka_unit_test(test_watertight_grid),   cmocka_unit_test(test_watertight_fan),
        cmocka_unit_test(test_watertight_sphere), cmocka_unit_test(test_clip_near),
        cmocka_unit_test(test_clip_behind),       cmocka_unit_test(test_clip_enormous),
        cmocka_unit_test(test_clip_slivers),      cmocka_unit_test(test_clip_watertight),      cmocka_unit_test(test_bad_geometry),
        cmocka_unit_test(test_bad_varyings),      cmocka_unit_test(test_stats),
        cmocka_unit_test(test_many_small_draws),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
