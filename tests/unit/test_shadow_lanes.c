/* test_shadow_lanes.c - the shadow maps' lookups made for a run of points at once, a SIMD lane a
 * point, which the batched lighting reads: sl_shadow_sun_visibility_lanes and
 * sl_shadow_point_visibility_lanes against the one-point lookups sl_shadow_sun_visibility and
 * sl_shadow_point_visibility that the port, the trace and the GLSL twin mirror, bit for bit, for
 * thousands of points of a small scene (a floor, a sphere and a box) under two orthographic maps,
 * one steep and one low, and two point lights' cube maps, one over the scene and one low beside
 * the box: on the surfaces (in the shadows, on their edges, on slopes, edge-on to a map), anywhere
 * about the scene with any normal (every face of a cube), and odd points (off a map, huge, NaN, at
 * a light); in runs of every length from 1 to SL_SHADOW_LANES, and one longer. */
#include "occluder_points.h"
#include "shading_fixtures.h"

#include "raster/raster.h"
#include "scene/scene.h"
#include "shadow/shadow.h"

static const char *SCENE = FX_OCCLUDER_SCENE ",\n"
                           /* over the scene, and low beside the box (long shadows across the floor) */
                           " \"lights\": [{\"position\": [1, -1, 5], \"shadow\": true},\n"
                           "            {\"position\": [-3, 2.5, 0.4], \"shadow\": true}]}";

static fx_rng rng = {2024u};

/* Points waiting for a lanes lookup, with the one-point lookup's value of each. */
typedef struct {
    float px[SL_SHADOW_LANES], py[SL_SHADOW_LANES], pz[SL_SHADOW_LANES];
    float nx[SL_SHADOW_LANES], ny[SL_SHADOW_LANES], nz[SL_SHADOW_LANES];
    float expect[SL_SHADOW_LANES];
    int n, size; /* points held; the run's length that flushes them */
} batch;

/* The maps under test: the env lights' (suns) or the point lights' (cubes), and which. */
typedef struct {
    const sl_shadow_suns *suns;
    const sl_shadow_maps *cubes;
    int s;
} maps;

static float one_point(const maps *m, vec3 P, vec3 N)
{
    return m->suns ? sl_shadow_sun_visibility(m->suns, m->s, P, N) : sl_shadow_point_visibility(m->cubes, m->s, P, N);
}

static void flush(const maps *m, batch *b)
{
    if (b->n == 0)
        return;
    float vis[SL_SHADOW_LANES];
    if (m->suns)
        sl_shadow_sun_visibility_lanes(m->suns, m->s, b->n, b->px, b->py, b->pz, b->nx, b->ny, b->nz, vis);
    else
        sl_shadow_point_visibility_lanes(m->cubes, m->s, b->n, b->px, b->py, b->pz, b->nx, b->ny, b->nz, vis);
    for (int i = 0; i < b->n; i++)
        if (memcmp(&vis[i], &b->expect[i], sizeof vis[i]) != 0)
            fail_msg("%s %d, lane %d of %d, P (%.9g %.9g %.9g) N (%.9g %.9g %.9g): lanes %.9g, one point %.9g",
                     m->suns ? "sun map" : "point light", m->s, i,
                     b->n, b->px[i], b->py[i], b->pz[i], b->nx[i], b->ny[i], b->nz[i], vis[i], b->expect[i]);
    b->n = 0;
    b->size = b->size % SL_SHADOW_LANES + 1; /* every run length in turn */
}

/* One point joins the batch. Returns the one-point lookup's value. */
static float add_point(const maps *m, batch *b, vec3 P, vec3 N)
{
    const int i = b->n;
    b->px[i] = P.x, b->py[i] = P.y, b->pz[i] = P.z, b->nx[i] = N.x, b->ny[i] = N.y, b->nz[i] = N.z;
    const float v = one_point(m, P, N);
    b->expect[i] = v;
    if (++b->n == b->size)
        flush(m, b);
    return v;
}

/* Thousands of points of the scene, and odd ones, through both lookups of m; the lookups must
 * see shadows and their edges (else the comparison says little). */
static void check_scene(const maps *m)
{
    batch b = {.n = 0, .size = 1};
    int partial = 0, dark = 0;
    for (int i = 0; i < 40000; i++) {
        vec3 P, N;
        fx_occluder_point(&rng, i, &P, &N);
        float vis = add_point(m, &b, P, N);
        partial += vis > 0.0f && vis < 1.0f;
        dark += vis == 0.0f;
    }
    /* off the map, huge, non-finite, at a light */
    const vec3 odd_P[] = {vec3(1e4f, 0, 0), vec3(-3e9f, 2e9f, 1), vec3(0, 0, 1e30f), vec3(NAN, 0, 0),
                          vec3(INFINITY, 0, 0), vec3(0, -INFINITY, 0), vec3(1, -1, 5), vec3(-3, 2.5f, 0.4f)};
    for (size_t p = 0; p < sizeof odd_P / sizeof odd_P[0]; p++) {
        for (int j = 0; j < 20; j++)
            add_point(m, &b, odd_P[p], fx_rnd_dir(&rng));
        add_point(m, &b, odd_P[p], vec3(0, 0, 1));
    }
    add_point(m, &b, vec3(0, 0, 0), vec3(NAN, 0, 0));
    add_point(m, &b, vec3(0, 0, 0), vec3(0, 0, 0));
    flush(m, &b);
    if (partial < 200 || dark < 1000)
        fail_msg("%s %d: %d points on a shadow's edge, %d in the shadow", m->suns ? "sun map" : "point light", m->s,
                 partial, dark);
}

/* A run longer than the lanes (taken SL_SHADOW_LANES at a time): each value still the one-point
 * lookup's. */
static void check_long_run(const maps *m)
{
    enum { RUN = 2 * SL_SHADOW_LANES + 13 };
    float px[RUN], py[RUN], pz[RUN], nx[RUN], ny[RUN], nz[RUN], vis[RUN];
    for (int i = 0; i < RUN; i++) {
        vec3 N = fx_rnd_dir(&rng), P = add(vec3(0.5f, 0, 1), N); /* the sphere */
        px[i] = P.x, py[i] = P.y, pz[i] = P.z, nx[i] = N.x, ny[i] = N.y, nz[i] = N.z;
    }
    if (m->suns)
        sl_shadow_sun_visibility_lanes(m->suns, m->s, RUN, px, py, pz, nx, ny, nz, vis);
    else
        sl_shadow_point_visibility_lanes(m->cubes, m->s, RUN, px, py, pz, nx, ny, nz, vis);
    for (int i = 0; i < RUN; i++) {
        float one = one_point(m, vec3(px[i], py[i], pz[i]), vec3(nx[i], ny[i], nz[i]));
        if (memcmp(&one, &vis[i], sizeof one) != 0)
            fail_msg("a run of %d, point %d: lanes %.9g, one point %.9g", RUN, i, vis[i], one);
    }
}

static void scene_and_raster(sl_scene *scene, sl_raster **r)
{
    sl_error err = {0};
    if (!sl_scene_parse(SCENE, strlen(SCENE), "t.json", "", true, scene, &err))
        fail_msg("%s", err.msg);
    if (!(*r = sl_raster_create(&(sl_raster_desc){.threads = 1}, &err)))
        fail_msg("%s", err.msg);
}

static void test_sun_lanes_match_scalar(void **state)
{
    (void)state;
    sl_error err = {0};
    sl_scene scene;
    sl_raster *r;
    scene_and_raster(&scene, &r);
    sl_shadow_suns m;
    memset(&m, 0, sizeof m);
    m.count = 2;
    m.maps[0].dir = normalize(vec3(0.4f, -0.3f, 0.8f)); /* steep */
    m.maps[1].dir = normalize(vec3(-0.9f, 0.2f, 0.12f)); /* low: long shadows, grazing floor */
    if (!sl_shadow_ortho_build(m.maps, m.count, 256, r, &scene, NULL, &err))
        fail_msg("%s", err.msg);
    for (int s = 0; s < m.count; s++) {
        check_scene(&(maps){.suns = &m, .s = s});
        check_long_run(&(maps){.suns = &m, .s = s});
    }
    sl_shadow_suns_free(&m);
    sl_raster_destroy(r);
    sl_scene_free(&scene);
}

static void test_point_lanes_match_scalar(void **state)
{
    (void)state;
    sl_error err = {0};
    sl_scene scene;
    sl_raster *r;
    scene_and_raster(&scene, &r);
    assert_int_equal(scene.light_count, 2);
    sl_shadow_maps m;
    memset(&m, 0, sizeof m);
    if (!sl_shadow_build(&m, r, &scene, NULL, false, &err))
        fail_msg("%s", err.msg);
    for (int s = 0; s < m.count; s++) {
        check_scene(&(maps){.cubes = &m, .s = s});
        check_long_run(&(maps){.cubes = &m, .s = s});
    }
    sl_shadow_free(&m);
    sl_raster_destroy(r);
    sl_scene_free(&scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sun_lanes_match_scalar),
        cmocka_unit_test(test_point_lanes_match_scalar),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
