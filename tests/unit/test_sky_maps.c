/* test_sky_maps.c - the sky visibility maps (src/shadow/sky.c). The lookup:
 * sl_shadow_sky_visibility reads every map in one loop, a lane a map;
 * sl_shadow_sky_visibility_points reads the maps one after another, a lane a point;
 * sl_shadow_sky_map_visibility is the scalar lookup of one map that the GLSL twin mirrors. Over
 * maps drawn from a small scene (a floor, a sphere and a box under a bright sky), V and each map's
 * v_k from the first, and V from the second, must equal, bit for bit, the third's per-map loop,
 * for thousands of points on the surfaces (in contact shadows, on slopes, edge-on to a map) and of
 * odd points (off every map, huge, NaN). The cells: split at the horizon, each wholly on the sky's
 * side or the ground's; sl_shadow_sky_cell, the cell of a direction (which the lighting's part
 * across the horizon reads), is the rule the weights were summed by. The cone's share across the
 * horizon (shade_cone_across, which opens the specular occlusion's cone where the maps take the
 * part its occluders hide): 0 without the maps, all of the cone's lean when it points across from
 * R, none when it points to R's side, and the specular's factor never falls as the share grows.
 * The plane the batched lighting reads (sky_plane.c): the anchors hold their lookups bit for bit,
 * a texel next to an empty one it would be filled from is looked up, about a fifth of the texels
 * are at 1280x720 (every one where the pixels are coarser than the maps' texels, 80x45), and the
 * fill stays near the lookups, nearer than a fill without the agreement test. A wide lobe's factor takes the map of
 * R's cell (shade_lobe_map) where that map is hidden, and only there. A ball's underside a few
 * texels over a floor 160 units wide reads hidden in every steep ground map. A run of points'
 * lookups each in the map of its own direction's cell (sl_shadow_sky_cell_visibility_lanes) equal
 * the one-point functions' bits. */
#include "occluder_points.h"
#include "shading_fixtures.h"

#include <stdio.h>

#include "raster/raster.h"
#include "scene/scene.h"
#include "shading/lighting_internal.h"
#include "shadow/sky.h"

static const char *SCENE = FX_OCCLUDER_SCENE "}";

/* brighter upward, a dim ground, a sun: every cell weighs something, unevenly */
static vec3 sky(vec3 d)
{
    float up = d.z > 0.0f ? d.z : 0.0f;
    float sun = dot(d, normalize(vec3(0.4f, -0.3f, 0.8f))) > 0.99f ? 50.0f : 0.0f;
    return vec3(0.2f + up + sun, 0.25f + up + sun, 0.3f + 1.5f * up + sun);
}

static fx_rng rng = {12345u};
static float rnd(void) { return fx_rnd(&rng); } /* [0, 1) */
static vec3 rnd_dir(void) { return fx_rnd_dir(&rng); }

/* The reference: V from the scalar lookup, map by map (sky.h's formula, in k order). */
static float reference(const sl_shadow_sky *s, vec3 P, vec3 N, float *each)
{
    float seen = 0.0f, all = 0.0f;
    for (int k = 0; k < s->count; k++) {
        float w = fmaxf(dot(N, s->weight[k]), 0.0f);
        float v = w > 0.0f ? sl_shadow_sky_map_visibility(s, k, P, N) : -1.0f;
        each[k] = v;
        if (w > 0.0f) {
            seen += v * w;
            all += w;
        }
    }
    return all > 0.0f ? seen / all : 1.0f;
}

/* The points checked, SL_SKY_POINTS at a time for sl_shadow_sky_visibility_points, with the V of
 * the one-point lookup of each. */
typedef struct {
    sl_shadow_sky_points points;
    float V[SL_SKY_POINTS];
    int n;
} point_batch;

/* The batch's points looked up together: each lane's V the one-point lookup's bits. */
static void check_points(const sl_shadow_sky *s, point_batch *b)
{
    if (b->n == 0)
        return;
    sl_shadow_sky_points *p = &b->points;
    for (int i = b->n; i < SL_SKY_POINTS; i++)
        p->px[i] = p->py[i] = p->pz[i] = p->nx[i] = p->ny[i] = p->nz[i] = 0.0f;
    float V[SL_SKY_POINTS];
    sl_shadow_sky_visibility_points(s, p, V);
    for (int i = 0; i < SL_SKY_POINTS; i++)
        if (memcmp(&V[i], i < b->n ? &b->V[i] : &(float){1.0f}, sizeof V[i]) != 0)
            fail_msg("K %d, lane %d of %d, P (%.9g %.9g %.9g) N (%.9g %.9g %.9g): points %.9g, one point %.9g",
                     s->count, i, b->n, p->px[i], p->py[i], p->pz[i], p->nx[i], p->ny[i], p->nz[i], V[i],
                     i < b->n ? b->V[i] : 1.0f);
    b->n = 0;
}

/* One (P, N): V and every v_k equal the reference's bits, and V the points lookup's (the point
 * joins the batch). Counts the points partly hidden. */
static void check(const sl_shadow_sky *s, point_batch *batch, vec3 P, vec3 N, int *partial, int *checked)
{
    float each[SL_SKY_MAPS_MAX], ref_each[SL_SKY_MAPS_MAX];
    float V = sl_shadow_sky_visibility(s, P, N, each);
    float R = reference(s, P, N, ref_each);
    if (memcmp(&V, &R, sizeof V) != 0 || memcmp(each, ref_each, (size_t)s->count * sizeof *each) != 0) {
        int k = 0;
        while (k < s->count && memcmp(&each[k], &ref_each[k], sizeof *each) == 0)
            k++;
        fail_msg("K %d, P (%.9g %.9g %.9g) N (%.9g %.9g %.9g): V %.9g, reference %.9g; first map apart %d: %.9g %.9g",
                 s->count, P.x, P.y, P.z, N.x, N.y, N.z, V, R, k, k < s->count ? each[k] : 0.0f,
                 k < s->count ? ref_each[k] : 0.0f);
    }
    *partial += V > 0.0f && V < 1.0f;
    *checked += 1;
    sl_shadow_sky_points *p = &batch->points;
    const int i = batch->n++;
    p->px[i] = P.x, p->py[i] = P.y, p->pz[i] = P.z, p->nx[i] = N.x, p->ny[i] = N.y, p->nz[i] = N.z;
    batch->V[i] = V;
    if (batch->n == SL_SKY_POINTS)
        check_points(s, batch);
}

/* A scene from its text and the tests' environment (sky). */
static void scene_text_and_env(const char *text, sl_scene *scene, sl_env *env)
{
    sl_error err = {0};
    if (!sl_scene_parse(text, strlen(text), "t.json", "", true, scene, &err))
        fail_msg("%s", err.msg);
    fx_env(env, 64, 32, sky);
}

/* The tests' scene and environment (SCENE, sky). */
static void scene_and_env(sl_scene *scene, sl_env *env) { scene_text_and_env(SCENE, scene, env); }

static void test_lanes_match_scalar(void **state)
{
    (void)state;
    sl_error err = {0};
    sl_scene scene;
    sl_env env;
    scene_and_env(&scene, &env);
    sl_raster *r = sl_raster_create(&(sl_raster_desc){.threads = 1}, &err);
    if (!r)
        fail_msg("%s", err.msg);
    sl_shadow_sky s;
    memset(&s, 0, sizeof s);
    /* 64 then 7 then 32: a block reused by fewer maps, then grown */
    const int counts[] = {64, 7, 32};
    for (int c = 0; c < 3; c++) {
        if (!sl_shadow_sky_build(&s, counts[c], &env, 20.0f * (float)c, r, &scene, NULL, &err))
            fail_msg("%s", err.msg);
        assert_non_null(s.block);
        int partial = 0, checked = 0;
        point_batch batch = {.n = 0};
        for (int i = 0; i < 60000; i++) {
            vec3 P, N;
            fx_occluder_point(&rng, i, &P, &N);
            check(&s, &batch, P, N, &partial, &checked);
        }
        /* off every map, huge, non-finite */
        const vec3 odd_P[] = {vec3(1e4f, 0, 0), vec3(-3e9f, 2e9f, 1), vec3(0, 0, 1e30f), vec3(NAN, 0, 0),
                              vec3(INFINITY, 0, 0), vec3(0, -INFINITY, 0)};
        for (size_t p = 0; p < sizeof odd_P / sizeof odd_P[0]; p++) {
            for (int j = 0; j < 20; j++)
                check(&s, &batch, odd_P[p], rnd_dir(), &partial, &checked);
            check(&s, &batch, odd_P[p], vec3(0, 0, 1), &partial, &checked);
        }
        check(&s, &batch, vec3(0, 0, 0), vec3(NAN, 0, 0), &partial, &checked);
        check(&s, &batch, vec3(0, 0, 0), vec3(0, 0, 0), &partial, &checked);
        check_points(&s, &batch);
        /* the comparison means something: many points see part of the sky */
        if (partial < checked / 20)
            fail_msg("K %d: only %d of %d points partly hidden", counts[c], partial, checked);
    }
    sl_shadow_sky_free(&s);
    assert_null(s.block);
    sl_raster_destroy(r);
    sl_env_free(&env);
    sl_scene_free(&scene);
}

/* The directions and cells split at the horizon: the first count - count / 2 directions over the
 * sky, the rest over the ground, unit and spread over each side (no two of a side within a few
 * degrees at K = 64; across the horizon the ground's mirror the sky's, a band's width apart); every
 * cell's weight vector on its direction's side, under an environment that is bright on both
 * sides and turned (a cell across the horizon would pull its weight towards the other side); the
 * weights sum to the whole environment's sum of lum(L) w dOmega, whatever K. sl_shadow_sky_cell
 * puts each site in its own cell and every direction in a cell on its side whose site is the
 * nearest there, and the weights summed again texel by texel into the cells it gives are the
 * frames' (turned into the world). */
static void test_cells_split_at_horizon(void **state)
{
    (void)state;
    sl_scene scene;
    sl_env env;
    scene_and_env(&scene, &env);
    vec3 total = vec3s(0.0f);
    const int counts[] = {1, 2, 7, 32, 64};
    for (int c = 0; c < 5; c++) {
        const int K = counts[c], sky_count = K - K / 2;
        for (int k = 0; k < K; k++) {
            vec3 d = sl_shadow_sky_direction(k, K);
            assert_float_equal(length(d), 1.0, 1e-6);
            if (k < sky_count ? !(d.z > 0.0f) : !(d.z < 0.0f))
                fail_msg("K %d: direction %d at z %g, on the wrong side", K, k, (double)d.z);
            for (int j = k < sky_count ? 0 : sky_count; j < k; j++)
                if (dot(d, sl_shadow_sky_direction(j, K)) > cosf(radians(K == 64 ? 5.0f : 10.0f)))
                    fail_msg("K %d: directions %d and %d within a few degrees", K, j, k);
        }
        sl_shadow_sky s;
        memset(&s, 0, sizeof s);
        assert_true(sl_shadow_sky_frames(&s, K, &env, 30.0f, &scene));
        vec3 sum = vec3s(0.0f);
        for (int k = 0; k < K; k++) {
            vec3 m = s.weight[k];
            sum = add(sum, m);
            if (K > 1 && (k < sky_count ? !(m.z > 0.0f) : !(m.z < 0.0f)))
                fail_msg("K %d: cell %d's weight at z %g, across the horizon", K, k, (double)m.z);
        }
        /* each site its own cell; random directions in the nearest site's cell on their side */
        for (int k = 0; k < K; k++)
            if (sl_shadow_sky_cell(&s, s.site[k]) != k)
                fail_msg("K %d: site %d in cell %d", K, k, sl_shadow_sky_cell(&s, s.site[k]));
        for (int i = 0; i < 2000; i++) {
            vec3 d = rnd_dir();
            int k = sl_shadow_sky_cell(&s, d);
            assert_true(k >= 0 && k < K);
            if (K > 1 && (k < sky_count) != (d.z >= 0.0f))
                fail_msg("K %d: direction at z %g in cell %d, across the horizon", K, (double)d.z, k);
            for (int j = 0; j < K; j++)
                if ((K == 1 || (j < sky_count) == (k < sky_count)) && dot(d, s.site[j]) > dot(d, s.site[k]))
                    fail_msg("K %d: site %d nearer than cell %d's", K, j, k);
        }
        /* the weights again, each texel into sl_shadow_sky_cell's cell (sky.c cell_weights' sum),
         * then turned by the environment's 30 degrees */
        vec3 m[SL_SKY_MAPS_MAX];
        for (int k = 0; k < K; k++)
            m[k] = vec3s(0.0f);
        const sl_env_level *l0 = &env.levels[0];
        for (int y = 0; y < l0->height; y++)
            for (int x = 0; x < l0->width; x++) {
                vec3 w = sl_uv_to_dir(vec2(((float)x + 0.5f) / (float)l0->width, ((float)y + 0.5f) / (float)l0->height));
                float lum = sl_luminance(l0->texels[(size_t)y * (size_t)l0->width + (size_t)x]);
                float dw = 2.0f * SL_PI * SL_PI / ((float)l0->width * (float)l0->height) * sqrtf(1.0f - w.z * w.z);
                int k = sl_shadow_sky_cell(&s, w);
                m[k] = add(m[k], scale(w, lum * dw));
            }
        const float cr = cosf(radians(30.0f)), sr = sinf(radians(30.0f));
        for (int k = 0; k < K; k++) {
            vec3 mw = vec3(cr * m[k].x - sr * m[k].y, sr * m[k].x + cr * m[k].y, m[k].z);
            if (length(sub(mw, s.weight[k])) > 1e-4f * length(sum))
                fail_msg("K %d: cell %d's weight summed by sl_shadow_sky_cell is (%g, %g, %g), the frames' (%g, %g, "
                         "%g)", K, k, (double)mw.x, (double)mw.y, (double)mw.z, (double)s.weight[k].x,
                         (double)s.weight[k].y, (double)s.weight[k].z);
        }
        if (c == 0)
            total = sum;
        assert_float_equal(sum.x, total.x, 1e-4 * length(total));
        assert_float_equal(sum.y, total.y, 1e-4 * length(total));
        assert_float_equal(sum.z, total.z, 1e-4 * length(total));
        sl_shadow_sky_free(&s);
    }
    sl_env_free(&env);
    sl_scene_free(&scene);
}

static void test_cone_across(void **state)
{
    (void)state;
    sl_shadow_sky maps = {0};
    sl_lighting_uniforms u = {.uEnvRotation = mat3_identity(), .skyMaps = &maps};
    sl_lighting_uniforms none = u;
    none.skyMaps = NULL;
    /* a face turned a little down, and cone axes each leaning from it along one axis (the
     * function reads only the lean's direction) */
    vec3 N = normalize(vec3(-0.95f, 0.0f, -0.3f));
    vec3 up_lean = vec3(N.x, N.y, -N.z);          /* occluders below: the floor */
    vec3 down_lean = vec3(N.x, N.y, N.z - 0.3f);  /* occluders above: an overhang */
    vec3 side_lean = vec3(N.x, N.y + 0.3f, N.z);  /* occluders beside */
    vec3 R_sky = normalize(vec3(-0.44f, 0.9f, 0.06f)), R_ground = normalize(vec3(-0.44f, 0.9f, -0.06f));
    assert_float_equal(shade_cone_across(&none, up_lean, N, R_sky), 0.0f, 0.0f);
    float a = shade_cone_across(&u, up_lean, N, R_sky);
    assert_true(a > 0.99f && a <= 1.0f);
    assert_float_equal(shade_cone_across(&u, up_lean, N, R_ground), 0.0f, 0.0f);
    assert_true(shade_cone_across(&u, down_lean, N, R_ground) > 0.99f);
    assert_float_equal(shade_cone_across(&u, down_lean, N, R_sky), 0.0f, 0.0f);
    assert_true(shade_cone_across(&u, side_lean, N, R_sky) < 1e-6f);
    assert_float_equal(shade_cone_across(&u, N, N, R_sky), 0.0f, 0.0f); /* no lean: nothing said */
    /* the factor: a pedestal's side face beside the floor (model.json, GGX r = 0.3), R just above
     * the horizon and outside the cone, which leans up. The whole share across gives the
     * material's occlusion back, and the factor grows with the share. */
    vec3 Np = normalize(vec3(-0.866f, 0.049f, 0.498f)), Bp = normalize(vec3(-0.694f, 0.034f, 0.719f));
    vec3 Rp = normalize(vec3(-0.442f, 0.895f, 0.059f));
    assert_true(shade_cone_across(&u, Bp, Np, Rp) > 0.7f); /* most of the lean is up */
    sl_so_lobe lobe = sl_so_lobe_cone(sl_gbuffer_ggx_alpha(0.3f));
    float ao = 0.859f, material = 0.9f, occlusion = material * ao;
    float b_dot_r = dot(Bp, Rp), n_dot_v = dot(Np, Rp), last = -1.0f;
    for (int k = 0; k <= 10; k++) {
        float f = shade_spec_occlusion(ao, occlusion, b_dot_r, n_dot_v, lobe, (float)k / 10.0f);
        assert_true(f >= last);
        last = f;
    }
    assert_true(shade_spec_occlusion(ao, occlusion, b_dot_r, n_dot_v, lobe, 0.0f) < 0.8f * material);
    assert_float_equal(last, material, 1e-6);
}

/* A scene (its text) and the tests' environment with 32 maps drawn, and the lighting's uniforms
 * that read them (the environment unrotated, the eye the scene's camera's); draw_maps, the tests'
 * scene's. */
typedef struct {
    sl_scene scene;
    sl_env env;
    sl_raster *raster;
    sl_shadow_sky sky;
    sl_lighting_uniforms u;
} drawn_maps;

static void draw_scene_maps(drawn_maps *m, const char *text)
{
    sl_error err = {0};
    memset(m, 0, sizeof *m);
    scene_text_and_env(text, &m->scene, &m->env);
    m->raster = sl_raster_create(&(sl_raster_desc){.threads = 1}, &err);
    if (!m->raster || !sl_shadow_sky_build(&m->sky, 32, &m->env, 0.0f, m->raster, &m->scene, NULL, &err))
        fail_msg("%s", err.msg);
    m->u = (sl_lighting_uniforms){.uEnvRotation = mat3_identity(), .uEye = m->scene.camera.eye, .skyMaps = &m->sky};
}

static void free_maps(drawn_maps *m)
{
    sl_shadow_sky_free(&m->sky);
    sl_raster_destroy(m->raster);
    sl_env_free(&m->env);
    sl_scene_free(&m->scene);
}

static void draw_maps(drawn_maps *m) { draw_scene_maps(m, SCENE); }

/* A ball's underside three to five map texels over a wide floor: the floor hides every direction
 * below the horizon from it, so each steep ground map its normal faces reads it hidden. The floor
 * is 160 units wide, the maps' texel 0.16 units (SL_SKY_MAP_SIZE 1024). Measured: 70 maps read,
 * none open; with maps of 512 texels (a build with -DSL_SKY_MAP_SIZE=512), whose texel is as tall
 * as these heights, 18 of the 70 read open. */
static void test_underside_over_wide_floor(void **state)
{
    (void)state;
    static const char *wide =
        "{\"camera\": {\"eye\": [0, -8, 3], \"target\": [0, 0, 0.5]},\n"
        " \"environment\": {\"hdr\": \"none.hdr\"},\n"
        " \"materials\": {\"m\": {\"kd\": 0.5}},\n"
        " \"objects\": [\n"
        "  {\"shape\": \"plane\", \"material\": \"m\", \"transform\": {\"scale\": [80, 80, 1]}},\n"
        "  {\"shape\": \"sphere\", \"material\": \"m\", \"transform\": {\"translate\": [0, 0, 1]}}\n"
        " ]}";
    static drawn_maps m;
    draw_scene_maps(&m, wide);
    const sl_shadow_sky *s = &m.sky;
    const int sky_side = s->sky_sites; /* the ground's maps follow */
    int read = 0, open = 0;
    for (int h = 0; h < 3; h++)
        for (int a = 0; a < 8; a++) {
            /* heights 0.5, 0.6, 0.7 over the floor (three to five texels), eight ways round */
            float c = 1.0f - (0.5f + 0.1f * (float)h), sn = sqrtf(1.0f - c * c);
            float phi = 2.0f * SL_PI * (float)a / 8.0f;
            vec3 N = vec3(sn * cosf(phi), sn * sinf(phi), -c), P = add(vec3(0, 0, 1), N);
            float each[SL_SKY_MAPS_MAX];
            sl_shadow_sky_visibility(s, P, N, each);
            for (int k = sky_side; k < s->count; k++)
                /* read, facing N well, looking up from well below the horizon (a map nearer the
                 * horizon sees the floor edge-on, its depth across a texel spanning more than the
                 * height: "contact occlusion is a texel or two wide", docs/lighting.md) */
                if (each[k] >= 0.0f && dot(N, s->maps[k].axis) < -0.5f && s->maps[k].axis.z > 0.5f) {
                    read++;
                    open += each[k] > 0.25f;
                }
        }
    print_message("underside over a 160-unit floor: %d ground maps read, %d of them open\n", read, open);
    assert_true(read > 20);
    assert_int_equal(open, 0);
    free_maps(&m);
}

static void test_sky_plane(void **state)
{
    (void)state;
    sl_error err = {0};
    static drawn_maps m;
    draw_maps(&m);
    sl_gbuffer gb = {0};
    /* a frame whose pixels are coarser than the maps' texels: every texel looked up */
    if (!sl_gbuffer_resize(&gb, 80, 45, &err) || !sl_raster_scene(m.raster, &m.scene, &m.scene.camera, &gb, &err))
        fail_msg("%s", err.msg);
    const sl_lighting_uniforms u = m.u;
    float *coarse = malloc(sizeof(float) * 80 * 45);
    assert_non_null(coarse);
    int coarse_covered = 0;
    for (int i = 0; i < 80 * 45; i++)
        coarse_covered += !(gb.texels[i].depth >= 1.0f);
    assert_int_equal(sl_sky_plane_fill(&u, &gb, coarse, SL_SKY_PLANE_AGREE, 2), coarse_covered);
    free(coarse);
    const int w = 1280, h = 720;
    if (!sl_gbuffer_resize(&gb, w, h, &err) || !sl_raster_scene(m.raster, &m.scene, &m.scene.camera, &gb, &err))
        fail_msg("%s", err.msg);
    float *filled = malloc(sizeof(float) * w * h), *every = malloc(sizeof(float) * w * h),
          *loose = malloc(sizeof(float) * w * h);
    assert_non_null(filled);
    assert_non_null(every);
    assert_non_null(loose);
    int64_t lookups = sl_sky_plane_fill(&u, &gb, filled, SL_SKY_PLANE_AGREE, 2);
    int64_t all = sl_sky_plane_fill(&u, &gb, every, -1.0f, 2);
    sl_sky_plane_fill(&u, &gb, loose, 1.0f, 1); /* any V between anchors on one surface */
    int covered = 0, partial = 0, off = 0, loose_off = 0;
    double sum = 0.0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = (size_t)y * w + (size_t)x;
            if (gb.texels[i].depth >= 1.0f)
                continue;
            covered++;
            partial += every[i] < 0.95f;
            /* the every-texel plane is the lookup */
            const vec3 rows[3] = {u.uEnvRotation.c[0], u.uEnvRotation.c[1], u.uEnvRotation.c[2]};
            shade_view_frame f = shade_view_frame_at(u.uEye, gb.texels[i].position, gb.texels[i].normal, rows);
            assert_float_equal(every[i], sl_shadow_sky_visibility(&m.sky, gb.texels[i].position, f.N, NULL), 0.0f);
            /* the texel's grid: the coarsest spacing dividing x and y (the anchors' at most) */
            int step = 1;
            while (step < SL_SKY_PLANE_SPACING && x % (2 * step) == 0 && y % (2 * step) == 0)
                step *= 2;
            if (step == SL_SKY_PLANE_SPACING)
                assert_float_equal(filled[i], every[i], 0.0f);
            else {
                /* filled from the grid of twice its spacing, `step` away along each axis on which
                 * it lies between two of that grid's texels */
                const int sx = x % (2 * step) ? step : 0, sy = y % (2 * step) ? step : 0;
                bool edge = false; /* a texel it would be filled from is off the image or empty */
                for (int dy = -sy; dy <= sy; dy += sy ? 2 * sy : 1)
                    for (int dx = -sx; dx <= sx; dx += sx ? 2 * sx : 1) {
                        int ax = x + dx, ay = y + dy;
                        edge |= ax < 0 || ay < 0 || ax >= w || ay >= h ||
                                gb.texels[(size_t)ay * w + (size_t)ax].depth >= 1.0f;
                    }
                if (edge)
                    assert_float_equal(filled[i], every[i], 0.0f);
            }
            double d = fabs((double)filled[i] - (double)every[i]);
            sum += d;
            off += d > 1.0 / 255.0;
            loose_off += fabs((double)loose[i] - (double)every[i]) > 1.0 / 255.0;
        }
    print_message("sky plane %dx%d: %d covered (%d partly hidden), lookups %.3f a texel, > 1/255 off at %d "
                  "(without the agreement test %d), mean |dV| %.2g\n",
                  w, h, covered, partial, (double)lookups / covered, off, loose_off, sum / covered);
    assert_true(partial > covered / 10); /* the comparison means something */
    assert_int_equal(all, covered);
    assert_true(lookups < 0.3 * covered && lookups > covered / 16); /* measured 0.187 */
    assert_true(off <= covered / 500);                               /* measured 0.048% */
    assert_true(loose_off > 4 * off);
    assert_true(sum / covered < 1e-4);
    free(filled);
    free(every);
    free(loose);
    sl_gbuffer_free(&gb);
    free_maps(&m);
}

/* shade_lobe_map: a wide lobe about an R that meets the sphere takes the map of R's cell (the
 * sphere hides it), one about an R to the open sky keeps its factor, and so do a narrow lobe and
 * a frame without the maps. */
static void test_lobe_map(void **state)
{
    (void)state;
    static drawn_maps m;
    draw_maps(&m);
    const sl_lighting_uniforms u = m.u;
    sl_lighting_uniforms none = u;
    none.skyMaps = NULL;
    /* the floor in front of the sphere (centre (0.5, 0, 1), radius 1): 37 degrees of it from P */
    vec3 P = vec3(0.5f, -1.3f, 0.0f), N = vec3(0.0f, 0.0f, 1.0f);
    vec3 to_sphere = normalize(vec3(0.0f, 1.3f, 1.0f)), to_sky = normalize(vec3(0.0f, -1.0f, 1.0f));
    const float wide = sl_so_lobe_cone(sl_gbuffer_ggx_alpha(0.5f)).ts;
    const float narrow = sl_so_lobe_cone(sl_gbuffer_ggx_alpha(0.05f)).ts;
    const float half_cell = SL_LOBE_MAP_SHARE * m.sky.cell_angle;
    assert_true(wide > half_cell && narrow < half_cell);
    assert_true(shade_lobe_map(&u, 0.7f, 0.8f, P, N, to_sphere, wide) < 0.1f);
    assert_float_equal(shade_lobe_map(&u, 0.7f, 0.8f, P, N, to_sky, wide), 0.7f, 0.0f);
    assert_float_equal(shade_lobe_map(&u, 0.7f, 0.8f, P, N, to_sphere, narrow), 0.7f, 0.0f);
    assert_float_equal(shade_lobe_map(&none, 0.7f, 0.8f, P, N, to_sphere, wide), 0.7f, 0.0f);
    free_maps(&m);
}

/* sl_shadow_sky_cell_visibility_lanes against sl_shadow_sky_map_visibility of
 * sl_shadow_sky_cell, bit for bit: points on and about the scene, directions any way (on the
 * horizon, NaN among them), runs of every length up to twice SL_SHADOW_LANES and more, for K = 32
 * and 7 (an odd split) and 1 (one side alone). */
static void test_cell_lanes_match_scalar(void **state)
{
    (void)state;
    sl_error err = {0};
    static drawn_maps m;
    draw_maps(&m);
    sl_shadow_sky *s = &m.sky;
    const int counts[] = {32, 7, 1};
    for (int c = 0; c < 3; c++) {
        if (!sl_shadow_sky_build(s, counts[c], &m.env, 15.0f, m.raster, &m.scene, NULL, &err))
            fail_msg("%s", err.msg);
        int partial = 0;
        enum { MOST = 2 * SL_SHADOW_LANES + 5 }; /* runs longer than the lanes too */
        for (int run = 0, n = 1; run < 2000; run++, n = n % MOST + 1) {
            float dx[MOST], dy[MOST], dz[MOST], v[MOST];
            float px[MOST], py[MOST], pz[MOST];
            float nx[MOST], ny[MOST], nz[MOST];
            for (int i = 0; i < n; i++) {
                vec3 d = rnd_dir(), N = rnd_dir();
                vec3 P = i % 2 ? vec3(4.0f * rnd() - 2.0f, 4.0f * rnd() - 2.0f, 0.0f) : add(vec3(0.5f, 0, 1), N);
                if (i % 2)
                    N = vec3(0, 0, 1);
                if (run % 97 == 0 && i == 0)
                    d.z = NAN;
                if (run % 89 == 0 && i == 1)
                    d = normalize(vec3(d.x, d.y, 0.0f)); /* on the horizon */
                dx[i] = d.x, dy[i] = d.y, dz[i] = d.z, px[i] = P.x, py[i] = P.y, pz[i] = P.z;
                nx[i] = N.x, ny[i] = N.y, nz[i] = N.z;
            }
            sl_shadow_sky_cell_visibility_lanes(s, n, dx, dy, dz, px, py, pz, nx, ny, nz, v);
            for (int i = 0; i < n; i++) {
                vec3 d = vec3(dx[i], dy[i], dz[i]), P = vec3(px[i], py[i], pz[i]), N = vec3(nx[i], ny[i], nz[i]);
                float one = sl_shadow_sky_map_visibility(s, sl_shadow_sky_cell(s, d), P, N);
                if (memcmp(&one, &v[i], sizeof one) != 0)
                    fail_msg("K %d, lane %d of %d, d (%.9g %.9g %.9g) P (%.9g %.9g %.9g) N (%.9g %.9g %.9g): lanes "
                             "%.9g, one point %.9g",
                             counts[c], i, n, d.x, d.y, d.z, P.x, P.y, P.z, N.x, N.y, N.z, v[i], one);
                partial += one > 0.0f && one < 1.0f;
            }
        }
        if (partial < 100)
            fail_msg("K %d: only %d lookups partly hidden", counts[c], partial);
    }
    free_maps(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lanes_match_scalar),
        cmocka_unit_test(test_cell_lanes_match_scalar),
        cmocka_unit_test(test_cells_split_at_horizon),
        cmocka_unit_test(test_cone_across),
        cmocka_unit_test(test_sky_plane),
        cmocka_unit_test(test_lobe_map),
        cmocka_unit_test(test_underside_over_wide_floor),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
