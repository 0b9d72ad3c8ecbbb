/* test_raster_gbuffer.c - the built-in G-buffer pair, sl_raster_scene, determinism across
 * thread counts and tile sizes, and the AOV files (write, read back, row order).
 *
 * Meshes are built here (a tilted plane, a UV sphere, a ground quad) so the tests do not
 * depend on the scene module's loaders. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/image.h"
#include "raster/raster.h"
#include "scene/camera.h"
#include "testutil.h"

/* The plane x + z = 0 in object space, normal (1,0,1)/sqrt2, counter-clockwise seen from +normal. */
static vec3 tilted_pos[] = {{-1, -1, 1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, 1}};
static vec3 tilted_nrm[4];
static uint32_t quad_idx[] = {0, 1, 2, 0, 2, 3};
static vec3 ground_pos[] = {{-50, -50, -1}, {50, -50, -1}, {50, 50, -1}, {-50, 50, -1}};
static vec3 ground_nrm[] = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};

static sl_mesh make_tilted(void)
{
    for (int i = 0; i < 4; i++)
        tilted_nrm[i] = normalize(vec3(1, 0, 1));
    return (sl_mesh){.vertex_count = 4, .triangle_count = 2, .positions = tilted_pos, .normals = tilted_nrm,
                     .indices = quad_idx};
}

static sl_mesh make_sphere(int slices, int stacks)
{
    sl_mesh m = {0};
    m.vertex_count = slices * (stacks - 1) + 2;
    m.triangle_count = 2 * slices * (stacks - 1);
    m.positions = malloc((size_t)m.vertex_count * sizeof(vec3));
    m.normals = malloc((size_t)m.vertex_count * sizeof(vec3));
    m.indices = malloc((size_t)m.triangle_count * 3 * sizeof(uint32_t));
    assert_non_null(m.positions);
    assert_non_null(m.normals);
    assert_non_null(m.indices);
    for (int j = 1; j < stacks; j++)
        for (int i = 0; i < slices; i++) {
            double th = 3.14159265358979 * j / stacks, ph = 2.0 * 3.14159265358979 * i / slices;
            m.positions[(j - 1) * slices + i] = vec3(sin(th) * cos(ph), sin(th) * sin(ph), cos(th));
        }
    uint32_t north = (uint32_t)(m.vertex_count - 2), south = (uint32_t)(m.vertex_count - 1);
    m.positions[north] = vec3(0, 0, 1);
    m.positions[south] = vec3(0, 0, -1);
    for (int i = 0; i < m.vertex_count; i++)
        m.normals[i] = m.positions[i];
    uint32_t *t = m.indices;
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
    return m;
}

static void free_mesh(sl_mesh *m)
{
    free(m->positions);
    free(m->normals);
    free(m->indices);
}

static const sl_material mat_a = {.name = "a", .kd = {0.8f, 0.2f, 0.1f}, .ks = {0.04f, 0.05f, 0.06f}, .alpha = 20.0f};
static const sl_material mat_b = {.name = "b", .kd = {0.1f, 0.7f, 0.3f}, .ks = {0.9f, 0.8f, 0.7f}, .alpha = 500.0f};

/* The tilted plane scaled by (2,1,1), rotated and moved: the world normal is
 * normalize(R (1/2, 0, 1)), not normalize(R S (1,0,1)): only the normal matrix gets it right.
 * Every covered texel must lie on the world plane, face along its normal, carry the
 * material, and hold the window depth of its own position. */
static void test_gbuffer_shader(void **state)
{
    (void)state;
    enum { W = 96, H = 64 };
    sl_mesh plane = make_tilted();
    mat4 R = mat4_rotate(vec3(0, 0, 1), 0.4f);
    mat4 model = mat4_mul(mat4_translate(vec3(0.2f, 0.1f, -0.3f)), mat4_mul(R, mat4_scale(vec3(2, 1, 1))));
    sl_camera cam = {.eye = {3, -2.5f, 1.5f}, .target = {0, 0, 0}, .up = {0, 0, 1}, .fovy_deg = 60, .znear = 0.5f, .zfar = 30};
    sl_scene scene = {.meshes = &plane, .mesh_count = 1, .materials = (sl_material *)&mat_a, .material_count = 1,
                      .objects = &(sl_object){.name = "tilted", .mesh = 0, .material = 0, .model = model},
                      .object_count = 1};
    sl_gbuffer gb = {0};
    test_raster_scene(&(sl_raster_desc){.threads = 2, .tile_size = 16, .stats = true}, &scene, &cam, W, H, &gb);

    vec3 nw = normalize(mat3_mul_vec3(mat3_from_mat4(R), vec3(0.5f, 0, 1)));
    vec3 origin = vec3(0.2f, 0.1f, -0.3f);
    mat4 vp = sl_camera_view_proj(&cam, W, H);
    int covered = 0;
    double max_n = 0, max_plane = 0, max_depth = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(&gb, x, y);
            if (!sl_gbuffer_covered(t)) {
                sl_gbuffer_texel empty = {.depth = 1.0f};
                assert_memory_equal(t, &empty, sizeof empty);
                continue;
            }
            covered++;
            max_n = fmax(max_n, length(sub(t->normal, nw)));
            max_plane = fmax(max_plane, fabs(dot(sub(t->position, origin), nw)));
            vec4 c = mat4_mul_vec4(vp, vec4_from3(t->position, 1.0f));
            max_depth = fmax(max_depth, fabs(c.z / c.w * 0.5f + 0.5f - t->depth));
            assert_memory_equal(&t->kd, &mat_a.kd, sizeof(vec3));
            assert_memory_equal(&t->ks, &mat_a.ks, sizeof(vec3));
            assert_true(t->alpha == mat_a.alpha);
        }
    print_message("gbuffer: %d covered, max |n - n_world| %.3g, max plane distance %.3g, max depth error %.3g\n",
                  covered, max_n, max_plane, max_depth);
    assert_true(covered > W * H / 10);
    assert_true(max_n < 1e-5);
    assert_true(max_plane < 1e-4);
    assert_true(max_depth < 1e-5);

    /* sanity of the reference: the naive M n differs from the right normal by far more */
    vec3 naive = normalize(mat3_mul_vec3(mat3_from_mat4(model), normalize(vec3(1, 0, 1))));
    assert_true(length(sub(naive, nw)) > 0.1f);
    sl_gbuffer_free(&gb);
}

/* A scene with a sphere, the tilted plane, a ground quad crossing the near plane, and a
 * second copy of the tilted plane with another material at exactly the same depth. */
typedef struct {
    sl_mesh meshes[3];
    sl_material materials[2];
    sl_object objects[4];
    sl_scene scene;
    sl_camera cam;
} test_scene;

static void scene_init(test_scene *s)
{
    memset(s, 0, sizeof *s);
    s->meshes[0] = make_sphere(64, 32);
    s->meshes[1] = make_tilted();
    s->meshes[2] = (sl_mesh){.vertex_count = 4, .triangle_count = 2, .positions = ground_pos, .normals = ground_nrm,
                             .indices = quad_idx};
    s->materials[0] = mat_a;
    s->materials[1] = mat_b;
    s->objects[0] = (sl_object){"ground", 2, 0, mat4_identity()};
    s->objects[1] = (sl_object){"sphere", 0, 1, mat4_translate(vec3(0.5f, 0.3f, 0.2f))};
    s->objects[2] = (sl_object){"plane", 1, 0, mat4_translate(vec3(-1.2f, 0.5f, 0))};
    s->objects[3] = (sl_object){"plane again", 1, 1, mat4_translate(vec3(-1.2f, 0.5f, 0))};
    s->scene = (sl_scene){.meshes = s->meshes, .mesh_count = 3, .materials = s->materials, .material_count = 2,
                          .objects = s->objects, .object_count = 4};
    s->cam = (sl_camera){.eye = {0.3f, -4.5f, 0.4f}, .target = {0, 0, 0}, .up = {0, 0, 1}, .fovy_deg = 55,
                         .znear = 0.3f, .zfar = 40};
}

/* Bitwise-identical G-buffers for 1, 2 and 3 threads and tile sizes 16..256; the coplanar
 * second plane never wins (LESS keeps the first of equal depths, in every tile). */
static void test_determinism(void **state)
{
    (void)state;
    enum { W = 200, H = 150 };
    test_scene s;
    scene_init(&s);
    const int configs[][2] = {{1, 16}, {2, 16}, {2, 32}, {3, 64}, {1, 128}, {2, 256}};
    sl_gbuffer ref = {0}, gb = {0};
    sl_raster_stats ref_stats = {0};
    for (int k = 0; k < 6; k++) {
        sl_raster_desc desc = {.threads = configs[k][0], .tile_size = configs[k][1], .stats = true};
        sl_raster_stats st = test_raster_scene(&desc, &s.scene, &s.cam, W, H, k == 0 ? &ref : &gb);
        if (k == 0) {
            ref_stats = st;
        } else {
            assert_same_texels(ref.texels, gb.texels, (size_t)W * H, sizeof *gb.texels, W,
                               "threads %d, tile %d against threads 1, tile 16", configs[k][0], configs[k][1]);
            /* counters that do not depend on the tiling (binned does: a triangle covering no
             * pixel centre may pass a big tile's conservative test and fail a small one's) */
            assert_int_equal(st.fragments_shaded, ref_stats.fragments_shaded);
            assert_int_equal(st.triangles_in, ref_stats.triangles_in);
            assert_int_equal(st.triangles_clipped, ref_stats.triangles_clipped);
        }
    }
    assert_true(ref_stats.triangles_clipped > 0);
    /* The plane (material a) is visible and never overwritten by its coplanar twin (b). */
    int plane_px = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        const sl_gbuffer_texel *t = &ref.texels[i];
        if (sl_gbuffer_covered(t) && fabsf(t->normal.x - t->normal.z) < 1e-4f && t->normal.x > 0.5f) {
            plane_px++;
            assert_true(t->alpha == mat_a.alpha);
        }
    }
    assert_true(plane_px > 100);
    sl_gbuffer_free(&ref);
    sl_gbuffer_free(&gb);
    free_mesh(&s.meshes[0]);
}

static void test_aov_roundtrip(void **state)
{
    (void)state;
    enum { W = 80, H = 48 };
    test_scene s;
    scene_init(&s);
    sl_gbuffer gb = {0}, back = {0};
    sl_error err = {0};
    test_raster_scene(&(sl_raster_desc){.threads = 2, .tile_size = 32, .stats = true}, &s.scene, &s.cam, W, H, &gb);
    const char *dir = test_tmpdir();
    if (!sl_gbuffer_write_aovs(&gb, s.cam.eye, dir, &err))
        print_error("%s\n", err.msg);
    assert_true(err.code == SL_OK);
    if (!sl_gbuffer_read_aovs(dir, &back, &err))
        print_error("%s\n", err.msg);
    assert_int_equal(back.width, W);
    assert_int_equal(back.height, H);
    assert_memory_equal(gb.texels, back.texels, (size_t)W * H * sizeof *gb.texels);

    /* Row order: the file's first row is the G-buffer's row 0 (bottom), so an sl_image
     * (row 0 = top) read from it has the G-buffer's top row first. */
    sl_image img = {0};
    assert_true(sl_gbuffer_read_aov_image(test_tmpfile("position.pfm"), &img, &err));
    for (int x = 0; x < W; x++) {
        assert_memory_equal(sl_image_pixel(&img, x, 0), &sl_gbuffer_at(&gb, x, H - 1)->position, sizeof(vec3));
        assert_memory_equal(sl_image_pixel(&img, x, H - 1), &sl_gbuffer_at(&gb, x, 0)->position, sizeof(vec3));
    }
    sl_image_free(&img);
    /* view.pfm = normalize(eye - position) where covered, 0 elsewhere; mask.pfm = coverage */
    sl_image view = {0}, mask = {0};
    assert_true(sl_gbuffer_read_aov_image(test_tmpfile("view.pfm"), &view, &err));
    /* (sl_image_read_pfm would have repaired the negative components to 0) */
    assert_true(sl_image_read_pfm(test_tmpfile("mask.pfm"), 0, &mask, NULL, &err));
    int covered = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(&gb, x, y);
            const float *v = sl_image_pixel(&view, x, H - 1 - y);
            vec3 expect = sl_gbuffer_covered(t) ? normalize(sub(s.cam.eye, t->position)) : vec3s(0);
            assert_near(v[0], expect.x, 1e-6);
            assert_near(v[1], expect.y, 1e-6);
            assert_near(v[2], expect.z, 1e-6);
            assert_true(*sl_image_pixel(&mask, x, H - 1 - y) == (sl_gbuffer_covered(t) ? 1.0f : 0.0f));
            covered += sl_gbuffer_covered(t);
        }
    assert_true(covered > 0 && covered < W * H);

    /* A mask that disagrees with depth is refused, naming the file. */
    *sl_image_pixel(&mask, 0, 0) = sl_gbuffer_covered(sl_gbuffer_at(&gb, 0, H - 1)) ? 0.0f : 1.0f;
    assert_true(sl_image_write_pfm(test_tmpfile("mask.pfm"), &mask, &err));
    assert_false(sl_gbuffer_read_aovs(dir, &back, &err));
    assert_non_null(strstr(err.msg, "mask.pfm"));
    assert_false(sl_gbuffer_read_aovs("/nonexistent-softlight-dir", &back, &err));
    sl_image_free(&view);
    sl_image_free(&mask);

    /* The normal view: row 0 = top, normal * 0.5 + 0.5. */
    sl_image nimg = {0};
    assert_true(sl_gbuffer_normal_image(&gb, &nimg, &err));
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const sl_gbuffer_texel *t = sl_gbuffer_at(&gb, x, y);
            const float *p = sl_image_pixel(&nimg, x, H - 1 - y);
            float e = sl_gbuffer_covered(t) ? t->normal.y * 0.5f + 0.5f : 0.0f;
            assert_true(p[1] == e);
        }
    sl_image_free(&nimg);
    sl_gbuffer_free(&gb);
    sl_gbuffer_free(&back);
    free_mesh(&s.meshes[0]);
}

static void test_gbuffer_alloc(void **state)
{
    (void)state;
    sl_gbuffer gb = {0};
    sl_error err = {0};
    assert_false(sl_gbuffer_resize(&gb, 0, 10, &err));
    assert_false(sl_gbuffer_resize(&gb, 10, SL_RASTER_MAX_SIZE + 1, &err));
    assert_true(sl_gbuffer_resize(&gb, 7, 5, &err));
    sl_gbuffer_texel *first = gb.texels;
    assert_true(sl_gbuffer_resize(&gb, 7, 5, &err));
    assert_ptr_equal(gb.texels, first); /* same size: no reallocation */
    memset(gb.texels, 0x7f, 35 * sizeof *gb.texels);
    sl_gbuffer_clear(&gb, 0);
    sl_gbuffer_texel empty = {.depth = 1.0f};
    for (int i = 0; i < 35; i++)
        assert_memory_equal(&gb.texels[i], &empty, sizeof empty);
    sl_target t = sl_gbuffer_target(&gb);
    assert_int_equal(t.texel_size, 56);
    assert_int_equal(t.depth_offset, 52);
    sl_gbuffer_free(&gb);
    assert_null(gb.texels);
    /* A scene into an unallocated G-buffer is an error, not a crash. */
    test_scene s;
    scene_init(&s);
    sl_raster *r = test_make_raster(1, 16, true, false);
    assert_false(sl_raster_scene(r, &s.scene, &s.cam, &gb, &err));
    s.objects[1].mesh = 9;
    assert_true(sl_gbuffer_resize(&gb, 8, 8, &err));
    assert_false(sl_raster_scene(r, &s.scene, &s.cam, &gb, &err));
    assert_non_null(strstr(err.msg, "sphere"));
    sl_raster_destroy(r);
    sl_gbuffer_free(&gb);
    free_mesh(&s.meshes[0]);
}

/* The extra plane's clear and resolve over rectangles (the tile hooks of sl_gbuffer_target) leave
 * what the whole-plane functions leave, with the depths from a plane or from the texels; the
 * resolve keeps a tag equal to its texel's depth and makes every other extra texel "none". */
static void test_extra_rects(void **state)
{
    (void)state;
    enum { W = 7, H = 5 };
    sl_gbuffer a = {0}, b = {0};
    sl_error err = {0};
    assert_true(sl_gbuffer_resize(&a, W, H, &err) && sl_gbuffer_use_extra(&a, true, 0, &err));
    assert_true(sl_gbuffer_resize(&b, W, H, &err) && sl_gbuffer_use_extra(&b, true, 0, &err));
    sl_gbuffer_clear(&a, 0);
    memset(b.extra, 0x5a, W * H * sizeof *b.extra);
    for (int y0 = 0; y0 < H; y0 += 3) /* tiles of 4 x 3, the last ones cut */
        for (int x0 = 0; x0 < W; x0 += 4)
            sl_gbuffer_extra_clear_rect(&b, x0, y0, x0 + 3 < W ? x0 + 3 : W - 1, y0 + 2 < H ? y0 + 2 : H - 1);
    assert_memory_equal(a.extra, b.extra, W * H * sizeof *a.extra);
    for (int i = 0; i < W * H; i++) { /* depths; tags: equal (i % 3 == 0), other, or none */
        float d = 0.25f + 0.01f * (float)i;
        a.texels[i].depth = i % 5 == 4 ? 1.0f : d;
        a.extra[i] = (sl_gbuffer_extra){0.5f, vec3(2.0f, 3.0f, 4.0f), i % 3 == 0 ? a.texels[i].depth
                                                                       : i % 3 == 1 ? d + 0.5f : -1.0f};
        if (i % 3 == 2)
            a.extra[i] = (sl_gbuffer_extra){1.0f, vec3(0, 0, 0), -1.0f};
    }
    memcpy(b.texels, a.texels, W * H * sizeof *a.texels);
    memcpy(b.extra, a.extra, W * H * sizeof *a.extra);
    sl_gbuffer_extra_resolve(&a);
    for (int i = 0; i < W * H; i++) {
        const sl_gbuffer_extra e = a.extra[i];
        if (i % 3 == 0) /* kept */
            assert_true(e.occlusion == 0.5f && e.emissive.x == 2.0f && e.depth == a.texels[i].depth);
        else /* none */
            assert_true(e.occlusion == 1.0f && e.emissive.x == 0.0f && e.emissive.z == 0.0f && e.depth == -1.0f);
    }
    float depth[3 * 4];
    for (int y0 = 0; y0 < H; y0 += 3)
        for (int x0 = 0; x0 < W; x0 += 4) {
            int x1 = x0 + 3 < W ? x0 + 3 : W - 1, y1 = y0 + 2 < H ? y0 + 2 : H - 1;
            for (int y = y0; y <= y1; y++)
                for (int x = x0; x <= x1; x++)
                    depth[(y - y0) * 4 + (x - x0)] = b.texels[y * W + x].depth;
            /* the first tile column from the plane, the second from the texels; twice: idempotent */
            for (int k = 0; k < 2; k++)
                sl_gbuffer_extra_resolve_rect(&b, x0, y0, x1, y1, x0 == 0 ? depth : NULL, 4);
        }
    assert_memory_equal(a.extra, b.extra, W * H * sizeof *a.extra);
    sl_target t = sl_gbuffer_target(&b);
    assert_non_null(t.tile_clear);
    assert_non_null(t.tile_drawn);
    assert_true(sl_gbuffer_use_extra(&b, false, 0, &err));
    t = sl_gbuffer_target(&b);
    assert_null(t.tile_clear);
    assert_null(t.tile_drawn);
    sl_gbuffer_free(&a);
    sl_gbuffer_free(&b);
}

/* The facet plane (sl_target.facets) through each of the tile stage's paths: a texel of a float
 * depth and a mark, a program without varyings that only marks, in the forms that choose the
 * paths: per pixel, a span shader, derivatives (quads, generic rounds), a multi-quad shader, a
 * discarding one (late depth), and derivatives with discards. */
typedef struct {
    float depth, mark;
} facet_texel;

static void facet_vert(const void *uniforms, const sl_vertex_in *in, vec4 *clip, float *varyings)
{
    (void)varyings;
    *clip = mat4_mul_vec4(*(const mat4 *)uniforms, vec4_from3(in->position, 1.0f));
}
static void facet_frag(const void *uniforms, const sl_fragment_in *in, void *texel)
{
    (void)uniforms;
    (void)in;
    ((facet_texel *)texel)->mark = 1.0f;
}
static void facet_frag_span(const void *uniforms, const sl_fragment_span *span)
{
    (void)uniforms;
    for (int j = 0; j < span->n; j++)
        ((facet_texel *)(span->row + (size_t)span->x[j] * span->texel_size))->mark = 1.0f;
}
static void facet_frag_quads(const void *uniforms, const sl_fragment_quads *q)
{
    (void)uniforms;
    for (int l = 0; l < 4 * q->n; l++)
        ((facet_texel *)q->texel[l])->mark = 1.0f;
}

/* Draw `mesh` with `model` through program `prog` into a W x H target with facets (view_proj
 * `vp`), cleared first; returns the facets (the caller frees them) and the texels in *texels. */
static sl_vec3 *draw_facets(const sl_program *prog, const sl_mesh *mesh, mat4 model, mat4 vp, int w, int h, bool plain,
                            facet_texel **texels)
{
    sl_error err = {0};
    sl_raster *r = sl_raster_create(&(sl_raster_desc){.threads = 2, .tile_size = 16, .plain = plain}, &err);
    assert_non_null(r);
    *texels = calloc((size_t)w * (size_t)h, sizeof **texels);
    sl_vec3 *facets = malloc((size_t)w * (size_t)h * sizeof *facets);
    assert_non_null(*texels);
    assert_non_null(facets);
    for (size_t i = 0; i < (size_t)w * (size_t)h; i++)
        facets[i] = vec3s(9.0f); /* the clear sets 0 */
    sl_target target = {.width = w, .height = h, .texel_size = sizeof(facet_texel), .texels = *texels,
                        .depth_offset = 0, .facets = facets, .facet_view_proj = vp};
    const facet_texel clear = {.depth = 1.0f};
    mat4 mvp = mat4_mul(vp, model);
    sl_draw draw = {.program = prog, .vs_uniforms = &mvp, .fs_uniforms = NULL, .mesh = mesh, .clear = &clear};
    if (!sl_raster_draw(r, &target, &draw, &err))
        fail_msg("%s", err.msg);
    sl_raster_destroy(r);
    return facets;
}

/* Every path writes, at each texel a fragment wrote, the unit normal of the triangle's plane in
 * world space facing the viewer, the same bits in all; 0 where nothing was drawn. The tilted
 * plane scaled by (2, 1, 1) and turned: normalize(R (1/2, 0, 1)), which the model matrix applied
 * to the object's normal would get wrong; seen in perspective from either side, and from an
 * orthographic view (the viewer the direction it looks from). A UV sphere: each texel's facet
 * within a face's angle of its radial direction, facing the eye, and drawn at P: the texel's
 * position lies on a plane through P (the triangle's: P's neighbours on the same face lie on it). */
static void test_facet_plane(void **state)
{
    (void)state;
    enum { W = 64, H = 48 };
    const sl_program programs[] = {
        {.vertex = facet_vert, .fragment = facet_frag},
        {.vertex = facet_vert, .fragment = facet_frag, .fragment_span = facet_frag_span},
        {.vertex = facet_vert, .fragment = facet_frag, .derivatives = true},
        {.vertex = facet_vert, .fragment = facet_frag, .derivatives = true, .fragment_quads = facet_frag_quads},
        {.vertex = facet_vert, .fragment = facet_frag, .discards = true},
        {.vertex = facet_vert, .fragment = facet_frag, .derivatives = true, .discards = true},
    };
    sl_mesh plane = make_tilted();
    mat4 R = mat4_rotate(vec3(0, 0, 1), 0.4f);
    mat4 model = mat4_mul(mat4_translate(vec3(0.2f, 0.1f, -0.3f)), mat4_mul(R, mat4_scale(vec3(2, 1, 1))));
    vec3 nw = normalize(mat3_mul_vec3(mat3_from_mat4(R), vec3(0.5f, 0, 1)));
    /* two perspective views, one on each side of the plane, and an orthographic one */
    const sl_camera cams[2] = {
        {.eye = {3, -2.5f, 1.5f}, .target = {0, 0, 0}, .up = {0, 0, 1}, .fovy_deg = 60, .znear = 0.5f, .zfar = 30},
        {.eye = {-3, 1.0f, -2.0f}, .target = {0, 0, 0}, .up = {0, 0, 1}, .fovy_deg = 60, .znear = 0.5f, .zfar = 30},
    };
    for (int view = 0; view < 3; view++) {
        mat4 vp;
        vec3 toward_viewer;
        if (view < 2) {
            vp = sl_camera_view_proj(&cams[view], W, H);
            toward_viewer = normalize(cams[view].eye); /* the plane passes near the origin */
        } else {
            vec3 eye = vec3(2.0f, -1.0f, 3.0f);
            /* glOrtho(-3, 3, -2, 2, 0.1, 20) */
            mat4 ortho = {{{1.0f / 3.0f, 0, 0, 0}, {0, 0.5f, 0, 0}, {0, 0, -2.0f / 19.9f, 0},
                           {0, 0, -20.1f / 19.9f, 1}}};
            vp = mat4_mul(ortho, sl_mat4_look_at(eye, vec3(0, 0, 0), vec3(0, 0, 1)));
            toward_viewer = normalize(eye);
        }
        vec3 expect = dot(nw, toward_viewer) > 0.0f ? nw : scale(nw, -1.0f);
        sl_vec3 *ref = NULL;
        for (int k = 0; k < (int)(sizeof programs / sizeof programs[0]); k++) {
            for (int plain = 0; plain < 2; plain++) {
                facet_texel *tex;
                sl_vec3 *f = draw_facets(&programs[k], &plane, model, vp, W, H, plain, &tex);
                int drawn = 0;
                for (int i = 0; i < W * H; i++) {
                    if (tex[i].mark == 0.0f) {
                        assert_true(f[i].x == 0.0f && f[i].y == 0.0f && f[i].z == 0.0f);
                        continue;
                    }
                    drawn++;
                    assert_near(f[i].x, expect.x, 1e-5);
                    assert_near(f[i].y, expect.y, 1e-5);
                    assert_near(f[i].z, expect.z, 1e-5);
                }
                assert_true(drawn > W * H / 10);
                if (!ref)
                    ref = f;
                else {
                    if (memcmp(ref, f, (size_t)W * H * sizeof *f) != 0)
                        fail_msg("view %d, program %d, plain %d: facets differ from the first path's", view, k, plain);
                    free(f);
                }
                free(tex);
            }
        }
        free(ref);
    }

    /* a UV sphere through the G-buffer (sl_gbuffer_use_facet, sl_raster_scene) */
    sl_mesh sphere = make_sphere(32, 16);
    sl_camera cam = {.eye = {0.5f, -3.0f, 1.0f}, .target = {0, 0, 0}, .up = {0, 0, 1}, .fovy_deg = 50,
                     .znear = 0.5f, .zfar = 30};
    sl_scene scene = {.meshes = &sphere, .mesh_count = 1, .materials = (sl_material *)&mat_a, .material_count = 1,
                      .objects = &(sl_object){.name = "ball", .mesh = 0, .material = 0, .model = mat4_identity()},
                      .object_count = 1};
    sl_gbuffer gb = {0}, back = {0};
    sl_error err = {0};
    assert_true(sl_gbuffer_resize(&gb, W, H, &err) && sl_gbuffer_use_facet(&gb, true, &err));
    sl_raster *r = sl_raster_create(&(sl_raster_desc){.threads = 2, .tile_size = 16}, &err);
    assert_true(r && sl_raster_scene(r, &scene, &cam, &gb, &err));
    sl_raster_destroy(r);
    const float face_cos = cosf(2.0f * 3.14159265f / 32.0f); /* a face's largest turn from its points' radii */
    int covered = 0;
    for (int i = 0; i < W * H; i++) {
        const sl_gbuffer_texel *t = &gb.texels[i];
        vec3 f = gb.facet[i];
        if (!sl_gbuffer_covered(t)) {
            assert_true(f.x == 0.0f && f.y == 0.0f && f.z == 0.0f);
            continue;
        }
        covered++;
        assert_near(length(f), 1.0, 1e-5);
        assert_true(dot(f, normalize(t->position)) > face_cos);
        assert_true(dot(f, sub(cam.eye, t->position)) > 0.0f);
    }
    assert_true(covered > 200);
    /* facet.pfm: written and read back bit for bit */
    const char *dir = test_tmpdir();
    assert_true(sl_gbuffer_write_aovs(&gb, cam.eye, dir, &err));
    assert_true(sl_gbuffer_read_aovs(dir, &back, &err));
    assert_non_null(back.facet);
    assert_memory_equal(gb.facet, back.facet, (size_t)W * H * sizeof *gb.facet);
    /* a resize keeps the plane, turning it off frees it */
    assert_true(sl_gbuffer_resize(&gb, W / 2, H / 2, &err));
    assert_non_null(gb.facet);
    assert_true(sl_gbuffer_use_facet(&gb, false, &err));
    assert_null(gb.facet);
    sl_gbuffer_free(&gb);
    sl_gbuffer_free(&back);
    free_mesh(&sphere);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gbuffer_shader),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_aov_roundtrip),
        cmocka_unit_test(test_gbuffer_alloc),
        cmocka_unit_test(test_extra_rects),
        cmocka_unit_test(test_facet_plane),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
