/* test_raster_span.c - the tile stage's two paths and its fused clear (src/raster/tile.c).
 *
 * The span path (default) must leave every texel exactly as the plain per-pixel path
 * (sl_raster_desc.plain) does: for the built-in G-buffer pair (its span shader against
 * sl_gbuffer_frag), for a program without a span shader (the per-fragment adapter), with
 * depth on and off, for several thread counts and tile sizes. The clear (sl_draw.clear)
 * must give what clearing every texel first and then drawing gives, also when a draw has
 * no triangles and when it has more than one batch (the clear belongs to the first only).
 * Programs that take derivatives (2x2 quads) or discard keep the two paths equal too, and a
 * quad form (sl_program.fragment_quad, run on the span path) gives the generic rounds' bits. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raster/raster.h"
#include "raster/raster.h"
#include "scene/camera.h"
#include "testutil.h"

/* ---- meshes ---- */

/* A UV sphere (radius 1) with smooth normals: curved, many small triangles. */
static sl_mesh make_sphere(int slices, int stacks)
{
    sl_mesh m = {0};
    m.vertex_count = (slices + 1) * (stacks + 1);
    m.triangle_count = 2 * slices * stacks;
    m.positions = malloc((size_t)m.vertex_count * sizeof(vec3));
    m.normals = malloc((size_t)m.vertex_count * sizeof(vec3));
    m.indices = malloc((size_t)m.triangle_count * 3 * sizeof(uint32_t));
    assert_non_null(m.positions);
    assert_non_null(m.normals);
    assert_non_null(m.indices);
    for (int j = 0; j <= stacks; j++)
        for (int i = 0; i <= slices; i++) {
            double th = 3.14159265358979 * j / stacks, ph = 2.0 * 3.14159265358979 * i / slices;
            vec3 p = vec3(sin(th) * cos(ph), sin(th) * sin(ph), cos(th));
            m.positions[j * (slices + 1) + i] = p;
            m.normals[j * (slices + 1) + i] = p;
        }
    uint32_t *t = m.indices;
    for (int j = 0; j < stacks; j++)
        for (int i = 0; i < slices; i++) {
            uint32_t a = (uint32_t)(j * (slices + 1) + i), b = a + 1;
            uint32_t c = a + (uint32_t)(slices + 1), d = c + 1;
            *t++ = a, *t++ = c, *t++ = d;
            *t++ = a, *t++ = d, *t++ = b;
        }
    return m;
}

/* An n x n grid of quads over [-1,1]^2 at z = 0 with normal +Z: 2 n^2 triangles. */
static sl_mesh make_grid(int n)
{
    sl_mesh m = {0};
    m.vertex_count = (n + 1) * (n + 1);
    m.triangle_count = 2 * n * n;
    m.positions = malloc((size_t)m.vertex_count * sizeof(vec3));
    m.normals = malloc((size_t)m.vertex_count * sizeof(vec3));
    m.indices = malloc((size_t)m.triangle_count * 3 * sizeof(uint32_t));
    assert_non_null(m.positions);
    assert_non_null(m.normals);
    assert_non_null(m.indices);
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            m.positions[j * (n + 1) + i] =
                vec3(2.0f * (float)i / (float)n - 1.0f, 2.0f * (float)j / (float)n - 1.0f, 0);
            m.normals[j * (n + 1) + i] = vec3(0, 0, 1);
        }
    uint32_t *t = m.indices;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t a = (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)(n + 1), d = c + 1;
            *t++ = a, *t++ = b, *t++ = d;
            *t++ = a, *t++ = d, *t++ = c;
        }
    return m;
}

static void free_mesh(sl_mesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->indices);
}

/* Ground plane through the near plane (clipped), two overlapping spheres, a grid seen
 * edge-on-ish: big full tiles, partial blocks, slivers and overdraw in one frame. */
typedef struct {
    sl_mesh meshes[2]; /* sphere, grid */
    sl_material mats[2];
    sl_object objects[4];
    sl_scene scene;
    sl_camera cam;
} test_scene;

static void scene_init(test_scene *s)
{
    s->meshes[0] = make_sphere(40, 20);
    s->meshes[1] = make_grid(6);
    s->mats[0] = (sl_material){.name = "a", .kd = {0.8f, 0.2f, 0.1f}, .ks = {0.04f, 0.05f, 0.06f}, .alpha = 20.0f};
    s->mats[1] = (sl_material){.name = "b", .kd = {0.1f, 0.7f, 0.3f}, .ks = {0.9f, 0.8f, 0.7f}, .alpha = 500.0f};
    s->objects[0] = (sl_object){"ground", 1, 1, mat4_mul(mat4_translate(vec3(0, 0, -1)), mat4_scale(vec3(30, 30, 1)))};
    s->objects[1] = (sl_object){"s1", 0, 0, mat4_translate(vec3(-0.6f, 0.3f, 0))};
    s->objects[2] =
        (sl_object){"s2", 0, 1, mat4_mul(mat4_translate(vec3(0.5f, 0, 0.2f)), mat4_scale(vec3(1.2f, 0.7f, 1)))};
    s->objects[3] =
        (sl_object){"tilted", 1, 0, mat4_mul(mat4_translate(vec3(0, 2, 0)), mat4_rotate(vec3(1, 0, 0), 1.3f))};
    s->scene = (sl_scene){.meshes = s->meshes, .mesh_count = 2, .materials = s->mats, .material_count = 2,
                          .objects = s->objects, .object_count = 4};
    s->cam = (sl_camera){.eye = {0.3f, -4, 1.2f}, .target = {0, 0, -0.2f}, .up = {0, 0, 1}, .fovy_deg = 60,
                         .znear = 0.5f, .zfar = 40};
}

static void scene_free(test_scene *s)
{
    free_mesh(&s->meshes[0]);
    free_mesh(&s->meshes[1]);
}

/* ---- the built-in pair ---- */

/* sl_raster_scene through the span path and through the plain path: the same bits, for
 * several thread counts and tile sizes; and the fragment counters agree. */
static void test_gbuffer_span_vs_plain(void **state)
{
    (void)state;
    enum { W = 203, H = 157 };
    test_scene s;
    scene_init(&s);
    sl_error err = {0};
    sl_gbuffer ref = {0}, gb = {0};
    assert_true(sl_gbuffer_resize(&gb, W, H, &err));
    sl_raster_desc plain = {.threads = 1, .tile_size = 64, .stats = true, .plain = true};
    sl_raster_stats ps = test_raster_scene(&plain, &s.scene, &s.cam, W, H, &ref);
    size_t covered = 0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        covered += sl_gbuffer_covered(&ref.texels[i]);
    /* the ground fills the lower part, the sky the upper: both kinds of pixel are there */
    assert_true(covered > (size_t)W * H / 4 && covered < (size_t)W * H * 9 / 10);
    assert_true(ps.fragments_shaded > (long long)covered); /* overdraw happened */

    const int configs[][2] = {{1, 64}, {2, 16}, {2, 32}, {3, 128}, {1, 256}};
    for (int k = 0; k < 5; k++) {
        memset(gb.texels, 0xA5, (size_t)W * H * sizeof *gb.texels); /* the clear must overwrite this */
        sl_raster_desc desc = {.threads = configs[k][0], .tile_size = configs[k][1], .stats = true};
        sl_raster_stats st = test_raster_scene(&desc, &s.scene, &s.cam, W, H, &gb);
        assert_same_texels(ref.texels, gb.texels, (size_t)W * H, sizeof *gb.texels, W,
                           "threads %d, tile %d: span path against plain path", configs[k][0], configs[k][1]);
        assert_int_equal(st.fragments_tested, ps.fragments_tested);
        assert_int_equal(st.fragments_shaded, ps.fragments_shaded);
    }
    sl_gbuffer_free(&ref);
    sl_gbuffer_free(&gb);
    scene_free(&s);
}

/* Small triangles (bounds at most 8 x 8 in a tile: tile.c small_tri_spans, which packs a
 * triangle's rows into one set and runs its loops 8 columns wide, past the bounds, up to 7 floats
 * past the tile's depth plane): a dense sphere filling an odd-sized target, so that small
 * triangles lie on every tile border and at the target's last row and column. Span path and
 * plain path give the same bits, and the frame is what the path is for: most triangles small. */
static void test_small_triangles_span_vs_plain(void **state)
{
    (void)state;
    enum { W = 97, H = 61 };
    sl_mesh sphere = make_sphere(96, 48);
    sl_material mat = {.name = "m", .kd = {0.5f, 0.4f, 0.3f}, .ks = {0.1f, 0.2f, 0.3f}, .alpha = 40.0f};
    sl_object obj = {"sphere", 0, 0, mat4_scale(vec3(2.4f, 1.0f, 1.6f))};
    sl_scene scene = {.meshes = &sphere, .mesh_count = 1, .materials = &mat, .material_count = 1,
                      .objects = &obj, .object_count = 1};
    sl_camera cam = {.eye = {0, -2.2f, 0.2f}, .target = {0, 0, 0}, .up = {0, 0, 1}, .fovy_deg = 50,
                     .znear = 0.5f, .zfar = 10};
    sl_error err = {0};
    sl_gbuffer ref = {0}, gb = {0};
    assert_true(sl_gbuffer_resize(&gb, W, H, &err));
    sl_raster_desc plain = {.threads = 1, .tile_size = 64, .stats = true, .plain = true};
    sl_raster_stats ps = test_raster_scene(&plain, &scene, &cam, W, H, &ref);
    /* of 9216 triangles (both faces drawn), about 2400 in view, 5 pixels tested each */
    assert_true(ps.triangles_binned > 2000);
    assert_true(ps.fragments_tested < 8 * ps.triangles_binned);
    assert_true(sl_gbuffer_covered(&ref.texels[0]) && sl_gbuffer_covered(&ref.texels[(size_t)W * H - 1]));
    const int configs[][2] = {{1, 16}, {2, 16}, {1, 32}, {2, 64}};
    for (int k = 0; k < 4; k++) {
        memset(gb.texels, 0xA5, (size_t)W * H * sizeof *gb.texels);
        sl_raster_desc desc = {.threads = configs[k][0], .tile_size = configs[k][1], .stats = true};
        sl_raster_stats st = test_raster_scene(&desc, &scene, &cam, W, H, &gb);
        assert_same_texels(ref.texels, gb.texels, (size_t)W * H, sizeof *gb.texels, W,
                           "threads %d, tile %d: small triangles, span path against plain path", configs[k][0],
                           configs[k][1]);
        assert_int_equal(st.fragments_tested, ps.fragments_tested);
        assert_int_equal(st.fragments_shaded, ps.fragments_shaded);
    }
    sl_gbuffer_free(&ref);
    sl_gbuffer_free(&gb);
    free_mesh(&sphere);
}

/* The span shader against the per-pixel shader on chosen inputs: ordinary normals, a
 * zero normal and one too short to normalize (+Z, as sl_gbuffer_frag), large and tiny
 * magnitudes, a span with gaps in its columns and a texel stride larger than the texel. */
static void test_gbuffer_span_shader(void **state)
{
    (void)state;
    enum { N = 37, STRIDE = 64 };
    sl_gbuffer_uniforms u;
    sl_material m = {.name = "m", .kd = {0.25f, 0.5f, 0.75f}, .ks = {0.1f, 0.2f, 0.3f}, .alpha = 42.0f};
    sl_gbuffer_uniforms_init(&u, mat4_identity(), mat4_identity(), &m);
    static float vary[SL_GBUFFER_VARYINGS][SL_SPAN_MAX];
    static float z[SL_SPAN_MAX], iw[SL_SPAN_MAX];
    static int32_t xs[SL_SPAN_MAX];
    unsigned seed = 12345;
    for (int j = 0; j < N; j++) {
        for (int i = 0; i < SL_GBUFFER_VARYINGS; i++) {
            seed = seed * 1664525u + 1013904223u;
            vary[i][j] = ((float)(seed >> 8) / 16777216.0f - 0.5f) * 8.0f;
        }
        z[j] = (float)j / (float)N;
        iw[j] = 1.0f / (1.0f + (float)j);
        xs[j] = 3 * j + (j % 2);
    }
    vary[3][5] = vary[4][5] = vary[5][5] = 0.0f;            /* zero normal */
    vary[3][6] = 1e-16f, vary[4][6] = 0, vary[5][6] = 0;     /* d = 1e-32 < 1e-30: too short */
    vary[3][7] = 2e-15f, vary[4][7] = 0, vary[5][7] = 0;     /* d = 4e-30: normalized */
    vary[3][8] = 3e18f, vary[4][8] = -1e18f, vary[5][8] = 2; /* large */
    size_t bytes = (size_t)(3 * N + 2) * STRIDE;
    char *a = malloc(bytes), *b = malloc(bytes);
    assert_non_null(a);
    assert_non_null(b);
    memset(a, 0x5A, bytes);
    memset(b, 0x5A, bytes);
    sl_fragment_span span = {.n = N, .y = 4, .x = xs, .frag_z = z, .frag_w = iw, .front_facing = true,
                             .row = a, .texel_size = STRIDE};
    for (int i = 0; i < SL_GBUFFER_VARYINGS; i++)
        span.varyings[i] = vary[i];
    sl_gbuffer_frag_span(&u, &span);
    for (int j = 0; j < N; j++) {
        float v[SL_GBUFFER_VARYINGS];
        for (int i = 0; i < SL_GBUFFER_VARYINGS; i++)
            v[i] = vary[i][j];
        sl_fragment_in in = {.varyings = v, .frag_coord = vec4((float)xs[j] + 0.5f, 4.5f, z[j], iw[j]),
                             .front_facing = true, .x = xs[j], .y = 4};
        sl_gbuffer_frag(&u, &in, b + (size_t)xs[j] * STRIDE);
    }
    assert_same_texels(a, b, (size_t)(3 * N + 2), STRIDE, 0, "span shader against sl_gbuffer_frag (stride %d)",
                       STRIDE);
    const sl_gbuffer_texel *t5 = (const sl_gbuffer_texel *)(a + (size_t)xs[5] * STRIDE);
    const sl_gbuffer_texel *t6 = (const sl_gbuffer_texel *)(a + (size_t)xs[6] * STRIDE);
    const sl_gbuffer_texel *t7 = (const sl_gbuffer_texel *)(a + (size_t)xs[7] * STRIDE);
    assert_true(t5->normal.x == 0 && t5->normal.y == 0 && t5->normal.z == 1);
    assert_true(t6->normal.x == 0 && t6->normal.y == 0 && t6->normal.z == 1);
    assert_near(t7->normal.x, 1.0, 1e-6);
    assert_true(t5->alpha == 42.0f && t5->kd.y == 0.5f && t5->ks.z == 0.3f && t5->depth == z[5]);
    free(a);
    free(b);
}

/* ---- a program without a span shader ---- */

/* Everything a fragment shader sees, stored, so that the two paths can be compared on
 * their inputs (not just on what one shader makes of them). */
typedef struct {
    float vary[5];
    vec4 frag_coord;
    int32_t x, y, front, count;
    float depth;
} probe_texel;

typedef struct {
    mat4 mvp;
} probe_uniforms;

static void vs_probe(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *v)
{
    const probe_uniforms *u = uniforms;
    *clip = mat4_mul_vec4(u->mvp, vec4_from3(in->position, 1.0f));
    v[0] = in->position.x;
    v[1] = in->position.y * 3.0f;
    v[2] = in->position.z - 1.0f;
    v[3] = (float)in->index;
    v[4] = in->normal.x + in->normal.y;
}

static void fs_probe(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    (void)uniforms;
    probe_texel *t = texel;
    memcpy(t->vary, in->varyings, sizeof t->vary);
    t->frag_coord = in->frag_coord;
    t->x = in->x;
    t->y = in->y;
    t->front = in->front_facing;
    t->count++;
    t->depth = in->frag_coord.z;
}

static const sl_program prog_probe = {.vertex = vs_probe, .fragment = fs_probe, .varying_count = 5};

/* Draw the sphere and the grid (perspective, both faces, overlapping) into a probe target. */
static void draw_probe(sl_raster *r, probe_texel *texels, int w, int h, bool depth, const probe_texel *clear)
{
    sl_mesh sphere = make_sphere(24, 12), grid = make_grid(5);
    mat4 proj = perspective(radians(50.0f), (float)w / (float)h, 0.5f, 20.0f);
    mat4 view = lookAt(vec3(0.4f, -3.5f, 1.0f), vec3(0, 0, 0), vec3(0, 0, 1));
    probe_uniforms u1 = {mat4_mul(mat4_mul(proj, view), mat4_scale(vec3(1.3f, 1.3f, 1.3f)))};
    probe_uniforms u2 = {mat4_mul(mat4_mul(proj, view), mat4_rotate(vec3(1, 0.2f, 0), 1.1f))};
    sl_target target = {.width = w, .height = h, .texel_size = sizeof(probe_texel), .texels = texels, .depth_offset = depth ? (long)offsetof(probe_texel, depth) : SL_NO_DEPTH};
    sl_error err = {0};
    assert_true(sl_raster_draw(r, &target,
                               &(sl_draw){.program = &prog_probe, .vs_uniforms = &u1, .mesh = &sphere, .clear = clear},
                               &err));
    assert_true(
        sl_raster_draw(r, &target, &(sl_draw){.program = &prog_probe, .vs_uniforms = &u2, .mesh = &grid}, &err));
    free_mesh(&sphere);
    free_mesh(&grid);
}

static void test_generic_span_vs_plain(void **state)
{
    (void)state;
    enum { W = 150, H = 111 };
    size_t n = (size_t)W * H;
    probe_texel *ref = malloc(n * sizeof *ref), *out = malloc(n * sizeof *out);
    assert_non_null(ref);
    assert_non_null(out);
    probe_texel clear = {.depth = 1.0f};
    for (int depth = 0; depth < 2; depth++) {
        memset(ref, 0, n * sizeof *ref);
        for (size_t i = 0; i < n; i++)
            ref[i].depth = 1.0f;
        sl_raster *plain = test_make_raster(1, 32, true, true);
        draw_probe(plain, ref, W, H, depth, NULL);
        sl_raster_stats ps = sl_raster_get_stats(plain);
        sl_raster_destroy(plain);
        long long shaded = 0;
        for (size_t i = 0; i < n; i++)
            shaded += ref[i].count;
        assert_int_equal(shaded, ps.fragments_shaded); /* every shaded fragment counted once */
        if (!depth)
            assert_true(ps.fragments_shaded > ps.fragments_tested / 2 && ps.fragments_shaded == ps.fragments_tested);
        const int configs[][2] = {{1, 16}, {2, 64}, {3, 256}};
        for (int k = 0; k < 3; k++) {
            /* the span path, cleared by the first draw from garbage */
            memset(out, 0xC3, n * sizeof *out);
            sl_raster *r = test_make_raster(configs[k][0], configs[k][1], true, false);
            draw_probe(r, out, W, H, depth, &clear);
            sl_raster_stats st = sl_raster_get_stats(r);
            sl_raster_destroy(r);
            assert_same_texels(ref, out, n, sizeof *out, W,
                               "depth %d, threads %d, tile %d: span path against plain path", depth, configs[k][0],
                               configs[k][1]);
            assert_int_equal(st.fragments_shaded, ps.fragments_shaded);
            assert_int_equal(st.fragments_tested, ps.fragments_tested);
        }
    }
    free(ref);
    free(out);
}

/* A second program on the same texels: two varyings, the rest zero. */
static void vs_probe2(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *v)
{
    const probe_uniforms *u = uniforms;
    *clip = mat4_mul_vec4(u->mvp, vec4_from3(in->position, 1.0f));
    v[0] = in->position.z * 7.0f;
    v[1] = (float)in->index * 0.5f;
}

static void fs_probe2(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    (void)uniforms;
    probe_texel *t = texel;
    memset(t->vary, 0, sizeof t->vary);
    memcpy(t->vary, in->varyings, 2 * sizeof(float));
    t->frag_coord = in->frag_coord;
    t->x = -in->x;
    t->y = in->y;
    t->front = in->front_facing;
    t->count += 10;
    t->depth = in->frag_coord.z;
}

static const sl_program prog_probe2 = {.vertex = vs_probe2, .fragment = fs_probe2, .varying_count = 2};

/* sl_raster_draw_list against the same draws one by one: two programs with different
 * varying counts, a draw without triangles, a clear in the middle of the list (it
 * starts over: what came before is cleared away), depth on; span and plain paths.
 * And an error in one draw of a list names that draw. */
static void test_draw_list(void **state)
{
    (void)state;
    enum { W = 130, H = 97 };
    size_t n = (size_t)W * H;
    probe_texel *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    assert_non_null(a);
    assert_non_null(b);
    sl_mesh sphere = make_sphere(24, 12), grid = make_grid(5);
    sl_mesh none = grid;
    none.triangle_count = 0;
    mat4 vp = mat4_mul(perspective(radians(50.0f), (float)W / (float)H, 0.5f, 20.0f),
                       lookAt(vec3(0.4f, -3.5f, 1.0f), vec3(0, 0, 0), vec3(0, 0, 1)));
    probe_uniforms u[4] = {{mat4_mul(vp, mat4_scale(vec3(1.3f, 1.3f, 1.3f)))},
                           {mat4_mul(vp, mat4_rotate(vec3(1, 0.2f, 0), 1.1f))},
                           {mat4_mul(vp, mat4_translate(vec3(0.5f, -1, 0.3f)))},
                           {mat4_mul(vp, mat4_scale(vec3(2, 2, 2)))}};
    const probe_texel clear = {.depth = 1.0f, .count = 1000};
    sl_draw draws[7] = {
        {.program = &prog_probe, .vs_uniforms = &u[3], .mesh = &grid, .clear = &clear},
        {.program = &prog_probe, .vs_uniforms = &u[0], .mesh = &sphere, .clear = &clear}, /* starts over */
        {.program = &prog_probe2, .vs_uniforms = &u[1], .mesh = &grid},
        {.program = &prog_probe, .vs_uniforms = &u[2], .mesh = &none},
        {.program = &prog_probe2, .vs_uniforms = &u[2], .mesh = &sphere},
        {.program = &prog_probe, .vs_uniforms = &u[3], .mesh = &sphere, .cull = SL_CULL_BACK},
        {.program = &prog_probe2, .vs_uniforms = &u[1], .mesh = &sphere},
    };
    sl_target ta = {.width = W, .height = H, .texel_size = sizeof *a, .texels = a, .depth_offset = (long)offsetof(probe_texel, depth)}, tb = ta;
    tb.texels = b;
    sl_error err = {0};
    for (int plain = 0; plain < 2; plain++) {
        memset(a, 0x3C, n * sizeof *a);
        memset(b, 0x3C, n * sizeof *b);
        sl_raster *r = test_make_raster(2, 32, true, plain);
        for (int i = 0; i < 7; i++)
            assert_true(sl_raster_draw(r, &ta, &draws[i], &err));
        sl_raster_stats one = sl_raster_get_stats(r);
        sl_raster_reset_stats(r);
        assert_true(sl_raster_draw_list(r, &tb, draws, 7, &err));
        sl_raster_stats list = sl_raster_get_stats(r);
        sl_raster_destroy(r);
        assert_same_texels(a, b, n, sizeof *a, W, "plain %d: the list against single draws", plain);
        assert_int_equal(list.fragments_shaded, one.fragments_shaded);
        assert_int_equal(list.triangles_in, one.triangles_in);
        assert_int_equal(list.triangles_culled, one.triangles_culled);
        assert_true(list.triangles_culled > 0);
        /* both programs won somewhere, and nothing of draw 0 survived the second clear */
        int by1 = 0, by2 = 0, cleared = 0;
        for (size_t i = 0; i < n; i++) {
            by1 += b[i].count > 1000 && b[i].x >= 0 && b[i].vary[3] != 0.0f;
            by2 += b[i].x < 0;
            cleared += b[i].count == 1000;
        }
        assert_true(by1 > 100 && by2 > 100 && cleared > 100);
    }
    /* a bad index in draw 2 */
    sl_mesh bad = grid;
    uint32_t idx[3] = {0, 1, 99};
    bad.indices = idx;
    bad.triangle_count = 1;
    draws[2].mesh = &bad;
    sl_raster *r = test_make_raster(1, 64, true, false);
    assert_false(sl_raster_draw_list(r, &tb, draws, 7, &err));
    assert_non_null(strstr(err.msg, "draw 2"));
    assert_non_null(strstr(err.msg, "index 2"));
    sl_raster_destroy(r);
    free_mesh(&sphere);
    free_mesh(&grid);
    free(a);
    free(b);
}

/* ---- quads and discard on both paths ---- */

/* The probe's inputs plus derivatives of a computed value and of one computed from a
 * derivative, discarding where the first derivative is large: helpers, rounds, discard
 * and late depth on perspective geometry. */
static void fs_quad_probe(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    float a = in->varyings[0] * in->varyings[1] + in->frag_coord.w;
    float da = dFdx(in, a);
    float b = floorf(log2f(fabsf(da) + 1.0f)) * in->varyings[2];
    vec2 db = vec2(dFdy(in, b), fwidth(in, b));
    if (fabsf(da) > 0.05f) {
        discard(in);
        return;
    }
    fs_probe(uniforms, in, texel);
    probe_texel *t = texel;
    t->vary[3] = da;
    t->vary[4] = db.x + db.y;
}

/* The same shader on one quad's four lanes: their values, then their differences (glsl.h);
 * discards[l] says which lanes discard (the caller marks them in its form's way). */
static void probe_quad_lanes(const void *uniforms, const sl_fragment_in in[4], void *const texel[4], bool discards[4])
{
    float a[4], da[4], b[4];
    for (int l = 0; l < 4; l++)
        a[l] = in[l].varyings[0] * in[l].varyings[1] + in[l].frag_coord.w;
    for (int l = 0; l < 4; l++) {
        da[l] = sl_quad_dfdx(a, l);
        b[l] = floorf(log2f(fabsf(da[l]) + 1.0f)) * in[l].varyings[2];
    }
    for (int l = 0; l < 4; l++) {
        float dy = sl_quad_dfdy(b, l), fw = fabsf(sl_quad_dfdx(b, l)) + fabsf(dy);
        discards[l] = fabsf(da[l]) > 0.05f;
        if (discards[l])
            continue;
        fs_probe(uniforms, &in[l], texel[l]);
        probe_texel *t = texel[l];
        t->vary[3] = da[l];
        t->vary[4] = dy + fw;
    }
}

/* The same shader in quad form. */
static void fs_quad_probe_q(const void *uniforms, const sl_fragment_in in[4], void *const texel[4])
{
    bool discards[4];
    probe_quad_lanes(uniforms, in, texel, discards);
    for (int l = 0; l < 4; l++)
        if (discards[l])
            discard(&in[l]);
}

/* The same shader in multi-quad form (sl_program.fragment_quads): each quad's lanes rebuilt as
 * sl_fragment_in from the structure of arrays (so fs_probe stores exactly the inputs the call
 * got), then probe_quad_lanes, discards marked in q->discarded. */
static void fs_quad_probe_m(const void *uniforms, const sl_fragment_quads *q)
{
    for (int k = 0; k < q->n; k++) {
        float vary[4][5];
        sl_fragment_in in[4];
        for (int l = 0; l < 4; l++) {
            int j = 4 * k + l, x = q->qx[k] + (l & 1), y = q->qy[k] + (l >> 1);
            for (int i = 0; i < 5; i++)
                vary[l][i] = q->varyings[i][j];
            in[l] = (sl_fragment_in){.varyings = vary[l],
                                     .frag_coord = vec4((float)x + 0.5f, (float)y + 0.5f, q->frag_z[j], q->frag_w[j]),
                                     .front_facing = q->front_facing,
                                     .x = x,
                                     .y = y,
                                     .lane = l,
                                     .helper = q->helper[j] != 0};
        }
        bool discards[4];
        probe_quad_lanes(uniforms, in, q->texel + 4 * k, discards);
        for (int l = 0; l < 4; l++)
            q->discarded[4 * k + l] = discards[l];
    }
}

/* A shader that writes every byte of its texel and reads none (quad_writes_texel), cannot
 * discard, takes no derivative: its multi-quad form writes live lanes in place. */
static void fs_probe_w(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    probe_texel *t = texel;
    t->count = 0;
    fs_probe(uniforms, in, texel);
}

static void fs_probe_w_m(const void *uniforms, const sl_fragment_quads *q)
{
    for (int j = 0; j < 4 * q->n; j++) {
        int x = q->qx[j >> 2] + (j & 1), y = q->qy[j >> 2] + ((j >> 1) & 1);
        float vary[5];
        for (int i = 0; i < 5; i++)
            vary[i] = q->varyings[i][j];
        sl_fragment_in in = {.varyings = vary,
                             .frag_coord = vec4((float)x + 0.5f, (float)y + 0.5f, q->frag_z[j], q->frag_w[j]),
                             .front_facing = q->front_facing,
                             .x = x,
                             .y = y};
        fs_probe_w(uniforms, &in, q->texel[j]);
    }
}

/* Every fourth pixel column discarded, no derivative. */
static void fs_probe_cut(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    if (in->x % 4 == 1) {
        discard(in);
        return;
    }
    fs_probe(uniforms, in, texel);
}

static const sl_program prog_quad = {.vertex = vs_probe, .fragment = fs_quad_probe, .varying_count = 5,
                                     .derivatives = true, .discards = true};
static const sl_program prog_quad_q = {.vertex = vs_probe, .fragment = fs_quad_probe, .varying_count = 5,
                                       .derivatives = true, .discards = true, .fragment_quad = fs_quad_probe_q};
static const sl_program prog_quad_m = {.vertex = vs_probe, .fragment = fs_quad_probe, .varying_count = 5,
                                       .derivatives = true, .discards = true, .fragment_quad = fs_quad_probe_q,
                                       .fragment_quads = fs_quad_probe_m};
static const sl_program prog_quad_m_fresh = {.vertex = vs_probe, .fragment = fs_probe_w, .varying_count = 5,
                                             .derivatives = true, .quad_writes_texel = true,
                                             .fragment_quads = fs_probe_w_m};
static const sl_program prog_cut = {.vertex = vs_probe, .fragment = fs_probe_cut, .varying_count = 5,
                                    .discards = true};

/* Sphere and grid (draw_probe's) with one program, span path against plain path, for
 * several thread counts and tile sizes, depth on and off; the quad form against the
 * generic rounds (the plain path always runs the rounds). */
static void test_quads_span_vs_plain(void **state)
{
    (void)state;
    enum { W = 150, H = 111 };
    size_t n = (size_t)W * H;
    probe_texel *ref = malloc(n * sizeof *ref), *out = malloc(n * sizeof *out);
    assert_non_null(ref);
    assert_non_null(out);
    const sl_program *progs[5] = {&prog_quad, &prog_quad_q, &prog_cut, &prog_quad_m, &prog_quad_m_fresh};
    for (int p = 0; p < 5; p++)
        for (int depth = 0; depth < 2; depth++) {
            sl_mesh sphere = make_sphere(24, 12), grid = make_grid(5), wall = make_grid(1);
            mat4 vp = mat4_mul(perspective(radians(50.0f), (float)W / (float)H, 0.5f, 20.0f),
                               lookAt(vec3(0.4f, -3.5f, 1.0f), vec3(0, 0, 0), vec3(0, 0, 1)));
            probe_uniforms u1 = {mat4_mul(vp, mat4_scale(vec3(1.3f, 1.3f, 1.3f)))};
            probe_uniforms u2 = {mat4_mul(vp, mat4_rotate(vec3(1, 0.2f, 0), 1.1f))};
            /* a wall behind them, two triangles over most of the target: bin items that cover
             * whole tiles (setup.c's full flag), drawn without edge tests */
            probe_uniforms u3 = {mat4_mul(vp, mat4_mul(mat4_translate(vec3(0, 2.5f, 0)),
                                                       mat4_mul(mat4_rotate(vec3(1, 0, 0), radians(-90.0f)),
                                                                mat4_scale(vec3(5, 5, 5)))))};
            sl_draw draws[3] = {{.program = progs[p], .vs_uniforms = &u1, .mesh = &sphere},
                                {.program = progs[p], .vs_uniforms = &u2, .mesh = &grid},
                                {.program = progs[p], .vs_uniforms = &u3, .mesh = &wall}};
            sl_target target = {.width = W, .height = H, .texel_size = sizeof(probe_texel), .texels = ref, .depth_offset = depth ? (long)offsetof(probe_texel, depth) : SL_NO_DEPTH};
            sl_error err = {0};
            memset(ref, 0, n * sizeof *ref);
            for (size_t i = 0; i < n; i++)
                ref[i].depth = 1.0f;
            sl_raster *r = test_make_raster(1, 32, true, true);
            assert_true(sl_raster_draw_list(r, &target, draws, 3, &err));
            sl_raster_stats ps = sl_raster_get_stats(r);
            sl_raster_destroy(r);
            if (p != 4)
                assert_true(ps.fragments_discarded > 100 && ps.fragments_shaded > ps.fragments_discarded + 1000);
            if (p != 2 && p != 4)
                assert_true(ps.helper_invocations > 100 && ps.quad_rounds >= 2 * ps.quads);
            const int configs[][2] = {{1, 16}, {2, 64}, {3, 256}};
            for (int k = 0; k < 3; k++) {
                memset(out, 0, n * sizeof *out);
                for (size_t i = 0; i < n; i++)
                    out[i].depth = 1.0f;
                target.texels = out;
                r = test_make_raster(configs[k][0], configs[k][1], true, false);
                assert_true(sl_raster_draw_list(r, &target, draws, 3, &err));
                sl_raster_stats st = sl_raster_get_stats(r);
                sl_raster_destroy(r);
                target.texels = ref;
                assert_same_texels(ref, out, n, sizeof *out, W, "program %d, depth %d, threads %d, tile %d: span path "
                                   "against plain path", p, depth, configs[k][0], configs[k][1]);
                assert_int_equal(st.fragments_shaded, ps.fragments_shaded);
                assert_int_equal(st.fragments_discarded, ps.fragments_discarded);
                assert_int_equal(st.fragments_late_z, ps.fragments_late_z);
                assert_int_equal(st.helper_invocations, ps.helper_invocations);
                if (p == 1 || p >= 3) /* the quad and multi-quad forms: one round a quad */
                    assert_int_equal(st.quad_rounds, st.quads);
                assert_int_equal(st.quads, ps.quads);
                if (configs[k][1] == 16) /* the wall covers whole 16x16 tiles (32: 12 of them) */
                    assert_true(st.tiles_full > 0);
            }
            free_mesh(&sphere);
            free_mesh(&grid);
            free_mesh(&wall);
        }
    free(ref);
    free(out);
}

/* ---- the fill rule on the span path ---- */

static void vs_window64(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *v)
{
    (void)uniforms;
    (void)v;
    *clip = vec4(in->position.x / 32.0f - 1.0f, in->position.y / 32.0f - 1.0f, 0.0f, 1.0f);
}

static void fs_inc(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    (void)uniforms;
    (void)in;
    (*(uint32_t *)texel)++;
}

/* Triangles whose edges run exactly through pixel centres (horizontal, vertical and
 * diagonal), wide enough for the span path: a fan of 8 around (32.5, 32.5) over the
 * square of centres [2.5, 62.5]^2 (window coordinates, a 64x64 target: exact). Shared
 * edges are drawn once (watertight), and the square's own edges follow the top-left
 * rule: its left and bottom columns are in, its right and top are out (llvmpipe's rule
 * on GL's y-up rows: the horizontal edge with the interior above it is in). The same
 * counts on the plain path, for several tile sizes. */
static void test_span_fill_rule(void **state)
{
    (void)state;
    const vec3 p[9] = {{32.5f, 32.5f, 0}, {2.5f, 2.5f, 0},   {32.5f, 2.5f, 0},  {62.5f, 2.5f, 0}, {62.5f, 32.5f, 0},
                       {62.5f, 62.5f, 0}, {32.5f, 62.5f, 0}, {2.5f, 62.5f, 0},  {2.5f, 32.5f, 0}};
    uint32_t idx[24];
    for (int k = 0; k < 8; k++) {
        idx[3 * k] = 0;
        idx[3 * k + 1] = (uint32_t)(1 + k);
        idx[3 * k + 2] = (uint32_t)(1 + (k + 1) % 8);
    }
    sl_mesh m = {.vertex_count = 9, .triangle_count = 8, .positions = (vec3 *)p, .indices = idx};
    const sl_program prog = {.vertex = vs_window64, .fragment = fs_inc, .varying_count = 0};
    static uint32_t ref[64 * 64], out[64 * 64];
    sl_error err = {0};
    memset(ref, 0, sizeof ref);
    sl_raster *r = test_make_raster(1, 16, true, true);
    assert_true(sl_raster_draw(r, &(sl_target){.width = 64, .height = 64, .texel_size = sizeof(uint32_t), .texels = ref, .depth_offset = SL_NO_DEPTH},
                               &(sl_draw){.program = &prog, .mesh = &m}, &err));
    sl_raster_destroy(r);
    int bad = 0;
    for (int y = 0; y < 64; y++)
        for (int x = 0; x < 64; x++)
            bad += ref[y * 64 + x] != (x >= 2 && x < 62 && y >= 2 && y < 62 ? 1u : 0u);
    assert_int_equal(bad, 0);
    const int tiles[] = {16, 32, 64};
    for (int k = 0; k < 3; k++) {
        memset(out, 0, sizeof out);
        r = test_make_raster(2, tiles[k], true, false);
        assert_true(sl_raster_draw(r, &(sl_target){.width = 64, .height = 64, .texel_size = sizeof(uint32_t), .texels = out, .depth_offset = SL_NO_DEPTH},
                                   &(sl_draw){.program = &prog, .mesh = &m}, &err));
        sl_raster_destroy(r);
        assert_same_texels(ref, out, 64 * 64, sizeof(uint32_t), 64, "tile %d against the plain path", tiles[k]);
    }
}

/* ---- the clear ---- */

typedef struct {
    uint32_t tag;
    float depth;
    uint32_t count;
} count_texel;

static void vs_pass(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *v)
{
    (void)uniforms;
    (void)v;
    *clip = vec4(in->position.x, in->position.y, in->position.z, 1.0f);
}

static void fs_count(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    (void)uniforms;
    count_texel *t = texel;
    t->tag = 0x7777u;
    t->depth = in->frag_coord.z;
    t->count++;
}

static const sl_program prog_count = {.vertex = vs_pass, .fragment = fs_count, .varying_count = 0};

/* The target's tile hooks, counted per pixel (tiles are disjoint, so two threads never count
 * the same pixel): how often each pixel was cleared, passed to tile_drawn, and passed with a
 * depth that is not its texel's. */
typedef struct {
    int w;
    const count_texel *texels;
    int *cleared, *drawn, *wrong_depth;
} hook_counts;

static void hook_clear(void *ctx, int x0, int y0, int x1, int y1)
{
    hook_counts *h = ctx;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            h->cleared[y * h->w + x]++;
}

static void hook_drawn(void *ctx, int x0, int y0, int x1, int y1, const float *depth, int stride)
{
    hook_counts *h = ctx;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            h->drawn[y * h->w + x]++;
            if (depth && depth[(y - y0) * stride + (x - x0)] != h->texels[y * h->w + x].depth)
                h->wrong_depth[y * h->w + x]++;
        }
}

/* More than one batch (RAST_BATCH = 131072 triangles): a 257 x 257 grid is 132,098 triangles
 * over the middle of the target, at depth 0.5 (z = 0), plus a nearer triangle (z = -0.5,
 * depth 0.25) in the second batch's part of the index list. The second batch must draw
 * over the first, not clear it again; pixels outside the grid keep the clear value. */
static void test_clear_batches(void **state)
{
    (void)state;
    enum { W = 96, H = 80 };
    sl_mesh grid = make_grid(257);
    assert_true(grid.triangle_count > 131072);
    for (int i = 0; i < grid.vertex_count; i++)
        grid.positions[i] = scale3(grid.positions[i], 0.5f); /* the middle half of the target */
    /* the last triangle (a corner of the grid, in the second batch) becomes a big nearer
     * one, on three vertices of its own */
    vec3 *pos = realloc(grid.positions, (size_t)(grid.vertex_count + 3) * sizeof *pos);
    assert_non_null(pos);
    grid.positions = pos;
    pos[grid.vertex_count] = vec3(-0.9f, -0.9f, -0.5f);
    pos[grid.vertex_count + 1] = vec3(1.5f, -0.9f, -0.5f);
    pos[grid.vertex_count + 2] = vec3(-0.9f, 1.5f, -0.5f);
    uint32_t *last = grid.indices + 3 * (grid.triangle_count - 1);
    for (int k = 0; k < 3; k++)
        last[k] = (uint32_t)(grid.vertex_count + k);
    grid.vertex_count += 3;
    free(grid.normals); /* no normals: the mesh's normals array would be too short */
    grid.normals = NULL;
    count_texel *a = malloc((size_t)W * H * sizeof *a), *b = malloc((size_t)W * H * sizeof *b);
    assert_non_null(a);
    assert_non_null(b);
    const count_texel clear = {.tag = 0xC1EAu, .depth = 1.0f, .count = 100};
    sl_error err = {0};
    for (int depth = 0; depth < 2; depth++) {
        for (int plain = 0; plain < 2; plain++) {
            sl_target ta = {.width = W, .height = H, .texel_size = sizeof *a, .texels = a, .depth_offset = depth ? (long)offsetof(count_texel, depth) : SL_NO_DEPTH};
            sl_target tb = ta;
            tb.texels = b;
            /* reference: clear by hand, then draw */
            for (int i = 0; i < W * H; i++)
                a[i] = clear;
            sl_raster *r = test_make_raster(2, 16, true, plain);
            assert_true(sl_raster_draw(r, &ta, &(sl_draw){.program = &prog_count, .mesh = &grid}, &err));
            /* fused: from garbage, with the tile hooks counting */
            memset(b, 0xEE, (size_t)W * H * sizeof *b);
            int *counts = calloc(3 * (size_t)W * H, sizeof *counts);
            assert_non_null(counts);
            hook_counts h = {.w = W, .texels = b, .cleared = counts, .drawn = counts + W * H,
                             .wrong_depth = counts + 2 * W * H};
            tb.tile_clear = hook_clear;
            tb.tile_drawn = hook_drawn;
            tb.tile_ctx = &h;
            const sl_draw dc = {.program = &prog_count, .mesh = &grid, .clear = &clear};
            assert_true(sl_raster_draw(r, &tb, &dc, &err));
            sl_raster_destroy(r);
            /* every pixel cleared once; the depths given are the texels'; the centre's tile drawn
             * by both batches (the grid, then the near triangle), a corner's by the second's only */
            for (int i = 0; i < W * H; i++) {
                assert_int_equal(h.cleared[i], 1);
                assert_int_equal(h.wrong_depth[i], 0);
            }
            assert_int_equal(h.drawn[(H / 2) * W + W / 2], 2);
            assert_int_equal(h.drawn[(H / 10) * W + W / 10], 1);
            free(counts);
            assert_same_texels(a, b, (size_t)W * H, sizeof *a, W,
                               "depth %d, plain %d: fused clear against cleared by hand", depth, plain);
            /* by hand: a corner pixel is never covered; the centre is covered by the grid
             * (once) and by the near triangle (with depth it wins; without, both count) */
            assert_true(b[0].tag == clear.tag && b[0].count == 100 && b[0].depth == 1.0f);
            const count_texel *mid = &b[(H / 2) * W + W / 2];
            assert_int_equal(mid->count, 102);
            assert_near(mid->depth, 0.25, 1e-6);
            /* a pixel inside the near triangle but outside the grid: drawn once */
            const count_texel *low = &b[(H / 10) * W + W / 10];
            assert_int_equal(low->count, 101);
        }
    }
    free(a);
    free(b);
    free_mesh(&grid);
}

/* A clearing draw with nothing to draw (no triangles; or all outside) still clears. */
static void test_clear_empty(void **state)
{
    (void)state;
    enum { W = 70, H = 33 };
    count_texel *t = malloc((size_t)W * H * sizeof *t);
    assert_non_null(t);
    const count_texel clear = {.tag = 1, .depth = 0.75f, .count = 9};
    const vec3 p[] = {{5, 5, 0}, {6, 5, 0}, {5, 6, 0}}; /* off screen */
    const uint32_t idx[] = {0, 1, 2};
    sl_mesh none = {.vertex_count = 3, .triangle_count = 0, .positions = (vec3 *)p, .indices = (uint32_t *)idx};
    sl_mesh off = none;
    off.triangle_count = 1;
    const sl_mesh *meshes[2] = {&none, &off};
    sl_error err = {0};
    for (int k = 0; k < 4; k++) {
        memset(t, 0xEE, (size_t)W * H * sizeof *t);
        sl_target target = {.width = W, .height = H, .texel_size = sizeof *t, .texels = t, .depth_offset = (k & 2) ? (long)offsetof(count_texel, depth) : SL_NO_DEPTH};
        sl_raster *r = test_make_raster(2, 32, true, false);
        const sl_draw dc = {.program = &prog_count, .mesh = meshes[k & 1], .clear = &clear};
        assert_true(sl_raster_draw(r, &target, &dc, &err));
        sl_raster_destroy(r);
        size_t diff = 0;
        for (int i = 0; i < W * H; i++)
            diff += memcmp(&t[i], &clear, sizeof clear) != 0;
        if (diff)
            print_error("case %d: %zu texels not cleared\n", k, diff);
        assert_int_equal(diff, 0);
    }
    free(t);
}

/* sl_raster_scene (fused clear) against sl_gbuffer_clear and the same draws without a clear. The
 * draws' program is the built-in one without writes_depth (the tiles copy their depth planes back
 * into the texels): what sl_gbuffer_program's own depth writes must give, bit for bit. */
static void test_scene_clear(void **state)
{
    (void)state;
    enum { W = 120, H = 90 };
    test_scene s;
    scene_init(&s);
    sl_error err = {0};
    sl_gbuffer a = {0}, b = {0};
    assert_true(sl_gbuffer_resize(&a, W, H, &err));
    assert_true(sl_gbuffer_resize(&b, W, H, &err));
    memset(a.texels, 0x77, (size_t)W * H * sizeof *a.texels);
    memset(b.texels, 0x77, (size_t)W * H * sizeof *b.texels);
    sl_raster *r = test_make_raster(2, 32, true, false);
    assert_true(sl_raster_scene(r, &s.scene, &s.cam, &a, &err));
    sl_gbuffer_clear(&b, 0);
    mat4 vp = sl_camera_view_proj(&s.cam, W, H);
    sl_target target = sl_gbuffer_target(&b);
    sl_program copied = sl_gbuffer_program;
    assert_true(copied.writes_depth);
    copied.writes_depth = false;
    for (int i = 0; i < s.scene.object_count; i++) {
        sl_gbuffer_uniforms u;
        sl_gbuffer_uniforms_init(&u, s.objects[i].model, vp, &s.mats[s.objects[i].material]);
        sl_draw d = {.program = &copied, .vs_uniforms = &u, .fs_uniforms = &u,
                     .mesh = &s.meshes[s.objects[i].mesh]};
        assert_true(sl_raster_draw(r, &target, &d, &err));
    }
    assert_same_texels(a.texels, b.texels, (size_t)W * H, sizeof *a.texels, W,
                       "sl_raster_scene against sl_gbuffer_clear and the draws");
    /* an empty scene still clears */
    sl_scene empty = s.scene;
    empty.object_count = 0;
    assert_true(sl_raster_scene(r, &empty, &s.cam, &a, &err));
    for (int i = 0; i < W * H; i++)
        assert_false(sl_gbuffer_covered(&a.texels[i]));
    sl_raster_destroy(r);
    sl_gbuffer_free(&a);
    sl_gbuffer_free(&b);
    scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gbuffer_span_vs_plain), cmocka_unit_test(test_small_triangles_span_vs_plain),
        cmocka_unit_test(test_gbuffer_span_shader),
        cmocka_unit_test(test_generic_span_vs_plain), cmocka_unit_test(test_clear_batches),
        cmocka_unit_test(test_clear_empty),           cmocka_unit_test(test_scene_clear),
        cmocka_unit_test(test_draw_list),             cmocka_unit_test(test_span_fill_rule),
        cmocka_unit_test(test_quads_span_vs_plain),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
