/* test_scene.c - the scene file (scene.c): values and defaults, sRGB hex colours, transform
 * order, mesh sharing, path resolution, every class of error with its JSON path, and every
 * shipped scene. Most tests parse from memory with load_meshes false. */
#include "testutil.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/options.h" /* SL_LIGHTING_MAX_LIGHTS */
#include "scene/scene.h"

static void parse_ok(const char *json, sl_scene *s)
{
    sl_error err = {0};
    if (!sl_scene_parse(json, strlen(json), "t.json", "base", false, s, &err)) {
        print_error("unexpected error: %s\n", err.msg);
        fail();
    }
}

/* Parsing must fail with a message containing `want`; the scene must be left empty. */
static void parse_fails(const char *json, const char *want)
{
    sl_scene s;
    sl_error err = {0};
    bool ok = sl_scene_parse(json, strlen(json), "t.json", "base", false, &s, &err);
    if (ok || !strstr(err.msg, want)) {
        print_error("JSON: %s\nexpected an error containing\n  %s\ngot %s\n  %s\n", json, want,
                    ok ? "success" : "error", err.msg);
        sl_scene_free(&s);
        fail();
    }
    assert_int_equal(s.object_count, 0);
    assert_null(s.objects);
    assert_null(s.materials);
}

static void assert_vec3_near(vec3 a, vec3 b, float tol)
{
    assert_near(a.x, b.x, tol);
    assert_near(a.y, b.y, tol);
    assert_near(a.z, b.z, tol);
}

static vec3 transform_point(mat4 m, vec3 p) { return xyz(mat4_mul_vec4(m, vec4_from3(p, 1.0f))); }

static const char *FULL =
    "{\n"
    "  \"comment\": \"every field given\",\n"
    "  \"camera\": {\"eye\": [1, -8, 3], \"target\": [0, 0, 1], \"up\": [0, 0, 1], \"fovy\": 50,\n"
    "             \"near\": 0.5, \"far\": 40},\n"
    "  \"environment\": {\"hdr\": \"env/a.hdr\", \"irradiance\": \"/abs/irr.hdr\", \"intensity\": 2,\n"
    "                  \"rotation\": 450},\n"
    "  \"materials\": {\n"
    "    \"red\": {\"kd\": [0.5, 0.1, 0.1], \"ks\": 0.04, \"alpha\": 200, \"comment\": \"linear\"},\n"
    "    \"hex\": {\"kd\": \"#ff800a\", \"ks\": \"#BCBCBC\"}\n"
    "  },\n"
    "  \"objects\": [\n"
    "    {\"name\": \"ball\", \"shape\": \"sphere\", \"slices\": 12, \"stacks\": 6, \"material\": \"red\"},\n"
    "    {\"mesh\": \"meshes/thing.obj\", \"material\": \"hex\",\n"
    "     \"transform\": {\"translate\": [1, 2, 3], \"rotate\": [0, 0, 1, 90], \"scale\": [2, 1, 1]}},\n"
    "    {\"shape\": \"box\", \"material\": \"red\", \"transform\": {\"scale\": 3}},\n"
    "    {\"mesh\": \"meshes/thing.obj\", \"material\": \"red\"},\n"
    "    {\"shape\": \"sphere\", \"slices\": 12, \"stacks\": 6, \"material\": \"hex\"},\n"
    "    {\"shape\": \"sphere\", \"material\": \"hex\"}\n"
    "  ],\n"
    "  \"lights\": [{\"position\": [0, 0, 5], \"color\": [1, 0.5, 0.25], \"intensity\": 30, \"shadow\": true},\n"
    "             {\"position\": [1, 1, 1]}],\n"
    "  \"render\": {\"width\": 640, \"height\": 360, \"samples\": 20, \"exposure\": 2.5, \"contrast\": 1.2}\n"
    "}\n";

static void test_full_scene(void **state)
{
    (void)state;
    sl_scene s;
    parse_ok(FULL, &s);
    assert_string_equal(s.path, "t.json");
    assert_vec3_near(s.camera.eye, vec3(1, -8, 3), 0.0f);
    assert_vec3_near(s.camera.target, vec3(0, 0, 1), 0.0f);
    assert_near(s.camera.fovy_deg, 50.0f, 0.0f);
    assert_near(s.camera.znear, 0.5f, 0.0f);
    assert_near(s.camera.zfar, 40.0f, 0.0f);
    /* Relative paths join the base folder; absolute ones stay. */
    assert_string_equal(s.environment.hdr_path, "base/env/a.hdr");
    assert_string_equal(s.environment.irradiance_path, "/abs/irr.hdr");
    assert_near(s.options.env_intensity, 2.0f, 0.0f);
    assert_near(s.environment.rotation_deg, 90.0f, 0.0f); /* 450 mod 360 */

    assert_int_equal(s.material_count, 2);
    assert_string_equal(s.materials[0].name, "red");
    assert_vec3_near(s.materials[0].kd, vec3(0.5f, 0.1f, 0.1f), 0.0f);
    assert_vec3_near(s.materials[0].ks, vec3s(0.04f), 0.0f);
    assert_near(s.materials[0].alpha, 200.0f, 0.0f);
    assert_string_equal(s.materials[1].name, "hex");
    assert_near(s.materials[1].alpha, 100.0f, 0.0f); /* default */

    assert_int_equal(s.object_count, 6);
    assert_string_equal(s.objects[0].name, "ball");
    assert_string_equal(s.objects[1].name, "thing"); /* default: the OBJ's base name */
    assert_string_equal(s.objects[2].name, "box");   /* default: the shape */
    assert_int_equal(s.objects[0].material, 0);
    assert_int_equal(s.objects[1].material, 1);
    /* Meshes: sphere 12x6, thing.obj, box, sphere 64x32 -> 4 distinct; repeats share. */
    assert_int_equal(s.mesh_count, 4);
    assert_int_equal(s.objects[3].mesh, s.objects[1].mesh);
    assert_int_equal(s.objects[4].mesh, s.objects[0].mesh);
    assert_true(s.objects[5].mesh != s.objects[0].mesh);
    const sl_mesh_source *src = &s.mesh_sources[s.objects[1].mesh];
    assert_int_equal(src->kind, SL_MESH_OBJ);
    assert_string_equal(src->path, "base/meshes/thing.obj");
    src = &s.mesh_sources[s.objects[0].mesh];
    assert_int_equal(src->kind, SL_MESH_SPHERE);
    assert_int_equal(src->slices, 12);
    assert_int_equal(src->stacks, 6);
    src = &s.mesh_sources[s.objects[5].mesh];
    assert_int_equal(src->slices, 64); /* defaults */
    assert_int_equal(src->stacks, 32);
    assert_int_equal(s.mesh_sources[s.objects[2].mesh].kind, SL_MESH_BOX);
    /* load_meshes false: nothing built. */
    for (int i = 0; i < s.mesh_count; i++)
        assert_int_equal(s.meshes[i].vertex_count, 0);
    vec3 lo, hi;
    assert_false(sl_scene_bounds(&s, &lo, &hi));
    /* Uniform scale 3. */
    assert_vec3_near(transform_point(s.objects[2].model, vec3(1, 1, 1)), vec3(3, 3, 3), 0.0f);

    assert_int_equal(s.light_count, 2);
    assert_vec3_near(s.lights[0].position, vec3(0, 0, 5), 0.0f);
    assert_vec3_near(s.lights[0].color, vec3(1, 0.5f, 0.25f), 0.0f);
    assert_near(s.lights[0].intensity, 30.0f, 0.0f);
    assert_vec3_near(s.lights[1].color, vec3s(1.0f), 0.0f); /* defaults */
    assert_near(s.lights[1].intensity, 1.0f, 0.0f);
    assert_true(s.lights[0].shadow);
    assert_false(s.lights[1].shadow); /* default: casts only with render.shadows */

    assert_int_equal(s.options.size[0], 640);
    assert_int_equal(s.options.size[1], 360);
    assert_int_equal(s.options.samples, 20);
    assert_near(s.options.exposure, 2.5f, 0.0f);
    assert_near(s.options.contrast, 1.2f, 0.0f);
    sl_scene_free(&s);
    assert_null(s.objects);
}

static void test_defaults(void **state)
{
    (void)state;
    sl_scene s;
    parse_ok("{}", &s);
    assert_vec3_near(s.camera.eye, vec3(0, -5, 2), 0.0f);
    assert_vec3_near(s.camera.target, vec3(0, 0, 0), 0.0f);
    assert_vec3_near(s.camera.up, vec3(0, 0, 1), 0.0f);
    assert_near(s.camera.fovy_deg, 45.0f, 0.0f);
    assert_near(s.camera.znear, 0.1f, 0.0f);
    assert_near(s.camera.zfar, 100.0f, 0.0f);
    assert_string_equal(s.environment.hdr_path, ""); /* black environment */
    assert_near(s.options.env_intensity, 1.0f, 0.0f);
    assert_near(s.environment.rotation_deg, 0.0f, 0.0f);
    assert_int_equal(s.options.size[0], 1280);
    assert_int_equal(s.options.size[1], 720);
    assert_int_equal(s.options.samples, 40);
    assert_near(s.options.exposure, 1.0f, 0.0f);
    assert_near(s.options.contrast, 1.0f, 0.0f);
    assert_int_equal(s.object_count, 0);
    assert_int_equal(s.material_count, 0);
    assert_int_equal(s.light_count, 0);
    sl_scene_free(&s);

    /* An object without a material gets the built-in "default" (Kd 0.5, Ks 0.04, alpha 100),
     * added once however many objects use it; the environment shorthand is a path string. */
    parse_ok("{\"environment\": \"sky.hdr\", \"objects\": [{\"shape\": \"plane\"}, {\"shape\": \"box\"}]}", &s);
    assert_string_equal(s.environment.hdr_path, "base/sky.hdr");
    assert_int_equal(s.material_count, 1);
    assert_string_equal(s.materials[0].name, "default");
    assert_vec3_near(s.materials[0].kd, vec3s(0.5f), 0.0f);
    assert_vec3_near(s.materials[0].ks, vec3s(0.04f), 0.0f);
    assert_near(s.materials[0].alpha, 100.0f, 0.0f);
    assert_int_equal(s.objects[1].material, 0);
    /* Identity transform. */
    assert_vec3_near(transform_point(s.objects[0].model, vec3(1, 2, 3)), vec3(1, 2, 3), 0.0f);
    sl_scene_free(&s);

    /* A scene-defined "default" material is used instead. */
    parse_ok("{\"materials\": {\"x\": {}, \"default\": {\"kd\": 0.2}},"
             " \"objects\": [{\"shape\": \"plane\"}]}",
             &s);
    assert_int_equal(s.material_count, 2);
    assert_int_equal(s.objects[0].material, 1);
    assert_vec3_near(s.materials[1].kd, vec3s(0.2f), 0.0f);
    sl_scene_free(&s);
}

/* "#rrggbb" is sRGB, decoded with the exact piecewise curve (IEC 61966-2-1):
 * c <= 0.04045 ? c / 12.92 : ((c + 0.055) / 1.055)^2.4, c = byte / 255. Hand values:
 * 0x0a -> 10/255 = 0.0392 (linear segment) = 0.00303527; 0x0b -> 0.0431 (power segment)
 * = 0.00334654; 0x80 -> 0.2158605; 0xbc -> 0.5028865; 0xff -> 1. A plain 2.2 power would
 * give 0x80 -> 0.2195 and 0x0a -> 0.00081, both outside the tolerance. */
static void test_hex_colours(void **state)
{
    (void)state;
    sl_scene s;
    parse_ok("{\"materials\": {\"a\": {\"kd\": \"#ff800a\", \"ks\": \"#BCbc0B\"}, \"b\": {\"kd\": \"#000000\"}},"
             " \"lights\": [{\"position\": [0, 0, 1], \"color\": \"#80ff00\"}]}",
             &s);
    assert_vec3_near(s.materials[0].kd, vec3(1.0f, 0.2158605f, 0.00303527f), 1e-7f);
    assert_vec3_near(s.materials[0].ks, vec3(0.5028865f, 0.5028865f, 0.00334654f), 1e-7f);
    assert_vec3_near(s.materials[1].kd, vec3s(0.0f), 0.0f);
    assert_vec3_near(s.lights[0].color, vec3(0.2158605f, 1.0f, 0.0f), 1e-7f);
    sl_scene_free(&s);
}

/* model = T * R * S. With scale (2,1,1), a 90 degree turn about +Z and translate (1,2,3), the
 * point (1,0,0) scales to (2,0,0), turns to (0,2,0) and moves to (1,4,3). Any other order
 * gives something else (S after R: (0,1,0) -> (1,3,3); T first: (4,4,3) ...). */
static void test_transform_order(void **state)
{
    (void)state;
    sl_scene s;
    parse_ok("{\"objects\": [{\"shape\": \"box\", \"transform\": {\"translate\": [1, 2, 3],"
             " \"rotate\": [0, 0, 1, 90], \"scale\": [2, 1, 1]}},"
             /* A list of rotations applies the first listed first: (0,0,1) -> X 90 -> (0,-1,0)
              * -> Z 90 -> (1,0,0). The other order would give (0,-1,0). */
             " {\"shape\": \"box\", \"transform\": {\"rotate\": [[1, 0, 0, 90], [0, 0, 1, 90]]}},"
             /* An unnormalised axis is normalised: 180 degrees about (0,0,5) maps (1,0,0) to (-1,0,0). */
             " {\"shape\": \"box\", \"transform\": {\"rotate\": [0, 0, 5, 180]}}]}",
             &s);
    assert_vec3_near(transform_point(s.objects[0].model, vec3(1, 0, 0)), vec3(1, 4, 3), 1e-6f);
    assert_vec3_near(transform_point(s.objects[0].model, vec3(0, 0, 0)), vec3(1, 2, 3), 0.0f);
    assert_vec3_near(transform_point(s.objects[1].model, vec3(0, 0, 1)), vec3(1, 0, 0), 1e-6f);
    assert_vec3_near(transform_point(s.objects[2].model, vec3(1, 0, 0)), vec3(-1, 0, 0), 1e-6f);
    sl_scene_free(&s);
}

static void test_paths(void **state)
{
    (void)state;
    sl_scene s;
    sl_error err = {0};
    const char *json = "{\"environment\": {\"hdr\": \"a.hdr\"}}";
    assert_true(sl_scene_parse(json, strlen(json), "x", "", false, &s, &err));
    assert_string_equal(s.environment.hdr_path, "a.hdr");
    sl_scene_free(&s);
    assert_true(sl_scene_parse(json, strlen(json), "x", NULL, false, &s, &err));
    assert_string_equal(s.environment.hdr_path, "a.hdr");
    sl_scene_free(&s);
    assert_true(sl_scene_parse(json, strlen(json), "x", "dir/", false, &s, &err));
    assert_string_equal(s.environment.hdr_path, "dir/a.hdr");
    sl_scene_free(&s);
    assert_true(sl_scene_parse(json, strlen(json), NULL, "/", false, &s, &err));
    assert_string_equal(s.environment.hdr_path, "/a.hdr");
    sl_scene_free(&s);
    /* A path too long after joining is an error, not a truncation. */
    char big[SL_PATH_MAX + 64];
    int n = snprintf(big, sizeof big, "{\"environment\": \"");
    for (int i = 0; i < SL_PATH_MAX - 8; i++)
        big[n++] = 'a';
    snprintf(big + n, sizeof big - (size_t)n, "\"}");
    assert_false(sl_scene_parse(big, strlen(big), "x", "some/dir", false, &s, &err));
    assert_non_null(strstr(err.msg, "x: environment: resolved path is longer than"));
}

/* Errors: the file name, the JSON path and what was wrong. */
static void test_error_paths(void **state)
{
    (void)state;
    parse_fails("{\"materials\": {\"red\": {}}, \"objects\": [{\"shape\": \"box\"}, {\"shape\": \"box\"},"
                " {\"shape\": \"box\"}, {\"shape\": \"box\", \"material\": \"gold\"}]}",
                "t.json: objects[3].material: no material named \"gold\"");
    parse_fails("{\"render\": {\"samples\": 5000}}", "t.json: render.samples: 5000 is outside 1..1024");
    parse_fails("{\"render\": {\"samples\": 0}}", "render.samples: 0 is outside 1..1024");
    parse_fails("{\"camera\": {\"eye\": [1, 2]}}", "t.json: camera.eye: expected an array of 3 numbers");
    parse_fails("{\"camera\": {\"eye\": [1, 2, \"3\"]}}", "camera.eye: expected an array of 3 numbers");
    parse_fails("{\"camera\": {\"eye\": {\"x\": 1}}}", "camera.eye: expected an array of 3 numbers");
    parse_fails("{\"camera\": [1]}", "t.json: camera: expected an object");
}

static void test_unknown_and_duplicate_keys(void **state)
{
    (void)state;
    parse_fails("{\"camra\": {}}", "t.json: unknown key \"camra\" (expected camera, environment, materials, "
                                   "objects, lights, render or comment)");
    parse_fails("{\"camera\": {\"fov\": 40}}", "t.json: camera: unknown key \"fov\" (expected eye, target, up, "
                                               "fovy, near, far or comment)");
    parse_fails("{\"objects\": [{\"shape\": \"box\"}, {\"shape\": \"box\", \"transfrom\": {}}]}",
                "objects[1]: unknown key \"transfrom\"");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"transform\": {\"rotation\": [0, 0, 1, 5]}}]}",
                "objects[0].transform: unknown key \"rotation\"");
    parse_fails("{\"materials\": {\"m\": {\"kd\": 0.5, \"Ks\": 0.5}}}", "materials.m: unknown key \"Ks\"");
    parse_fails("{\"lights\": [{\"position\": [0, 0, 1], \"power\": 3}]}", "lights[0]: unknown key \"power\"");
    parse_fails("{\"render\": {\"spp\": 3}}", "render: unknown key \"spp\"");
    parse_fails("{\"environment\": {\"hdr\": \"a.hdr\", \"exposure\": 3}}",
                "environment: unknown key \"exposure\"");
    parse_fails("{\"camera\": {\"fovy\": 30, \"fovy\": 40}}", "t.json: camera: duplicate key \"fovy\"");
    parse_fails("{\"render\": {}, \"render\": {}}", "t.json: duplicate key \"render\"");
    parse_fails("{\"materials\": {\"m\": {}, \"n\": {}, \"m\": {\"kd\": 1}}}",
                "t.json: materials.m: defined twice");
    parse_fails("{\"comment\": 3}", "t.json: comment: expected a string or an array of strings");
    parse_fails("{\"camera\": {\"comment\": [\"a\", 1]}}", "camera.comment: expected a string or an array");
}

/* The microfacet set per material: "brdf" and its parameter (scene.c's parse_material), each
 * error with its JSON path. */
static void test_brdf_keys(void **state)
{
    (void)state;
    sl_scene s;
    parse_ok("{\"materials\": {\"p\": {\"alpha\": 50}, \"q\": {\"brdf\": \"phong\", \"alpha\": 7},"
             " \"g\": {\"brdf\": \"ggx\", \"roughness\": 0.3}, \"d\": {\"brdf\": \"ggx\"},"
             " \"z\": {\"brdf\": \"ggx\", \"roughness\": 0}, \"o\": {\"brdf\": \"ggx\", \"roughness\": 1}}}",
             &s);
    const sl_material *p = NULL, *q = NULL, *g = NULL, *d = NULL, *z = NULL, *o = NULL;
    for (int i = 0; i < s.material_count; i++) {
        const sl_material *m = &s.materials[i];
        const char *n = m->name;
        p = !strcmp(n, "p") ? m : p;
        q = !strcmp(n, "q") ? m : q;
        g = !strcmp(n, "g") ? m : g;
        d = !strcmp(n, "d") ? m : d;
        z = !strcmp(n, "z") ? m : z;
        o = !strcmp(n, "o") ? m : o;
    }
    assert_non_null(p);
    assert_non_null(q);
    assert_non_null(g);
    assert_non_null(d);
    assert_non_null(z);
    assert_non_null(o);
    assert_int_equal(p->brdf, SL_BRDF_PHONG); /* the default for scene materials */
    assert_near(p->alpha, 50.0f, 0.0f);
    assert_int_equal(q->brdf, SL_BRDF_PHONG);
    assert_near(q->alpha, 7.0f, 0.0f);
    assert_int_equal(g->brdf, SL_BRDF_GGX);
    assert_near(g->roughness, 0.3f, 0.0f);
    assert_int_equal(d->brdf, SL_BRDF_GGX);
    assert_near(d->roughness, 0.5f, 0.0f); /* documented default */
    assert_near(z->roughness, 0.0f, 0.0f); /* both ends of [0, 1] are legal */
    assert_near(o->roughness, 1.0f, 0.0f);
    sl_scene_free(&s);

    /* out of range, wrong types, unknown sets */
    parse_fails("{\"materials\": {\"m\": {\"brdf\": \"ggx\", \"roughness\": 1.5}}}",
                "t.json: materials.m.roughness: 1.5 is outside 0..1");
    parse_fails("{\"materials\": {\"m\": {\"brdf\": \"ggx\", \"roughness\": -0.01}}}",
                "materials.m.roughness: -0.01 is outside 0..1");
    parse_fails("{\"materials\": {\"m\": {\"brdf\": \"ggx\", \"roughness\": \"0.5\"}}}",
                "materials.m.roughness: expected a number");
    parse_fails("{\"materials\": {\"m\": {\"brdf\": \"ggx\", \"roughness\": 1e999}}}",
                "materials.m.roughness: inf is not a finite float");
    parse_fails("{\"materials\": {\"m\": {\"brdf\": \"beckmann\"}}}",
                "t.json: materials.m.brdf: unknown brdf \"beckmann\": expected \"phong\" or \"ggx\"");
    parse_fails("{\"materials\": {\"m\": {\"brdf\": \"GGX\"}}}", "materials.m.brdf: unknown brdf \"GGX\"");
    parse_fails("{\"materials\": {\"m\": {\"brdf\": 1}}}", "materials.m.brdf: expected \"phong\" or \"ggx\"");
    /* each set's parameter on the other set is an error, not silently ignored */
    parse_fails("{\"materials\": {\"m\": {\"brdf\": \"ggx\", \"alpha\": 100}}}",
                "t.json: materials.m.alpha: alpha is the Phong exponent; a \"ggx\" material takes \"roughness\"");
    parse_fails("{\"materials\": {\"m\": {\"roughness\": 0.5}}}",
                "t.json: materials.m.roughness: roughness needs \"brdf\": \"ggx\"");
    parse_fails("{\"materials\": {\"m\": {\"brdf\": \"phong\", \"roughness\": 0.5}}}",
                "materials.m.roughness: roughness needs \"brdf\": \"ggx\"");
}

static void test_absurd_values(void **state)
{
    (void)state;
    /* Non-finite: JSON has no NaN, but 1e999 parses to infinity. */
    parse_fails("{\"camera\": {\"fovy\": 1e999}}", "t.json: camera.fovy: inf is not a finite float");
    parse_fails("{\"camera\": {\"eye\": [0, -1e39, 0]}}", "camera.eye[1]: -1e+39 is not a finite float");
    parse_fails("{\"render\": {\"width\": 0}}", "render.width: 0 is outside 1..8192");
    parse_fails("{\"render\": {\"height\": 8193}}", "render.height: 8193 is outside 1..8192");
    parse_fails("{\"render\": {\"width\": 640.5}}", "render.width: expected an integer, got 640.5");
    parse_fails("{\"render\": {\"width\": \"640\"}}", "render.width: expected a number");
    parse_fails("{\"render\": {\"exposure\": 0.01}}", "render.exposure: 0.01 is outside 0.1..10000");
    parse_fails("{\"render\": {\"exposure\": 20000}}", "render.exposure: 20000 is outside 0.1..10000");
    parse_fails("{\"render\": {\"contrast\": 0}}", "render.contrast: 0 must be greater than 0");
    parse_fails("{\"render\": {\"contrast\": -1}}", "render.contrast: -1 is outside 0..10");
    parse_fails("{\"camera\": {\"near\": 0}}", "t.json: camera.near: 0 must be greater than 0");
    parse_fails("{\"camera\": {\"near\": -1}}", "camera.near: -1 must be greater than 0");
    parse_fails("{\"camera\": {\"near\": 2, \"far\": 2}}", "camera.far: 2 must be greater than near (2)");
    parse_fails("{\"camera\": {\"near\": 1e-6, \"far\": 1e6}}", "camera.far: far/near = 1e+12 exceeds 1e+07");
    parse_fails("{\"camera\": {\"fovy\": 180}}", "camera.fovy: 180 is outside (0, 180)");
    parse_fails("{\"camera\": {\"fovy\": 0}}", "camera.fovy: 0 is outside (0, 180)");
    parse_fails("{\"camera\": {\"eye\": [1, 2, 3], \"target\": [1, 2, 3]}}", "camera.target: equals camera.eye");
    parse_fails("{\"camera\": {\"eye\": [0, 0, 10], \"target\": [0, 0, 0]}}",
                "camera.up: (0, 0, 1) is parallel to the view direction");
    parse_fails("{\"camera\": {\"eye\": [0, 0, 10], \"target\": [0, 0, 0], \"up\": [0, 0, -3]}}",
                "camera.up: (0, 0, -3) is parallel");
    parse_fails("{\"camera\": {\"up\": [0, 0, 0]}}", "camera.up: must not be the zero vector");
    parse_fails("{\"materials\": {\"m\": {\"kd\": [1.5, 0, 0]}}}", "materials.m.kd[0]: 1.5 is outside 0..1");
    parse_fails("{\"materials\": {\"m\": {\"ks\": -0.1}}}", "materials.m.ks: -0.1 is outside 0..1");
    parse_fails("{\"materials\": {\"m\": {\"kd\": \"#12345\"}}}",
                "materials.m.kd: expected an sRGB colour \"#rrggbb\", got \"#12345\"");
    parse_fails("{\"materials\": {\"m\": {\"kd\": \"#12345g\"}}}", "materials.m.kd: expected an sRGB colour");
    parse_fails("{\"materials\": {\"m\": {\"kd\": true}}}", "materials.m.kd: expected [r, g, b]");
    parse_fails("{\"materials\": {\"m\": {\"alpha\": 2e6}}}", "materials.m.alpha: 2e+06 is outside 0..1e+06");
    parse_fails("{\"materials\": {\"m\": {\"alpha\": -1}}}", "materials.m.alpha: -1 is outside 0..1e+06");
    parse_fails("{\"materials\": {\"\": {}}}", "a material name must have 1..63 bytes");
    parse_fails("{\"materials\": [1]}", "t.json: materials: expected an object");
    parse_fails("{\"lights\": [{\"color\": [1, 1, 1]}]}", "t.json: lights[0]: missing \"position\"");
    parse_fails("{\"lights\": [{\"position\": [0, 0, 1], \"intensity\": -2}]}",
                "lights[0].intensity: -2 is outside 0..1e+09");
    parse_fails("{\"lights\": {}}", "t.json: lights: expected an array");
    parse_fails("{\"lights\": [{\"position\": [0, 0, 1], \"shadow\": 1}]}",
                "t.json: lights[0].shadow: expected true or false");
    parse_fails("{\"environment\": {\"intensity\": 2}}", "environment: missing \"hdr\"");
    parse_fails("{\"environment\": {\"hdr\": \"\"}}", "environment.hdr: expected a non-empty string");
    parse_fails("{\"environment\": {\"hdr\": \"a.hdr\", \"intensity\": -1}}",
                "environment.intensity: -1 is outside 0..1e+06");
    parse_fails("{\"environment\": 3}", "environment: expected an object");
}

static void test_object_errors(void **state)
{
    (void)state;
    parse_fails("{\"objects\": {}}", "t.json: objects: expected an array");
    parse_fails("{\"objects\": [3]}", "t.json: objects[0]: expected an object");
    parse_fails("{\"objects\": [{}]}", "objects[0]: needs \"mesh\" (an .obj path), \"shape\"");
    parse_fails("{\"objects\": [{\"mesh\": \"a.obj\", \"shape\": \"box\"}]}",
                "objects[0]: has more than one of \"mesh\", \"shape\" and \"model\"");
    parse_fails("{\"objects\": [{\"shape\": \"cube\"}]}",
                "objects[0].shape: unknown shape \"cube\" (expected sphere, plane or box)");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"slices\": 8}]}",
                "objects[0].slices: only a sphere has slices");
    parse_fails("{\"objects\": [{\"shape\": \"sphere\", \"stacks\": 1}]}",
                "objects[0].stacks: 1 is outside 2..512");
    parse_fails("{\"objects\": [{\"shape\": \"sphere\", \"slices\": 4096}]}",
                "objects[0].slices: 4096 is outside 3..1024");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"material\": 3}]}",
                "objects[0].material: expected a material name");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"transform\": {\"scale\": -1}}]}",
                "objects[0].transform.scale: -1 is outside 1e-06..1e+06");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"transform\": {\"scale\": [1, 0, 1]}}]}",
                "objects[0].transform.scale: 0 is outside");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"transform\": {\"scale\": \"big\"}}]}",
                "objects[0].transform.scale: expected a number or an array of 3 numbers");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"transform\": {\"rotate\": [0, 0, 0, 90]}}]}",
                "objects[0].transform.rotate: the rotation axis must not be the zero vector");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"transform\": {\"rotate\": [[0, 0, 1, 90], [1, 0, 0]]}}]}",
                "objects[0].transform.rotate[1]: expected [ax, ay, az, degrees]");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"transform\": {\"rotate\": []}}]}",
                "objects[0].transform.rotate: expected [ax, ay, az, degrees]");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"transform\": {\"translate\": [0, 0]}}]}",
                "objects[0].transform.translate: expected an array of 3 numbers");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"name\": \"a-name-that-is-much-longer-than-the-sixty-three-"
                "bytes-allowed-for-names\"}]}",
                "objects[0].name: 71 bytes is longer than the 63 allowed");
}

/* n objects, object i naming "m<i % distinct>.obj" (with distinct = n, the same as
 * python3 -c "print('{\"objects\":[' + ','.join('{\"mesh\":\"m%d.obj\"}' % i for i in range(80000)) + ']}')"). */
static char *many_objects_json(int n, int distinct)
{
    char *json = malloc((size_t)n * 32 + 32), *at = json;
    assert_non_null(json);
    at += sprintf(at, "{\"objects\": [");
    for (int i = 0; i < n; i++)
        at += sprintf(at, "%s{\"mesh\": \"m%d.obj\"}", i ? ", " : "", i % distinct);
    sprintf(at, "]}");
    return json;
}

/* CPU seconds of this thread: unlike the wall clock, not inflated by other work on a loaded
 * machine (the parser runs on one thread). */
static double thread_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU seconds to parse n objects naming n distinct meshes (the fastest of `reps`). */
static double parse_seconds(int n, int reps)
{
    char *json = many_objects_json(n, n);
    double best = 1e30;
    for (int r = 0; r < reps; r++) {
        sl_scene s;
        double t0 = thread_seconds();
        parse_ok(json, &s);
        double t = thread_seconds() - t0;
        best = t < best ? t : best;
        assert_int_equal(s.mesh_count, n);
        sl_scene_free(&s);
    }
    free(json);
    return best;
}

/* Many objects naming distinct meshes: a duplicate-mesh check that compares each object with
 * every mesh before it takes 18.6 s at 80,000 objects. The cost must be linear:
 * 4 times the objects (20,000 -> 80,000, each the faster of two runs; both sizes are past the
 * caches, so the ratio measures the algorithm: about 4 here) may take at most 10 times as long,
 * quadratic would be 16, plus 0.25 s of slack for noise; and 80,000 objects must parse in
 * under 5 s of CPU (a generous cap for sanitizer builds: a Release build takes about 0.35 s). */
static void test_many_objects_linear(void **state)
{
    (void)state;
    /* Sharing still works: 3000 objects over 1000 distinct paths. */
    char *json = many_objects_json(3000, 1000);
    sl_scene s;
    parse_ok(json, &s);
    assert_int_equal(s.object_count, 3000);
    assert_int_equal(s.mesh_count, 1000);
    for (int i = 0; i < 3000; i++) {
        assert_int_equal(s.objects[i].mesh, i % 1000);
        char want[32];
        snprintf(want, sizeof want, "base/m%d.obj", i % 1000);
        assert_string_equal(s.mesh_sources[s.objects[i].mesh].path, want);
    }
    sl_scene_free(&s);
    free(json);

    double small = parse_seconds(20000, 2), large = parse_seconds(80000, 2);
    printf("parse (CPU): 20,000 objects naming distinct meshes %.3f s, 80,000 %.3f s (ratio %.1f)\n", small, large,
           large / small);
    if (large > 10.0 * small + 0.25) {
        print_error("80,000 objects took %.3f s, 20,000 took %.3f s: worse than linear\n", large, small);
        fail();
    }
    if (large > 5.0) {
        print_error("80,000 objects took %.3f s of CPU (cap 5 s)\n", large);
        fail();
    }
}

/* A 17th point light is refused where the scene is read, with the file and the JSON path (not
 * only when a frame is lit, and also with --no-lights). */
static void test_light_limit(void **state)
{
    (void)state;
    char json[4096] = "{\"lights\": [";
    for (int i = 0; i < SL_LIGHTING_MAX_LIGHTS; i++)
        strcat(json, i ? ", {\"position\": [0, 0, 1]}" : "{\"position\": [0, 0, 1]}");
    strcat(json, "]}");
    sl_scene s;
    parse_ok(json, &s);
    assert_int_equal(s.light_count, 16);
    sl_scene_free(&s);
    json[strlen(json) - 2] = '\0';
    strcat(json, ", {\"position\": [0, 0, 2]}, {\"bad\": 1}]}");
    parse_fails(json, "t.json: lights[16]: at most 16 point lights (MAX_LIGHTS of shaders/lighting.frag)");
}

/* Nesting past cJSON's limit is named as such, not reported as mere "invalid JSON". */
static void test_json_nesting(void **state)
{
    (void)state;
    /* {"camera": {"eye": [[...]]}}: 2 objects, then n arrays */
    char *json = malloc(4096);
    assert_non_null(json);
    for (int n = 998; n <= 999; n++) {
        int at = sprintf(json, "{\"camera\": {\"eye\": ");
        memset(json + at, '[', (size_t)n);
        memset(json + at + n, ']', (size_t)n);
        strcpy(json + at + 2 * n, "}}");
        /* 1000 levels parse (and the shape is then wrong); 1001 do not */
        parse_fails(json, n == 998 ? "t.json: camera.eye: expected an array of 3 numbers"
                                   : "t.json:1:1018: camera.eye[0][0][0]");
        if (n == 999)
            parse_fails(json, "arrays and objects nested deeper than 1000 levels (the JSON parser's limit)");
    }
    free(json);
    /* other syntax errors keep their message */
    parse_fails("{\"a\": [[[1,]]]}", "t.json:1:12: invalid JSON near ']]]}'");
}

/* "\u0000" would cut a key short without a word ("na\u0000me" read as "na"), and a value (a
 * mesh path) too. Both are refused, with the path. */
static void test_json_nul(void **state)
{
    (void)state;
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"na\\u0000me\": \"x\"}]}",
                "t.json:1:34: objects[0]: the key \"na\\u0000me\" holds \\u0000 (a NUL character)");
    parse_fails("{\"cam\\u0000era\": {}}", "t.json:1:6: the key \"cam\\u0000era\" holds \\u0000");
    parse_fails("{\"materials\": {\"m\": {\"kd\\u0000\": 1}}}", "t.json:1:25: materials.m: the key \"kd\\u0000\"");
    parse_fails("{\"objects\": [{\"shape\": \"box\"}, {\"mesh\": \"a.obj\\u0000junk\"}]}",
                "t.json:1:47: objects[1].mesh: the string \"a.obj\\u0000junk\" holds \\u0000");
    parse_fails("{\"comment\": [\"a\", \"\\u0000\"]}", "t.json:1:20: comment[1]: the string");
    /* an escaped backslash before u0000 is text, not the escape; other escapes are fine */
    sl_scene s;
    parse_ok("{\"objects\": [{\"shape\": \"box\", \"name\": \"a\\\\u0000\"}], \"comment\": \"\\u0001\\n\"}", &s);
    assert_string_equal(s.objects[0].name, "a\\u0000");
    sl_scene_free(&s);
    /* A backslash as the file's last byte: the string scan stepped past the end and copied a byte
     * beyond the buffer (found by fuzz_scene; the exact-size buffer lets ASan see it). */
    char *tail = malloc(3);
    assert_non_null(tail);
    memcpy(tail, "{\"\\", 3);
    sl_error err;
    sl_scene t;
    assert_false(sl_scene_parse(tail, 3, "t.json", "base", false, &t, &err));
    assert_non_null(strstr(err.msg, "t.json:1:"));
    free(tail);
}

/* Bytes from the file are not echoed raw into messages (an escape sequence in a key would reach
 * the terminal): they are masked as the .hdr and OBJ readers do; names and paths may not hold
 * control characters at all. */
static void test_messages_masked(void **state)
{
    (void)state;
    parse_fails("{\"\x1b[2J\": 1}", "t.json: unknown key \"?[2J\"");
    parse_fails("{\"camera\": {\"fovy\": 1, \"fovy\": 2, \"\x1b\": 0}}", "camera: duplicate key \"fovy\"");
    parse_fails("{\"camera\": {\"\xff\xfe\": 1}}", "camera: unknown key \"??\"");
    parse_fails("{\"objects\": [{\"shape\": \"\x1b[31mred\"}]}", "objects[0].shape: unknown shape \"?[31mred\"");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"material\": \"\x07\xc3\xa9\"}]}",
                "objects[0].material: no material named \"???\"");
    parse_fails("{\"materials\": {\"m\": {\"kd\": \"#\x1b\x1b\x1b\x1b\x1b\x1b\"}}}", "got \"#??????\"");
    parse_fails("{\"materials\": {\"m\\u001b[2J\": {}}}",
                "t.json: materials.m?[2J: \"m?[2J\" holds a control character (byte 0x1b at 1)");
    parse_fails("{\"objects\": [{\"mesh\": \"a\\n.obj\"}]}",
                "objects[0].mesh: \"a?.obj\" holds a control character (byte 0x0a at 1)");
    parse_fails("{\"objects\": [{\"shape\": \"box\", \"name\": \"a\\tb\"}]}", "objects[0].name: \"a?b\" holds");
    /* a long key is cut at 64 bytes */
    parse_fails("{\"render\": {\"aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa\": 1}}",
                "render: unknown key \"aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa...\"");
    /* non-ASCII names are still fine (UTF-8), only shown masked */
    sl_scene s;
    parse_ok("{\"materials\": {\"caf\xc3\xa9\": {}}, \"objects\": [{\"shape\": \"box\", \"material\": \"caf\xc3\xa9\"}]}",
             &s);
    assert_string_equal(s.materials[0].name, "caf\xc3\xa9");
    sl_scene_free(&s);
}

static void test_json_syntax(void **state)
{
    (void)state;
    parse_fails("{\n  \"camera\": {\n    \"eye\": [1, 2, 3],,\n  }\n}\n", "t.json:3:");
    parse_fails("", "t.json:1:1: invalid JSON");
    parse_fails("{\"render\": {}", "t.json:1:");
    parse_fails("{} {}", "t.json:1:4: unexpected text after the JSON object");
    parse_fails("[1, 2]", "t.json: expected a JSON object {...} at the top level");
    /* Whitespace after the object is fine; so is a UTF-8 byte order mark before it. */
    sl_scene s;
    parse_ok("\xEF\xBB\xBF{}\n\n  \t", &s);
    sl_scene_free(&s);
}

static void test_free_is_safe(void **state)
{
    (void)state;
    sl_scene s;
    memset(&s, 0, sizeof s);
    sl_scene_free(&s);
    sl_scene_free(&s);
    sl_scene_free(NULL);
    vec3 lo, hi;
    assert_false(sl_scene_bounds(&s, &lo, &hi));
}

/* With load_meshes true: shapes are built, bounds are exact, a broken mesh reports its object. */
static void test_load_meshes(void **state)
{
    (void)state;
    sl_scene s;
    sl_error err = {0};
    const char *json = "{\"objects\": [{\"shape\": \"plane\", \"transform\": {\"translate\": [1, 0, 0],"
                       " \"scale\": [2, 3, 1]}},"
                       " {\"shape\": \"box\", \"transform\": {\"translate\": [0, 0, 5]}}]}";
    assert_true(sl_scene_parse(json, strlen(json), "t.json", "", true, &s, &err));
    assert_int_equal(s.meshes[0].vertex_count, 4);
    assert_int_equal(s.meshes[1].vertex_count, 24);
    vec3 lo, hi;
    assert_true(sl_scene_bounds(&s, &lo, &hi));
    assert_vec3_near(lo, vec3(-1, -3, 0), 0.0f); /* plane x in [-2,2]+1, y in [-3,3]; box z in [4,6] */
    assert_vec3_near(hi, vec3(3, 3, 6), 0.0f);
    sl_scene_free(&s);

    /* A broken OBJ: the message says which object, which file and which line. */
    const char *bad = test_tmpfile("bad.obj");
    test_write_bytes(bad, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", 32);
    char scene_json[1024];
    snprintf(scene_json, sizeof scene_json,
             "{\"objects\": [{\"shape\": \"box\"}, {\"mesh\": \"bad.obj\"}, {\"mesh\": \"bad.obj\"}]}");
    assert_false(sl_scene_parse(scene_json, strlen(scene_json), "t.json", test_tmpdir(), true, &s, &err));
    assert_non_null(strstr(err.msg, "t.json: objects[1].mesh: "));
    assert_non_null(strstr(err.msg, "bad.obj:4: face index 7 out of range (1..3)"));
    assert_null(s.meshes);
    /* A missing OBJ. */
    snprintf(scene_json, sizeof scene_json, "{\"objects\": [{\"mesh\": \"nowhere.obj\"}]}");
    assert_false(sl_scene_parse(scene_json, strlen(scene_json), "t.json", test_tmpdir(), true, &s, &err));
    assert_non_null(strstr(err.msg, "t.json: objects[0].mesh: "));
    assert_non_null(strstr(err.msg, "nowhere.obj: cannot open"));
}

/* sl_scene_load resolves paths against the scene file's folder. */
static void test_load_relative(void **state)
{
    (void)state;
    const char *obj = test_tmpfile("tri.obj");
    test_write_bytes(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 32);
    const char *path = test_tmpfile("tri.json");
    const char *json = "{\"objects\": [{\"mesh\": \"tri.obj\"}], \"environment\": \"sky.hdr\"}";
    test_write_bytes(path, json, strlen(json));
    sl_scene s;
    sl_error err = {0};
    if (!sl_scene_load(path, &s, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
    assert_int_equal(s.meshes[0].triangle_count, 1);
    char want[SL_PATH_MAX];
    snprintf(want, sizeof want, "%s/sky.hdr", test_tmpdir());
    assert_string_equal(s.environment.hdr_path, want);
    assert_string_equal(s.path, path);
    sl_scene_free(&s);
    assert_false(sl_scene_load("scenes/no-such-scene.json", &s, &err));
    assert_int_equal(err.code, SL_ERR_IO);
    assert_non_null(strstr(err.msg, "no-such-scene.json"));
}

static void load_shipped(const char *path, sl_scene *s)
{
    sl_error err = {0};
    if (!sl_scene_load(path, s, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
    for (int i = 0; i < s->mesh_count; i++)
        assert_true(sl_mesh_validate(&s->meshes[i], path, &err));
    vec3 lo, hi;
    assert_true(sl_scene_bounds(s, &lo, &hi));
    assert_true(s->environment.hdr_path[0] != '\0');
    /* Every shipped scene's environment exists beside it. */
    FILE *f = fopen(s->environment.hdr_path, "rb");
    assert_non_null(f);
    fclose(f);
}

static void test_shipped_scenes(void **state)
{
    (void)state;
    static const char *const scenes[] = {"scenes/default.json", "scenes/bunny.json", "scenes/city-sun.json",
                                         "scenes/top-down.json", "scenes/grazing.json"};
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        sl_scene s;
        load_shipped(scenes[i], &s);
        sl_scene_free(&s);
    }

    /* default.json: the 5 x 4 chart, one shared sphere mesh, the values the scene file gives. */
    sl_scene s;
    load_shipped("scenes/default.json", &s);
    assert_int_equal(s.object_count, 20);
    assert_int_equal(s.material_count, 20);
    assert_int_equal(s.mesh_count, 1);
    assert_string_equal(s.environment.hdr_path, "scenes/envmaps/studio.hdr");
    assert_int_equal(s.options.size[0], 1280);
    assert_int_equal(s.options.size[1], 720);
    assert_int_equal(s.options.samples, 40);
    assert_near(s.options.contrast, 1.0f, 0.0f);
    static const float alphas[5] = {1, 10, 100, 1000, 10000}, kss[4] = {0.04f, 0.2f, 0.5f, 0.9f};
    for (int o = 0; o < 20; o++) {
        const sl_material *m = &s.materials[s.objects[o].material];
        assert_near(m->alpha, alphas[o % 5], 0.0f);
        assert_near(m->ks.x, kss[o / 5], 0.0f);
        assert_near(m->kd.x, 0.5f * (1.0f - kss[o / 5]), 1e-6f);
    }
    /* The grid fits the 16:9 frustum: every sphere's centre +- 1 is inside the view. */
    float aspect = (float)s.options.size[0] / (float)s.options.size[1];
    mat4 vp = mat4_mul(perspective(radians(s.camera.fovy_deg), aspect, s.camera.znear, s.camera.zfar),
                       lookAt(s.camera.eye, s.camera.target, s.camera.up));
    for (int o = 0; o < 20; o++) {
        vec3 c = transform_point(s.objects[o].model, vec3(0, 0, 0));
        for (int k = 0; k < 4; k++) {
            vec3 p = add3(c, vec3(k & 1 ? 1.0f : -1.0f, 0.0f, k & 2 ? 1.0f : -1.0f));
            vec4 clip = mat4_mul_vec4(vp, vec4_from3(p, 1.0f));
            assert_true(fabsf(clip.x) < clip.w && fabsf(clip.y) < clip.w);
        }
    }
    sl_scene_free(&s);

    /* bunny.json: the Y-up bunny stands upright on the floor (z = 0): feet at 0, about 1.93
     * tall (9.65 x 0.2), and taller than it is deep (Y extent of the Z-up world). */
    load_shipped("scenes/bunny.json", &s);
    const sl_object *bunny = NULL;
    for (int o = 0; o < s.object_count; o++)
        if (strcmp(s.objects[o].name, "bunny") == 0)
            bunny = &s.objects[o];
    assert_non_null(bunny);
    const sl_mesh *m = &s.meshes[bunny->mesh];
    assert_int_equal(m->vertex_count, 1839);
    vec3 lo = vec3s(INFINITY), hi = vec3s(-INFINITY);
    for (int v = 0; v < m->vertex_count; v++) {
        vec3 w = transform_point(bunny->model, m->positions[v]);
        lo = vmin3(lo, w);
        hi = vmax3(hi, w);
    }
    assert_near(lo.z, 0.0f, 0.002f);
    assert_near(hi.z, 1.931f, 0.002f);
    assert_true(hi.z - lo.z > hi.y - lo.y);
    assert_int_equal(s.light_count, 1);
    sl_scene_free(&s);

    /* top-down.json looks straight down -Z. */
    load_shipped("scenes/top-down.json", &s);
    vec3 dir = normalize3(sub3(s.camera.target, s.camera.eye));
    assert_vec3_near(dir, vec3(0, 0, -1), 0.0f);
    sl_scene_free(&s);

    /* grazing.json: the view direction is within a few degrees of the floor. */
    load_shipped("scenes/grazing.json", &s);
    dir = normalize3(sub3(s.camera.target, s.camera.eye));
    assert_true(fabsf(dir.z) < sinf(radians(5.0f)));
    assert_true(s.camera.eye.z > 0.0f && s.camera.eye.z < 1.0f);
    sl_scene_free(&s);
}

/* The complete example in docs/scene-format.md parses, so the documentation cannot drift
 * from the reader. */
/* Texture maps: both spellings, defaults, one image per (file, colour space), the cutoff rules. */
static void test_texture_maps(void **state)
{
    (void)state;
    sl_scene s;
    parse_ok("{\"materials\": {"
             "\"a\": {\"kd_map\": \"bricks.png\", \"normal_map\": \"bricks_n.png\"},"
             "\"b\": {\"kd\": [0.5, 1, 1], \"kd_map\": {\"file\": \"bricks.png\", \"wrap\": \"mirror\","
             " \"filter\": \"nearest\", \"uv_scale\": [4, 2], \"uv_offset\": [0.5, -1]},"
             " \"ks_map\": {\"file\": \"bricks.png\", \"srgb\": false}, \"alpha_map\": \"gloss.png\"},"
             "\"c\": {\"mask_map\": \"leaf.png\"},"
             "\"d\": {\"kd_map\": \"leaf.png\", \"alpha_cutoff\": 0.25},"
             "\"e\": {\"kd\": [1, 0, 0]}}}",
             &s);
    assert_int_equal(s.material_count, 5);
    /* bricks.png sRGB (a.kd, b.kd), bricks_n.png linear, bricks.png linear (b.ks), gloss.png, leaf.png
     * linear (c.mask), leaf.png sRGB (d.kd): 6 images for 8 maps. */
    assert_int_equal(s.image_count, 6);
    const sl_material *a = &s.materials[0], *b = &s.materials[1], *c = &s.materials[2], *d = &s.materials[3];
    assert_true(a->textured && !a->masked);
    assert_true(a->maps[SL_MAP_KD].set && a->maps[SL_MAP_NORMAL].set && !a->maps[SL_MAP_KS].set);
    assert_string_equal(s.images[a->maps[SL_MAP_KD].image].path, "base/bricks.png");
    assert_true(s.images[a->maps[SL_MAP_KD].image].srgb);
    assert_false(s.images[a->maps[SL_MAP_NORMAL].image].srgb); /* data maps are linear */
    assert_string_equal(s.images[a->maps[SL_MAP_KD].image].used_by, "materials.a.kd_map");
    assert_int_equal(a->maps[SL_MAP_KD].wrap, SL_MAP_REPEAT);
    assert_int_equal(a->maps[SL_MAP_KD].filter, SL_MAP_TRILINEAR);
    assert_near(a->maps[SL_MAP_KD].uv_scale.x, 1.0f, 0.0f);
    assert_near(a->maps[SL_MAP_KD].uv_offset.y, 0.0f, 0.0f);
    assert_int_equal(b->maps[SL_MAP_KD].image, a->maps[SL_MAP_KD].image); /* loaded once */
    assert_true(b->maps[SL_MAP_KS].image != b->maps[SL_MAP_KD].image);    /* same file, linear */
    assert_false(s.images[b->maps[SL_MAP_KS].image].srgb);
    assert_int_equal(b->maps[SL_MAP_KD].wrap, SL_MAP_MIRROR);
    assert_int_equal(b->maps[SL_MAP_KD].filter, SL_MAP_NEAREST);
    assert_near(b->maps[SL_MAP_KD].uv_scale.x, 4.0f, 0.0f);
    assert_near(b->maps[SL_MAP_KD].uv_offset.y, -1.0f, 0.0f);
    assert_near(b->kd.x, 0.5f, 0.0f); /* the constant stays: a tint */
    assert_true(c->masked && c->alpha_cutoff == 0.5f);
    assert_true(d->masked && d->alpha_cutoff == 0.25f);
    assert_false(s.materials[4].textured);
    sl_scene_free(&s);

    parse_fails("{\"materials\": {\"m\": {\"kd_map\": 3}}}", "materials.m.kd_map: expected an image path");
    parse_fails("{\"materials\": {\"m\": {\"kd_map\": {\"srgb\": true}}}}", "materials.m.kd_map: needs \"file\"");
    parse_fails("{\"materials\": {\"m\": {\"kd_map\": {\"file\": \"x.png\", \"wrap\": \"border\"}}}}",
                "materials.m.kd_map.wrap: expected \"repeat\", \"clamp\" or \"mirror\", got \"border\"");
    parse_fails("{\"materials\": {\"m\": {\"kd_map\": {\"file\": \"x.png\", \"filter\": 1}}}}",
                "materials.m.kd_map.filter: expected \"trilinear\"");
    parse_fails("{\"materials\": {\"m\": {\"kd_map\": {\"file\": \"x.png\", \"uv_scale\": [1e5, 1]}}}}",
                "materials.m.kd_map.uv_scale: 100000 is outside -10000..10000");
    parse_fails("{\"materials\": {\"m\": {\"kd_map\": {\"file\": \"x.png\", \"uv_offset\": [1]}}}}",
                "materials.m.kd_map.uv_offset: expected an array of 2 numbers");
    parse_fails("{\"materials\": {\"m\": {\"kd_map\": {\"file\": \"x.png\", \"srgb\": 1}}}}",
                "materials.m.kd_map.srgb: expected true or false");
    parse_fails("{\"materials\": {\"m\": {\"kd_map\": {\"file\": \"x.png\", \"mip\": 1}}}}",
                "materials.m.kd_map: unknown key \"mip\"");
    parse_fails("{\"materials\": {\"m\": {\"ks_map\": \"x.png\", \"alpha_cutoff\": 0.5}}}",
                "materials.m.alpha_cutoff: needs a mask_map or a kd_map");
    parse_fails("{\"materials\": {\"m\": {\"mask_map\": \"x.png\", \"alpha_cutoff\": 2}}}",
                "materials.m.alpha_cutoff: 2 is outside 0..1");
    /* 65 distinct files: over the limit, named at the map that crosses it. */
    char json[8192];
    int n = snprintf(json, sizeof json, "{\"materials\": {");
    for (int i = 0; i <= SL_SCENE_MAX_IMAGES; i++)
        n += snprintf(json + n, sizeof json - (size_t)n, "%s\"m%d\": {\"kd_map\": \"t%d.png\"}", i ? ", " : "", i, i);
    snprintf(json + n, sizeof json - (size_t)n, "}}");
    parse_fails(json, "materials.m64.kd_map: more than 64 distinct image files in one scene");
}

/* Maps on a mesh without texture coordinates: an error naming the object, the material, the map's
 * file and the mesh. Shapes always have them. */
static void test_maps_need_uvs(void **state)
{
    (void)state;
    const char *obj = test_tmpfile("no_uv.obj");
    test_write_bytes(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 32);
    char json[1024];
    snprintf(json, sizeof json,
             "{\"materials\": {\"brick\": {\"kd_map\": \"bricks.png\"}},"
             " \"objects\": [{\"shape\": \"plane\", \"material\": \"brick\"},"
             " {\"mesh\": \"no_uv.obj\", \"material\": \"brick\"}]}");
    sl_scene s;
    sl_error err = {0};
    assert_false(sl_scene_parse(json, strlen(json), "t.json", test_tmpdir(), true, &s, &err));
    assert_msg_contains(err, "t.json: objects[1]: material \"brick\" has a kd_map (");
    assert_msg_contains(err, "bricks.png) but the mesh ");
    assert_msg_contains(err, "no_uv.obj has no texture coordinates");
    assert_null(s.materials);
    /* Without meshes loaded (the fuzz target), nothing is opened and nothing is checked. */
    assert_true(sl_scene_parse(json, strlen(json), "t.json", test_tmpdir(), false, &s, &err));
    sl_scene_free(&s);
}

static void test_documented_example(void **state)
{
    (void)state;
    FILE *f = fopen("docs/scene-format.md", "rb");
    assert_non_null(f);
    static char doc[65536];
    size_t n = fread(doc, 1, sizeof doc - 1, f);
    fclose(f);
    doc[n] = '\0';
    char *start = strstr(doc, "```json\n");
    assert_non_null(start);
    start += strlen("```json\n");
    char *end = strstr(start, "```");
    assert_non_null(end);
    sl_scene s;
    sl_error err = {0};
    if (!sl_scene_parse(start, (size_t)(end - start), "scene-format.md", "scenes", false, &s, &err)) {
        print_error("%s\n", err.msg);
        fail();
    }
    assert_int_equal(s.object_count, 4);
    assert_int_equal(s.material_count, 3);
    assert_int_equal(s.light_count, 1);
    assert_string_equal(s.mesh_sources[0].path, "scenes/meshes/bunny.obj");
    sl_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_scene),
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_hex_colours),
        cmocka_unit_test(test_transform_order),
        cmocka_unit_test(test_paths),
        cmocka_unit_test(test_error_paths),
        cmocka_unit_test(test_unknown_and_duplicate_keys),
        cmocka_unit_test(test_absurd_values),
        cmocka_unit_test(test_brdf_keys),
        cmocka_unit_test(test_object_errors),
        cmocka_unit_test(test_many_objects_linear),
        cmocka_unit_test(test_json_syntax),
        cmocka_unit_test(test_light_limit),
        cmocka_unit_test(test_json_nesting),
        cmocka_unit_test(test_json_nul),
        cmocka_unit_test(test_messages_masked),
        cmocka_unit_test(test_free_is_safe),
        cmocka_unit_test(test_load_meshes),
        cmocka_unit_test(test_load_relative),
        cmocka_unit_test(test_shipped_scenes),
        cmocka_unit_test(test_texture_maps),
        cmocka_unit_test(test_maps_need_uvs),
        cmocka_unit_test(test_documented_example),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
