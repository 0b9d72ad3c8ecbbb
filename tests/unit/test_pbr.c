/* test_pbr.c - glTF metallic-roughness per texel, occlusion and emission:
 * a glTF written here whose metallicRoughnessTexture makes the surface a metal, with an
 * occlusionTexture at strength 0.5 and an emissive factor, drawn into the G-buffer (Kd, Ks,
 * roughness and the extra plane checked against hand-computed values); then the lighting shader
 * on a one-texel G-buffer with the extra plane: occlusion 0.5 halves the image-based terms and
 * leaves a point light alone; emission adds exactly its value under a black environment; both
 * paths (the port and the batched one). And the G-buffer's size: a scene without the channels
 * has no extra plane. */
#include "shading_fixtures.h"

#include <stdio.h>

#include "raster/gbuffer_textured.h"

/* One big triangle (-2,-2,0), (2,-2,0), (0,2,0) in glTF's Y-up space (Z-up: the plane y = 0), all UVs (0.5, 0.5): every
 * fragment reads the centre of the 2x2 texture, whose four texels are equal, so filtering and the
 * level of detail cannot change the value. The buffer: positions 36 B, UVs 24 B, indices 6 B. */
static void write_model(const char *name, const char *mr_png, const char *occ_png)
{
    const float pos[9] = {-2, -2, 0, 2, -2, 0, 0, 2, 0};
    const float uv[6] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
    const unsigned short idx[4] = {0, 1, 2, 0};
    unsigned char bin[68];
    memcpy(bin, pos, 36);
    memcpy(bin + 36, uv, 24);
    memcpy(bin + 60, idx, 8);
    char binname[64], path[64], text[4096];
    snprintf(binname, sizeof binname, "%s.bin", name);
    test_write_bytes(test_tmpfile(binname), bin, sizeof bin);
    snprintf(text, sizeof text,
             "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],\n"
             " \"nodes\": [{\"mesh\": 0}],\n"
             " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"TEXCOORD_0\": 1},"
             " \"indices\": 2, \"material\": 0}]}],\n"
             " \"materials\": [{\"name\": \"gold\", \"pbrMetallicRoughness\": {\"baseColorFactor\": [0.8, 0.4, 0.2, 1],"
             " \"metallicFactor\": 1, \"roughnessFactor\": 0.5, \"metallicRoughnessTexture\": {\"index\": 0}},"
             " \"occlusionTexture\": {\"index\": 1, \"strength\": 0.5}, \"emissiveFactor\": [0.25, 0.5, 1]}],\n"
             " \"textures\": [{\"source\": 0}, {\"source\": 1}],\n"
             " \"images\": [{\"uri\": \"%s\"}, {\"uri\": \"%s\"}],\n"
             " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC3\","
             " \"min\": [-2, -2, 0], \"max\": [2, 2, 0]},\n"
             "   {\"bufferView\": 1, \"componentType\": 5126, \"count\": 3, \"type\": \"VEC2\"},\n"
             "   {\"bufferView\": 2, \"componentType\": 5123, \"count\": 3, \"type\": \"SCALAR\"}],\n"
             " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 36},\n"
             "   {\"buffer\": 0, \"byteOffset\": 36, \"byteLength\": 24},\n"
             "   {\"buffer\": 0, \"byteOffset\": 60, \"byteLength\": 6}],\n"
             " \"buffers\": [{\"uri\": \"%s\", \"byteLength\": 68}]}\n",
             mr_png, occ_png, binname);
    snprintf(path, sizeof path, "%s.gltf", name);
    test_write_bytes(test_tmpfile(path), text, strlen(text));
}

/* A 2x2 RGB PNG of one colour, given as codes 0..255 (the encoder takes display values). */
static void write_png(const char *name, int r, int g, int b)
{
    sl_image img;
    sl_error err = {0};
    assert_true(sl_image_alloc(&img, 2, 2, 3, &err));
    for (int i = 0; i < 4; i++) {
        img.data[3 * i] = (float)r / 255.0f;
        img.data[3 * i + 1] = (float)g / 255.0f;
        img.data[3 * i + 2] = (float)b / 255.0f;
    }
    unsigned char *bytes = NULL;
    size_t size = 0;
    assert_true(sl_image_encode_png(&img, &bytes, &size, &err));
    test_write_bytes(test_tmpfile(name), bytes, size);
    free(bytes);
    sl_image_free(&img);
}

/* The scene's G-buffer (33x33, camera on -Y looking at the origin), through the textured program. */
static void draw(sl_scene *scene, sl_gbuffer *gb)
{
    sl_error err = {0};
    scene->camera = (sl_camera){.eye = vec3(0, -5, 0), .target = vec3(0, 0, 0), .up = vec3(0, 0, 1),
                                .fovy_deg = 30, .znear = 0.1f, .zfar = 100};
    sl_scene_textures tex;
    sl_raster *r = sl_raster_create(&(sl_raster_desc){.threads = 1}, &err);
    if (!r || !sl_scene_textures_load(scene, 0, &tex, &err) || !sl_gbuffer_resize(gb, 33, 33, &err) ||
        !sl_raster_scene_textured(r, scene, &tex, &scene->camera, gb, &err))
        fail_msg("%s", err.msg);
    sl_scene_textures_free(&tex);
    sl_raster_destroy(r);
}

/* metallicRoughnessTexture texel (0, 128, 255) read linear: roughness = 0.5 * 128/255, metallic =
 * 1 * 1 = 1, so Kd = base (1 - 1) = 0 and Ks = mix(0.04, base, 1) = base = (0.8, 0.4, 0.2).
 * occlusionTexture texel R = 64/255 at strength 0.5: 1 + 0.5 (64/255 - 1). Emission (0.25, 0.5, 1). */
static void test_gltf_metal_texel(void **state)
{
    (void)state;
    write_png("mr.png", 0, 128, 255);
    write_png("occ.png", 64, 0, 0);
    write_model("pbr", "mr.png", "occ.png");
    sl_scene scene;
    sl_error err = {0};
    if (!sl_scene_load(test_tmpfile("pbr.gltf"), &scene, &err))
        fail_msg("%s", err.msg);
    assert_string_equal(scene.warnings, ""); /* everything is drawn */
    sl_gbuffer gb = {0};
    draw(&scene, &gb);
    const sl_gbuffer_texel *t = sl_gbuffer_at(&gb, 16, 16);
    assert_true(sl_gbuffer_covered(t));
    assert_near(t->kd.x, 0.0f, 1e-7f);
    assert_near(t->kd.y, 0.0f, 1e-7f);
    assert_near(t->ks.x, 0.8f, 1e-6f);
    assert_near(t->ks.y, 0.4f, 1e-6f);
    assert_near(t->ks.z, 0.2f, 1e-6f);
    assert_near(t->alpha, sl_gbuffer_ggx_alpha(0.5f * 128.0f / 255.0f), 1e-6f);
    assert_non_null(gb.extra);
    const sl_gbuffer_extra *e = &gb.extra[16 * 33 + 16];
    assert_near(e->occlusion, 1.0f + 0.5f * (64.0f / 255.0f - 1.0f), 1e-6f);
    assert_near(e->emissive.x, 0.25f, 1e-7f);
    assert_near(e->emissive.y, 0.5f, 1e-7f);
    assert_near(e->emissive.z, 1.0f, 1e-7f);
    /* an empty pixel (the corner is off the triangle) has none */
    assert_false(sl_gbuffer_covered(sl_gbuffer_at(&gb, 0, 32)));
    assert_near(gb.extra[32 * 33].occlusion, 1.0f, 0.0f);
    assert_near(gb.extra[32 * 33].emissive.x, 0.0f, 0.0f);
    sl_gbuffer_free(&gb);
    sl_scene_free(&scene);
}

/* A dielectric texel (B = 0): Kd = base, Ks = 0.04; roughness 0.5 * 1. */
static void test_gltf_dielectric_texel(void **state)
{
    (void)state;
    write_png("mr0.png", 0, 255, 0);
    write_png("occ1.png", 255, 0, 0);
    write_model("pbr0", "mr0.png", "occ1.png");
    sl_scene scene;
    sl_error err = {0};
    if (!sl_scene_load(test_tmpfile("pbr0.gltf"), &scene, &err))
        fail_msg("%s", err.msg);
    sl_gbuffer gb = {0};
    draw(&scene, &gb);
    const sl_gbuffer_texel *t = sl_gbuffer_at(&gb, 16, 16);
    assert_near(t->kd.x, 0.8f, 1e-6f);
    assert_near(t->kd.z, 0.2f, 1e-6f);
    assert_near(t->ks.x, 0.04f, 1e-7f);
    assert_near(t->ks.z, 0.04f, 1e-7f);
    assert_near(t->alpha, sl_gbuffer_ggx_alpha(0.5f), 1e-6f);
    assert_near(gb.extra[16 * 33 + 16].occlusion, 1.0f, 1e-7f);
    sl_gbuffer_free(&gb);
    sl_scene_free(&scene);
}

/* The scene-file form: a metallic material folded to constants when it has no per-texel input
 * (drawn by the untextured program, no extra plane: 56 bytes a pixel); with an emissive
 * constant, the textured program and the plane (76). */
static void test_scene_keys_and_plane(void **state)
{
    (void)state;
    const char *json = "{\"materials\": {\"m\": {\"brdf\": \"ggx\", \"kd\": [0.8, 0.4, 0.2], \"metallic\": 0.5}},"
                       " \"objects\": [{\"shape\": \"sphere\", \"material\": \"m\"}]}";
    sl_scene scene;
    sl_error err = {0};
    if (!sl_scene_parse(json, strlen(json), "k.json", "", true, &scene, &err))
        fail_msg("%s", err.msg);
    const sl_material *m = &scene.materials[scene.objects[0].material];
    assert_false(m->textured);
    assert_near(m->kd.x, 0.4f, 1e-6f);                 /* 0.8 (1 - 0.5) */
    assert_near(m->ks.x, 0.04f + 0.5f * 0.76f, 1e-6f); /* mix(0.04, 0.8, 0.5) = 0.42 */
    sl_gbuffer gb = {0};
    draw(&scene, &gb);
    assert_null(gb.extra);
    assert_int_equal(sl_gbuffer_pixel_bytes(gb.extra != NULL), 56);
    sl_scene_free(&scene);

    const char *lit = "{\"materials\": {\"m\": {\"kd\": 0.5, \"emissive\": [2, 0, 0]}},"
                      " \"objects\": [{\"shape\": \"sphere\", \"material\": \"m\"}]}";
    if (!sl_scene_parse(lit, strlen(lit), "e.json", "", true, &scene, &err))
        fail_msg("%s", err.msg);
    assert_true(scene.materials[scene.objects[0].material].textured);
    draw(&scene, &gb);
    assert_non_null(gb.extra);
    assert_int_equal(sl_gbuffer_pixel_bytes(true), 76);
    assert_near(gb.extra[16 * 33 + 16].emissive.x, 2.0f, 0.0f);
    sl_gbuffer_free(&gb);
    sl_scene_free(&scene);

    /* the keys' errors */
    const char *bad[] = {
        "{\"materials\": {\"m\": {\"kd\": 0.5, \"metallic\": 0.5}}}",                       /* Phong */
        "{\"materials\": {\"m\": {\"brdf\": \"ggx\", \"ks\": 0.5, \"metallic\": 0.5}}}",    /* ks too */
        "{\"materials\": {\"m\": {\"brdf\": \"ggx\", \"metallic\": 1.5}}}",                 /* range */
        "{\"materials\": {\"m\": {\"occlusion_strength\": 0.5}}}",                          /* no map */
        "{\"materials\": {\"m\": {\"emissive\": [-1, 0, 0]}}}",                             /* range */
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        bool ok = sl_scene_parse(bad[i], strlen(bad[i]), "bad.json", "", false, &scene, &err);
        if (ok) {
            sl_scene_free(&scene);
            fail_msg("accepted %s", bad[i]);
        }
        assert_non_null(strstr(err.msg, "bad.json: materials.m."));
    }
}

static vec3 zero_env(vec3 d)
{
    (void)d;
    return vec3s(0.0f);
}

/* One texel facing +Z seen at N.V = 0.8, with its extra texel, shaded by the port or the batched
 * path; the rest through fx_* (shading_fixtures.h). */
static vec3 shade(const sl_env *env, const sl_irradiance *irr, bool plain, bool lights, sl_gbuffer_extra e)
{
    sl_point_light light = {.position = vec3(0, 0, 3), .color = vec3s(1.0f), .intensity = 9.0f};
    sl_lighting_desc d = {.options = {.samples = 16, .plain = plain}, .env = env, .irradiance = irr,
                          .eye = scale3(fx_view_dir(0.8f, 0.3f), 10.0f), .inv_view_proj = mat4_identity(),
                          .width = 1, .height = 1, .lights = lights ? &light : NULL, .light_count = lights};
    sl_lighting_uniforms *u = fx_uniforms_for(&d);
    sl_gbuffer_texel t = fx_texel(vec3(0, 0, 1), vec3(0.5f, 0.4f, 0.3f), vec3s(0.04f), sl_gbuffer_ggx_alpha(0.4f));
    e.depth = t.depth;
    sl_gbuffer gb = {.width = 1, .height = 1, .texels = &t, .extra = &e};
    vec3 c;
    if (plain)
        c = sl_lighting_shade(u, &gb, 0, 0, NULL, NULL);
    else
        sl_lighting_shade_row(u, &gb, 0, 0, 1, NULL, &c);
    free(u);
    return c;
}

static void test_lighting_occlusion_emission(void **state)
{
    (void)state;
    sl_env env = {0}, black = {0};
    fx_env(&env, 64, 32, fx_const_one);
    fx_env(&black, 64, 32, zero_env);
    sl_irradiance irr = {0}, irr_black = {0};
    sl_error err;
    assert_true(sl_irradiance_sh9(&irr, &env, &err));
    assert_true(sl_irradiance_sh9(&irr_black, &black, &err));
    const sl_gbuffer_extra none = {.occlusion = 1.0f}, half = {.occlusion = 0.5f};
    for (int plain = 0; plain < 2; plain++) {
        /* occlusion 0.5 halves the image-based terms (exactly: one multiplication by 0.5) */
        vec3 ibl = shade(&env, &irr, plain, false, none), ibl_half = shade(&env, &irr, plain, false, half);
        assert_true(ibl.x > 0.1f);
        assert_near(ibl_half.x, 0.5f * ibl.x, 0.0f);
        assert_near(ibl_half.z, 0.5f * ibl.z, 0.0f);
        /* ... and not the point light: (with light, half) - (no light, half) = light alone */
        vec3 light = sub3(shade(&black, &irr_black, plain, true, none), shade(&black, &irr_black, plain, false, none));
        assert_true(light.x > 0.01f);
        vec3 lit_half = shade(&env, &irr, plain, true, half);
        assert_near(lit_half.x, ibl_half.x + light.x, 1e-6f * lit_half.x);
        /* emission adds exactly its value under a black environment */
        sl_gbuffer_extra glow = {.occlusion = 1.0f, .emissive = vec3(0.25f, 0.5f, 1.0f)};
        vec3 c = shade(&black, &irr_black, plain, false, glow);
        assert_near(c.x, 0.25f, 0.0f);
        assert_near(c.y, 0.5f, 0.0f);
        assert_near(c.z, 1.0f, 0.0f);
    }
    sl_irradiance_free(&irr);
    sl_irradiance_free(&irr_black);
    sl_env_free(&env);
    sl_env_free(&black);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gltf_metal_texel),
        cmocka_unit_test(test_gltf_dielectric_texel),
        cmocka_unit_test(test_scene_keys_and_plane),
        cmocka_unit_test(test_lighting_occlusion_emission),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
